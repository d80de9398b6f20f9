"""The crowned tooth-surface model (issue 10): the derivation, the generated kernels, the TOML
keys and the TCA of crowned pairs.

* derivation: the displaced rack moves exactly delta along -n_c; its unit normal is the cross
  product of its tangents; Eq 7, solved once for a generic cutter point and normal, is the
  envelope condition of the displaced rack too; the explicit surface equals the
  abstract-then-substituted one the generator differentiates;
* kernels: zero crowning is the involute model (1e-12); the generated flank deviates from the
  involute one by -delta along the normal at the same (l, u), to first order (the remainder
  is quadratic in the crowning);
* spec: the keys select the model, tooth_surface = "crowned" names it, members may differ,
  bad values are one-line errors naming the key;
* TCA: the aligned crowned pair has a TE that is zero at the pitch point and negative about
  it (material removed), Newton takes iterations, each of the five errors changes the TE, and
  the functional backlash is the minimum over the mesh cycle.
"""
from __future__ import annotations

import copy
import functools
import math
import tomllib

import mpmath
import numpy as np
import pytest
import sympy as sp

from beveloid import tca
from beveloid.derivations import crowned_flank as cf
from beveloid.derivations import eq04_07_tooth_surface as involute
from beveloid.derivations.eq01_03_rack_cutter import LEFT, RIGHT, rack_normal, rack_point
from beveloid.derivations.symbols import a, alpha_n, b, beta, gamma, l, m_n, phi, r, s, u
from beveloid.design import design
from beveloid.generated import layouts, surface_crowned, surface_involute
from beveloid.solver import Solver, backends
from beveloid.spec import SpecError, example_text, spec_from_dict
from beveloid.status import Status

SIGMAS = (LEFT, RIGHT)
FLANKS = ("left", "right")


def _domain(rng):
    """A 50-digit point of the physical domain of the rack and its crowning."""
    def uni(lo, hi):
        return mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * mpmath.mpf(rng.random())
    return {l: uni(0, 15), u: uni(-30, 30), alpha_n: uni(0.25, 0.45), beta: uni(-0.6, 0.6), gamma: uni(-0.12, 0.12),
            a: uni(2.5, 10), b: uni(1.5, 6.5), s: uni(-3, 3), r: uni(15, 400), m_n: uni(2, 8), cf.W: uni(10, 120),
            cf.C_alpha: uni(0, 200), cf.C_beta: uni(0, 200)}


def _max_abs(exprs, n=12, seed=5):
    """max |expr| over n random 50-digit domain points."""
    import random
    rng = random.Random(seed)
    exprs = list(exprs)
    syms = sorted(set().union(*[e.free_symbols for e in exprs]), key=str)
    f = sp.lambdify(syms, exprs, modules="mpmath")
    worst = mpmath.mpf(0)
    with mpmath.workdps(50):
        for _ in range(n):
            point = _domain(rng)
            worst = max(worst, max(abs(v) for v in f(*[point[k] for k in syms])))
    return float(worst)


# --------------------------------------------------------------------------------------------
# the derivation
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("sigma", SIGMAS)
def test_rack_is_displaced_by_exactly_delta_along_its_normal(sigma):
    shift = cf.displaced_rack_point(sigma) - rack_point(sigma)
    delta = cf.crowning()
    n = rack_normal(sigma)
    assert sp.expand(shift + delta * n) == sp.zeros(3, 1)  # -delta n_c: toward the tooth, nothing else
    assert _max_abs([n.dot(n) - 1, shift.dot(n) + delta]) < 1e-45  # n_c is a unit vector: exactly delta


def test_crowning_is_the_issue_parabola():
    lp = a / sp.cos(alpha_n)
    want = (cf.C_alpha * ((l - lp) / m_n) ** 2 + cf.C_beta * (u / (cf.W / 2)) ** 2) / 1000
    assert sp.expand(cf.crowning() - want) == 0
    # l_p is where the straight edge crosses the rack's pitch line (the edge's depth x_n - s is 0)
    x_n = (rack_point(RIGHT).subs({gamma: 0, beta: 0})[0] - s).subs(l, cf.pitch_line_l())
    assert sp.simplify(x_n) == 0


@pytest.mark.parametrize("sigma", SIGMAS)
def test_displaced_rack_normal_is_the_unit_cross_product(sigma):
    p = cf.displaced_rack_point(sigma)
    cross = sigma * p.diff(l).cross(p.diff(u))
    unnormalised = cf.displaced_rack_normal(sigma, unit=False)
    assert _max_abs(list(cross - unnormalised)) < 1e-45
    n = cf.displaced_rack_normal(sigma)
    assert _max_abs([n.dot(n) - 1, (n - unnormalised / unnormalised.norm()).norm()]) < 1e-45
    assert _max_abs([n.dot(p.diff(l)), n.dot(p.diff(u))]) < 1e-40


@pytest.mark.parametrize("sigma", SIGMAS)
def test_eq7_is_the_envelope_condition_of_the_displaced_rack(sigma):
    """n . dR/dphi = 0 on the family of displaced racks at phi(l, u): the generic solution of
    eq04_07_tooth_surface.meshing_equation applies unchanged."""
    pc = cf.displaced_rack_point(sigma)
    nc = cf.displaced_rack_normal(sigma)
    family = involute.generated_family(pc)
    condition = (involute.M_ic[:3, :3] * nc).dot(family.diff(phi))
    point, normal, phi_lu = cf.tooth_surface(sigma)
    assert _max_abs([condition.subs(phi, phi_lu)]) < 1e-40
    # the surface is that family at phi(l, u), the normal the turned displaced-rack normal
    assert _max_abs(list(point - family.subs(phi, phi_lu))) < 1e-40
    assert _max_abs(list(normal - (involute.M_ic[:3, :3] * nc).subs(phi, phi_lu))) < 1e-45


@pytest.mark.parametrize("sigma", SIGMAS)
def test_abstract_and_explicit_surfaces_and_derivatives_agree(sigma):
    """What the generator differentiates (abstract phi, w, substituted after) is the explicit model."""
    p, n, ph, late = cf.tooth_surface_late(sigma)
    P, N, PH = cf.tooth_surface(sigma)
    diffs = list(late(p) - P) + list(late(n) - N) + [late(ph) - PH]
    # first derivatives (the second ones: complex step against the jets in test_generated.py)
    diffs += list(late(p.diff(l)) - P.diff(l)) + list(late(n.diff(u)) - N.diff(u))
    assert _max_abs(diffs, n=6) < 1e-35


def test_zero_crowning_is_the_involute_model_symbolically():
    for sigma in SIGMAS:
        P, N, PH = cf.tooth_surface(sigma)
        p0, n0, ph0 = involute.tooth_surface(sigma)
        zero = {cf.C_alpha: 0, cf.C_beta: 0}
        assert _max_abs(list(P.subs(zero) - p0) + list(N.subs(zero) - n0) + [PH.subs(zero) - ph0]) < 1e-40


# --------------------------------------------------------------------------------------------
# the generated kernels
# --------------------------------------------------------------------------------------------
def _params(rng, n, profile_um, lead_um):
    common = dict(normal_pressure_angle=rng.uniform(14, 25, n) * math.pi / 180,
                  helix_angle=rng.uniform(-40, 40, n) * math.pi / 180,
                  cone_angle=rng.choice([-1, 1], n) * rng.uniform(0.5, 8, n) * math.pi / 180,
                  cutter_addendum_mm=rng.uniform(2.5, 10, n), half_thickness_mm=rng.uniform(1.5, 6.5, n),
                  rack_shift_mm=rng.uniform(-3, 3, n), pitch_radius_mm=rng.uniform(15, 400, n))
    inv = np.stack(layouts.InvoluteSurfaceParams.pack(common), axis=-1)
    cro = np.stack(layouts.CrownedSurfaceParams.pack(dict(
        **common, profile_crowning_um=np.broadcast_to(profile_um, n), lead_crowning_um=np.broadcast_to(lead_um, n),
        face_width_mm=rng.uniform(10, 120, n), normal_module_mm=rng.uniform(2, 8, n))), axis=-1)
    return inv, cro


@pytest.mark.parametrize("flank", FLANKS)
def test_zero_crowning_kernels_equal_the_involute_kernels(flank):
    rng = np.random.default_rng(10)
    n = 200
    inv, cro = _params(rng, n, 0.0, 0.0)
    lu = rng.uniform(0, 15, n), rng.uniform(-40, 40, n)
    want = getattr(surface_involute, f"surface_jet_{flank}")(*lu, inv)
    got = getattr(surface_crowned, f"surface_jet_{flank}")(*lu, cro)
    assert np.abs(got.point - want.point).max() <= 1e-12
    assert np.abs(got.normal - want.normal).max() <= 1e-12
    assert np.abs(got.point_D_lu - want.point_D_lu).max() <= 1e-12
    assert np.abs(got.normal_D_lu - want.normal_D_lu).max() <= 1e-12
    d2 = getattr(surface_crowned, f"surface_second_derivatives_{flank}")(*lu, cro).point_D2_lu
    assert np.abs(d2 - getattr(surface_involute, f"surface_second_derivatives_{flank}")(*lu, inv).point_D2_lu).max() \
        <= 1e-12


def _delta_mm(params, l_mm, u_mm):
    f = layouts.CrownedSurfaceParams(*np.moveaxis(params, -1, 0))
    lp = f.cutter_addendum_mm / np.cos(f.normal_pressure_angle)
    return 1e-3 * (f.profile_crowning_um * ((l_mm - lp) / f.normal_module_mm) ** 2
                   + f.lead_crowning_um * (u_mm / (f.face_width_mm / 2)) ** 2)


@pytest.mark.parametrize("flank", FLANKS)
def test_generated_flank_deviates_by_delta_along_the_normal(flank):
    """(R_crowned - R_involute) . n = -delta + O(C^2) at the same (l, u): halving the crowning
    quarters the remainder, which is small against delta for small crowning.  (At tens of um
    the remainder can reach a third of delta on wide, strongly helical members of small
    radius: the crowned rack's tilted normal moves the point of tangency along the flank.)"""
    rng = np.random.default_rng(11)
    n = 100
    ca, cb = rng.uniform(5, 50, n), rng.uniform(5, 50, n)
    inv, cro = _params(rng, n, ca, cb)
    f = layouts.CrownedSurfaceParams(*cro.T)
    # the working depth of the rack: l_p +- m_n, |u| <= W/2
    l_mm = f.cutter_addendum_mm / np.cos(f.normal_pressure_angle) + f.normal_module_mm * rng.uniform(-1, 1, n)
    u_mm = f.face_width_mm / 2 * rng.uniform(-1, 1, n)
    plain = getattr(surface_involute, f"surface_{flank}")(l_mm, u_mm, inv)
    remainders = []
    for scale in (0.02, 0.01):  # 0.1 .. 1 um
        c = cro.copy()
        fields = layouts.CrownedSurfaceParams._fields
        c[:, fields.index("profile_crowning_um")] *= scale
        c[:, fields.index("lead_crowning_um")] *= scale
        crowned = getattr(surface_crowned, f"surface_{flank}")(l_mm, u_mm, c)
        along = np.einsum("ij,ij->i", crowned.point - plain.point, plain.normal)
        delta = _delta_mm(c, l_mm, u_mm)
        assert np.all(delta > 0)
        remainders.append(along + delta)
        assert np.all(np.abs(along + delta) <= 0.02 * delta)  # first order: -delta along the normal
    ratio = remainders[0] / remainders[1]
    big = np.abs(remainders[1]) > 1e-10  # well above the round-off (1e-12 mm) of 400 mm coordinates
    assert big.sum() > n // 2
    assert np.allclose(ratio[big], 4.0, rtol=0.05)  # the remainder is quadratic in the crowning


# --------------------------------------------------------------------------------------------
# the TOML keys
# --------------------------------------------------------------------------------------------
def _case1(**members):
    data = tomllib.loads(example_text("case1"))
    data = copy.deepcopy(data)
    for name, keys in members.items():
        data[name].update(keys)
    return spec_from_dict(data)


def test_keys_select_the_crowned_model_per_member():
    spec = _case1(pinion={"lead_crowning_um": 12.5})
    assert spec.pinion.tooth_surface == "crowned" and spec.gear.tooth_surface == "involute"
    assert dict(spec.pinion.surface_options) == {"lead_crowning_um": 12.5, "profile_crowning_um": 0.0}
    spec = _case1(pinion={"profile_crowning_um": 0.0}, gear={"profile_crowning_um": 7.0, "lead_crowning_um": 3.0})
    assert spec.pinion.tooth_surface == "involute" and spec.gear.tooth_surface == "crowned"
    assert dict(spec.gear.surface_options) == {"lead_crowning_um": 3.0, "profile_crowning_um": 7.0}
    spec = _case1(gear={"tooth_surface": "crowned"})  # explicitly, with zero crowning
    assert spec.gear.tooth_surface == "crowned" and dict(spec.gear.surface_options) == {
        "lead_crowning_um": 0.0, "profile_crowning_um": 0.0}


@pytest.mark.parametrize("key, value, fragment", [
    ("profile_crowning_um", -1.0, "from 0 to 200 (um)"), ("lead_crowning_um", 1e4, "from 0 to 200 (um)"),
    ("lead_crowning_um", float("nan"), "lead_crowning_um")])
def test_bad_crowning_is_a_one_line_error(key, value, fragment):
    with pytest.raises(SpecError) as err:
        _case1(gear={key: value})
    msg = str(err.value)
    assert "\n" not in msg and f"gear.{key}" in msg and fragment in msg


def test_crowning_keys_with_another_model_are_refused():
    with pytest.raises(SpecError, match="tooth_surface"):
        _case1(gear={"tooth_surface": "involute", "lead_crowning_um": 5.0})


def test_runtime_fills_face_width_and_module_from_the_design():
    geom = tca.PairGeometry.from_design(design(_case1(pinion={"profile_crowning_um": 4.0})))
    f = layouts.CrownedSurfaceParams(*geom.surface_params("pinion")[:len(layouts.CrownedSurfaceParams._fields)])
    assert f.face_width_mm == geom.pinion.face_width_mm == 50.0 and f.normal_module_mm == 6.0
    assert (f.profile_crowning_um, f.lead_crowning_um) == (4.0, 0.0)


# --------------------------------------------------------------------------------------------
# TCA of crowned pairs (numpy backend unless said: the same core as the compiled one)
# --------------------------------------------------------------------------------------------
@functools.cache
def _geom(c_um=20.0):
    keys = {"profile_crowning_um": c_um, "lead_crowning_um": c_um}
    return tca.PairGeometry.from_design(design(_case1(pinion=keys, gear=keys)))


def test_aligned_crowned_pair_has_a_parabola_per_tooth_pair():
    geom = _geom()
    fr = tca.mesh_flank(geom, "right", positions=41, pairs=3, solver=Solver("numpy"))
    te = fr.transmission_error.reshape(3, 41)
    mid = te[1]
    # surface contact only: at the ends of its engagement a pair bears with an edge (issue 12)
    ok = np.isfinite(mid) & (np.array(fr.status).reshape(3, 41)[1] == "ok")
    assert ok.sum() > 20
    # zero at the pitch point (the reference), negative about it: crowning removes material
    assert abs(mid[20]) < 1e-9
    # the gear rests against the pair that constrains it most; material removed away from P
    # lets it turn toward closing the gap: TE on the closing side only (sign as tca.mesh_flank)
    closing = -tca.gap_sign(geom, "right", tca.reference_contact(geom, "right")) * mid
    assert np.nanmin(closing) >= -1e-9 and np.nanmax(closing) > 1e-6
    # a parabola in the pinion angle about the reference (the curvature is the same on both sides)
    phi = fr.pinion_angle[:41] - fr.pinion_angle[20]
    coef = np.polyfit(phi[ok], mid[ok], 2)
    fit = np.polyval(coef, phi[ok])
    assert np.abs(fit - mid[ok]).max() < 0.1 * np.ptp(mid[ok])
    # Newton iterated at every point but the reference angle itself, where the path starts (the
    # involute pair's predictor lands on the contact at once: 0 iterations everywhere)
    its = fr.iterations[np.array(fr.status) == "ok"]
    assert np.count_nonzero(its == 0) <= 1 and its.mean() >= 1
    assert fr.te_peak_to_peak > 1e-6


@pytest.mark.parametrize("k", range(5))
def test_each_error_changes_the_crowned_te(k):
    geom = _geom()
    errors = np.zeros(5)
    errors[k] = (0.05, 0.05, 0.05, 0.01 * math.pi / 180, 0.01 * math.pi / 180)[k]
    base = tca.mesh_flank(geom, "right", positions=9, pairs=1, solver=Solver("numpy")).transmission_error
    moved = tca.mesh_flank(geom, "right", errors, positions=9, pairs=1, solver=Solver("numpy")).transmission_error
    both = np.isfinite(base) & np.isfinite(moved)
    assert both.sum() >= 5
    assert np.abs(moved[both] - base[both]).max() > 1e-7


@pytest.mark.skipif(not backends.AVAILABLE, reason="the compiled backend needs numba")
@pytest.mark.parametrize("flank", FLANKS)
def test_backends_agree_on_a_crowned_pair(flank):
    """The crowned kernels through both backends: identical statuses, the same unknowns (1e-9),
    aligned and misaligned, surface and edge contacts over three pinion pitches."""
    geom = _geom()
    ref = tca.reference_contact(geom, flank)
    E = np.array([np.zeros(5), [0.3, -0.2, 0.4, 0.1 * math.pi / 180, -0.02 * math.pi / 180]])
    grid = ref.pinion_angle + np.linspace(-1.5, 1.5, 13) * geom.pitch_angles[0]
    a = tca.solve_grid(geom, flank, E, grid, solver=Solver("numpy"))
    b = tca.solve_grid(geom, flank, E, grid, solver=Solver("compiled"))
    np.testing.assert_array_equal(a.status, b.status)
    np.testing.assert_array_equal(a.active, b.active)
    assert (a.status == Status.OK).any() and (a.status == Status.EDGE).any() and (a.iterations > 0).any()
    solved = a.status != Status.FAILED
    np.testing.assert_allclose(a.x[solved], b.x[solved], rtol=0, atol=1e-9)


def test_functional_backlash_is_the_minimum_over_the_mesh_cycle():
    """The default backend (compiled when numba is there): a property of the backlash, not of a
    backend (the test above holds the two together on crowned pairs); on the interpreted one
    the ~10 two-flank solves of the crowned pair take ~25 s."""
    geom = _geom()
    bl = tca.backlash(geom)
    assert bl.status == "ok" and bl.um is not None
    # the play at every pinion angle of the cycle is at least the functional backlash, and the
    # reference-angle play is one of them
    assert bl.um <= bl.at_reference_um + 1e-9
    assert bl.um <= bl.max_um
    assert bl.um > 0  # crowning adds play to the backlash-free design (Eq 27)
    flat = tca.backlash(tca.PairGeometry.from_design(design(_case1())))
    assert abs(flat.um) < 1e-6 and abs(flat.max_um - flat.um) < 1e-6  # involute: constant, zero


def test_aligned_te_grows_in_proportion_to_small_crowning():
    """First order: the aligned TE of a crowned pair is proportional to the crowning (the
    crowning study's search for the paper's 7.5 / 14.3 urad relies on it to converge fast)."""
    from beveloid.studies import crowning as crowning_study

    ptp = [tca.mesh_flank(crowning_study.crowned_geometry("case1", c), "right", positions=31,
                          solver=Solver("numpy")).te_peak_to_peak for c in (2.0, 4.0)]
    assert ptp[0] > 1e-6
    assert ptp[1] / ptp[0] == pytest.approx(2.0, rel=0.03)


# --------------------------------------------------------------------------------------------
# the commands on a crowned spec
# --------------------------------------------------------------------------------------------
def _crowned_toml(tmp_path, extra="profile_crowning_um = 15.0\nlead_crowning_um = 5.0\n"):
    import re

    text = re.sub(r"^\[(pinion|gear)\][^\n]*\n", lambda m: m.group(0) + extra, example_text("case1"), flags=re.M)
    assert text.count(extra) == 2
    path = tmp_path / "crowned.toml"
    path.write_text(text)
    return path


def test_tca_and_sweep_commands_on_a_crowned_pair(tmp_path, capsys):
    import json

    from beveloid import cli

    path = _crowned_toml(tmp_path)
    assert cli.main(["tca", str(path), "--positions", "15", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for flank in FLANKS:
        assert data["te_peak_to_peak_urad"][flank] > 1.0  # crowned: TE no longer zero
        assert data["newton_iterations_mean"][flank] >= 1.0
        assert len(data["flanks"][flank]["newton_iterations"]) == 45
    assert data["backlash_status"] == "ok"
    assert 0 < data["backlash_um"] <= data["backlash_at_reference_um"] <= data["backlash_max_um"]
    assert cli.main(["tca", str(path), "--positions", "15"]) == 0
    text = capsys.readouterr().out
    assert "Newton its (mean)" in text and "smallest play over a mesh cycle" in text
    assert cli.main(["sweep", str(path), "--samples", "20", "--positions", "10", "--json"]) == 0
    sw = json.loads(capsys.readouterr().out)
    assert sw["newton_iterations_mean"] >= 1.0 and sw["te_peak_to_peak_urad"]["count"] > 0
    assert cli.main(["sweep", str(path), "--samples", "20", "--positions", "10"]) == 0
    assert "Newton iterations per point" in capsys.readouterr().out


def test_bad_crowning_in_a_file_exits_2_with_one_line(tmp_path, capsys):
    from beveloid import cli

    path = _crowned_toml(tmp_path, "lead_crowning_um = -3\n")
    assert cli.main(["tca", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "lead_crowning_um = -3" in err and "Traceback" not in err


def test_statuses_do_not_flip_under_round_off_perturbations():
    """Crowned case 1 (10 um on both members): the offset moved by +-1e-12 mm (alpha_nw by ~1e-13 rad)
    leaves every point's status as it was and the TE peak-to-peak to 1e-9 (no point sits on a
    decision boundary of the solver without the one tolerance deciding it)."""
    import tomllib
    from pathlib import Path

    from beveloid import tca
    from beveloid.pair import Pair

    d = tomllib.loads((Path(__file__).resolve().parents[2] / "examples" / "case1.toml").read_text())
    for member in ("pinion", "gear"):
        d[member]["profile_crowning_um"] = d[member]["lead_crowning_um"] = 10.0
    runs = []
    for eps in (0.0, 1e-12, -1e-12):
        spec = {k: dict(v) for k, v in d.items()}
        spec["pair"]["offset_mm"] += eps
        runs.append(tca.analyze(Pair.from_spec(spec), tca.Options(positions=120, approach_mm=None), solver=tca.Solver()))
    for flank in ("left", "right"):
        ref = runs[0].flanks[flank]
        for other in runs[1:]:
            fr = other.flanks[flank]
            assert fr.status == ref.status
            assert fr.te_peak_to_peak == pytest.approx(ref.te_peak_to_peak, rel=1e-9)
