"""The generated kernels: the generator's validation and interfaces (helpers: generated_support.py, fixtures: conftest.py)."""
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
    ns = exec_module(codegen.render_module(_spec(fn)), "<toy>")
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
    ns = exec_module(codegen.render_module(_spec(fn)), "<toy>")
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
    assert exec_module(text, "<toy>")["f"](1.0) == (2.0, 2.0)
