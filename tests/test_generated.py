"""The generated kernels (generated/*.py) against the generator and the symbolic models.

* staleness: the committed files (kernels, their scalar twins, layouts.py and the glue
  tca_kernels*.py) are exactly what the generator renders today;
* determinism: rendering is repeatable, also under another PYTHONHASHSEED;
* hygiene: header, "do not edit", no timestamps, imports (numpy modules only typing and numpy,
  the scalar twins only math, layouts.py only typing, the glue only numpy/typing and its
  sibling generated modules), an ``# ops:`` count per function;
* interfaces: documented input and output shapes, the generated NamedTuple outputs and
  parameter layouts;
* maths: generated == lambdified symbolic outputs at seeded random points; Jacobians ==
  complex-step derivatives (also of the composed Eq 38 system of the glue); CSE build ==
  non-CSE build; scalar twins == numpy kernels; batches broadcast;
* the generator's validation (free symbols, duplicate argument names), the registry's
  model-variant mechanism, and ``beveloid derive --check``.

The sympy models are built once per session (``kernels.module_specs()`` takes ~5 s,
``module_specs()`` below caches it).  Three generator bugs found while writing these tests
(outputs not broadcast against all inputs, output names shadowing inputs, an unused source
name) are fixed; the tests that found them stay.

Tolerances are relative with a unit floor, ``|a - b| <= rtol * max(|a|, |b|, 1)``: every
quantity is in mm, rad or 1 and of order 1..500 in these domains, so the floor only
matters for values that are small by cancellation (a TCA residual, x_t2, E - offset).
"""
from __future__ import annotations

import ast
import functools
import importlib
import inspect
import os
import re
import shutil
import subprocess
import sys
import tokenize
import types
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import codegen, kernels

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
TEMPLATES = {False: "derivations/templates/module.py.jinja", True: "derivations/templates/scalar_module.py.jinja"}
HINT = "run `beveloid derive` to update"

# One xdist worker runs this module: its sympy models and renderings (~60 s) are built once per process.
pytestmark = pytest.mark.xdist_group("generated")

SEED = 20130101
N_POINTS = 20
RTOL = 1e-12  # generated vs symbolic, CSE vs no-CSE, complex step
DEG = np.pi / 180
MODEL = "involute"  # the surface model of both members wherever one is needed
FLANKS = tuple(name for name, _ in kernels.FLANKS)


# ---------------------------------------------------------------------------------------
# fixtures: build the sympy specs and the renderings once
# ---------------------------------------------------------------------------------------


@functools.cache
def module_specs():
    """{module name: ModuleSpec} from one ``kernels.module_specs()`` call (the sampler needs it too)."""
    return {s.module: s for s in kernels.module_specs()}


@pytest.fixture(scope="module")
def specs():
    return module_specs()


@pytest.fixture(scope="module")
def rendered(specs):
    """{file name: text} rendered in memory, as ``beveloid derive`` would write it."""
    return codegen.generate(None, list(specs.values()), extra=kernels.glue_files())


@pytest.fixture(scope="module")
def nocse_texts(specs):
    return {name: codegen.render_module(spec, cse=False) for name, spec in specs.items()}


@pytest.fixture(scope="module")
def nocse(nocse_texts):
    """{module name: namespace} of the non-CSE builds, exec'd in memory."""
    return {name: _exec_module(text, f"<{name} (no CSE)>") for name, text in nocse_texts.items()}


def _exec_module(text, name):
    ns = {"__name__": name}
    exec(compile(text, name, "exec"), ns)
    return ns


def _committed(module):
    return importlib.import_module(f"beveloid.generated.{module}")


def _public_functions(mod):
    return [n for n, f in vars(mod).items()
            if inspect.isfunction(f) and not n.startswith("_") and f.__module__ == mod.__name__]


# Module lists of the committed package (cheap to import; checked against the registry below).
_PACKAGE = importlib.import_module("beveloid.generated")
MODULES = tuple(_PACKAGE.MODULES)
SCALAR_MODULES = tuple(_PACKAGE.SCALAR_MODULES)
SUPPORT_MODULES = tuple(_PACKAGE.SUPPORT_MODULES)
SURFACE_MODULES = tuple(m for m in MODULES if m.startswith("surface_"))
FILES = ["__init__.py"] + [f"{m}.py" for m in MODULES + SCALAR_MODULES + SUPPORT_MODULES]

# (module, function) pairs of the committed kernels; checked against the specs below.
FUNCTIONS = [(m, f) for m in MODULES for f in _public_functions(_committed(m))]
FUNCTION_IDS = [f"{m}.{f}" for m, f in FUNCTIONS]


def _spec_function(specs, module, name):
    (fn,) = [f for f in specs[module].functions if f.name == name]
    return fn


def _spec_arg(module, function, name):
    (arg,) = [a for a in _spec_function(module_specs(), module, function).inputs if a.name == name]
    return arg


# ---------------------------------------------------------------------------------------
# sampling the physical domain
# ---------------------------------------------------------------------------------------


def _uniform(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n)


def _degrees(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n) * DEG


def _signed(lo, hi, unit=1.0):
    """+-[lo, hi] * unit: either sign, never near zero."""
    return lambda rng, n: rng.choice([-1.0, 1.0], n) * rng.uniform(lo, hi, n) * unit


def _around(centre, half_width):
    return lambda rng, n: centre + rng.uniform(-half_width, half_width, n)


def _teeth(centre, half_width):
    return lambda rng, n: rng.integers(centre - half_width, centre + half_width + 1, n).astype(float)


# Scalars and layout fields of the surfaces, placement, TCA and blanks: a wide physical domain.
# "pinion_"/"gear_" prefixes share a domain.
PHYSICAL = {
    "l": _uniform(0, 15), "u": _uniform(-20, 20),
    "l_mm": _uniform(0, 15), "u_mm": _uniform(-20, 20), "angle_rad": _uniform(-0.5, 0.5),  # tca_kernels.UNKNOWNS
    "angle": _uniform(-0.5, 0.5),  # pinion_angle, gear_angle
    "normal_pressure_angle": _degrees(14, 25),
    "helix_angle": _degrees(-40, 40),
    "cone_angle": _signed(0.5, 8, DEG),
    "cutter_addendum_mm": _uniform(2.5, 10),  # 1.25 m_n, m_n 2..8 mm
    "half_thickness_mm": _uniform(1.5, 6.5),  # pi m_n / 4
    "rack_shift_mm": _uniform(-3, 3),
    "pitch_radius_mm": _uniform(15, 400),  # m_n N / (2 cos beta), N 15..80
    "face_width_mm": _uniform(10, 120), "normal_module_mm": _uniform(2, 8),  # crowned model
    "profile_crowning_um": _uniform(0, 200), "lead_crowning_um": _uniform(0, 200),
    "dx_mm": _uniform(-0.5, 0.5), "dy_mm": _uniform(-0.5, 0.5), "dz_mm": _uniform(-0.5, 0.5),
    "vertical_rad": _degrees(-0.3, 0.3), "horizontal_rad": _degrees(-0.3, 0.3),
    "offset_mm": _uniform(20, 300),
    "shaft_angle": _degrees(5, 30),
    "axial_placement_mm": _uniform(-100, 100),
    "tip_height_mm": _uniform(2, 8),  # m_n
    "toe_z_mm": _signed(5, 60), "heel_z_mm": _signed(5, 60),  # either order: the margins take both
    "cutter_tip_radius_mm": _uniform(0, 3), "psi": _uniform(0, 1.3),  # root fillet: rho_a0 <= 0.47 m_n
    "form_limit_l_mm": _uniform(0, 1.5),
    "z": _uniform(-40, 40),  # tooth_sections: a transverse section
    "radius": _uniform(400, 600),  # tooth_sections: above every base radius (pitch radius <= 400)  # the blank's form limit: l_t = rho_a0 (1 - sin alpha_n) / cos alpha_n
}

# Design equations: case 1 of the paper, perturbed (the asin/acos arguments stay real).
CASE1 = {
    "alpha_nw": _around(21.25 * DEG, 1 * DEG),
    "normal_module": _around(6.0, 0.5),
    "normal_pressure_angle": _around(20 * DEG, 1 * DEG),
    "pinion_teeth": _teeth(29, 2), "gear_teeth": _teeth(45, 2),
    "shaft_angle": _around(13 * DEG, 1 * DEG),
    "pinion_profile_shift": _around(0.15, 0.1),
    "pinion_cone_angle": _around(2 * DEG, 0.3 * DEG), "gear_cone_angle": _around(0.8 * DEG, 0.2 * DEG),
    "pinion_helix_angle": _around(23 * DEG, 1 * DEG),
    "offset": _around(229.0, 5.0),
    "pinion_working_cone_angle": _around(1.8873 * DEG, 0.2 * DEG),
    "gear_working_cone_angle": _around(0.7549 * DEG, 0.1 * DEG),
    "pinion_working_helix_angle": _around(23.199 * DEG, 1 * DEG),
}


def _points(rng, n, shape):
    """Points of a member frame S_i at radii 10..400 mm, |z| < 60 mm."""
    assert shape == (3,)
    r, t, z = rng.uniform(10, 400, n), rng.uniform(-np.pi, np.pi, n), rng.uniform(-60, 60, n)
    return np.stack([r * np.cos(t), r * np.sin(t), z], axis=-1)


def _unit_vectors(rng, n, shape):
    assert shape == (3,)
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# Vector and matrix arguments, by name without the member prefix; others entry-wise uniform(-1, 1).
ARRAYS = {"point": _points, "normal": _unit_vectors}


def _member(name):
    return name.removeprefix("pinion_").removeprefix("gear_")


def _domain(module, name):
    if module == "design_equations":
        return CASE1[name]
    return PHYSICAL[name] if name in PHYSICAL else PHYSICAL[_member(name)]


def sample_arg(module, arg, rng, n):
    """Float array (n, *arg.shape) drawn from the argument's domain (layouts field by field)."""
    if isinstance(arg.symbol, codegen.Layout):
        # the base entries from their domains, the derived ones (with_trig) computed from them as pack does
        base = {f.symbol: _domain(module, f.name)(rng, n) for f in arg.symbol.base_fields()}
        derived = lambda f: np.broadcast_to(sp.lambdify(list(base), f.derived, "numpy")(*base.values()), (n,))  # noqa: E731
        return np.stack([base[f.symbol] if f.derived is None else derived(f) for f in arg.symbol.fields], axis=-1)
    if isinstance(arg.symbol, sp.MatrixBase):
        draw = ARRAYS.get(_member(arg.name), lambda rng, n, shape: rng.uniform(-1, 1, (n,) + shape))
        return draw(rng, n, arg.shape)
    return _domain(module, arg.name)(rng, n)


def sample(module, function, n, seed=SEED):
    """{argument name: float array (n, *per-point shape)} for a generated kernel."""
    rng = np.random.default_rng(seed)
    return {a.name: sample_arg(module, a, rng, n) for a in _spec_function(module_specs(), module, function).inputs}


def sample_contact(n, seed=SEED):
    """Arguments of ``tca_kernels.contact_system`` after (pinion_model, gear_model, flank), both
    members of MODEL (parameters zero-padded to PARAMETER_COUNT as pack_surface_params does)."""
    tk = _committed("tca_kernels")
    rng = np.random.default_rng(seed)
    params = _spec_arg(f"surface_{MODEL}", "surface_left", "params")

    def member():
        p = sample_arg(f"surface_{MODEL}", params, rng, n)
        return np.concatenate([p, np.zeros((n, tk.PARAMETER_COUNT - p.shape[-1]))], axis=-1)

    def arg(name):
        return sample_arg("contact_system", _spec_arg("contact_system", "contact_residual", name), rng, n)

    values = dict(x=np.stack([_domain("tca_kernels", k)(rng, n) for k in tk.UNKNOWNS], axis=-1),
                  pinion_angle=arg("pinion_angle"), errors=arg("errors"), pinion_params=member(),
                  gear_params=member(), pair=arg("pair"))
    assert list(inspect.signature(tk.contact_system).parameters)[3:] == list(values)
    return values


def _args_of(module, function):
    return list(inspect.signature(getattr(_committed(module), function)).parameters)


def _at(value, i):
    """Point i of a sampled argument: a float for a scalar argument, an array for the others."""
    return float(value[i]) if np.ndim(value) == 1 else value[i]


# ---------------------------------------------------------------------------------------
# shapes and comparison
# ---------------------------------------------------------------------------------------


def _expr_shape(expr):
    """Per-point shape of an output, as codegen documents it ((k, 1) matrices are vectors)."""
    if isinstance(expr, sp.MatrixBase):
        return (expr.shape[0],) if expr.shape[1] == 1 else tuple(expr.shape)
    return ()


_DOC_LINE = re.compile(r"^        (\w+): .*?(?:, shape \(\.\.\.((?:, \d+)*)\))?$", re.M)
_RETURNS = re.compile(r"^    Returns (\w+):$", re.M)


def documented(function):
    """(outputs class, {input: per-point shape}, {output: per-point shape}) from the docstring."""
    parts = _RETURNS.split(function.__doc__)
    assert len(parts) == 3, f"{function.__name__}: no single 'Returns <Class>:' line in the docstring"
    head, cls, returns = parts

    def shapes(text):
        return {m[1]: tuple(int(k) for k in (m[2] or "").split(", ")[1:]) for m in _DOC_LINE.finditer(text)}

    return cls, shapes(head.split("\n    Inputs", 1)[1]), shapes(returns)


def documented_shapes(function):
    """{output name: per-point shape} parsed from the 'Returns <Class>:' part of the docstring."""
    return documented(function)[2]


def _as_batch(value, n, shape):
    """Output value -> float array (n, *shape), broadcasting an unbatched value."""
    return np.broadcast_to(np.asarray(value), (n,) + shape)


def assert_close(actual, expected, rtol, what):
    """|a - b| <= rtol * max(|a|, |b|, 1) elementwise; both finite (NaN == NaN is a failure)."""
    a, b = np.asarray(actual), np.asarray(expected)
    assert a.shape == b.shape, f"{what}: shape {a.shape} != {b.shape}"
    assert np.all(np.isfinite(a)), f"{what}: non-finite values {a[~np.isfinite(a)][:5]}"
    assert np.all(np.isfinite(b)), f"{what}: non-finite reference values {b[~np.isfinite(b)][:5]}"
    err = np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), 1.0)
    if err.size and err.max() > rtol:
        i = np.unravel_index(np.argmax(err), err.shape)
        pytest.fail(f"{what}: relative difference {err.max():.3g} > {rtol:g} at index {i}: "
                    f"{a[i]!r} vs {b[i]!r}")


# ---------------------------------------------------------------------------------------
# 1. staleness
# ---------------------------------------------------------------------------------------


def test_committed_files_are_current(rendered):
    """Byte-for-byte: what the generator renders today is what is committed."""
    committed = {p.name for p in GENERATED.glob("*.py")}
    stale = sorted(n for n in set(rendered) | committed
                   if n not in committed or n not in rendered or (GENERATED / n).read_text() != rendered[n])
    if stale:
        pytest.fail(f"stale generated files {stale}: {HINT}\n{codegen.diff(GENERATED, rendered)}", pytrace=False)


def test_no_unaccounted_file_in_generated(rendered):
    present = {p.name for p in GENERATED.iterdir() if p.name != "__pycache__"}
    assert present == set(rendered), (f"files in generated/ not produced by any registered model: "
                                      f"{sorted(present - set(rendered))}; missing: {sorted(set(rendered) - present)}")


def test_package_lists_the_registered_modules(specs, rendered):
    assert MODULES == tuple(specs)
    assert SCALAR_MODULES == tuple(f"{m}_scalar" for m, s in specs.items() if s.scalar_twin)
    assert SUPPORT_MODULES == ("layouts",) + tuple(sorted(n.removesuffix(".py") for n in kernels.glue_files()))
    assert {"tca_kernels", "tca_kernels_scalar"} <= set(SUPPORT_MODULES)
    assert SURFACE_MODULES == tuple(f"surface_{k}" for k in kernels.SURFACE_MODELS)
    assert sorted(rendered) == sorted(FILES)


def test_specs_and_committed_functions_agree(specs):
    """The parametrization below (read from the committed modules) covers every spec Function."""
    assert [(s.module, f.name) for s in specs.values() for f in s.functions] == FUNCTIONS
    for module in SCALAR_MODULES:
        numpy_twin = module.removesuffix("_scalar")
        assert _public_functions(_committed(module)) == [f"{f.name}_point" for f in specs[numpy_twin].functions]


def test_layouts_module_holds_the_spec_layouts(specs):
    """One NamedTuple per layout of any kernel: fields in the kernels' order, units and docs."""
    layouts = _committed("layouts")
    expected = {}
    for spec in specs.values():
        expected.update(spec.layouts())
    classes = {n for n, c in vars(layouts).items() if isinstance(c, type) and c.__module__ == layouts.__name__}
    assert classes == set(expected) and {"AssemblyErrors", "PairPlacement", "FlankBlank"} <= classes
    for name, lay in expected.items():
        cls = getattr(layouts, name)
        assert cls._fields == tuple(f.name for f in lay.fields), name
        assert cls.UNITS == {f.name: f.unit for f in lay.fields} and cls.DOCS == {f.name: f.doc for f in lay.fields}
        values = {f: 0.1 * i for i, f in enumerate(reversed(cls._fields))} | {"not_a_field": 1.0}
        packed = cls.pack(values)
        base = [f.name for f in lay.fields if f.derived is None]
        assert [getattr(packed, f) for f in base] == [values[f] for f in base]
        # derived entries: computed from the base ones (the values given for them are ignored)
        assert cls.DERIVED == tuple(f.name for f in lay.fields if f.derived is not None)
        for f in lay.fields:
            if f.derived is not None:
                at = {b.symbol: values[b.name] for b in lay.fields if b.derived is None}
                assert getattr(packed, f.name) == pytest.approx(float(f.derived.subs(at)), rel=1e-15), f.name
                assert getattr(packed, f.name) != values[f.name]
        batch = cls.pack({f: np.full(3, v) for f, v in values.items()})  # arrays: a batch of vectors
        np.testing.assert_array_equal(np.stack(batch, axis=-1), np.tile(np.asarray(packed, dtype=float), (3, 1)))


def test_trigonometry_of_layout_angles_is_read_not_evaluated():
    """Kernels taking a layout with derived sin/cos/tan entries never evaluate those functions of
    its angles again (the point of with_trig), and their values agree with the model's."""
    import inspect

    for module in ("surface_involute_scalar", "surface_crowned_scalar", "flank_boundaries_scalar",
                   "contact_system_scalar"):
        text = inspect.getsource(_committed(module))
        for angle in ("normal_pressure_angle", "helix_angle", "cone_angle", "shaft_angle"):
            for fn in ("sin", "cos", "tan"):
                assert f"math.{fn}({angle})" not in text, (module, fn, angle)
        assert "sin_" in text or "tan_" in text or "cos_" in text


def test_glue_constants_follow_the_registry():
    tk, tks = _committed("tca_kernels"), _committed("tca_kernels_scalar")
    layouts = _committed("layouts")
    assert tk.MODELS == tuple(kernels.SURFACE_MODELS) == _committed("surface_models").MODELS and tk.FLANKS == FLANKS
    assert _committed("surface_models").DEFAULT_MODEL in tk.MODELS
    assert tk.UNKNOWNS == kernels.UNKNOWNS == _committed("contact_system").UNKNOWNS
    assert tk.BOUNDARIES == _committed("flank_boundaries").BOUNDARIES
    assert tk.CONTACT_BOUNDARIES == tuple(f"{who} {b}" for who in ("pinion", "gear") for b in tk.BOUNDARIES)
    params = {k: _spec_arg(f"surface_{k}", "surface_left", "params").symbol for k in tk.MODELS}
    assert {k: v.__name__ for k, v in tk.SURFACE_LAYOUTS.items()} == {k: lay.name for k, lay in params.items()}
    assert tk.PARAMETER_COUNT == max(len(lay.fields) for lay in params.values())
    assert (tks.N_UNKNOWNS, tks.N_ERRORS, tks.N_MARGINS) == (len(tk.UNKNOWNS), len(layouts.AssemblyErrors._fields),
                                                            len(tk.CONTACT_BOUNDARIES))
    for k, lay in params.items():
        values = {f.name: 1.0 + i for i, f in enumerate(lay.fields)}
        packed = tk.pack_surface_params(k, values)
        assert packed.shape == (tk.PARAMETER_COUNT,)
        cls = tk.SURFACE_LAYOUTS[k]
        assert list(packed) == list(np.asarray(cls.pack(values))) + [0.0] * (packed.size - len(lay.fields))
        assert list(packed[:len(cls._fields) - len(cls.DERIVED)]) == [values[f.name] for f in lay.fields
                                                                     if f.derived is None]
    assert [tk.model_id(k) for k in tk.MODELS] == list(range(len(tk.MODELS)))
    assert [tk.flank_id(f) for f in FLANKS] == list(range(len(FLANKS)))


# ---------------------------------------------------------------------------------------
# 2. determinism
# ---------------------------------------------------------------------------------------


def test_rendering_twice_is_identical(specs, rendered):
    assert codegen.generate(None, list(specs.values()), extra=kernels.glue_files()) == rendered


_SEPARATOR = "\n#### scalar twin ####\n"
_HASHSEED_SCRIPT = (
    "import sys\n"
    "from beveloid.derivations import codegen, kernels\n"
    f"spec = kernels.surface_module({MODEL!r}, kernels.SURFACE_MODELS[{MODEL!r}])\n"
    f"sys.stdout.write(codegen.render_module(spec) + {_SEPARATOR!r} + codegen.render_scalar_module(spec))\n"
)


def test_rendering_does_not_depend_on_the_hash_seed(rendered, tmp_path):
    """A fresh build under two other PYTHONHASHSEEDs (set iteration order) renders the same bytes."""
    expected = rendered[f"surface_{MODEL}.py"] + _SEPARATOR + rendered[f"surface_{MODEL}_scalar.py"]
    procs = []
    for seed in ("1", "4242"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        procs.append((seed, subprocess.Popen([sys.executable, "-c", _HASHSEED_SCRIPT], cwd=tmp_path, env=env,
                                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)))
    for seed, proc in procs:
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        assert out == expected, f"PYTHONHASHSEED={seed} renders different text"


# ---------------------------------------------------------------------------------------
# 3. headers and hygiene
# ---------------------------------------------------------------------------------------

_TIMESTAMP_OR_VERSION = [
    re.compile(r"\b(19|20)\d\d-\d\d-\d\d\b"),  # ISO date
    re.compile(r"\b\d\d:\d\d(:\d\d)?\b"),  # clock time
    re.compile(r"\b(sympy|numpy|jinja2|python|beveloid|numba)\s+v?\d+\.\d+", re.I),  # tool version
    re.compile(r"\bversion\b|__version__|generated (on|at)\b", re.I),
    re.compile(r"\b(Mon|Tue|Wed|Thu|Fri|Sat|Sun)\b"),
]


def _is_scalar(module):
    return module in SCALAR_MODULES


@pytest.mark.parametrize("module", MODULES + SCALAR_MODULES)
def test_module_header(specs, module):
    spec = specs[module.removesuffix("_scalar")]
    template = TEMPLATES[_is_scalar(module)]
    text = (GENERATED / f"{module}.py").read_text()
    lines = text.splitlines()
    assert lines[0] == f"# Generated by `beveloid derive` from derivations/{spec.source} with template {template}."
    assert lines[1].startswith("# Do not edit")
    assert (ROOT / "derivations" / spec.source).is_file()
    assert (ROOT / template).is_file()
    assert ast.get_docstring(ast.parse(text)).startswith(spec.doc)


_SUPPORT_HEADER = re.compile(r"# Generated by `beveloid derive` (?:from (derivations/\S+)|\((derivations/\S+)\)) "
                             r"with template (derivations/templates/\S+)\.")


@pytest.mark.parametrize("module", SUPPORT_MODULES)
def test_support_module_header(module):
    """layouts.py and the glue name the file that renders them and their own template."""
    text = (GENERATED / f"{module}.py").read_text()
    lines = text.splitlines()
    m = _SUPPORT_HEADER.fullmatch(lines[0])
    assert m, lines[0]
    source, template = m[1] or m[2], m[3]
    assert source == ("derivations/codegen.py" if module == "layouts" else "derivations/kernels.py")
    assert template == f"derivations/templates/{module}.py.jinja"
    assert (ROOT / source).is_file() and (ROOT / template).is_file()
    assert lines[1].startswith("# Do not edit")
    assert ast.get_docstring(ast.parse(text))


def test_package_init_header():
    lines = (GENERATED / "__init__.py").read_text().splitlines()
    assert lines[0].startswith("# Generated by `beveloid derive`") and "Do not edit" in lines[0]


@pytest.mark.parametrize("name", FILES)
def test_no_timestamp_or_version(name):
    text = (GENERATED / name).read_text()
    for pattern in _TIMESTAMP_OR_VERSION:
        m = pattern.search(text)
        assert m is None, f"generated/{name}: {m.group(0)!r} looks like a timestamp or a version"


# exact `import X` statements; the glue is checked separately (relative imports of its siblings)
EXACT_IMPORTS = {"__init__": [], "layouts": ["numpy", "typing"], "surface_models": [],  # the spec reads it without numpy
                 **{m: ["numpy", "typing"] for m in MODULES}, **{m: ["math"] for m in SCALAR_MODULES}}


@pytest.mark.parametrize("name", FILES)
def test_imports(name):
    """numpy modules import typing and numpy, scalar twins only math (numba-compilable),
    layouts.py typing and numpy (pack computes the derived entries), __init__ and surface_models.py nothing; the other glue numpy/typing
    and sibling generated modules only (the scalar glue only scalar twins), and a glue that
    dispatches to surface kernels imports those of every registered model."""
    module = name.removesuffix(".py")
    tree = ast.parse((GENERATED / name).read_text())
    imports = [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))]
    assert all(node in tree.body for node in imports), f"generated/{name}: an import below the top level"
    plain = [n for n in imports if isinstance(n, ast.Import)]
    for node in plain:
        assert len(node.names) == 1 and node.names[0].asname is None, f"generated/{name}: `{ast.unparse(node)}`"
    absolute = sorted(node.names[0].name for node in plain)
    relative = [n for n in imports if isinstance(n, ast.ImportFrom)]
    if module in EXACT_IMPORTS:
        assert absolute == EXACT_IMPORTS[module] and not relative, \
            f"generated/{name}: {[ast.unparse(n) for n in imports]} (only {EXACT_IMPORTS[module]})"
        return
    assert module in SUPPORT_MODULES and set(absolute) <= {"numpy", "typing"}, absolute
    siblings = set(MODULES + SCALAR_MODULES + SUPPORT_MODULES) - {module}
    imported = set()
    for node in relative:
        assert node.level == 1, f"generated/{name}: `{ast.unparse(node)}` is not a sibling import"
        if node.module is None:  # from . import <module> [as _<name>]
            imported |= {a.name for a in node.names}
        else:  # from .<module> import <function> as _<name>
            imported.add(node.module)
            for a in node.names:
                assert hasattr(_committed(node.module), a.name), f"generated/{name}: `{ast.unparse(node)}`"
    assert imported <= siblings, f"generated/{name} imports {sorted(imported - siblings)}"
    scalar = module.endswith("_scalar")
    assert all(m.endswith("_scalar") == scalar for m in imported - {"layouts"}), sorted(imported)
    surfaces = {m + ("_scalar" if scalar else "") for m in SURFACE_MODULES}
    assert not imported & surfaces or surfaces <= imported, sorted(imported)


_OPS = re.compile(r"^    # ops: (\d+)$", re.M)


@pytest.mark.parametrize("module", MODULES + SCALAR_MODULES)
def test_every_function_has_an_op_count(module):
    text = (GENERATED / f"{module}.py").read_text()
    tree = ast.parse(text)
    lines = text.splitlines()
    functions = [n for n in tree.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")]
    assert functions
    for fn in functions:
        assert isinstance(fn.body[0].value, ast.Constant)  # the docstring
        m = _OPS.match(lines[fn.body[0].end_lineno])  # the line right after it (0-based index)
        assert m and int(m[1]) > 0, f"{module}.{fn.name}: no `# ops: N` comment after the docstring"


@pytest.mark.parametrize("module", SCALAR_MODULES)
def test_scalar_twin_comes_from_the_same_cse_pass(module):
    numpy_ops = ops_counts((GENERATED / f"{module.removesuffix('_scalar')}.py").read_text())
    scalar_ops = ops_counts((GENERATED / f"{module}.py").read_text())
    assert scalar_ops == {f"{name}_point": n for name, n in numpy_ops.items()}


def ops_counts(text):
    """{function name: op count} from a rendered module."""
    out, name = {}, None
    for line in text.splitlines():
        if line.startswith("def "):
            name = line[4:].split("(")[0]
        m = _OPS.match(line)
        if m:
            out[name] = int(m[1])
    return out


# ---------------------------------------------------------------------------------------
# 4. generated vs symbolic
# ---------------------------------------------------------------------------------------


def _lambdified_outputs(fn, values, n):
    """[array (n, *shape)] of the symbolic outputs of ``fn`` via lambdify (no CSE), every entry of
    a vector, matrix or layout argument passed as its own value."""
    symbols, args = [], []
    for a in fn.inputs:
        for _, symbol, index in a.entries():
            symbols.append(symbol)
            value = np.asarray(values[a.name])
            args.append(value if index is None else value[(...,) + (index if isinstance(index, tuple) else (index,))])
    outs = []
    for o in fn.outputs:
        entries = list(o.expr) if isinstance(o.expr, sp.MatrixBase) else [o.expr]
        f = sp.lambdify(symbols, entries, modules="numpy", cse=False)
        flat = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in f(*args)], axis=-1)
        outs.append(flat.reshape((n,) + _expr_shape(o.expr)))
    return outs


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_generated_matches_symbolic(specs, module, function):
    fn = _spec_function(specs, module, function)
    values = sample(module, function, N_POINTS)
    generated = getattr(_committed(module), function)(**values)
    assert len(generated) == len(fn.outputs)
    for o, got, want in zip(fn.outputs, generated, _lambdified_outputs(fn, values, N_POINTS)):
        assert_close(_as_batch(got, N_POINTS, _expr_shape(o.expr)), want, RTOL, f"{function}.{o.name}")


# ---------------------------------------------------------------------------------------
# 5. interfaces, batches and broadcasting
# ---------------------------------------------------------------------------------------

BATCH = 7


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_outputs_have_documented_shapes(specs, module, function):
    mod = _committed(module)
    f = getattr(mod, function)
    fn = _spec_function(specs, module, function)
    cls, inputs, outputs = documented(f)
    assert outputs == {o.name: _expr_shape(o.expr) for o in fn.outputs}
    assert list(inputs.items()) == [(a.name, a.shape) for a in fn.inputs] and list(inputs) == _args_of(module, function)
    assert cls == fn.outputs_class
    values = sample(module, function, BATCH)
    out = f(**values)
    assert type(out) is getattr(mod, cls) and isinstance(out, tuple)
    assert type(out)._fields == tuple(o.name for o in fn.outputs)
    for name, value in zip(outputs, out):
        assert np.shape(value) == (BATCH,) + outputs[name], f"{function}.{name}"
        assert getattr(out, name) is value
    # one point given as scalars and per-point arrays: per-point shapes
    for name, value in zip(outputs, f(**{k: v[0] for k, v in values.items()})):
        assert np.shape(value) == outputs[name], f"{function}.{name}"


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_batch_equals_stack_of_scalar_calls(module, function):
    f = getattr(_committed(module), function)
    values = sample(module, function, BATCH)
    batch = f(**values)
    singles = [f(**{k: _at(v, i) for k, v in values.items()}) for i in range(BATCH)]
    for j, name in enumerate(documented_shapes(f)):
        stacked = np.stack([np.asarray(s[j], dtype=float) for s in singles])
        # array and scalar numpy math may differ in the last bit (SIMD loops)
        assert_close(batch[j], stacked, 1e-14, f"{function}.{name}")


def test_design_kernels_take_integer_tooth_numbers():
    values = sample("design_equations", "direct_design", BATCH)
    as_int = dict(values, pinion_teeth=values["pinion_teeth"].astype(int),
                  gear_teeth=values["gear_teeth"].astype(int))
    dm = _committed("design_equations")
    for a, b in zip(dm.direct_design(**as_int), dm.direct_design(**values)):
        assert_close(_as_batch(a, BATCH, ()), _as_batch(b, BATCH, ()), 0.0, "direct_design with int teeth")


def _broadcast_failures(module, function):
    """Arguments that, alone given as a batch (others one point), do not batch every output."""
    f = getattr(_committed(module), function)
    shapes = documented_shapes(f)
    values = sample(module, function, BATCH)
    failures = []
    for arg in values:
        mixed = {k: (v if k == arg else v[0]) for k, v in values.items()}
        for name, out in zip(shapes, f(**mixed)):
            if np.shape(out) != (BATCH,) + shapes[name]:
                failures.append(f"{arg} -> {name} {np.shape(out)}")
    return failures


# Every output carries the broadcast shape of all inputs, including outputs that do not
# depend on the one batched argument (a bug this test found in the first generator).


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_one_batched_argument_batches_every_output(module, function):
    failures = _broadcast_failures(module, function)
    assert not failures, f"{function}: outputs without the batch axis: {failures[:6]} ..."


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_mixed_scalar_and_array_arguments_broadcast(module, function):
    """Half the arguments as one point, half as batches: same values as the all-batch call."""
    f = getattr(_committed(module), function)
    shapes = documented_shapes(f)
    values = sample(module, function, BATCH)
    keep_scalar = list(values)[1::2]
    mixed = {k: (v[0] if k in keep_scalar else v) for k, v in values.items()}
    full = {k: (np.broadcast_to(v[0], v.shape) if k in keep_scalar else v) for k, v in values.items()}
    for name, a, b in zip(shapes, f(**mixed), f(**full)):
        assert_close(_as_batch(a, BATCH, shapes[name]), b, 1e-14, f"{function}.{name}")


def test_positions_times_misalignments_broadcast():
    """Points (7,) x assembly-error sets (4, 1, 5) -> (4, 7, ...) in one call of the composed
    contact system, equal to row-by-row calls."""
    tk = _committed("tca_kernels")
    shapes = documented_shapes(_committed("contact_system").contact_residual)
    values = sample_contact(BATCH)
    errors = values["errors"]
    grid = tk.contact_system(MODEL, MODEL, "left", **dict(values, errors=errors[:4, None, :]))
    for name in shapes:
        assert getattr(grid, name).shape == (4, BATCH) + shapes[name], name
    for i in range(4):
        row = tk.contact_system(MODEL, MODEL, "left", **dict(values, errors=np.broadcast_to(errors[i], errors.shape)))
        for name, a, b in zip(grid._fields, grid, row):
            assert_close(np.broadcast_to(a, (4,) + b.shape)[i], b, 1e-14, f"{name}, error set {i}")


# ---------------------------------------------------------------------------------------
# 6. Jacobians vs complex step (central differences where complex arithmetic fails)
# ---------------------------------------------------------------------------------------

H_COMPLEX = 1e-30
COMPLEX_STEP_RTOL = RTOL  # exact derivative, no truncation error (measured worst 5e-15 over 2000 points)
CENTRAL_RTOL = 1e-6


def derivative(f, values, arg, output, index=None):
    """d f(**values).<output> / d values[arg][..., index] (index None: the whole scalar argument;
    i or (i, j): one component of a vector or matrix argument) by complex step, else central
    differences (a complex input that raises, is cast to float or gives a real output).

    Returns (derivative, rtol appropriate to the method).
    """
    key = (...,) if index is None else (...,) + (index if isinstance(index, tuple) else (index,))

    def at(step):
        v = np.array(values[arg], dtype=np.result_type(values[arg], step))
        v[key] += step
        return getattr(f(**dict(values, **{arg: v})), output)

    try:
        with warnings.catch_warnings(), np.errstate(all="raise"):
            warnings.simplefilter("error", np.exceptions.ComplexWarning)
            out = at(1j * H_COMPLEX)
        d = np.imag(out) / H_COMPLEX
        if np.iscomplexobj(out) and np.all(np.isfinite(d)):
            return d, COMPLEX_STEP_RTOL
    except (TypeError, FloatingPointError, np.exceptions.ComplexWarning):
        pass
    h = 1e-6 * np.maximum(1.0, np.abs(np.asarray(values[arg], dtype=float)[key]))
    plus, minus = at(h), at(-h)
    return (plus - minus) / (2 * h.reshape(h.shape + (1,) * (np.ndim(plus) - h.ndim))), CENTRAL_RTOL


def _contact_jacobian_cases(tk):
    """(argument, index, output, column of that output) of every Jacobian of tca_kernels.contact_system."""
    return ([("x", k, "residual_D_unknowns", k) for k in range(len(tk.UNKNOWNS))]
            + [("errors", k, "residual_D_errors", k) for k in range(len(_committed("layouts").AssemblyErrors._fields))]
            + [("pinion_angle", None, "residual_D_pinion_angle", None)])


@pytest.mark.parametrize("flank", FLANKS)
def test_contact_system_jacobians(flank):
    """The composed Eq 38 system (surface jets -> contact_residual): its exact Jacobians are the
    derivatives of its residual, which checks the chain rule inside contact_residual."""
    tk = _committed("tca_kernels")
    f = functools.partial(tk.contact_system, MODEL, MODEL, flank)
    values = sample_contact(N_POINTS)
    out = f(**values)
    for arg, index, output, column in _contact_jacobian_cases(tk):
        d, rtol = derivative(f, values, arg, "residual", index)
        got = getattr(out, output) if column is None else getattr(out, output)[..., column]
        assert_close(got, d, rtol, f"contact_system {flank}: {output}[..., {column}] (d/d {arg}[{index}])")


@pytest.mark.parametrize("module", SURFACE_MODULES)
@pytest.mark.parametrize("flank", FLANKS)
def test_surface_jet_and_second_derivatives(module, flank):
    sm = _committed(module)
    surface = getattr(sm, f"surface_{flank}")
    jet = getattr(sm, f"surface_jet_{flank}")
    values = sample(module, surface.__name__, N_POINTS)
    s, j = surface(**values), jet(**values)
    assert_close(j.point, s.point, RTOL, "jet point")
    assert_close(j.normal, s.normal, RTOL, "jet normal")
    # a unit normal, normal to the surface
    assert_close(np.linalg.norm(j.normal, axis=-1), np.ones(N_POINTS), RTOL, "|normal|")
    assert_close(np.einsum("...i,...ik->...k", j.normal, j.point_D_lu), np.zeros((N_POINTS, 2)), RTOL, "n . dR")
    for k, arg in enumerate(("l", "u")):
        for of, name in (("point", "point_D_lu"), ("normal", "normal_D_lu")):
            d, rtol = derivative(surface, values, arg, of)
            assert_close(getattr(j, name)[..., k], d, rtol, f"{name}[..., {k}] (d {of}/d{arg})")
    d2 = getattr(sm, f"surface_second_derivatives_{flank}")(**values).point_D2_lu
    # columns of point_D2_lu: d2R/dl2, d2R/dldu, d2R/du2
    for column, of, arg in ((0, 0, "l"), (1, 0, "u"), (1, 1, "l"), (2, 1, "u")):
        d, rtol = derivative(jet, values, arg, "point_D_lu")
        assert_close(d2[..., column], d[..., of], rtol,
                     f"point_D2_lu[..., {column}] (d point_D_lu[..., {of}] / d{arg})")


def test_flank_margins_derivatives():
    f = _committed("flank_boundaries").flank_margins
    values = sample("flank_boundaries", "flank_margins", N_POINTS)
    fields = _committed("layouts").FlankBlank._fields
    toe, heel = (values["blank"][:, fields.index(k)] for k in ("toe_z_mm", "heel_z_mm"))
    assert {False, True} <= set(toe < heel)  # the sampled blanks have the toe on either side of the heel
    out = f(**values)
    for k in range(3):
        d, rtol = derivative(f, values, "point", "margins", k)
        assert_close(out.margins_D_point[..., k], d, rtol, f"margins_D_point[..., {k}]")
    d, rtol = derivative(f, values, "l", "margins")
    assert_close(out.margins_D_l, d, rtol, "margins_D_l")


def test_offset_residual_derivative():
    f = _committed("design_equations").offset_residual
    values = sample("design_equations", "offset_residual", N_POINTS)
    d, rtol = derivative(f, values, "alpha_nw", "residual")
    assert_close(f(**values).residual_D_alpha_nw, d, rtol, "residual_D_alpha_nw")


def test_complex_step_is_what_the_jacobian_tests_use():
    """The kernels are complex-analytic (numpy trig/sqrt/arc*), so the exact complex step applies:
    to every kernel differentiated above, and through the glue's composition."""
    def case(module, function, *args):
        return getattr(_committed(module), function), sample(module, function, 3), *args

    contact = functools.partial(_committed("tca_kernels").contact_system, MODEL, MODEL, "right")
    cases = ([case("design_equations", "offset_residual", "alpha_nw", None, "residual"),
              case("flank_boundaries", "flank_margins", "l", None, "margins")]
             + [case("flank_boundaries", "flank_margins", "point", k, "margins") for k in range(3)]
             + [case(m, f"surface{kind}_{flank}", arg, None, "point")
                for m in SURFACE_MODULES for kind in ("", "_jet") for flank in FLANKS for arg in ("l", "u")]
             + [(contact, sample_contact(3), arg, index, "residual")
                for arg, index, _, _ in _contact_jacobian_cases(_committed("tca_kernels"))])
    fallback = [f"{getattr(f, '__name__', 'tca_kernels.contact_system')} d/d {arg}[{index}]"
                for f, values, arg, index, output in cases
                if derivative(f, values, arg, output, index)[1] != COMPLEX_STEP_RTOL]
    assert not fallback, f"no complex step (complex input raised, was cast to float or gave real output): {fallback}"


# ---------------------------------------------------------------------------------------
# 7. CSE vs no CSE, scalar twins
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_cse_and_plain_builds_agree(nocse, module, function):
    f = getattr(_committed(module), function)
    plain = nocse[module][function]
    values = sample(module, function, N_POINTS)
    shapes = documented_shapes(f)
    for name, a, b in zip(shapes, f(**values), plain(**values)):
        assert_close(_as_batch(a, N_POINTS, shapes[name]), _as_batch(b, N_POINTS, shapes[name]), RTOL,
                     f"{function}.{name} (CSE vs no CSE)")


def test_plain_build_differs_from_cse_build_only_in_bodies(nocse_texts, rendered):
    for module in MODULES:
        cse_text = rendered[f"{module}.py"]
        assert nocse_texts[module] != cse_text
        assert "_x0 = " in cse_text and "_x0 = " not in nocse_texts[module]
        assert _module_docstring(nocse_texts[module]) == _module_docstring(cse_text)


def _module_docstring(text):
    """``ast.get_docstring(ast.parse(text))`` from the module's first statement only: a module
    docstring is its first statement, and parsing the whole no-CSE surface_crowned module
    (~4.7 MB) takes ~9 s."""
    lines = iter(text.splitlines(keepends=True))
    head = []

    def readline():
        line = next(lines, "")
        head.append(line)
        return line

    for tok in tokenize.generate_tokens(readline):
        if tok.type in (tokenize.NEWLINE, tokenize.ENDMARKER):  # the end of the first statement
            break
    return ast.get_docstring(ast.parse("".join(head)))


def test_cse_reduces_the_op_count_of_the_contact_system(nocse_texts):
    cse_ops = ops_counts((GENERATED / "contact_system.py").read_text())
    plain_ops = ops_counts(nocse_texts["contact_system"])
    assert set(cse_ops) == set(plain_ops) == {"contact_residual"}
    for name in cse_ops:
        assert cse_ops[name] < plain_ops[name], f"{name}: CSE {cse_ops[name]} ops vs {plain_ops[name]} without"


SCALAR_FUNCTIONS = [(m, f) for m in SCALAR_MODULES for f in _public_functions(_committed(m))]


@pytest.mark.parametrize("module, function", SCALAR_FUNCTIONS, ids=[f"{m}.{f}" for m, f in SCALAR_FUNCTIONS])
def test_scalar_twin_matches_numpy_kernel(module, function):
    """``<f>_point(args..., out_<output>...)`` (one point, math) == the numpy kernel ``<f>``."""
    numpy_module, name = module.removesuffix("_scalar"), function.removesuffix("_point")
    f = getattr(_committed(numpy_module), name)
    point = getattr(_committed(module), function)
    shapes = documented_shapes(f)
    args = _args_of(numpy_module, name)
    assert list(inspect.signature(point).parameters) == args + [f"out_{o}" for o in shapes]
    values = sample(numpy_module, name, N_POINTS)
    got = {o: np.full((N_POINTS,) + (shape or (1,)), np.nan) for o, shape in shapes.items()}
    for i in range(N_POINTS):
        assert point(**{k: _at(v, i) for k, v in values.items()},
                     **{f"out_{o}": got[o][i] for o in shapes}) is None
    for (o, shape), want in zip(shapes.items(), f(**values)):
        assert_close(got[o] if shape else got[o][:, 0], _as_batch(want, N_POINTS, shape), RTOL,
                     f"{function}: out_{o}")


def _scalar_contact(tk, tks, models, flank, values, i):
    """(residual, d/d unknowns, d/d errors, d/d pinion angle) of point i from the scalar glue tks
    (models named as in tk.MODELS), and the workspace it leaves."""
    ws = tks.workspace()
    n, m = tks.N_UNKNOWNS, tks.N_ERRORS
    out = (np.full(n, np.nan), np.full((n, n), np.nan), np.full((n, m), np.nan), np.full(n, np.nan))
    assert tks.contact_system_point(*(tk.model_id(k) for k in models), tk.flank_id(flank),
                                    *(_at(v, i) for v in values.values()), ws, *out) is None
    return out, ws


@pytest.mark.parametrize("flank", FLANKS)
def test_scalar_glue_matches_the_numpy_glue(flank):
    """tca_kernels_scalar (what the solver core runs) == tca_kernels, point by point: the
    contact system and the smallest margin of a contact with its boundary."""
    tk, tks = _committed("tca_kernels"), _committed("tca_kernels_scalar")
    values = sample_contact(N_POINTS)
    want = tk.contact_system(MODEL, MODEL, flank, **values)
    rng = np.random.default_rng(SEED + 1)
    blank = _spec_arg("flank_boundaries", "flank_margins", "blank")
    pinion_blank, gear_blank = (sample_arg("flank_boundaries", blank, rng, N_POINTS) for _ in range(2))
    margins = tk.contact_margins(values["x"], want.pinion_point, want.gear_point, pinion_blank, gear_blank)
    fm = _committed("flank_boundaries").flank_margins
    assert_close(margins, np.concatenate([fm(want.pinion_point, values["x"][:, 0], pinion_blank).margins,
                                          fm(want.gear_point, values["x"][:, 2], gear_blank).margins], axis=-1),
                 0.0, "contact_margins")
    for i in range(N_POINTS):
        got, ws = _scalar_contact(tk, tks, (MODEL, MODEL), flank, values, i)
        for name, a, b in zip(want._fields, got, want):
            assert_close(a, b[i], RTOL, f"contact_system_point {name}, point {i}")
        best, which = tks.contact_margin_point(values["x"][i], pinion_blank[i], gear_blank[i], ws)
        assert which == np.argmin(margins[i]) and best == margins[i, which], (i, best, which, margins[i])


# ---------------------------------------------------------------------------------------
# 8. generation-time validation and the generator's interfaces
# ---------------------------------------------------------------------------------------

x, y, z = sp.symbols("x y z", real=True)


def _spec(*functions):
    return codegen.ModuleSpec("toy", "toy.py", "Toy module.", list(functions))


def test_free_symbol_missing_from_the_arguments_is_an_error():
    fn = codegen.Function("f", "doc", [codegen.Arg("x", x, "mm", "x")],
                          [codegen.Output("ok", x**2, "mm2", ""),
                           codegen.Output("bad", sp.Matrix([x, x * y, sp.sin(z)]), "mm", "")])
    with pytest.raises(codegen.GenerationError, match=r"f: output bad has free symbols \['y', 'z'\]"):
        codegen.render_module(_spec(fn))
    with pytest.raises(codegen.GenerationError):
        codegen.render_module(_spec(fn), cse=False)
    with pytest.raises(codegen.GenerationError):
        codegen.generate(None, [_spec(fn)])


def test_duplicate_argument_name_is_an_error():
    fn = codegen.Function("f", "doc", [codegen.Arg("x", x, "mm", "x"), codegen.Arg("x", y, "mm", "y")],
                          [codegen.Output("s", x + y, "mm", "")])
    with pytest.raises(codegen.GenerationError, match="duplicate argument"):
        codegen.render_module(_spec(fn))
    lay = codegen.Layout("Toy", "Toy.", (codegen.Field("x", y, "mm", ""),))
    fn = codegen.Function("f", "doc", [codegen.Arg("x", x, "mm", "x"), codegen.Arg("p", lay, "", "p")],
                          [codegen.Output("s", x + y, "mm", "")])
    with pytest.raises(codegen.GenerationError, match="duplicate argument"):
        codegen.render_module(_spec(fn))
    fn = codegen.Function("f", "doc", [codegen.Arg("a", x, "mm", "x"), codegen.Arg("b", sp.Matrix([y, x]), "mm", "")],
                          [codegen.Output("s", x + y, "mm", "")])
    with pytest.raises(codegen.GenerationError, match="appears twice"):
        codegen.render_module(_spec(fn))


def test_toy_module_renders_and_runs():
    fn = codegen.Function("f", "Toy.", [codegen.Arg("x", x, "mm", "x"), codegen.Arg("y", y, "rad", "y")],
                          [codegen.Output("v", sp.Matrix([x * sp.cos(y), x * sp.sin(y)]), "mm", "vector"),
                           codegen.Output("v_D_y", sp.Matrix([-x * sp.sin(y), x * sp.cos(y)]), "mm/rad", "")])
    ns = _exec_module(codegen.render_module(_spec(fn)), "<toy>")
    v, dv = ns["f"](np.array([1.0, 2.0]), np.array([0.0, np.pi / 2]))
    np.testing.assert_allclose(v, [[1, 0], [0, 2]], atol=1e-15)
    np.testing.assert_allclose(dv, [[0, 1], [-2, 0]], atol=1e-15)


def test_toy_vector_matrix_and_layout_arguments():
    """Array arguments hold their entries in the trailing axes (a layout in field order) and
    broadcast over the leading ones; the output is the named tuple of the function."""
    p = sp.Matrix(sp.symbols("p_0:2", real=True))
    m = sp.Matrix(2, 2, sp.symbols("m_0:4", real=True))
    lay = codegen.Layout("ToyParams", "Toy.", (codegen.Field("angle", y, "rad", "turn"),
                                               codegen.Field("scale_mm", x, "mm", "scale")))
    turn = sp.Matrix([[sp.cos(y), -sp.sin(y)], [sp.sin(y), sp.cos(y)]])
    fn = codegen.Function("toy_map", "Toy.", [codegen.Arg("p", p, "mm", "p"), codegen.Arg("m", m, "1", "m"),
                                             codegen.Arg("params", lay, "", "params")],
                          [codegen.Output("q", x * turn * m * p, "mm", "scaled, turned m p"),
                           codegen.Output("size", x, "mm", "the scale")])
    ns = _exec_module(codegen.render_module(_spec(fn)), "<toy>")
    rng = np.random.default_rng(SEED)
    pv, mv, params = rng.normal(size=(3, 1, 2)), rng.normal(size=(2, 2)), rng.normal(size=(4, 2))
    out = ns["toy_map"](pv, mv, params)
    assert type(out).__name__ == "ToyMap" and type(out)._fields == ("q", "size")
    c, s = np.cos(params[:, 0]), np.sin(params[:, 0])
    turns = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)  # (4, 2, 2)
    want = params[None, :, 1, None] * np.einsum("kij,jl,nl->nki", turns, mv, pv[:, 0])  # (3, 4, 2)
    np.testing.assert_allclose(out.q, want, rtol=1e-14)
    assert out.size.shape == (3, 4) and np.all(out.size == params[:, 1])
    assert "class ToyParams(typing.NamedTuple)" in codegen.render_layouts([_spec(fn)])


def test_output_named_like_an_input_is_rejected_or_harmless():
    fn = codegen.Function("f", "doc", [codegen.Arg("x", x, "1", "x")],
                          [codegen.Output("x", 2 * x, "1", "twice x"), codegen.Output("y", x + 1, "1", "x + 1")])
    try:
        text = codegen.render_module(_spec(fn))
    except codegen.GenerationError:
        return
    assert _exec_module(text, "<toy>")["f"](1.0) == (2.0, 2.0)


# ---------------------------------------------------------------------------------------
# 9. a model variant through the registry
# ---------------------------------------------------------------------------------------

SHIFT = np.array([0.1, -0.05, 0.2])
VARIANT_PACKAGE = "beveloid_variant_kernels"


def _shifted_surface_model():
    """The committed model with every point moved by the constant vector SHIFT (normals unchanged)."""
    original = kernels.SURFACE_MODELS[MODEL]

    def tooth_surface(sigma):
        point, normal, roll = original.tooth_surface(sigma)
        return point + sp.Matrix(SHIFT), normal, roll

    return types.SimpleNamespace(tooth_surface=tooth_surface, PARAMETERS=getattr(original, "PARAMETERS", ()),
                                 __name__="beveloid.derivations.shifted_surface")


@pytest.fixture(scope="module")
def variant(tmp_path_factory):
    """The package `beveloid derive` writes with a "shifted" model registered next to MODEL,
    rendered through kernels.module_specs / kernels.glue_files and imported from a temp dir."""
    models = {MODEL: kernels.SURFACE_MODELS[MODEL], "shifted": _shifted_surface_model()}
    files = codegen.generate(None, kernels.module_specs(models), extra=kernels.glue_files(models))
    package = tmp_path_factory.mktemp("variant") / VARIANT_PACKAGE
    codegen.write(package, files)
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(package.parent))
        try:
            modules = ("surface_shifted", "tca_kernels", "tca_kernels_scalar")
            yield types.SimpleNamespace(files=files,
                                        **{m: importlib.import_module(f"{VARIANT_PACKAGE}.{m}") for m in modules})
        finally:
            for name in [n for n in sys.modules if n.split(".")[0] == VARIANT_PACKAGE]:
                del sys.modules[name]


def test_registry_variant_adds_its_surface_module(variant):
    """A registered model adds its surface module; only the registry-wide files change, and its
    kernels are the committed ones moved by SHIFT (same normals and derivatives)."""
    changed = sorted(n for n, text in variant.files.items()
                     if not (GENERATED / n).exists() or (GENERATED / n).read_text() != text)
    assert changed == sorted({"__init__.py", "layouts.py", "surface_shifted.py", "surface_shifted_scalar.py"}
                             | set(kernels.glue_files()))
    assert "class ShiftedSurfaceParams(typing.NamedTuple)" in variant.files["layouts.py"]
    committed = _committed(f"surface_{MODEL}")
    for flank in FLANKS:
        values = sample(f"surface_{MODEL}", f"surface_{flank}", N_POINTS)
        for kind in ("surface", "surface_jet", "surface_second_derivatives"):
            new = getattr(variant.surface_shifted, f"{kind}_{flank}")(**values)
            old = getattr(committed, f"{kind}_{flank}")(**values)
            assert new._fields == old._fields
            for name, a, b in zip(new._fields, new, old):
                assert_close(a, b + SHIFT if name == "point" else b, RTOL, f"shifted {kind}_{flank}.{name}")


@pytest.mark.parametrize("flank", FLANKS)
def test_registry_variant_reaches_the_contact_system(variant, flank):
    """A pinion moved by SHIFT in S_1: the composed residual changes by exactly [L_f1 SHIFT, 0, 0]
    (normals unchanged), its pinion-angle derivative by [dL_f1/dphi'_1 SHIFT, 0, 0], nothing else;
    a gear moved by SHIFT in S_2 changes it by [-L_f2 SHIFT, 0, 0].  Numpy and scalar glue."""
    tk = variant.tca_kernels
    assert tk.MODELS == (MODEL, "shifted")
    values = sample_contact(N_POINTS)
    base = tk.contact_system(MODEL, MODEL, flank, **values)
    for name, a, b in zip(base._fields, base, _committed("tca_kernels").contact_system(MODEL, MODEL, flank, **values)):
        assert_close(a, b, 0.0, f"{MODEL} pair through the variant glue: {name}")

    placement = _committed("placement")
    at = dict(pinion_angle=values["pinion_angle"], pair=values["pair"])
    rotation = placement.pinion_placement(**at).rotation
    d_rotation, rtol = derivative(placement.pinion_placement, at, "pinion_angle", "rotation")
    zeros = np.zeros((N_POINTS, 2))
    change = {"residual": (np.concatenate([rotation @ SHIFT, zeros], axis=-1), RTOL),
              "residual_D_pinion_angle": (np.concatenate([d_rotation @ SHIFT, zeros], axis=-1), rtol),
              "pinion_point": (SHIFT, RTOL)}
    moved = tk.contact_system("shifted", MODEL, flank, **values)
    assert not np.allclose(moved.residual, base.residual)
    for name, a, b in zip(moved._fields, moved, base):
        delta, tol = change.get(name, (0.0, RTOL))
        assert_close(a, b + delta, tol, f"pinion shifted: {name}")
    gear_rotation = placement.gear_placement(values["x"][:, 4], values["errors"], values["pair"]).rotation
    gear_moved = tk.contact_system(MODEL, "shifted", flank, **values)
    assert_close(gear_moved.residual, base.residual - np.concatenate([gear_rotation @ SHIFT, zeros], axis=-1), RTOL,
                 "gear shifted: residual")
    assert_close(gear_moved.gear_point, base.gear_point + SHIFT, RTOL, "gear shifted: gear_point")

    for models, want in (((MODEL, "shifted"), gear_moved), (("shifted", MODEL), moved)):
        for i in range(3):
            got, _ = _scalar_contact(tk, variant.tca_kernels_scalar, models, flank, values, i)
            for name, a, b in zip(want._fields, got, want):
                assert_close(a, b[i], RTOL, f"scalar glue {models}: {name}, point {i}")


def test_registry_variant_names_its_source_in_the_header():
    from beveloid.derivations.symbols import l, u

    flat = types.SimpleNamespace(tooth_surface=lambda sigma: (sp.Matrix([l, sigma * u, 0]), sp.Matrix([0, 0, 1]),
                                                              sp.Integer(0)),
                                 __name__="beveloid.derivations.flat_rack_variant")
    spec = kernels.surface_module("flat", flat)
    assert spec.module == "surface_flat"
    for text, template in ((codegen.render_module(spec), TEMPLATES[False]),
                           (codegen.render_scalar_module(spec), TEMPLATES[True])):
        assert text.startswith("# Generated by `beveloid derive` from derivations/flat_rack_variant.py "
                               f"with template {template}.\n")
    assert "(flat_rack_variant.py)" in codegen.render_layouts([spec])
    glue = kernels.glue_files({"flat": flat})
    assert "from . import surface_flat as _flat\n" in glue["tca_kernels.py"]
    assert "from .surface_flat_scalar import surface_jet_left_point" in glue["tca_kernels_scalar.py"]


# ---------------------------------------------------------------------------------------
# 10. `beveloid derive --check` / `--no-docs` and the sympy-free runtime
# ---------------------------------------------------------------------------------------


@pytest.fixture
def cheap_derive(monkeypatch, specs, rendered):
    """`beveloid derive` without the 18 s equation verification, the 5 s model build and the
    8 s rendering: the docs page renders as committed, the models are the ones built for this
    session and their files are this session's rendering (``rendered``: what the generator
    renders is checked above, against the committed files and against a second rendering).
    The tests below are about the command: its comparison, diff, exit status and writing nothing."""
    from beveloid.derivations import docs, registry

    committed_docs = (ROOT / "docs" / "derivations.md").read_text()
    session_specs = list(specs.values())
    real_generate = codegen.generate

    def generate(out_dir, specs_, cse=True, progress=None, extra=None):
        if out_dir is None and cse and list(specs_) == session_specs and extra == kernels.glue_files():
            return dict(rendered)
        return real_generate(out_dir, specs_, cse=cse, progress=progress, extra=extra)

    monkeypatch.setattr(registry, "verify", lambda *a, **k: None)
    monkeypatch.setattr(docs, "render_derivations_md", lambda results=None: committed_docs)
    monkeypatch.setattr(kernels, "module_specs", lambda models=None: session_specs)
    monkeypatch.setattr(codegen, "generate", generate)


def test_derive_check_passes_on_a_clean_checkout(cheap_derive, capsys):
    from beveloid.cli import main

    before = {p.name: p.read_bytes() for p in GENERATED.glob("*.py")}
    assert main(["derive", "--check"]) == 0
    out, err = capsys.readouterr()
    assert out == ""
    assert "up to date" in err
    assert {p.name: p.read_bytes() for p in GENERATED.glob("*.py")} == before


def test_derive_check_reports_a_stale_copy(cheap_derive, capsys, monkeypatch, tmp_path):
    from beveloid.cli import main
    from beveloid.derivations import derive

    shutil.copytree(GENERATED, tmp_path / "generated", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "docs", tmp_path / "docs")
    (tmp_path / "pyproject.toml").write_text("")
    stale = tmp_path / "generated" / "contact_system.py"
    ops = _OPS.search(stale.read_text())[1]
    stale.write_text(_OPS.sub("    # ops: 0", stale.read_text(), count=1))
    (tmp_path / "generated" / "orphan.py").write_text("x = 1\n")
    monkeypatch.setattr(derive, "source_root", lambda: tmp_path)

    assert main(["derive", "--check"]) == 1
    out, err = capsys.readouterr()
    assert "--- generated/contact_system.py (committed)\n+++ generated/contact_system.py (regenerated)\n" in out
    assert f"\n-    # ops: 0\n+    # ops: {ops}\n" in out
    assert "generated/orphan.py" in out
    for other in ["docs/derivations.md"] + [f"generated/{n}" for n in FILES if n != "contact_system.py"]:
        assert f"--- {other} " not in out, other
    assert HINT in err
    # --check writes nothing
    assert "# ops: 0\n" in stale.read_text() and (tmp_path / "generated" / "orphan.py").exists()


def test_derive_no_docs_leaves_the_docs_page_and_its_verification_out(cheap_derive, capsys, monkeypatch, tmp_path):
    from beveloid.cli import main
    from beveloid.derivations import derive, registry

    shutil.copytree(GENERATED, tmp_path / "generated", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "docs", tmp_path / "docs")
    (tmp_path / "pyproject.toml").write_text("")
    page = tmp_path / "docs" / "derivations.md"
    page.write_text("stale\n")
    monkeypatch.setattr(derive, "source_root", lambda: tmp_path)

    assert main(["derive", "--check"]) == 1
    assert "--- docs/derivations.md (committed)\n" in capsys.readouterr().out

    def no_verification(*args, **kwargs):
        raise AssertionError("--no-docs verified the equations")

    monkeypatch.setattr(registry, "verify", no_verification)
    assert main(["derive", "--check", "--no-docs"]) == 0
    out, err = capsys.readouterr()
    assert out == "" and "generated/ is up to date" in err
    (tmp_path / "generated" / "orphan.py").write_text("x = 1\n")
    assert main(["derive", "--no-docs"]) == 0
    assert "(files changed)" in capsys.readouterr().err
    assert not (tmp_path / "generated" / "orphan.py").exists() and page.read_text() == "stale\n"


def test_runtime_kernels_import_without_sympy(tmp_path):
    modules = ", ".join(f"beveloid.generated.{m}" for m in MODULES + SCALAR_MODULES + SUPPORT_MODULES)
    code = (f"import sys, beveloid.generated, {modules}\n"
            "bad = sorted(m for m in ('sympy', 'jinja2', 'mpmath', 'beveloid.derivations') if m in sys.modules)\n"
            "assert not bad, bad\n"
            "print(beveloid.generated.__file__)\n")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    # editable install: the checkout's generated/; regular install: an identical copy
    imported = Path(proc.stdout.strip()).parent
    assert {"design_equations.py", f"surface_{MODEL}.py", "contact_system.py"} <= set(FILES)
    for name in FILES:
        assert (imported / name).read_bytes() == (GENERATED / name).read_bytes(), name
