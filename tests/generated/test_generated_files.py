"""The generated kernels: staleness, determinism, headers and hygiene of the committed files (helpers: generated_support.py, fixtures: conftest.py)."""
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
from generated_support import *  # noqa: F401,F403  (the shared samplers and comparisons)


# One xdist worker runs these modules: their sympy models and renderings (~15 s) are built once per process.
pytestmark = pytest.mark.xdist_group("generated")

# ---------------------------------------------------------------------------------------
# 1. staleness
# ---------------------------------------------------------------------------------------


def test_committed_files_are_current(rendered):
    """Byte-for-byte: what the generator renders today is what is committed (the surface models of
    RENDERED_IN_THE_SLOW_TIER: by the next test, in the slow tier)."""
    committed = {p.name for p in GENERATED.glob("*.py")}
    stale = sorted(n for n in set(rendered) | committed
                   if n not in committed or n not in rendered or (GENERATED / n).read_text() != rendered[n])
    if stale:
        pytest.fail(f"stale generated files {stale}: {HINT}\n{codegen.diff(GENERATED, rendered)}", pytrace=False)


@pytest.mark.slow
@pytest.mark.parametrize("module", RENDERED_IN_THE_SLOW_TIER)
def test_slow_tier_surfaces_render_as_committed(specs, fresh_stack, module):
    """The surface models whose files the fast tier's rendering takes as committed, rendered as `beveloid
    derive` renders them (both files from one reduction), byte for byte."""
    files = fresh_stack(codegen.generate, None, [specs[module]])
    for name in (f"{module}.py", f"{module}_scalar.py"):
        if (GENERATED / name).read_text() != files[name]:
            committed = {p.name: p.read_text() for p in GENERATED.glob("*.py")}
            pytest.fail(f"stale generated file {name}: {HINT}\n{codegen.diff(GENERATED, committed | {name: files[name]})}",
                        pytrace=False)


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
        assert public_functions(committed_module(module)) == [f"{f.name}_point" for f in specs[numpy_twin].functions]


def test_layouts_module_holds_the_spec_layouts(specs):
    """One NamedTuple per layout of any kernel: fields in the kernels' order, units and docs."""
    layouts = committed_module("layouts")
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
    its angles again (the point of a layout's trig setting), and their values agree with the model's."""
    import inspect

    for module in ("surface_involute_scalar", "surface_crowned_scalar", "flank_boundaries_scalar",
                   "contact_system_scalar"):
        text = inspect.getsource(committed_module(module))
        for angle in ("normal_pressure_angle", "helix_angle", "cone_angle", "shaft_angle"):
            for fn in ("sin", "cos", "tan"):
                assert f"math.{fn}({angle})" not in text, (module, fn, angle)
        assert "sin_" in text or "tan_" in text or "cos_" in text


def test_glue_constants_follow_the_registry():
    tk, tks = committed_module("tca_kernels"), committed_module("tca_kernels_scalar")
    layouts = committed_module("layouts")
    assert tk.MODELS == tuple(kernels.SURFACE_MODELS) == committed_module("surface_models").MODELS and tk.FLANKS == FLANKS
    assert committed_module("surface_models").DEFAULT_MODEL in tk.MODELS
    assert tk.UNKNOWNS == kernels.UNKNOWNS == committed_module("contact_system").UNKNOWNS
    assert tk.BOUNDARIES == committed_module("flank_boundaries").BOUNDARIES
    assert tk.CONTACT_BOUNDARIES == tuple(f"{who} {b}" for who in ("pinion", "gear") for b in tk.BOUNDARIES)
    params = {k: spec_arg(f"surface_{k}", "surface_left", "params").symbol for k in tk.MODELS}
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


def test_rendering_again_in_the_same_process_is_identical(specs, rendered):
    """State left by a whole rendering (symbol counters, caches) does not change the next one: the
    surface model and the contact system rendered again, after everything, give the same text (the
    whole rendering is compared with the committed files by test_committed_files_are_current, and a
    fresh process under other hash seeds by the next test)."""
    for module in (f"surface_{MODEL}", "contact_system"):
        assert codegen.render_module(specs[module]) == rendered[f"{module}.py"], module
        assert codegen.render_scalar_module(specs[module]) == rendered[f"{module}_scalar.py"], module


_SEPARATOR = "\n#### scalar twin ####\n"
_HASHSEED_SCRIPT = (
    "import sys\n"
    "from beveloid.derivations import codegen, kernels\n"
    f"spec = kernels.surface_module({MODEL!r}, kernels.SURFACE_MODELS[{MODEL!r}])\n"
    "r = {}\n"  # as `derive` renders them: the two files share the symbolic reduction
    f"sys.stdout.write(codegen.render_module(spec, reduced_by=r) + {_SEPARATOR!r} + codegen.render_scalar_module(spec, reduced_by=r))\n"
)


@pytest.mark.slow
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
                assert hasattr(committed_module(node.module), a.name), f"generated/{name}: `{ast.unparse(node)}`"
    assert imported <= siblings, f"generated/{name} imports {sorted(imported - siblings)}"
    scalar = module.endswith("_scalar")
    assert all(m.endswith("_scalar") == scalar for m in imported - {"layouts"}), sorted(imported)
    surfaces = {m + ("_scalar" if scalar else "") for m in SURFACE_MODULES}
    assert not imported & surfaces or surfaces <= imported, sorted(imported)


@pytest.mark.parametrize("module", MODULES + SCALAR_MODULES)
def test_every_function_has_an_op_count(module):
    text = (GENERATED / f"{module}.py").read_text()
    tree = ast.parse(text)
    lines = text.splitlines()
    functions = [n for n in tree.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")]
    assert functions
    for fn in functions:
        assert isinstance(fn.body[0].value, ast.Constant)  # the docstring
        m = OPS.match(lines[fn.body[0].end_lineno])  # the line right after it (0-based index)
        assert m and int(m[1]) > 0, f"{module}.{fn.name}: no `# ops: N` comment after the docstring"


@pytest.mark.parametrize("module", SCALAR_MODULES)
def test_scalar_twin_comes_from_the_same_cse_pass(module):
    numpy_ops = ops_counts((GENERATED / f"{module.removesuffix('_scalar')}.py").read_text())
    scalar_ops = ops_counts((GENERATED / f"{module}.py").read_text())
    assert scalar_ops == {f"{name}_point": n for name, n in numpy_ops.items()}


