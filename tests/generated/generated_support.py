"""Shared by tests/generated/test_generated_*.py: the generated kernels (generated/*.py) against the
generator and the symbolic models.

* staleness: the committed files (kernels, their scalar twins, layouts.py and the glue
  tca_kernels*.py) are exactly what the generator renders today;
* determinism: rendering is repeatable, also under another PYTHONHASHSEED;
* hygiene: header, "do not edit", no timestamps, imports (numpy modules only typing and numpy,
  the scalar twins only math, layouts.py only typing, the glue only numpy/typing and its
  sibling generated modules), an ``# ops:`` count per function;
* interfaces: documented input and output shapes, the generated NamedTuple outputs and
  parameter layouts;
* maths: generated == the symbolic outputs evaluated node by node at seeded random points; Jacobians ==
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

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
TEMPLATES = {False: "derivations/templates/module.py.jinja", True: "derivations/templates/scalar_module.py.jinja"}
HINT = "run `beveloid derive` to update"


SEED = 20130101
N_POINTS = 20
RTOL = 1e-12  # generated vs symbolic, CSE vs no-CSE, complex step
DEG = np.pi / 180
MODEL = "involute"  # the surface model of both members wherever one is needed
#: the surface models whose two files (numpy, scalar twin) the fast tier takes as committed instead of rendering them:
#: their CSE is ~12 of the ~16 s of CPU that rendering every module costs (micro_geometry 9.2 s, crowned 2.7 s, on the
#: slow host of docs/performance.md "Test suite").  The fast tier still renders MODEL's surface through the same
#: templates and holds these two models' values (test_generated_symbolic.py, the scalar twins in
#: test_generated_builds.py); their bytes are compared in the slow tier (test_generated_files.py)
RENDERED_IN_THE_SLOW_TIER = ("surface_crowned", "surface_micro_geometry")
FLANKS = tuple(name for name, _ in kernels.FLANKS)


# ---------------------------------------------------------------------------------------
# fixtures: build the sympy specs and the renderings once
# ---------------------------------------------------------------------------------------


@functools.cache
def module_specs():
    """{module name: ModuleSpec} from one ``kernels.module_specs()`` call (the sampler needs it too)."""
    return {s.module: s for s in kernels.module_specs()}


def exec_module(text, name):
    ns = {"__name__": name}
    exec(compile(text, name, "exec"), ns)
    return ns


def committed_module(module):
    return importlib.import_module(f"beveloid.generated.{module}")


def public_functions(mod):
    return [n for n, f in vars(mod).items()
            if inspect.isfunction(f) and not n.startswith("_") and f.__module__ == mod.__name__]


# Module lists of the committed package (cheap to import; checked against the registry below).
PACKAGE = importlib.import_module("beveloid.generated")
MODULES = tuple(PACKAGE.MODULES)
SCALAR_MODULES = tuple(PACKAGE.SCALAR_MODULES)
SUPPORT_MODULES = tuple(PACKAGE.SUPPORT_MODULES)
SURFACE_MODULES = tuple(m for m in MODULES if m.startswith("surface_"))
FILES = ["__init__.py"] + [f"{m}.py" for m in MODULES + SCALAR_MODULES + SUPPORT_MODULES]

# (module, function) pairs of the committed kernels; checked against the specs below.
FUNCTIONS = [(m, f) for m in MODULES for f in public_functions(committed_module(m))]
FUNCTION_IDS = [f"{m}.{f}" for m, f in FUNCTIONS]

#: the modules rendered a second time without CSE, for the CSE-vs-plain comparison: those whose plain
#: text stays small.  The plain renderings of surface_involute, surface_crowned, surface_micro_geometry,
#: design_equations and root_fillet are 0.5-8 MB each and take ~2 min of CPU to render; every function
#: of every module, those included, is checked against its symbolic outputs evaluated node by node (no
#: CSE, no printing) by test_generated_symbolic.py, so CSE is still checked everywhere.
PLAIN_MODULES = ("placement", "contact_system", "flank_boundaries", "edge_contact", "patch_clearance",
                 "tooth_sections", "tooth_plate_coupling")


def spec_function(specs, module, name):
    (fn,) = [f for f in specs[module].functions if f.name == name]
    return fn


def spec_arg(module, function, name):
    (arg,) = [a for a in spec_function(module_specs(), module, function).inputs if a.name == name]
    return arg


# ---------------------------------------------------------------------------------------
# sampling the physical domain
# ---------------------------------------------------------------------------------------


def uniform(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n)


def degrees(lo, hi):
    return lambda rng, n: rng.uniform(lo, hi, n) * DEG


def signed(lo, hi, unit=1.0):
    """+-[lo, hi] * unit: either sign, never near zero."""
    return lambda rng, n: rng.choice([-1.0, 1.0], n) * rng.uniform(lo, hi, n) * unit


def around(centre, half_width):
    return lambda rng, n: centre + rng.uniform(-half_width, half_width, n)


def teeth(centre, half_width):
    return lambda rng, n: rng.integers(centre - half_width, centre + half_width + 1, n).astype(float)


# Scalars and layout fields of the surfaces, placement, TCA and blanks: a wide physical domain.
# "pinion_"/"gear_" prefixes share a domain.
PHYSICAL = {
    "l": uniform(0, 15), "u": uniform(-20, 20),
    "l_mm": uniform(0, 15), "u_mm": uniform(-20, 20), "angle_rad": uniform(-0.5, 0.5),  # tca_kernels.UNKNOWNS
    "angle": uniform(-0.5, 0.5),  # pinion_angle, gear_angle
    "speed": uniform(1, 600),  # contact_kinematics: pinion_speed, rad/s
    "teeth": teeth(40, 25),  # contact_kinematics: pinion_teeth, gear_teeth
    "normal_pressure_angle": degrees(14, 25),
    "helix_angle": degrees(-40, 40),
    "cone_angle": signed(0.5, 8, DEG),
    "cutter_addendum_mm": uniform(2.5, 10),  # 1.25 m_n, m_n 2..8 mm
    "half_thickness_mm": uniform(1.5, 6.5),  # pi m_n / 4
    "rack_shift_mm": uniform(-3, 3),
    "pitch_radius_mm": uniform(15, 400),  # m_n N / (2 cos beta), N 15..80
    "face_width_mm": uniform(10, 120), "normal_module_mm": uniform(2, 8),  # crowned model
    "profile_crowning_um": uniform(0, 200), "lead_crowning_um": uniform(0, 200),
    "dx_mm": uniform(-0.5, 0.5), "dy_mm": uniform(-0.5, 0.5), "dz_mm": uniform(-0.5, 0.5),
    "vertical_rad": degrees(-0.3, 0.3), "horizontal_rad": degrees(-0.3, 0.3),
    "offset_mm": uniform(20, 300),
    "shaft_angle": degrees(5, 30),
    "axial_placement_mm": uniform(-100, 100),
    "tip_height_mm": uniform(2, 8),  # m_n
    "cutter_tip_radius_mm": uniform(0, 3), "psi": uniform(0, 1.3),  # root fillet: rho_a0 <= 0.47 m_n
    "form_limit_l_mm": uniform(0, 1.5),  # the blank's form limit: l_t = rho_a0 (1 - sin alpha_n) / cos alpha_n
    "z": uniform(-40, 40),  # tooth_sections: a transverse section
    "radius": uniform(400, 600),  # tooth_sections: above every base radius (pitch radius <= 400)
    # micro-geometry model (reliefs below the working depth, end zones below half the narrowest face)
    "reference_section_offset_mm": uniform(-10, 10), "tip_relief_um": uniform(0, 200),
    "tip_relief_height_mm": uniform(0.5, 5), "end_relief_um": uniform(0, 200), "end_relief_length_mm": uniform(1, 5),
    "lead_slope_um": uniform(-200, 200),
    "tip_relief_shape": lambda rng, n: rng.choice([1.0, 2.0], n), "end_relief_shape": lambda rng, n: rng.choice([1.0, 2.0], n),
    "toe_z_mm": signed(5, 60), "heel_z_mm": signed(5, 60),  # either order: the margins take both
}

# Design equations: case 1 of the paper, perturbed (the asin/acos arguments stay real).
CASE1 = {
    "alpha_nw": around(21.25 * DEG, 1 * DEG),
    "normal_module": around(6.0, 0.5),
    "normal_pressure_angle": around(20 * DEG, 1 * DEG),
    "pinion_teeth": teeth(29, 2), "gear_teeth": teeth(45, 2),
    "shaft_angle": around(13 * DEG, 1 * DEG),
    "pinion_profile_shift": around(0.15, 0.1),
    "pinion_cone_angle": around(2 * DEG, 0.3 * DEG), "gear_cone_angle": around(0.8 * DEG, 0.2 * DEG),
    "pinion_helix_angle": around(23 * DEG, 1 * DEG),
    "offset": around(229.0, 5.0),
    "pinion_working_cone_angle": around(1.8873 * DEG, 0.2 * DEG),
    "gear_working_cone_angle": around(0.7549 * DEG, 0.1 * DEG),
    "pinion_working_helix_angle": around(23.199 * DEG, 1 * DEG),
}


def points(rng, n, shape):
    """Points of a member frame S_i at radii 10..400 mm, |z| < 60 mm."""
    assert shape == (3,)
    r, t, z = rng.uniform(10, 400, n), rng.uniform(-np.pi, np.pi, n), rng.uniform(-60, 60, n)
    return np.stack([r * np.cos(t), r * np.sin(t), z], axis=-1)


def unit_vectors(rng, n, shape):
    assert shape == (3,)
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# Vector and matrix arguments, by name without the member prefix; others entry-wise uniform(-1, 1).
ARRAYS = {"point": points, "normal": unit_vectors}


def member(name):
    return name.removeprefix("pinion_").removeprefix("gear_")


# The plate strip's edge compliance: k h from the longest face mode to the truncation, steel-like nu.
PLATE = {"t": uniform(0.03, 60.0), "nu": uniform(0.2, 0.4)}


def domain(module, name):
    if module == "design_equations":
        return CASE1[name]
    if module == "tooth_plate_coupling":
        return PLATE[name]
    return PHYSICAL[name] if name in PHYSICAL else PHYSICAL[member(name)]


def sample_arg(module, arg, rng, n):
    """Float array (n, *arg.shape) drawn from the argument's domain (layouts field by field)."""
    if isinstance(arg.symbol, codegen.Layout):
        # the base entries from their domains, the derived ones (the layout's trig setting) computed from them as pack does
        base = {f.symbol: domain(module, f.name)(rng, n) for f in arg.symbol.base_fields()}
        derived = lambda f: np.broadcast_to(sp.lambdify(list(base), f.derived, "numpy")(*base.values()), (n,))  # noqa: E731
        return np.stack([base[f.symbol] if f.derived is None else derived(f) for f in arg.symbol.fields], axis=-1)
    if isinstance(arg.symbol, sp.MatrixBase):
        draw = ARRAYS.get(member(arg.name), lambda rng, n, shape: rng.uniform(-1, 1, (n,) + shape))
        return draw(rng, n, arg.shape)
    return domain(module, arg.name)(rng, n)


def sample(module, function, n, seed=SEED):
    """{argument name: float array (n, *per-point shape)} for a generated kernel."""
    rng = np.random.default_rng(seed)
    return {a.name: sample_arg(module, a, rng, n) for a in spec_function(module_specs(), module, function).inputs}


def sample_contact(n, seed=SEED):
    """Arguments of ``tca_kernels.contact_system`` after (pinion_model, gear_model, flank), both
    members of MODEL (parameters zero-padded to PARAMETER_COUNT as pack_surface_params does)."""
    tk = committed_module("tca_kernels")
    rng = np.random.default_rng(seed)
    params = spec_arg(f"surface_{MODEL}", "surface_left", "params")

    def member():
        p = sample_arg(f"surface_{MODEL}", params, rng, n)
        return np.concatenate([p, np.zeros((n, tk.PARAMETER_COUNT - p.shape[-1]))], axis=-1)

    def arg(name):
        return sample_arg("contact_system", spec_arg("contact_system", "contact_residual", name), rng, n)

    values = dict(x=np.stack([domain("tca_kernels", k)(rng, n) for k in tk.UNKNOWNS], axis=-1),
                  pinion_angle=arg("pinion_angle"), errors=arg("errors"), pinion_params=member(),
                  gear_params=member(), pair=arg("pair"))
    assert list(inspect.signature(tk.contact_system).parameters)[3:] == list(values)
    return values


def args_of(module, function):
    return list(inspect.signature(getattr(committed_module(module), function)).parameters)


def at(value, i):
    """Point i of a sampled argument: a float for a scalar argument, an array for the others."""
    return float(value[i]) if np.ndim(value) == 1 else value[i]


# ---------------------------------------------------------------------------------------
# shapes and comparison
# ---------------------------------------------------------------------------------------


def expr_shape(expr):
    """Per-point shape of an output, as codegen documents it ((k, 1) matrices are vectors)."""
    if isinstance(expr, sp.MatrixBase):
        return (expr.shape[0],) if expr.shape[1] == 1 else tuple(expr.shape)
    return ()


DOC_LINE = re.compile(r"^        (\w+): .*?(?:, shape \(\.\.\.((?:, \d+)*)\))?$", re.M)
RETURNS = re.compile(r"^    Returns (\w+):$", re.M)


def documented(function):
    """(outputs class, {input: per-point shape}, {output: per-point shape}) from the docstring."""
    parts = RETURNS.split(function.__doc__)
    assert len(parts) == 3, f"{function.__name__}: no single 'Returns <Class>:' line in the docstring"
    head, cls, returns = parts

    def shapes(text):
        return {m[1]: tuple(int(k) for k in (m[2] or "").split(", ")[1:]) for m in DOC_LINE.finditer(text)}

    return cls, shapes(head.split("\n    Inputs", 1)[1]), shapes(returns)


def documented_shapes(function):
    """{output name: per-point shape} parsed from the 'Returns <Class>:' part of the docstring."""
    return documented(function)[2]


def as_batch(value, n, shape):
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


OPS = re.compile(r"^    # ops: (\d+)$", re.M)


def ops_counts(text):
    """{function name: op count} from a rendered module."""
    out, name = {}, None
    for line in text.splitlines():
        if line.startswith("def "):
            name = line[4:].split("(")[0]
        m = OPS.match(line)
        if m:
            out[name] = int(m[1])
    return out


def scalar_contact(tk, tks, models, flank, values, i):
    """(residual, d/d unknowns, d/d errors, d/d pinion angle) of point i from the scalar glue tks
    (models named as in tk.MODELS), and the workspace it leaves."""
    ws = tks.workspace()
    n, m = tks.N_UNKNOWNS, tks.N_ERRORS
    out = (np.full(n, np.nan), np.full((n, n), np.nan), np.full((n, m), np.nan), np.full(n, np.nan))
    assert tks.contact_system_point(*(tk.model_id(k) for k in models), tk.flank_id(flank),
                                    *(at(v, i) for v in values.values()), ws, *out) is None
    return out, ws


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
