"""The generated kernels: the CSE build vs the plain build, the scalar twins vs the numpy kernels (helpers: generated_support.py, fixtures: conftest.py)."""
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
# 7. CSE vs no CSE, scalar twins
# ---------------------------------------------------------------------------------------


PLAIN_FUNCTIONS = [(m, f) for m, f in FUNCTIONS if m in PLAIN_MODULES]


def test_the_plain_build_covers_the_contact_system_and_the_boundaries():
    assert {"contact_system", "flank_boundaries", "edge_contact"} <= {m for m, _ in PLAIN_FUNCTIONS}
    assert set(PLAIN_MODULES) <= set(MODULES)


@pytest.mark.slow
@pytest.mark.parametrize("module, function", PLAIN_FUNCTIONS, ids=[f"{m}.{f}" for m, f in PLAIN_FUNCTIONS])
def test_cse_and_plain_builds_agree(nocse, module, function):
    f = getattr(committed_module(module), function)
    plain = nocse[module][function]
    values = sample(module, function, N_POINTS)
    shapes = documented_shapes(f)
    for name, a, b in zip(shapes, f(**values), plain(**values)):
        assert_close(as_batch(a, N_POINTS, shapes[name]), as_batch(b, N_POINTS, shapes[name]), RTOL,
                     f"{function}.{name} (CSE vs no CSE)")


@pytest.mark.slow
def test_plain_build_differs_from_cse_build_only_in_bodies(nocse_texts, rendered):
    for module in PLAIN_MODULES:
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


@pytest.mark.slow
def test_cse_reduces_the_op_count_of_the_contact_system(nocse_texts):
    cse_ops = ops_counts((GENERATED / "contact_system.py").read_text())
    plain_ops = ops_counts(nocse_texts["contact_system"])
    assert set(cse_ops) == set(plain_ops) == {"contact_residual", "position_residual"}
    for name in cse_ops:
        assert cse_ops[name] < plain_ops[name], f"{name}: CSE {cse_ops[name]} ops vs {plain_ops[name]} without"


SCALAR_FUNCTIONS = [(m, f) for m in SCALAR_MODULES for f in public_functions(committed_module(m))]


@pytest.mark.parametrize("module, function", SCALAR_FUNCTIONS, ids=[f"{m}.{f}" for m, f in SCALAR_FUNCTIONS])
def test_scalar_twin_matches_numpy_kernel(module, function, specs):
    """``<f>_point(args..., out_<output>...)`` (one point, math) == the numpy kernel ``<f>``.  (``specs``: the
    sampler's models built by the fixture, on a fresh stack; built here, ~60 frames deep in pytest, they cost
    1.9 s more of system time, tests/conftest.py ``on_a_fresh_stack``.)"""
    numpy_module, name = module.removesuffix("_scalar"), function.removesuffix("_point")
    f = getattr(committed_module(numpy_module), name)
    point = getattr(committed_module(module), function)
    shapes = documented_shapes(f)
    args = args_of(numpy_module, name)
    assert list(inspect.signature(point).parameters) == args + [f"out_{o}" for o in shapes]
    values = sample(numpy_module, name, N_POINTS)
    got = {o: np.full((N_POINTS,) + (shape or (1,)), np.nan) for o, shape in shapes.items()}
    for i in range(N_POINTS):
        assert point(**{k: at(v, i) for k, v in values.items()},
                     **{f"out_{o}": got[o][i] for o in shapes}) is None
    for (o, shape), want in zip(shapes.items(), f(**values)):
        assert_close(got[o] if shape else got[o][:, 0], as_batch(want, N_POINTS, shape), RTOL,
                     f"{function}: out_{o}")


@pytest.mark.parametrize("flank", FLANKS)
def test_scalar_glue_matches_the_numpy_glue(flank, specs):
    """tca_kernels_scalar (what the solver core runs) == tca_kernels, point by point: the
    contact system and the smallest margin of a contact with its boundary (``specs``: as above)."""
    tk, tks = committed_module("tca_kernels"), committed_module("tca_kernels_scalar")
    values = sample_contact(N_POINTS)
    want = tk.contact_system(MODEL, MODEL, flank, **values)
    rng = np.random.default_rng(SEED + 1)
    blank = spec_arg("flank_boundaries", "flank_margins", "blank")
    pinion_blank, gear_blank = (sample_arg("flank_boundaries", blank, rng, N_POINTS) for _ in range(2))
    margins = tk.contact_margins(values["x"], want.pinion_point, want.gear_point, pinion_blank, gear_blank)
    fm = committed_module("flank_boundaries").flank_margins
    assert_close(margins, np.concatenate([fm(want.pinion_point, values["x"][:, 0], pinion_blank).margins,
                                          fm(want.gear_point, values["x"][:, 2], gear_blank).margins], axis=-1),
                 0.0, "contact_margins")
    for i in range(N_POINTS):
        got, ws = scalar_contact(tk, tks, (MODEL, MODEL), flank, values, i)
        for name, a, b in zip(want._fields, got, want):
            assert_close(a, b[i], RTOL, f"contact_system_point {name}, point {i}")
        best, which = tks.contact_margin_point(values["x"][i], pinion_blank[i], gear_blank[i], ws)
        assert which == np.argmin(margins[i]) and best == margins[i, which], (i, best, which, margins[i])
