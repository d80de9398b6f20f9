"""The generated kernels: generated == lambdified symbolic outputs at seeded random points (helpers: generated_support.py, fixtures: conftest.py)."""
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


# One xdist worker runs these modules: their sympy models and renderings (~60 s) are built once per process.
pytestmark = pytest.mark.xdist_group("generated")

# ---------------------------------------------------------------------------------------
# 4. generated vs symbolic
# ---------------------------------------------------------------------------------------


#: lambdify's printer, with the terms of a sum in their stored order: sorting them for print
#: (sympy's default) was ~40 % of these tests' time; the sum is the same (RTOL covers the rounding)
def _printer():
    from sympy.printing.numpy import NumPyPrinter

    return NumPyPrinter({"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
                         "order": "none"})


def _lambdified_outputs(fn, values, n):
    """[array (n, *shape)] of the symbolic outputs of ``fn`` via lambdify (no CSE), every entry of
    a vector, matrix or layout argument passed as its own value."""
    symbols, args = [], []
    for a in fn.inputs:
        for _, symbol, index in a.entries():
            symbols.append(symbol)
            value = np.asarray(values[a.name])
            args.append(value if index is None else value[(...,) + (index if isinstance(index, tuple) else (index,))])
    # a staged function's outputs are written over named intermediate values: evaluate those first,
    # in batches whose symbols are known (lambdify's own CSE inside a batch: they are the base model's jets)
    todo = list(fn.stages)
    while todo:
        batch = [(sym, e) for sym, e in todo if e.free_symbols <= set(symbols)]
        assert batch, "a stage uses an unknown symbol"
        f = sp.lambdify(symbols, [e for _, e in batch], modules="numpy", cse=True, printer=_printer())
        for (sym, _), v in zip(batch, f(*args)):
            symbols.append(sym)
            args.append(np.broadcast_to(np.asarray(v, dtype=float), (n,)))
        todo = [t for t in todo if t not in batch]
    outs = []
    for o in fn.outputs:
        entries = list(o.expr) if isinstance(o.expr, sp.MatrixBase) else [o.expr]
        f = sp.lambdify(symbols, entries, modules="numpy", cse=False, printer=_printer())
        flat = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in f(*args)], axis=-1)
        outs.append(flat.reshape((n,) + expr_shape(o.expr)))
    return outs


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_generated_matches_symbolic(specs, module, function, fresh_stack):
    fn = spec_function(specs, module, function)
    values = sample(module, function, N_POINTS)
    generated = getattr(committed_module(module), function)(**values)
    assert len(generated) == len(fn.outputs)
    for o, got, want in zip(fn.outputs, generated, fresh_stack(_lambdified_outputs, fn, values, N_POINTS)):
        assert_close(as_batch(got, N_POINTS, expr_shape(o.expr)), want, RTOL, f"{function}.{o.name}")
