"""The generated kernels (generated/*.py) against the generator and the symbolic models.

* staleness: the committed files are exactly what the generator renders today;
* determinism: rendering is repeatable, also under another PYTHONHASHSEED;
* hygiene: header, "do not edit", no timestamps, imports only numpy (the scalar twins
  *_scalar.py only math), an ``# ops:`` count per function;
* maths: generated == lambdified symbolic outputs at seeded random points; Jacobians ==
  complex-step derivatives; CSE build == non-CSE build; scalar twins == numpy kernels;
  batches broadcast;
* the generator's validation (free symbols, duplicate argument names), the registry's
  model-variant mechanism, and ``beveloid derive --check``.

The sympy models are built once per module (``kernels.module_specs()`` takes ~6 s).
Three generator bugs found while writing these tests (outputs not broadcast against all
inputs, output names shadowing inputs, kernels.SURFACE_SOURCE unused) are fixed; the tests
that found them stay.

Tolerances are relative with a unit floor, ``|a - b| <= rtol * max(|a|, |b|, 1)``: every
quantity is in mm, rad or 1 and of order 1..500 in these domains, so the floor only
matters for values that are small by cancellation (a TCA residual, x_t2, E - offset).
"""
from __future__ import annotations

import ast
import importlib
import inspect
import os
import re
import shutil
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import codegen, kernels

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
TEMPLATES = {False: "derivations/templates/module.py.jinja", True: "derivations/templates/scalar_module.py.jinja"}
HINT = "run `beveloid derive` to update"

SEED = 20130101
N_POINTS = 20
RTOL = 1e-12  # generated vs symbolic, CSE vs no-CSE, complex step
DEG = np.pi / 180


# ---------------------------------------------------------------------------------------
# fixtures: build the sympy specs and the renderings once
# ---------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def specs():
    """{module name: ModuleSpec} from one ``kernels.module_specs()`` call."""
    return {s.module: s for s in kernels.module_specs()}


@pytest.fixture(scope="module")
def rendered(specs):
    """{file name: text} rendered in memory, as ``beveloid derive`` would write it."""
    return codegen.generate(None, list(specs.values()))


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
SCALAR_MODULES = tuple(getattr(_PACKAGE, "SCALAR_MODULES", ()))
FILES = ["__init__.py"] + [f"{m}.py" for m in MODULES + SCALAR_MODULES]

# (module, function) pairs of the committed kernels; checked against the specs below.
FUNCTIONS = [(m, f) for m in MODULES for f in _public_functions(_committed(m))]
FUNCTION_IDS = [f"{m}.{f}" for m, f in FUNCTIONS]


def _spec_function(specs, module, name):
    (fn,) = [f for f in specs[module].functions if f.name == name]
    return fn


# ---------------------------------------------------------------------------------------
# sampling the physical domain
# ---------------------------------------------------------------------------------------


def _uniform(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n)


def _degrees(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n) * DEG


def _nonzero_degrees(lo, hi):
    """+-[lo, hi] degrees: a cone angle of either sign, never zero."""
    return lambda rng, n: rng.choice([-1.0, 1.0], n) * rng.uniform(lo, hi, n) * DEG


def _around(centre, half_width):
    return lambda rng, n: centre + rng.uniform(-half_width, half_width, n)


def _teeth(centre, half_width):
    return lambda rng, n: rng.integers(centre - half_width, centre + half_width + 1, n).astype(float)


# Surfaces and TCA: a wide physical domain.  "pinion_"/"gear_" prefixes share a domain.
PHYSICAL = {
    "l": _uniform(0, 15), "u": _uniform(-20, 20),
    "l1": _uniform(0, 15), "u1": _uniform(-20, 20), "l2": _uniform(0, 15), "u2": _uniform(-20, 20),
    "normal_pressure_angle": _degrees(14, 25),
    "helix_angle": _degrees(-40, 40),
    "cone_angle": _nonzero_degrees(0.5, 8),
    "cutter_addendum": _uniform(2.5, 10),  # 1.25 m_n, m_n 2..8 mm
    "half_thickness": _uniform(1.5, 6.5),  # pi m_n / 4
    "rack_shift": _uniform(-3, 3),
    "pitch_radius": _uniform(15, 400),  # m_n N / (2 cos beta), N 15..80
    "gear_angle": _uniform(-0.5, 0.5), "pinion_angle": _uniform(-0.5, 0.5),
    "dx_q": _uniform(-0.5, 0.5), "dy_q": _uniform(-0.5, 0.5), "dz_q": _uniform(-0.5, 0.5),
    "dgamma_v": _degrees(-0.3, 0.3), "dgamma_h": _degrees(-0.3, 0.3),
    "offset": _uniform(20, 300),
    "shaft_angle": _degrees(5, 30),
    "axial_placement": _uniform(-100, 100),
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


def _domain(module, name):
    if module == "design_equations":
        return CASE1[name]
    if name in PHYSICAL:
        return PHYSICAL[name]
    return PHYSICAL[name.removeprefix("pinion_").removeprefix("gear_")]


def sample(module, names, n, seed=SEED):
    """{argument name: float array of shape (n,)} drawn from the argument's domain."""
    rng = np.random.default_rng(seed)
    return {name: _domain(module, name)(rng, n) for name in names}


def _args_of(module, function):
    return list(inspect.signature(getattr(_committed(module), function)).parameters)


# ---------------------------------------------------------------------------------------
# shapes and comparison
# ---------------------------------------------------------------------------------------


def _expr_shape(expr):
    """Per-point shape of an output, as codegen documents it ((k, 1) matrices are vectors)."""
    if isinstance(expr, sp.MatrixBase):
        return (expr.shape[0],) if expr.shape[1] == 1 else tuple(expr.shape)
    return ()


_SHAPE_DOC = re.compile(r"^\s+(\w+): .*, shape \(\.\.\.((?:, \d+)*)\)$", re.M)


def documented_shapes(function):
    """{output name: per-point shape} parsed from the 'Returns a tuple:' part of the docstring."""
    doc = function.__doc__.split("Returns a tuple:", 1)[1]
    return {m[1]: tuple(int(k) for k in m[2].split(", ")[1:]) for m in _SHAPE_DOC.finditer(doc)}


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
    assert sorted(rendered) == sorted(FILES)


def test_specs_and_committed_functions_agree(specs):
    """The parametrization below (read from the committed modules) covers every spec Function."""
    assert [(s.module, f.name) for s in specs.values() for f in s.functions] == FUNCTIONS
    for module in SCALAR_MODULES:
        numpy_twin = module.removesuffix("_scalar")
        assert _public_functions(_committed(module)) == [f"{f.name}_point" for f in specs[numpy_twin].functions]


# ---------------------------------------------------------------------------------------
# 2. determinism
# ---------------------------------------------------------------------------------------


def test_rendering_twice_is_identical(specs, rendered):
    assert codegen.generate(None, list(specs.values())) == rendered


_SEPARATOR = "\n#### scalar twin ####\n"
_HASHSEED_SCRIPT = (
    "import sys\n"
    "from beveloid.derivations import codegen, kernels\n"
    "spec = kernels.tooth_surface_module()\n"
    f"sys.stdout.write(codegen.render_module(spec) + {_SEPARATOR!r} + codegen.render_scalar_module(spec))\n"
)


def test_rendering_does_not_depend_on_the_hash_seed(rendered, tmp_path):
    """A fresh build under two other PYTHONHASHSEEDs (set iteration order) renders the same bytes."""
    expected = rendered["tooth_surface.py"] + _SEPARATOR + rendered["tooth_surface_scalar.py"]
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


def test_package_init_header():
    lines = (GENERATED / "__init__.py").read_text().splitlines()
    assert lines[0].startswith("# Generated by `beveloid derive`") and "Do not edit" in lines[0]


@pytest.mark.parametrize("name", FILES)
def test_no_timestamp_or_version(name):
    text = (GENERATED / name).read_text()
    for pattern in _TIMESTAMP_OR_VERSION:
        m = pattern.search(text)
        assert m is None, f"generated/{name}: {m.group(0)!r} looks like a timestamp or a version"


@pytest.mark.parametrize("name", FILES)
def test_imports_only_numpy_or_math(name):
    """numpy modules import only numpy, scalar twins only math (numba-compilable), __init__ nothing."""
    allowed = {"__init__.py": None, **{f"{m}.py": "numpy" for m in MODULES},
               **{f"{m}.py": "math" for m in SCALAR_MODULES}}[name]
    tree = ast.parse((GENERATED / name).read_text())
    imports = [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))]
    for node in imports:
        assert isinstance(node, ast.Import) and [a.name for a in node.names] == [allowed] \
            and node.names[0].asname is None, f"generated/{name}: `{ast.unparse(node)}` (only `import {allowed}`)"
    if allowed:
        assert len(imports) == 1 and imports[0] in tree.body


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
    """[array (n, *shape)] of the symbolic outputs of ``fn`` via lambdify (no CSE)."""
    symbols = [a.symbol for a in fn.inputs]
    args = [values[a.name] for a in fn.inputs]
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
    values = sample(module, [a.name for a in fn.inputs], N_POINTS)
    generated = getattr(_committed(module), function)(**values)
    assert len(generated) == len(fn.outputs)
    for o, got, want in zip(fn.outputs, generated, _lambdified_outputs(fn, values, N_POINTS)):
        assert_close(_as_batch(got, N_POINTS, _expr_shape(o.expr)), want, RTOL, f"{function}.{o.name}")


# ---------------------------------------------------------------------------------------
# 5. batches and broadcasting
# ---------------------------------------------------------------------------------------

BATCH = 7


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_outputs_have_documented_shapes(specs, module, function):
    f = getattr(_committed(module), function)
    fn = _spec_function(specs, module, function)
    assert documented_shapes(f) == {o.name: _expr_shape(o.expr) for o in fn.outputs}
    values = sample(module, _args_of(module, function), BATCH)
    for name, out in zip(documented_shapes(f), f(**values)):
        assert np.shape(out) == (BATCH,) + documented_shapes(f)[name], f"{function}.{name}"
    # one point given as scalars: per-point shapes
    for name, out in zip(documented_shapes(f), f(**{k: v[0] for k, v in values.items()})):
        assert np.shape(out) == documented_shapes(f)[name], f"{function}.{name}"


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_batch_equals_stack_of_scalar_calls(module, function):
    f = getattr(_committed(module), function)
    values = sample(module, _args_of(module, function), BATCH)
    batch = f(**values)
    singles = [f(**{k: float(v[i]) for k, v in values.items()}) for i in range(BATCH)]
    for j, name in enumerate(documented_shapes(f)):
        stacked = np.stack([np.asarray(s[j], dtype=float) for s in singles])
        # array and scalar numpy math may differ in the last bit (SIMD loops)
        assert_close(batch[j], stacked, 1e-14, f"{function}.{name}")


def test_design_kernels_take_integer_tooth_numbers():
    values = sample("design_equations", _args_of("design_equations", "direct_design"), BATCH)
    as_int = dict(values, pinion_teeth=values["pinion_teeth"].astype(int),
                  gear_teeth=values["gear_teeth"].astype(int))
    dm = _committed("design_equations")
    for a, b in zip(dm.direct_design(**as_int), dm.direct_design(**values)):
        assert_close(_as_batch(a, BATCH, ()), _as_batch(b, BATCH, ()), 0.0, "direct_design with int teeth")


def _broadcast_failures(module, function):
    """Arguments that, alone given as an array (others scalar), do not broadcast every output."""
    f = getattr(_committed(module), function)
    shapes = documented_shapes(f)
    values = sample(module, _args_of(module, function), BATCH)
    failures = []
    for arg in values:
        mixed = {k: (v if k == arg else v[0]) for k, v in values.items()}
        for name, out in zip(shapes, f(**mixed)):
            if np.shape(out) != (BATCH,) + shapes[name]:
                failures.append(f"{arg} -> {name} {np.shape(out)}")
    return failures


# Every output carries the broadcast shape of all inputs, including outputs that do not
# depend on the one batched argument (a bug this test found in the first generator).


@pytest.mark.parametrize("module, function", [
    pytest.param(m, f, id=f"{m}.{f}")
    for m, f in FUNCTIONS])
def test_one_batched_argument_batches_every_output(module, function):
    failures = _broadcast_failures(module, function)
    assert not failures, f"{function}: outputs without the batch axis: {failures[:6]} ..."


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_mixed_scalar_and_array_arguments_broadcast(module, function):
    """Half the arguments as arrays, half as scalars: same values as the all-array call."""
    f = getattr(_committed(module), function)
    shapes = documented_shapes(f)
    values = sample(module, _args_of(module, function), BATCH)
    keep_scalar = list(values)[1::2]
    mixed = {k: (v[0] if k in keep_scalar else v) for k, v in values.items()}
    full = {k: (np.full(BATCH, v[0]) if k in keep_scalar else v) for k, v in values.items()}
    for name, a, b in zip(shapes, f(**mixed), f(**full)):
        assert_close(_as_batch(a, BATCH, shapes[name]), b, 1e-14, f"{function}.{name}")


def test_tca_positions_times_misalignments_broadcast():
    """Points (7,) x assembly-error sets (4, 1) -> (4, 7, ...) in one call, equal to row-by-row calls."""
    tca = _committed("tca_system")
    shapes = documented_shapes(tca.residual_left)
    values = sample("tca_system", _args_of("tca_system", "residual_left"), BATCH)
    errors = ("dx_q", "dy_q", "dz_q", "dgamma_v", "dgamma_h")
    grid = {k: (v[:4, None] if k in errors else v) for k, v in values.items()}
    out = dict(zip(shapes, tca.residual_left(**grid)))
    for name in ("residual", "residual_D_unknowns", "residual_D_errors"):
        assert out[name].shape == (4, BATCH) + shapes[name], name
    for i in range(4):
        row = tca.residual_left(**{k: (np.full(BATCH, v[i]) if k in errors else v) for k, v in values.items()})
        for (name, a), b in zip(out.items(), row):
            assert_close(np.broadcast_to(a, (4, BATCH) + shapes[name])[i], b, 1e-14, f"{name}, error set {i}")


# ---------------------------------------------------------------------------------------
# 6. Jacobians vs complex step (central differences where complex arithmetic fails)
# ---------------------------------------------------------------------------------------

H_COMPLEX = 1e-30
COMPLEX_STEP_RTOL = RTOL  # exact derivative, no truncation error (measured worst 5e-15 over 2000 points)
CENTRAL_RTOL = 1e-6


def derivative(f, values, arg, output):
    """d f(...)[output] / d arg at ``values``: complex step, else central differences.

    Returns (derivative, rtol appropriate to the method).
    """
    try:
        with np.errstate(all="raise"):
            shifted = dict(values, **{arg: values[arg] + 1j * H_COMPLEX})
            d = np.imag(f(**shifted)[output]) / H_COMPLEX
        if np.all(np.isfinite(d)):
            return d, COMPLEX_STEP_RTOL
    except (TypeError, FloatingPointError):
        pass
    h = 1e-6 * np.maximum(1.0, np.abs(values[arg]))
    hshape = h.reshape(h.shape + (1,) * (np.ndim(f(**values)[output]) - h.ndim))
    plus = f(**dict(values, **{arg: values[arg] + h}))[output]
    minus = f(**dict(values, **{arg: values[arg] - h}))[output]
    return (plus - minus) / (2 * hshape), CENTRAL_RTOL


TCA_UNKNOWNS = ("l1", "u1", "l2", "u2", "gear_angle")
TCA_ERRORS = ("dx_q", "dy_q", "dz_q", "dgamma_v", "dgamma_h")


@pytest.mark.parametrize("flank", ["left", "right"])
def test_tca_jacobians(flank):
    f = getattr(_committed("tca_system"), f"residual_{flank}")
    values = sample("tca_system", _args_of("tca_system", f.__name__), N_POINTS)
    _, d_unknowns, d_errors, d_pinion = f(**values)
    for k, arg in enumerate(TCA_UNKNOWNS):
        d, rtol = derivative(f, values, arg, 0)
        assert_close(d_unknowns[..., k], d, rtol, f"{f.__name__}: residual_D_unknowns[:, {k}] ({arg})")
    for k, arg in enumerate(TCA_ERRORS):
        d, rtol = derivative(f, values, arg, 0)
        assert_close(d_errors[..., k], d, rtol, f"{f.__name__}: residual_D_errors[:, {k}] ({arg})")
    d, rtol = derivative(f, values, "pinion_angle", 0)
    assert_close(d_pinion, d, rtol, f"{f.__name__}: residual_D_pinion_angle")


@pytest.mark.parametrize("flank", ["left", "right"])
def test_surface_derivatives(flank):
    ts = _committed("tooth_surface")
    surface = getattr(ts, f"surface_{flank}")
    derivs = getattr(ts, f"surface_derivatives_{flank}")
    values = sample("tooth_surface", _args_of("tooth_surface", surface.__name__), N_POINTS)
    d_lu, d2_lu = derivs(**values)
    for k, arg in enumerate(("l", "u")):
        d, rtol = derivative(surface, values, arg, 0)
        assert_close(d_lu[..., k], d, rtol, f"point_D_lu[:, {k}] (d/d{arg})")
    # columns of point_D2_lu: d2R/dl2, d2R/dldu, d2R/du2
    for column, of, arg in ((0, 0, "l"), (1, 0, "u"), (1, 1, "l"), (2, 1, "u")):
        d, rtol = derivative(derivs, values, arg, 0)
        assert_close(d2_lu[..., column], d[..., of], rtol, f"point_D2_lu[:, {column}] (d point_D_lu[:, {of}] / d{arg})")


def test_offset_residual_derivative():
    f = _committed("design_equations").offset_residual
    values = sample("design_equations", _args_of("design_equations", "offset_residual"), N_POINTS)
    _, d_alpha = f(**values)
    d, rtol = derivative(f, values, "alpha_nw", 0)
    assert_close(d_alpha, d, rtol, "residual_D_alpha_nw")


def test_complex_step_is_what_the_jacobian_tests_use():
    """The kernels are complex-analytic (numpy trig/sqrt/arc*), so the exact complex step applies."""
    f = _committed("design_equations").offset_residual
    values = sample("design_equations", _args_of("design_equations", "offset_residual"), 3)
    assert derivative(f, values, "alpha_nw", 0)[1] == COMPLEX_STEP_RTOL
    f = _committed("tca_system").residual_right
    values = sample("tca_system", _args_of("tca_system", "residual_right"), 3)
    assert derivative(f, values, "gear_angle", 0)[1] == COMPLEX_STEP_RTOL


# ---------------------------------------------------------------------------------------
# 7. CSE vs no CSE
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_cse_and_plain_builds_agree(nocse, module, function):
    f = getattr(_committed(module), function)
    plain = nocse[module][function]
    values = sample(module, _args_of(module, function), N_POINTS)
    shapes = documented_shapes(f)
    for name, a, b in zip(shapes, f(**values), plain(**values)):
        assert_close(_as_batch(a, N_POINTS, shapes[name]), _as_batch(b, N_POINTS, shapes[name]), RTOL,
                     f"{function}.{name} (CSE vs no CSE)")


def test_plain_build_differs_from_cse_build_only_in_bodies(nocse_texts, rendered):
    for module in MODULES:
        cse_text = rendered[f"{module}.py"]
        assert nocse_texts[module] != cse_text
        assert "_x0 = " in cse_text and "_x0 = " not in nocse_texts[module]
        assert ast.get_docstring(ast.parse(nocse_texts[module])) == ast.get_docstring(ast.parse(cse_text))


def test_cse_reduces_the_op_count_of_the_tca_system(nocse_texts):
    cse_ops = ops_counts((GENERATED / "tca_system.py").read_text())
    plain_ops = ops_counts(nocse_texts["tca_system"])
    assert set(cse_ops) == set(plain_ops) == {"residual_left", "residual_right"}
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
    values = sample(numpy_module, args, N_POINTS)
    got = {o: np.full((N_POINTS,) + (shape or (1,)), np.nan) for o, shape in shapes.items()}
    for i in range(N_POINTS):
        assert point(**{k: float(v[i]) for k, v in values.items()},
                     **{f"out_{o}": got[o][i] for o in shapes}) is None
    for (o, shape), want in zip(shapes.items(), f(**values)):
        assert_close(got[o] if shape else got[o][:, 0], _as_batch(want, N_POINTS, shape), RTOL,
                     f"{function}: out_{o}")


# ---------------------------------------------------------------------------------------
# 8. generation-time validation
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


def test_toy_module_renders_and_runs():
    fn = codegen.Function("f", "Toy.", [codegen.Arg("x", x, "mm", "x"), codegen.Arg("y", y, "rad", "y")],
                          [codegen.Output("v", sp.Matrix([x * sp.cos(y), x * sp.sin(y)]), "mm", "vector"),
                           codegen.Output("v_D_y", sp.Matrix([-x * sp.sin(y), x * sp.cos(y)]), "mm/rad", "")])
    ns = _exec_module(codegen.render_module(_spec(fn)), "<toy>")
    v, dv = ns["f"](np.array([1.0, 2.0]), np.array([0.0, np.pi / 2]))
    np.testing.assert_allclose(v, [[1, 0], [0, 2]], atol=1e-15)
    np.testing.assert_allclose(dv, [[0, 1], [-2, 0]], atol=1e-15)


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

SHIFT = sp.Matrix([0.1, -0.05, 0.2])


def _shifted_surface_model():
    original = kernels.SURFACE_MODEL

    def tooth_surface(sigma):
        point, normal, roll = original.tooth_surface(sigma)
        return point + SHIFT, normal, roll

    return types.SimpleNamespace(tooth_surface=tooth_surface, __name__="shifted_surface")


def _arg_symbol(fn, name):
    (arg,) = [a for a in fn.inputs if a.name == name]
    return arg.symbol


def test_registry_model_variant_reaches_the_tca_kernels(monkeypatch):
    """Surfaces moved by a constant vector c in S_i: the TCA residual changes by exactly
    [(L_f1 - L_f2) c, 0, 0] (normals unchanged), and its Jacobians by that term's derivatives."""
    from beveloid.derivations import eq28_38_meshing_model as mm

    monkeypatch.setattr(kernels, "SURFACE_MODEL", _shifted_surface_model())
    spec = kernels.tca_module()
    variant = _exec_module(codegen.render_module(spec), "<tca_system variant>")
    committed = _committed("tca_system")

    delta_r = (mm.L_f1 - mm.L_f2) * SHIFT
    delta = sp.Matrix([delta_r[0], delta_r[1], delta_r[2], 0, 0])
    for fn in spec.functions:
        values = sample("tca_system", [a.name for a in fn.inputs], N_POINTS)
        by_symbol = {a.symbol: a for a in fn.inputs}
        unknowns = [_arg_symbol(fn, n) for n in TCA_UNKNOWNS]
        errors = [_arg_symbol(fn, n) for n in TCA_ERRORS]
        expected_change = [delta, delta.jacobian(unknowns), delta.jacobian(errors),
                           delta.diff(_arg_symbol(fn, "pinion_angle"))]
        assert delta.free_symbols <= set(by_symbol)
        new = variant[fn.name](**values)
        old = getattr(committed, fn.name)(**values)
        change = _lambdified_outputs(
            codegen.Function(fn.name, "", fn.inputs,
                             [codegen.Output(o.name, e, "", "") for o, e in zip(fn.outputs, expected_change)]),
            values, N_POINTS)
        assert not np.allclose(new[0][..., :3], old[0][..., :3])
        assert_close(new[0][..., 3:], old[0][..., 3:], 1e-15, "normal components")  # same up to CSE order
        for o, a, b, c in zip(fn.outputs, new, old, change):
            assert_close(a, b + c, RTOL, f"variant {fn.name}.{o.name}")


def test_registry_variant_names_its_source_in_the_header(monkeypatch):
    from beveloid.derivations.symbols import l, u

    flat = types.SimpleNamespace(tooth_surface=lambda sigma: (sp.Matrix([l, sigma * u, 0]), sp.Matrix([0, 0, 1]),
                                                              sp.Integer(0)))
    monkeypatch.setattr(kernels, "SURFACE_MODEL", flat)
    monkeypatch.setattr(kernels, "SURFACE_SOURCE", "flat_rack_variant.py")
    spec = kernels.tooth_surface_module()
    assert codegen.render_module(spec).startswith(
        "# Generated by `beveloid derive` from derivations/flat_rack_variant.py")


# ---------------------------------------------------------------------------------------
# 10. `beveloid derive --check` and the sympy-free runtime
# ---------------------------------------------------------------------------------------


@pytest.fixture
def cheap_derive(monkeypatch, specs):
    """`beveloid derive` without the 18 s equation verification and the 6 s model build:
    the docs page renders as committed, the models are the ones built for this module."""
    from beveloid.derivations import docs, registry

    committed_docs = (ROOT / "docs" / "derivations.md").read_text()
    monkeypatch.setattr(registry, "verify", lambda *a, **k: None)
    monkeypatch.setattr(docs, "render_derivations_md", lambda results=None: committed_docs)
    monkeypatch.setattr(kernels, "module_specs", lambda: list(specs.values()))


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
    stale = tmp_path / "generated" / "tca_system.py"
    ops = _OPS.search(stale.read_text())[1]
    stale.write_text(_OPS.sub("    # ops: 0", stale.read_text(), count=1))
    (tmp_path / "generated" / "orphan.py").write_text("x = 1\n")
    monkeypatch.setattr(derive, "source_root", lambda: tmp_path)

    assert main(["derive", "--check"]) == 1
    out, err = capsys.readouterr()
    assert "--- generated/tca_system.py (committed)\n+++ generated/tca_system.py (regenerated)\n" in out
    assert f"\n-    # ops: 0\n+    # ops: {ops}\n" in out
    assert "generated/orphan.py" in out
    assert "docs/derivations.md" not in out and "tooth_surface.py" not in out
    assert HINT in err
    # --check writes nothing
    assert "# ops: 0\n" in stale.read_text() and (tmp_path / "generated" / "orphan.py").exists()


def test_runtime_kernels_import_without_sympy(tmp_path):
    modules = ", ".join(f"beveloid.generated.{m}" for m in ("tca_system", "tooth_surface", "design_equations")
                        + MODULES + SCALAR_MODULES)
    code = (f"import sys, beveloid.generated, {modules}\n"
            "bad = sorted(m for m in ('sympy', 'jinja2', 'mpmath', 'beveloid.derivations') if m in sys.modules)\n"
            "assert not bad, bad\n"
            "print(beveloid.generated.__file__)\n")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    # editable install: the checkout's generated/; regular install: an identical copy
    imported = Path(proc.stdout.strip()).parent
    for name in ("tca_system.py", "tooth_surface.py", "design_equations.py"):
        assert (imported / name).read_bytes() == (GENERATED / name).read_bytes(), name
