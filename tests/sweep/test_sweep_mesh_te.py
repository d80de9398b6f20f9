"""The sweep's TE peak-to-peak is the mesh TE envelope's, as tca computes it: with zero ranges
(the nominal pair only) the sweep equals tca's envelope over one mesh cycle with every pair
that touches."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from beveloid import assembly_errors, mesh, sweep, tca
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
    res = sweep.analyze(geom, sweep.Options(flank=flank, samples=2, positions=positions, ranges=ZERO, nominal=nominal))
    ref = tca.reference_contact(geom, flank)
    lo, hi = sweep.engagement_window(geom, flank, ref)
    grid, m, _ = sweep.position_lattice(ref.pinion_angle, lo, hi, positions, geom.pitch_angles[0])
    np.testing.assert_array_equal(res.pinion_angles, grid)
    expect = _tca_cycle_ptp(geom, flank, nominal, m)
    assert expect > 1e-6  # a TE that fluctuates (crowned; misaligned), not round-off
    np.testing.assert_allclose(res.te_peak_to_peak, expect, rtol=1e-7)
    # not one pair followed over its whole engagement (its TE spans far more than the envelope)
    one = tca.mesh_flank(geom, flank, assembly_errors.to_layout(dict(nominal)), positions=41, pairs=1,
                         window_pitches=(hi - lo) / geom.pitch_angles[0])
    assert np.isnan(one.te_peak_to_peak)  # one pair alone never makes a complete envelope (contact ratio > 1)
    assert mesh.peak_to_peak(one.transmission_error) > 3 * expect


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


@pytest.mark.parametrize("case, flags", [("case1", []), ("crowned", []), ("case1", ["--horizontal", "-0.03"]),
                                         ("case1", ["--horizontal", "0.03"])])
def test_zero_range_sweep_equals_tca_at_their_defaults(capsys, tmp_path, case, flags):
    """`beveloid tca` and `beveloid sweep` with zero ranges (the nominal pair only), each at its default
    positions, report the same TE peak-to-peak: the mesh envelope where it is complete.  They sample
    the cycle at different angles, so the envelope's kinks (where the carrying pair changes) fall
    between samples differently: each sampled extreme is within (largest slope of the envelope) x
    (half its step) of the true one, and the two agree within the sum of those bounds.  (On the
    same angles they agree to 1e-7: test_zero_range_sweep_is_the_tca_mesh_envelope.)"""
    import json

    from beveloid import cli

    text = (Path(__file__).resolve().parents[2] / "examples" / "case1.toml").read_text()
    if case == "crowned":  # 10 um of profile and lead crowning on both members
        text = text.replace("face_width_mm = 50.0", "face_width_mm = 50.0\nprofile_crowning_um = 10.0\nlead_crowning_um = 10.0")
        text = text.replace("face_width_mm = 60.0", "face_width_mm = 60.0\nprofile_crowning_um = 10.0\nlead_crowning_um = 10.0")
    spec = tmp_path / "pair.toml"
    spec.write_text(text)
    assert cli.main(["tca", str(spec), "--flank", "right", "--json", *flags]) == 0
    t = json.loads(capsys.readouterr().out)
    zero = [f"--{k}-max" for k in ("dx", "dy", "dz", "vertical", "horizontal")]
    nominal = {"--horizontal": "horizontal_deg"}
    sweep_args = ["sweep", str(spec), "--samples", "1", "--flank", "right", "--json"]
    for flag in zero:
        sweep_args += [flag, "0"]
    if flags:  # the nominal error goes in the file for the sweep (its --*-max are half-widths about it)
        spec.write_text(text.replace("horizontal_deg = 0.0", f"horizontal_deg = {flags[1]}"))
        assert nominal[flags[0]] == "horizontal_deg"
    assert cli.main(sweep_args) == 0
    s = json.loads(capsys.readouterr().out)
    ptp_tca = t["te_peak_to_peak_urad"]["right"]
    ptp_sweep = s["te_peak_to_peak_urad"]["max"]
    assert s["te_peak_to_peak_urad"]["count"] == 1 and ptp_tca is not None
    fd = t["flanks"]["right"]
    positions = len(fd["te_envelope_complete"])
    phi = np.array(fd["pinion_angle_rad"][:positions])
    te = np.array([np.nan if v is None else v for v in fd["transmission_error_rad"]]).reshape(-1, positions)
    from beveloid.pair import Pair

    env, _ = mesh.envelope(te, tca.first_touch_sign(Pair.from_spec(spec).geometry, "right"))
    complete = np.array(fd["te_envelope_complete"])
    both = complete[1:] & complete[:-1]
    slope = np.nanmax(np.abs(np.diff(env) / np.diff(phi))[both])  # rad / rad, the steepest carried TE
    step_tca = phi[1] - phi[0]
    window = s["pinion_angle_window_rad"]
    step_sweep = (window[1] - window[0]) / (s["positions"] - 1)
    # a kink lies within half a step of a sample: each sampled minimum is within slope x step / 2
    bound = slope * (step_tca + step_sweep) / 2 * 1e6 + 1e-4  # urad (+ round-off of a TE that is ~0)
    assert abs(ptp_tca - ptp_sweep) <= bound, (ptp_tca, ptp_sweep, bound)
