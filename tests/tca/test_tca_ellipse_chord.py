"""The contact ellipses' one chord search (beveloid/solver/chord.py) gives the same chords on both
backends (interpreted and compiled), on the involute case and on crowned and relieved flanks."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from beveloid import contact_ellipse, tca
from beveloid.solver import Solver

MICRO = dict(profile_crowning_um=10.0, lead_crowning_um=15.0, tip_relief_um=20.0, tip_relief_height_mm=1.5,
             tip_relief_shape="linear", end_relief_um=10.0, end_relief_length_mm=5.0, end_relief_shape="parabolic",
             lead_slope_um=0.0)


def _micro(geom):
    o = tuple(sorted(MICRO.items()))
    return dataclasses.replace(
        geom, pinion=dataclasses.replace(geom.pinion, tooth_surface="micro_geometry", surface_options=o),
        gear=dataclasses.replace(geom.gear, tooth_surface="micro_geometry", surface_options=o))


@pytest.mark.parametrize("flank", tca.FLANKS)
# the numpy backend's chord search is ~4x slower: the micro-geometry flank in the slow tier
@pytest.mark.parametrize("model", ["involute", pytest.param("micro_geometry", marks=pytest.mark.slow)])
def test_both_backends_give_the_same_chords(geom1, compiled_solver, flank, model, monkeypatch):
    geom = geom1 if model == "involute" else _micro(geom1)
    errors = np.array([0.1, -0.05, 0.05, 0.0, 0.0005])
    fr = tca.mesh_flank(geom, flank, errors, positions=12, pairs=3, solver=Solver("compiled"))
    seen = []
    real = contact_ellipse.chords
    monkeypatch.setattr(contact_ellipse, "chords", lambda *a: seen.append(a[-1].backend) or real(*a))
    ref = contact_ellipse.flank_ellipses(geom, fr, errors, solver=Solver("numpy"))
    got = contact_ellipse.flank_ellipses(geom, fr, errors, solver=Solver("compiled"))
    assert seen == ["numpy"] * 2 + ["compiled"] * 2  # each backend searched both directions itself
    assert got.status == ref.status
    chords = np.isfinite(ref.truncated_mm)
    assert chords.sum() >= 10, "too few chords to compare"
    np.testing.assert_array_equal(np.isfinite(got.truncated_mm), chords)
    np.testing.assert_allclose(got.truncated_mm[chords], ref.truncated_mm[chords], rtol=0, atol=1e-9)
    # some chords end on a flank boundary (shorter than the cap), so the bisection is exercised
    a = np.where(np.isfinite(ref.semi_axes_mm[:, 0]), ref.semi_axes_mm[:, 0], np.inf)
    assert (ref.truncated_mm[chords] < np.broadcast_to(a[:, None], ref.truncated_mm.shape)[chords] - 1e-6).any()
