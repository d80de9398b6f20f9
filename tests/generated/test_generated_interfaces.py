"""The generated kernels: documented shapes, batches and broadcasting (helpers: generated_support.py, fixtures: conftest.py)."""
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
# 5. interfaces, batches and broadcasting
# ---------------------------------------------------------------------------------------

BATCH = 7


@pytest.mark.parametrize("module, function", FUNCTIONS, ids=FUNCTION_IDS)
def test_outputs_have_documented_shapes(specs, module, function):
    mod = committed_module(module)
    f = getattr(mod, function)
    fn = spec_function(specs, module, function)
    cls, inputs, outputs = documented(f)
    assert outputs == {o.name: expr_shape(o.expr) for o in fn.outputs}
    assert list(inputs.items()) == [(a.name, a.shape) for a in fn.inputs] and list(inputs) == args_of(module, function)
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
    f = getattr(committed_module(module), function)
    values = sample(module, function, BATCH)
    batch = f(**values)
    singles = [f(**{k: at(v, i) for k, v in values.items()}) for i in range(BATCH)]
    for j, name in enumerate(documented_shapes(f)):
        stacked = np.stack([np.asarray(s[j], dtype=float) for s in singles])
        # array and scalar numpy math may differ in the last bit (SIMD loops)
        assert_close(batch[j], stacked, 1e-14, f"{function}.{name}")


def test_design_kernels_take_integer_tooth_numbers():
    values = sample("design_equations", "direct_design", BATCH)
    as_int = dict(values, pinion_teeth=values["pinion_teeth"].astype(int),
                  gear_teeth=values["gear_teeth"].astype(int))
    dm = committed_module("design_equations")
    for a, b in zip(dm.direct_design(**as_int), dm.direct_design(**values)):
        assert_close(as_batch(a, BATCH, ()), as_batch(b, BATCH, ()), 0.0, "direct_design with int teeth")


def _broadcast_failures(module, function):
    """Arguments that, alone given as a batch (others one point), do not batch every output."""
    f = getattr(committed_module(module), function)
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
    f = getattr(committed_module(module), function)
    shapes = documented_shapes(f)
    values = sample(module, function, BATCH)
    keep_scalar = list(values)[1::2]
    mixed = {k: (v[0] if k in keep_scalar else v) for k, v in values.items()}
    full = {k: (np.broadcast_to(v[0], v.shape) if k in keep_scalar else v) for k, v in values.items()}
    for name, a, b in zip(shapes, f(**mixed), f(**full)):
        assert_close(as_batch(a, BATCH, shapes[name]), b, 1e-14, f"{function}.{name}")


def test_positions_times_misalignments_broadcast():
    """Points (7,) x assembly-error sets (4, 1, 5) -> (4, 7, ...) in one call of the composed
    contact system, equal to row-by-row calls."""
    tk = committed_module("tca_kernels")
    shapes = documented_shapes(committed_module("contact_system").contact_residual)
    values = sample_contact(BATCH)
    errors = values["errors"]
    grid = tk.contact_system(MODEL, MODEL, "left", **dict(values, errors=errors[:4, None, :]))
    for name in shapes:
        assert getattr(grid, name).shape == (4, BATCH) + shapes[name], name
    for i in range(4):
        row = tk.contact_system(MODEL, MODEL, "left", **dict(values, errors=np.broadcast_to(errors[i], errors.shape)))
        for name, a, b in zip(grid._fields, grid, row):
            assert_close(np.broadcast_to(a, (4,) + b.shape)[i], b, 1e-14, f"{name}, error set {i}")
