"""TCA checks: contact found and verified independently, statuses at the flank edges,
sensitivities against finite differences of the solver, two-flank backlash against Eq 27."""
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from beveloid import tca
from beveloid.solver import Solver, backends
from beveloid.solver.records import settings
from beveloid.status import Status
from beveloid.design import design
from beveloid.pair import Pair

ROOT = Path(__file__).resolve().parents[2]
DEG = math.pi / 180


def _homotopy(geom, flank, e, backend="numpy"):
    """The contact at the reference pinion angle for the errors e: (x (1, 5), converged (1,),
    surface contact (1,))."""
    ref = tca.reference_contact(geom, flank)
    sol = tca.solve_grid(geom, flank, np.asarray(e)[None], [ref.pinion_angle], solver=Solver(backend))
    return sol.x[:, 0], sol.status[:, 0] != Status.FAILED, sol.status[:, 0] == Status.OK


@pytest.fixture(scope="module", params=["case1", "case2"])
def geom(request):
    return Pair.from_spec(ROOT / "examples" / f"{request.param}.toml").geometry


# ---- an independent transcription of the printed placement (Eqs 30, 33, 34) -----------------
def _printed_Mf1(phi1, z1):
    c, s = math.cos(phi1), math.sin(phi1)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, z1], [0, 0, 0, 1.0]])


def _printed_Mf2(phi2, e, E, delta, z2):
    dx, dy, dz, gv, gh = e
    cd, sd = math.cos(delta), math.sin(delta)
    Mfq = np.array([[1, 0, 0, E], [0, cd, sd, sd * z2], [0, -sd, cd, cd * z2], [0, 0, 0, 1.0]])
    cv, sv, ch, sh = math.cos(gv), math.sin(gv), math.cos(gh), math.sin(gh)
    Mq = np.array([[cv, 0, sv, dx], [-sv * sh, ch, sh * cv, dy], [-sv * ch, -sh, ch * cv, dz], [0, 0, 0, 1.0]])
    c, s = math.cos(phi2), math.sin(phi2)
    Rz = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    return Mfq @ Mq @ Rz


def _contact_in_frame(geom, flank, x, phi1, e):
    p1, n1, _ = tca.surface(geom, "pinion", flank, x[0], x[1])
    p2, n2, _ = tca.surface(geom, "gear", flank, x[2], x[3])
    M1 = _printed_Mf1(phi1, geom.pinion.axial_placement_mm)
    M2 = _printed_Mf2(x[4], e, geom.offset_mm, geom.shaft_angle, geom.gear.axial_placement_mm)
    return (M1[:3, :3] @ p1 + M1[:3, 3], M1[:3, :3] @ n1, M2[:3, :3] @ p2 + M2[:3, 3], M2[:3, :3] @ n2)


def _check_contacts(geom, flank, res_flank, e, p1_pitch):
    """Every point reported ok/edge is a true contact (printed transforms) inside both flanks."""
    fr = res_flank
    n_ok = 0
    for i, st in enumerate(fr.status):
        if st not in ("ok", "edge"):
            assert np.isnan(fr.gear_angle[i]) and np.all(np.isnan(fr.pinion_contact[i]))
            continue
        n_ok += 1
        k = fr.tooth_pair[i]
        P1 = fr.pinion_contact[i]
        c, s = math.cos(-k * p1_pitch), math.sin(-k * p1_pitch)
        P1_0 = np.array([c * P1[0] - s * P1[1], s * P1[0] + c * P1[1], P1[2]])
        # the pinion contact lies on the flank (edge points: on a boundary of it)
        tol = 1e-9
        assert abs(P1_0[2]) <= geom.pinion.face_width_mm / 2 + tol
        r1 = math.hypot(P1_0[0], P1_0[1])
        assert r1 <= geom.pinion.tip_radius(P1_0[2]) + tol
    return n_ok


def test_aligned_contact_at_pitch_point_both_flanks(geom):
    for flank in tca.FLANKS:
        ref = tca.reference_contact(geom, flank)
        rf1, nf1, rf2, nf2 = _contact_in_frame(geom, flank, ref.x, ref.pinion_angle, np.zeros(5))
        assert np.allclose(rf1, rf2, atol=1e-9)
        assert np.allclose(nf1, -nf2, atol=1e-12)
        # the contact is the pitch point P of the pitch-cone design (b_c = 0)
        assert math.hypot(rf1[0], rf1[1]) == pytest.approx(geom.pinion.working_pitch_radius_mm, rel=1e-12)
        assert rf1[2] == pytest.approx(geom.pinion.working_mounting_distance_mm, abs=1e-9)


def test_aligned_mesh_is_conjugate(geom):
    """Involute helicoids with a common normal base pitch: constant ratio, TE ~ 0."""
    res = tca.analyze(geom, tca.Options(positions=120, approach_mm=None))
    for flank in tca.FLANKS:
        fr = res.flanks[flank]
        assert sum(s == "ok" for s in fr.status) > 100
        assert "failed" not in fr.status
        assert fr.te_peak_to_peak < 1e-12
        _check_contacts(geom, flank, fr, np.zeros(5), geom.pitch_angles[0])


@pytest.mark.parametrize("errors", [
    (0.5, 0.5, 0.5, 0, 0), (-0.5, -0.5, -0.5, 0, 0), (1.0, 1.0, 1.0, 0, 0),
    (0, 0, 0, 0.2 * DEG, 0), (0, 0, 0, -0.2 * DEG, 0), (0, 0, 0, 0, 0.03 * DEG), (0, 0, 0, 0, -0.03 * DEG),
    (0, 0, 0, 0.25 * DEG, 0), (0, 0, 0, 0, 0.04 * DEG),
])
def test_each_error_alone_true_contacts(geom, errors):
    res = tca.analyze(geom, tca.Options(flanks=("right",), positions=60, approach_mm=None, errors=errors))
    fr = res.flanks["right"]
    assert "failed" not in fr.status
    _check_contacts(geom, "right", fr, np.asarray(errors), geom.pitch_angles[0])
    # independent check of the solved unknowns at every point of the path
    ref = tca.reference_contact(geom, "right")
    sol = tca.solve_grid(geom, "right", np.asarray(errors)[None], [ref.pinion_angle], solver=Solver("numpy"))
    assert sol.status[0, 0] in (Status.OK, Status.EDGE)
    rf1, nf1, rf2, nf2 = _contact_in_frame(geom, "right", sol.x[0, 0], ref.pinion_angle, np.asarray(errors))
    assert np.allclose(rf1, rf2, atol=1e-9)
    if sol.status[0, 0] == Status.OK:  # surface contact: opposed normals (edge contact: a boundary bears)
        assert np.allclose(nf1, -nf2, atol=1e-12)


def test_random_error_combinations(geom1):
    rng = np.random.default_rng(7)
    E = np.column_stack([rng.uniform(-0.5, 0.5, (12, 3)), rng.uniform(-0.2, 0.2, 12) * DEG,
                         rng.uniform(-0.03, 0.03, 12) * DEG])
    for e in E:
        for flank in tca.FLANKS:
            ref = tca.reference_contact(geom1, flank)
            x, conv, surface = _homotopy(geom1, flank, e)
            assert conv.all()
            rf1, nf1, rf2, nf2 = _contact_in_frame(geom1, flank, x[0], ref.pinion_angle, e)
            assert np.allclose(rf1, rf2, atol=1e-9)
            assert not surface[0] or np.allclose(nf1, -nf2, atol=1e-12)


def _independent_margins(geom, flank, x):
    """Signed distances inside the four boundaries of each member, from the blank's definition."""
    out = []
    for which, lc, uc in (("pinion", 0, 1), ("gear", 2, 3)):
        m = geom.pinion if which == "pinion" else geom.gear
        p, _, _ = tca.surface(geom, which, flank, x[:, lc], x[:, uc])
        z, rad = p[:, 2], np.hypot(p[:, 0], p[:, 1])
        tip = m.pitch_radius_mm + (m.tip_height_mm + m.rack_shift_mm) / math.cos(m.cone_angle) + z * math.tan(m.cone_angle)
        half = m.face_width_mm / 2
        out += [x[:, lc], tip - rad, z - (m.reference_section_offset_mm - half), (m.reference_section_offset_mm + half) - z]
    return np.min(np.stack(out, axis=1), axis=1)


@pytest.mark.parametrize("errors", [(1.0, 1.0, 1.0, 0, 0), (1.5, 1.5, 1.5, 0, 0), (0, 0, 0, 0, 0.02 * DEG)])
def test_status_at_flank_edges(geom1, errors):
    """ok points lie on both blanks (margins recomputed from the blank); edge points lie on the
    boundaries they name and inside the others, and carry numbers; outside points carry none."""
    tol = 1e-9
    fr = tca.analyze(geom1, tca.Options(flanks=("right",), positions=200, approach_mm=None, errors=errors)).flanks["right"]
    st = np.array(fr.status)
    margin = _independent_margins(geom1, "right", fr.unknowns)
    assert np.all(margin[st == "ok"] >= -tol)
    assert np.all(np.abs(margin[st == "edge"]) <= 1e-8)  # on the named boundary, inside the others
    assert all((b is None) == (s == "ok") for s, b in zip(st, fr.contact_boundary) if s in ("ok", "edge"))
    assert np.all(np.isfinite(fr.transmission_error[st == "edge"]))
    assert np.all(np.isnan(fr.transmission_error[st == "outside"]))
    assert (st == "ok").any() and (st == "edge").any()


def test_large_offset_reaches_the_heel(geom1):
    """Offsets along +x,+y,+z move the path toward the heel; at 1.5 mm a heel bears on the mating flank."""
    fr = tca.analyze(geom1, tca.Options(flanks=("right",), positions=200, approach_mm=None, errors=(1.5, 1.5, 1.5, 0, 0))).flanks["right"]
    p, _, _ = tca.surface(geom1, "pinion", "right", fr.unknowns[:, 0], fr.unknowns[:, 1])
    assert p[:, 2].max() >= geom1.pinion.face_width_mm / 2 - 1e-9
    assert any(b is not None and "heel" in b for b in fr.contact_boundary)


def test_classify_thresholds(geom1):
    """The tangency is ok on the patches and handed to the first-touch search off them; a failed
    point is 'failed'."""
    ref = tca.reference_contact(geom1, "right")
    margins, _ = tca.boundary_margins(geom1, "right", ref.x[None])
    m = float(margins[0])
    core = backends.namespace("numpy")
    assert core.classify(True, m, 1e-9) == Status.OK
    assert core.classify(True, -0.5e-9, 1e-9) == Status.OK
    assert core.classify(False, m, 1e-9) == Status.FAILED
    assert core.classify(True, float("nan"), 1e-9) == Status.FAILED
    assert core.classify(True, -2e-9, 1e-9) == Status.OUTSIDE


def test_vertical_error_moves_path_off_the_blank(geom1):
    """Paper (case 1): dgamma_v = 0.2 deg takes the surface contact off the blank: every contact
    is an edge or corner contact."""
    res = tca.analyze(geom1, tca.Options(flanks=("right",), positions=80, approach_mm=None, errors=(0, 0, 0, 0.2 * DEG, 0)))
    st = res.flanks["right"].status
    assert "ok" not in st and "edge" in st


@pytest.mark.parametrize("k", range(5))
def test_sensitivity_against_finite_differences(geom1, k):
    base = np.array([0.2, -0.1, 0.3, 0.05 * DEG, 0.01 * DEG])
    sens = tca.sensitivity(geom1, "right", base)
    assert sens["converged"]
    h = (1e-5, 1e-5, 1e-5, 1e-7, 1e-7)[k]

    def solve(e):
        x, conv, surface = _homotopy(geom1, "right", e)
        assert surface.all()
        return x[0]

    ep, em = base.copy(), base.copy()
    ep[k] += h
    em[k] -= h
    fd = (solve(ep) - solve(em)) / (2 * h)
    exact = sens["unknowns_D_errors"][:, k]
    assert np.allclose(fd, exact, rtol=1e-5, atol=1e-6 * max(1.0, np.abs(exact).max()))


def test_backlash_aligned_matches_eq27(geom):
    """Eq 27 designs zero backlash; the two-flank TCA measures it."""
    b = tca.backlash(geom)
    assert b.status == "ok" and abs(b.um) < 1e-6  # um


def test_backlash_changes_by_the_thickness_change(geom1):
    """Thickening the gear by dxt2 turns each involute flank rigidly: exact backlash change."""
    d = 0.01
    g = geom1.gear
    mn = geom1.normal_module_mm
    thicker = dataclasses.replace(g, rack_shift_mm=g.rack_shift_mm + d * mn * math.cos(g.cone_angle) / math.cos(g.helix_angle))
    geom2 = dataclasses.replace(geom1, gear=thicker)
    an = geom1.normal_pressure_angle
    sum_tan = 2 * math.tan(an) * math.cos(g.cone_angle) / math.cos(g.helix_angle)
    mt = mn / math.cos(g.helix_angle)
    expected = -d * mt * sum_tan * g.working_pitch_radius_mm / g.pitch_radius_mm * 1e3
    assert tca.backlash(geom2).um - tca.backlash(geom1).um == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("backend", ["numpy", "compiled"] if backends.AVAILABLE else ["numpy"])
def test_newton_reports_failure_not_numbers(geom1, backend):
    ref = tca.reference_contact(geom1, "left")
    bad = ref.x + np.array([1e3, 1e3, -1e3, 1e3, 2.0])
    core = backends.namespace(backend)
    limits = settings(scale_mm=geom1.gear.working_pitch_radius_mm, tol_mm=tca.newton_tolerance(geom1), max_iter=3)
    x, conv, it, res = core.solve_point(geom1.problem("left"), bad, ref.pinion_angle, np.zeros(5), limits)
    assert not conv and it <= 3 and not res <= tca.newton_tolerance(geom1)


def _random_feasible_specs(n, seed=11):
    """Designs off the paper's cases, feasible by construction: the offset is E(alpha_nw) of Eq 17
    for a drawn working pressure angle (generated kernel, offset argument 0)."""
    from beveloid.generated import design_equations as de
    from beveloid.spec import spec_from_dict

    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        mn, N1 = rng.uniform(2, 8), int(rng.integers(15, 40))
        N2 = int(rng.integers(N1, 80))
        an, delta = rng.uniform(17, 23), rng.uniform(5, 30)
        g1, g2 = rng.choice([-1, 1]) * rng.uniform(0.5, 4), rng.choice([-1, 1]) * rng.uniform(0.5, 4)
        b1, xt1 = rng.uniform(-30, 30), rng.uniform(0.0, 0.4)
        anw = an + rng.uniform(-1.5, 2.5)
        with np.errstate(all="ignore"):
            E, _ = de.offset_residual(alpha_nw=anw * DEG, normal_module=mn, normal_pressure_angle=an * DEG,
                                      pinion_teeth=N1, gear_teeth=N2, shaft_angle=delta * DEG, pinion_profile_shift=xt1,
                                      pinion_cone_angle=g1 * DEG, gear_cone_angle=g2 * DEG,
                                      pinion_helix_angle=b1 * DEG, offset=0.0)
        if not (np.isfinite(E) and E > 0):
            continue
        spec = spec_from_dict({
            "pair": {"normal_module_mm": mn, "normal_pressure_angle_deg": an, "shaft_angle_deg": delta,
                     "offset_mm": float(E)},
            "pinion": {"teeth": N1, "cone_angle_deg": g1, "helix_angle_deg": b1, "profile_shift": xt1,
                       "face_width_mm": 8 * mn},
            "gear": {"teeth": N2, "cone_angle_deg": g2, "face_width_mm": 9 * mn}})
        out.append((spec, anw))
    return out


@pytest.mark.parametrize("spec, anw", _random_feasible_specs(6))
def test_random_designs_mesh_at_the_pitch_point_without_te_or_backlash(spec, anw):
    from beveloid.design import DesignError

    try:
        d = design(spec)
    except DesignError as exc:  # e.g. pointed teeth for an extreme draw: a clear refusal is fine
        assert "\n" not in str(exc)
        return
    assert math.degrees(d.working_normal_pressure_angle) == pytest.approx(anw, abs=1e-9)
    geom = tca.PairGeometry.from_design(d)
    for flank in tca.FLANKS:
        ref = tca.reference_contact(geom, flank)
        rf1, nf1, rf2, nf2 = _contact_in_frame(geom, flank, ref.x, ref.pinion_angle, np.zeros(5))
        assert np.allclose(rf1, rf2, atol=1e-9) and np.allclose(nf1, -nf2, atol=1e-12)
        assert math.hypot(rf1[0], rf1[1]) == pytest.approx(geom.pinion.working_pitch_radius_mm, rel=1e-12)
    res = tca.analyze(geom, tca.Options(positions=40, approach_mm=None))
    for fr in res.flanks.values():
        assert "failed" not in fr.status
        if np.isfinite(fr.te_peak_to_peak):
            assert fr.te_peak_to_peak < 1e-12
    assert abs(res.backlash_um) < 1e-6


@pytest.mark.skipif(not backends.AVAILABLE, reason="the compiled backend needs numba")
def test_backends_agree_on_statuses_and_numbers_including_failures(geom1):
    """One core, two backends: identical statuses and the same unknowns (1e-9) on error sets
    from aligned to the documented extremes, where the homotopy loses track."""
    rng = np.random.default_rng(5)
    half = np.array([10.0, 10.0, 10.0, 5 * DEG, 5 * DEG])
    E = np.vstack([np.zeros(5), [0.5, 0.5, 0.5, 0.0, 0.01 * DEG], rng.uniform(-1, 1, (10, 5)) * half])
    ref = tca.reference_contact(geom1, "right")
    grid = ref.pinion_angle + np.linspace(-0.3, 0.3, 15)
    a = tca.solve_grid(geom1, "right", E, grid, solver=Solver("numpy"))
    b = tca.solve_grid(geom1, "right", E, grid, solver=Solver("compiled"))
    np.testing.assert_array_equal(a.status, b.status)
    np.testing.assert_array_equal(a.boundary, b.boundary)
    np.testing.assert_array_equal(a.active, b.active)
    assert (a.status == Status.FAILED).any() and (a.status == Status.OK).any() and (a.status == Status.EDGE).any()
    solved = a.status != Status.FAILED
    np.testing.assert_allclose(a.x[solved], b.x[solved], rtol=0, atol=1e-9)


def _unwritable_numba(monkeypatch, writable_folders):
    """numba.njit that cannot cache next to the sources; config.CACHE_DIR works when writable."""
    import numba

    real = numba.njit
    calls = []

    def njit(*args, cache=False, **kw):
        calls.append((cache, getattr(numba.config, "CACHE_DIR", "")))
        if cache and numba.config.CACHE_DIR not in writable_folders:
            raise RuntimeError("cannot cache function 'f': no locator available for file '/ro/f.py'")
        return real(*args, **kw)

    monkeypatch.setattr(numba, "njit", njit)
    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    monkeypatch.setattr(backends, "_cache_warned", False)
    monkeypatch.setattr(backends, "_cache_redirected", False)
    return calls


def _double(x):
    return 2.0 * x


@pytest.mark.skipif(not backends.AVAILABLE, reason="the compiled backend needs numba")
def test_read_only_install_caches_in_a_user_folder(monkeypatch, tmp_path, capsys):
    """A read-only install (numba: 'cannot cache function ...: no locator available') caches in
    the folder BEVELOID_CACHE_DIR names (else the user's cache folder, else the temporary one)."""
    folder = str(tmp_path / "cache")
    monkeypatch.setenv(backends.CACHE_ENV, folder)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    calls = _unwritable_numba(monkeypatch, {folder})
    g = backends._jit(_double)
    assert calls == [(True, folder)]  # the named folder first, and it works
    assert g(1.5) == 3.0
    assert capsys.readouterr().err == ""


@pytest.mark.skipif(not backends.AVAILABLE, reason="the compiled backend needs numba")
def test_compiled_backend_runs_without_any_writable_cache(monkeypatch, capsys):
    """No folder can be written: compiled in memory, with one line on stderr, once."""
    monkeypatch.delenv(backends.CACHE_ENV, raising=False)
    monkeypatch.setattr(backends, "fallback_cache_dir", lambda: None)
    calls = _unwritable_numba(monkeypatch, set())
    g = backends._jit(_double)
    assert [c for c, _ in calls] == [True, False]
    assert g(1.5) == 3.0
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "compiled in memory" in err and backends.CACHE_ENV in err
    h = backends._jit(_double)  # said once only
    assert h(2.0) == 4.0 and capsys.readouterr().err == ""


def test_fallback_cache_dir_is_writable(monkeypatch, tmp_path):
    monkeypatch.setenv(backends.CACHE_ENV, str(tmp_path / "mine"))
    assert backends.fallback_cache_dir() == str(tmp_path / "mine")
    monkeypatch.delenv(backends.CACHE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert backends.fallback_cache_dir() == str(tmp_path / "xdg" / "beveloid" / "numba")


def test_backlash_is_never_wrapped_and_has_a_status():
    """Issue 14, items 1-2: module 1 mm (case 1 scaled): the play grows with dx as long as both
    flanks touch on their flanks; beyond that it is 'outside' with no number, never a value
    reduced modulo the pitch.  Case 1 tilted by 5 deg (vertical): the flanks' edges bear on each
    other (edge contact) and the gear cannot fit: a negative play (interference), on the gear
    angle's own branch (no whole turns: issue 12), smaller than the tilt's axial sweep of the
    gear face, W2 sin 5 deg."""
    import tomllib

    from beveloid.spec import spec_from_dict

    data = tomllib.loads((ROOT / "examples" / "case1.toml").read_text())
    data["pair"].update(normal_module_mm=1.0, offset_mm=38.1666)
    geom = tca.PairGeometry.from_design(design(spec_from_dict(data)))
    b = [tca.backlash(geom, (dx, 0, 0, 0, 0)) for dx in (0.0, 0.05, 0.1, 3.0)]
    assert [x.status for x in b[:3]] == ["ok", "ok", "ok"]
    assert abs(b[0].um) < 1e-6 and 0 < b[1].um < b[2].um
    assert b[2].um == pytest.approx(2 * b[1].um, rel=0.05)  # first order in dx
    assert b[3].status == "outside" and b[3].um is None and "flank" in b[3].reason
    case1 = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
    off = tca.backlash(case1, (0, 0, 0, 5 * DEG, 0))
    sweep_um = case1.gear.face_width_mm * math.sin(5 * DEG) * 1e3
    assert off.status == "ok" and -sweep_um < off.um < 0


def test_envelope_complete_where_no_unsolved_pair_can_carry():
    """Synthetic mesh, pitch 1: pair 0's TE -psi^2 carries on |psi| <= 1/2; with pairs -1..1 solved over
    |phi| <= 1.5 only the ends, where pair +-2 (psi = phi -+ 2) would carry, are incomplete."""
    from beveloid import mesh

    phi = np.linspace(-1.5, 1.5, 31)
    ks, psi = mesh.pair_angles(phi, 3, 1.0)
    env, active = mesh.envelope(-psi**2, +1)
    step = phi[1] - phi[0]
    complete = mesh.envelope_complete(phi, ks, active, 1.0, step)
    lo, hi = psi[active].min() - step, psi[active].max() + step
    expect = ~(((phi - 2 >= lo) & (phi - 2 <= hi)) | ((phi + 2 >= lo) & (phi + 2 <= hi)))
    np.testing.assert_array_equal(complete, expect)
    assert complete[10:21].all() and not complete[0] and not complete[-1]
    # the complete envelope's peak-to-peak is the cycle's: 0 at the vertex, -1/4 where pairs change
    assert mesh.peak_to_peak(env[complete]) == pytest.approx(0.25, abs=1e-12)
    # a carrier at the end of the solved angles may go on beyond them: nothing is known complete
    assert not mesh.envelope_complete(phi, ks, np.ones_like(active), 1.0, step).any()
