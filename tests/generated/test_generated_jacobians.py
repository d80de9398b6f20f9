"""The generated kernels: Jacobians vs complex-step derivatives (helpers: generated_support.py, fixtures: conftest.py)."""
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
# 6. Jacobians vs complex step (central differences where complex arithmetic fails)
# ---------------------------------------------------------------------------------------



def _contact_jacobian_cases(tk):
    """(argument, index, output, column of that output) of every Jacobian of tca_kernels.contact_system."""
    return ([("x", k, "residual_D_unknowns", k) for k in range(len(tk.UNKNOWNS))]
            + [("errors", k, "residual_D_errors", k) for k in range(len(committed_module("layouts").AssemblyErrors._fields))]
            + [("pinion_angle", None, "residual_D_pinion_angle", None)])


@pytest.mark.parametrize("flank", FLANKS)
def test_contact_system_jacobians(flank):
    """The composed Eq 38 system (surface jets -> contact_residual): its exact Jacobians are the
    derivatives of its residual, which checks the chain rule inside contact_residual."""
    tk = committed_module("tca_kernels")
    f = functools.partial(tk.contact_system, MODEL, MODEL, flank)
    values = sample_contact(N_POINTS)
    out = f(**values)
    for arg, index, output, column in _contact_jacobian_cases(tk):
        d, rtol = derivative(f, values, arg, "residual", index)
        got = getattr(out, output) if column is None else getattr(out, output)[..., column]
        assert_close(got, d, rtol, f"contact_system {flank}: {output}[..., {column}] (d/d {arg}[{index}])")


def test_the_position_residual_is_the_contact_residuals_position_rows_at_its_packed_mesh_state():
    """position_residual (what the loaded TCA's gap Newton evaluates: Eq 38's position rows at a MeshState, its
    angles' sines and cosines packed once) is rows 0-2 of contact_residual, of its Jacobian in the unknowns and of
    its derivative in the pinion angle, at the same points and errors."""
    cs, layouts = committed_module("contact_system"), committed_module("layouts")
    values = sample("contact_system", "contact_residual", N_POINTS)
    full = cs.contact_residual(**values)
    errors = {n: values["errors"][..., i] for i, n in enumerate(layouts.AssemblyErrors._fields)}
    state = np.stack(layouts.MeshState.pack({**errors, "pinion_angle_rad": values["pinion_angle"],
                                             "gear_angle_rad": values["gear_angle"]}), axis=-1)
    part = cs.position_residual(values["pinion_point"], values["pinion_point_D_lu"], values["gear_point"],
                                values["gear_point_D_lu"], state, values["pair"])
    assert_close(part.residual, full.residual[..., :3], RTOL, "residual rows 0-2")
    assert_close(part.residual_D_unknowns, full.residual_D_unknowns[..., :3, :], RTOL, "d residual / d unknowns")
    assert_close(part.residual_D_pinion_angle, full.residual_D_pinion_angle[..., :3], RTOL, "d residual / d phi'_1")


@pytest.mark.parametrize("module", SURFACE_MODULES)
@pytest.mark.parametrize("flank", FLANKS)
def test_surface_jet_and_second_derivatives(module, flank):
    sm = committed_module(module)
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
    f = committed_module("flank_boundaries").flank_margins
    values = sample("flank_boundaries", "flank_margins", N_POINTS)
    fields = committed_module("layouts").FlankBlank._fields
    toe, heel = (values["blank"][:, fields.index(k)] for k in ("toe_z_mm", "heel_z_mm"))
    assert {False, True} <= set(toe < heel)  # the sampled blanks have the toe on either side of the heel
    out = f(**values)
    for k in range(3):
        d, rtol = derivative(f, values, "point", "margins", k)
        assert_close(out.margins_D_point[..., k], d, rtol, f"margins_D_point[..., {k}]")
    d, rtol = derivative(f, values, "l", "margins")
    assert_close(out.margins_D_l, d, rtol, "margins_D_l")


def test_offset_residual_derivative():
    f = committed_module("design_equations").offset_residual
    values = sample("design_equations", "offset_residual", N_POINTS)
    d, rtol = derivative(f, values, "alpha_nw", "residual")
    assert_close(f(**values).residual_D_alpha_nw, d, rtol, "residual_D_alpha_nw")


def test_complex_step_is_what_the_jacobian_tests_use():
    """The kernels are complex-analytic (numpy trig/sqrt/arc*), so the exact complex step applies:
    to every kernel differentiated above, and through the glue's composition."""
    def case(module, function, *args):
        return getattr(committed_module(module), function), sample(module, function, 3), *args

    contact = functools.partial(committed_module("tca_kernels").contact_system, MODEL, MODEL, "right")
    cases = ([case("design_equations", "offset_residual", "alpha_nw", None, "residual"),
              case("flank_boundaries", "flank_margins", "l", None, "margins")]
             + [case("flank_boundaries", "flank_margins", "point", k, "margins") for k in range(3)]
             + [case(m, f"surface{kind}_{flank}", arg, None, "point")
                for m in SURFACE_MODULES for kind in ("", "_jet") for flank in FLANKS for arg in ("l", "u")]
             + [(contact, sample_contact(3), arg, index, "residual")
                for arg, index, _, _ in _contact_jacobian_cases(committed_module("tca_kernels"))])
    fallback = [f"{getattr(f, '__name__', 'tca_kernels.contact_system')} d/d {arg}[{index}]"
                for f, values, arg, index, output in cases
                if derivative(f, values, arg, output, index)[1] != COMPLEX_STEP_RTOL]
    assert not fallback, f"no complex step (complex input raised, was cast to float or gave real output): {fallback}"
