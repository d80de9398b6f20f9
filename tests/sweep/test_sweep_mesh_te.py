"""The sweep's TE peak-to-peak is the mesh TE envelope's, as tca computes it: with zero ranges
(the nominal pair only) the sweep equals tca's envelope over one mesh cycle with every pair
that touches."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid import assembly_errors, sweep, tca
from beveloid.studies import crowning as crowning_study

ZERO = {k: 0.0 for k in sweep.DEFAULT_RANGES}


def _tca_cycle_ptp(geom, flank, nominal, per_pitch):
    """tca's mesh TE envelope over one pinion pitch about the reference on the sweep's lattice
    (p1 / per_pitch, even), with 5 pairs: every pair that touches at each angle (case 1: contact
    ratio < 2)."""
    assert per_pitch % 2 == 0  # the window's angles ref + (i - m/2) p1/m lie on the lattice
    e = assembly_errors.to_layout(dict(nominal))
    fr = tca.mesh_flank(geom, flank, e, positions=per_pitch + 1, pairs=5, window_pitches=1)
    return fr.te_peak_to_peak


@pytest.mark.parametrize("case, nominal, positions", [("crowned", {}, 20), ("horizontal", {"horizontal_deg": -0.03}, 22)])
def test_zero_range_sweep_is_the_tca_mesh_envelope(pair1, case, nominal, positions):
    geom = crowning_study.crowned_geometry("case1", 10.0) if case == "crowned" else pair1.geometry
    flank = "right"
    res = sweep.sweep(geom, flank, samples=2, positions=positions, ranges=ZERO, nominal=nominal)
    ref = tca.reference_contact(geom, flank)
    lo, hi = sweep.engagement_window(geom, flank, ref)
    grid, m, _ = sweep.position_lattice(ref.pinion_angle, lo, hi, positions, geom.pitch_angles[0])
    np.testing.assert_array_equal(res.pinion_angles, grid)
    expect = _tca_cycle_ptp(geom, flank, nominal, m)
    assert expect > 1e-6  # a TE that fluctuates (crowned; misaligned), not round-off
    np.testing.assert_allclose(res.te_peak_to_peak, expect, rtol=1e-7)
    # not one pair followed over its whole engagement (its TE spans far more than the envelope)
    te_pair0 = tca.mesh_flank(geom, flank, assembly_errors.to_layout(dict(nominal)), positions=41, pairs=1,
                              window_pitches=(hi - lo) / geom.pitch_angles[0]).te_peak_to_peak
    assert te_pair0 > 3 * expect


def test_lattice_folds_whole_pitches(pair1):
    geom = pair1.geometry
    ref = tca.reference_contact(geom, "left")
    lo, hi = sweep.engagement_window(geom, "left", ref)
    p1 = geom.pitch_angles[0]
    for n in (2, 5, 50):
        grid, m, first = sweep.position_lattice(ref.pinion_angle, lo, hi, n, p1)
        steps = (grid - ref.pinion_angle) / (p1 / m)
        np.testing.assert_allclose(steps, first + np.arange(n), atol=1e-9)
        assert lo < grid[0] and grid[-1] < hi
        assert n >= m  # every angle of the cycle is sampled


def test_mesh_te_peak_to_peak_takes_the_binding_pair():
    # pair 0's TE on 6 lattice points, 3 per pitch: angles 0, 3 and 1, 4 and 2, 5 are one cycle angle
    te = np.array([[0.0, 5.0, 1.0, 2.0, 4.0, np.nan]])
    np.testing.assert_allclose(sweep.mesh_te_peak_to_peak(te, 3, 0, +1), [5.0 - 1.0])
    np.testing.assert_allclose(sweep.mesh_te_peak_to_peak(te, 3, 0, -1), [4.0 - 0.0])
    assert np.isnan(sweep.mesh_te_peak_to_peak(np.full((1, 6), np.nan), 3, 0, +1)[0])
