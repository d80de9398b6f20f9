"""The generated kernels: generated == the symbolic outputs evaluated node by node from their trees, at seeded random points (helpers: generated_support.py, fixtures: conftest.py)."""
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
# 4. generated vs symbolic
# ---------------------------------------------------------------------------------------


#: sympy's elementary functions in the derived expressions, and numpy's
_FUNCTIONS = {sp.sin: np.sin, sp.cos: np.cos, sp.tan: np.tan, sp.asin: np.arcsin, sp.acos: np.arccos,
              sp.atan: np.arctan, sp.exp: np.exp, sp.log: np.log, sp.Abs: np.abs, sp.sign: np.sign}
_RELATIONS = {sp.LessThan: np.less_equal, sp.StrictLessThan: np.less, sp.GreaterThan: np.greater_equal,
              sp.StrictGreaterThan: np.greater, sp.Eq: np.equal, sp.Ne: np.not_equal}


def evaluate_symbolic(exprs, values):
    """[array] of sympy expressions at ``values`` ({symbol: array}), straight from their trees:
    each node's numpy operation on its arguments' values, each distinct subexpression once.  The
    reference of the generated code, independent of it: no common-subexpression pass, no printing
    (lambdify prints the whole tree, every repeated subexpression again: ~25x slower here)."""
    memo = {}  # by the node's identity: a dict lookup by value compares whole subtrees

    def ev(node):
        got = memo.get(id(node))
        if got is not None:
            return got[1]
        if node.is_Symbol and node in values:
            out = values[node]
        elif node.is_Number or node.is_NumberSymbol:
            out = float(node)
        elif node is sp.true or node is sp.false:
            out = bool(node)
        elif node.is_Symbol:
            raise KeyError(f"no value for {node}")
        elif node.is_Add:
            args = [ev(a) for a in node.args]
            out = args[0]
            for a in args[1:]:
                out = out + a
        elif node.is_Mul:
            args = [ev(a) for a in node.args]
            out = args[0]
            for a in args[1:]:
                out = out * a
        elif node.is_Pow:
            out = np.power(np.asarray(ev(node.base), dtype=float), ev(node.exp))
        elif isinstance(node, sp.Piecewise):  # the first branch whose condition holds
            both = np.broadcast_arrays(*[ev(c.cond) for c in node.args], *[ev(c.expr) for c in node.args])
            k = len(node.args)
            out = np.select(both[:k], both[k:], default=np.nan)
        elif type(node) in _RELATIONS:
            out = _RELATIONS[type(node)](ev(node.lhs), ev(node.rhs))
        elif node.func in _FUNCTIONS:
            (arg,) = node.args
            out = _FUNCTIONS[node.func](ev(arg))
        else:
            raise NotImplementedError(f"no numpy evaluation of {node.func} in the symbolic reference")
        memo[id(node)] = (node, out)  # the node kept alive: its id stays its own
        return out

    with np.errstate(all="ignore"):
        return [ev(sp.sympify(e)) for e in exprs]


def _symbolic_outputs(fn, values, n):
    """[array (n, *shape)] of the symbolic outputs of ``fn`` (:func:`evaluate_symbolic`), every entry
    of a vector, matrix or layout argument given its own value."""
    env = {}
    for a in fn.inputs:
        for _, symbol, index in a.entries():
            value = np.asarray(values[a.name])
            env[symbol] = np.asarray(value if index is None else value[(...,) + (index if isinstance(index, tuple) else (index,))],
                                     dtype=float)
    # a staged function's outputs are written over named intermediate values: each is evaluated in
    # order (a stage uses only earlier ones) and then stands for its symbol
    for sym, e in fn.stages:
        (env[sym],) = evaluate_symbolic([e], env)
    outs = []
    for o in fn.outputs:
        entries = list(o.expr) if isinstance(o.expr, sp.MatrixBase) else [o.expr]
        flat = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in evaluate_symbolic(entries, env)],
                        axis=-1)
        outs.append(flat.reshape((n,) + expr_shape(o.expr)))
    return outs


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_generated_matches_symbolic(specs, module, function, fresh_stack):
    fn = spec_function(specs, module, function)
    values = sample(module, function, N_POINTS)
    generated = getattr(committed_module(module), function)(**values)
    assert len(generated) == len(fn.outputs)
    for o, got, want in zip(fn.outputs, generated, fresh_stack(_symbolic_outputs, fn, values, N_POINTS)):
        assert_close(as_batch(got, N_POINTS, expr_shape(o.expr)), want, RTOL, f"{function}.{o.name}")


def test_the_symbolic_reference_is_sympys_value_on_every_kind_of_node():
    """evaluate_symbolic on a small tree with every kind of node of the derivations, against lambdify;
    an unknown function is refused, not guessed."""
    x, y = sp.symbols("x y", real=True)
    e = (sp.Piecewise((0, x <= 0), (x * (1 + x), True)) + sp.sqrt(1 + y**2) / (2 + sp.cos(x)) - sp.atan(y) * sp.exp(-x)
         + sp.Rational(3, 7) * sp.tan(x / 3) ** 2 + sp.asin(y / 3) - sp.acos(y / 4) + sp.Abs(x - y) + sp.pi * x**-2)
    vx, vy = np.linspace(-1.5, 2.0, 9), np.linspace(0.3, 2.5, 9)
    (got,) = evaluate_symbolic([e], {x: vx, y: vy})
    assert_close(got, sp.lambdify((x, y), e, "numpy")(vx, vy), RTOL, "small tree")
    with pytest.raises(NotImplementedError, match="gamma"):
        evaluate_symbolic([sp.gamma(x)], {x: vx})
