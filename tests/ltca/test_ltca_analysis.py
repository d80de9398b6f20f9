"""Loaded TCA (beveloid.ltca, `beveloid ltca`): equilibrium, the Hertz limit, the light-load
pattern on the unloaded path, load sharing, misalignment, the JSON contract and bad input.

Every check is a physical property or a contract; no number is copied from a run of the code.
The Hertz references come from the closed form (beveloid.ltca.mechanics.hertz) with the curvature of
the gap computed from the generated surfaces (see the docstring of test_hertz_limit_...).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, ltca, tca
from beveloid.ltca.mechanics import hertz
from beveloid.ltca.model.grid import centres
from beveloid.pair import Pair

ROOT = Path(__file__).resolve().parents[2]
CASE1 = ROOT / "examples" / "case1.toml"


@pytest.fixture(scope="module")
def loaded200(geom1):
    return ltca.analyze(geom1, ltca.LoadCase(200.0), ltca.Options(flank="right", positions=6, pairs=3, tooth_model="plate"))


def _cell_coordinates(result, j, k):
    """Cell centres (across, along) in the pair's tangent plane, shaped (across, along)."""
    g = result.grid
    xc, yc = centres(g.across_half_mm[j, k], g.across_cells), centres(g.along_half_mm[j, k], g.along_cells)
    x = xc[:, None] + result.gap.across_shift_mm[j, k][None, :]
    return x, np.broadcast_to(yc[None, :], x.shape)


def test_moment_balance_at_every_position(geom1, loaded200):
    """Sum over the cells of p a (R_1 x n_1)_z, recomputed from the pinion surface kernel at the
    cells' (l, u), equals the applied pinion torque to 1e-6 at every position."""
    r = loaded200
    assert all(s == "ok" for s in r.status)
    lu = r.gap.pinion_lu
    for j in range(len(r.status)):
        moment = 0.0
        for k in range(len(r.tooth_pairs)):
            on = r.pressure_mpa[j, k] > 0
            if not on.any():
                continue
            pt, n, _ = geom1.surface("pinion", "right", lu[j, k, on, 0], lu[j, k, on, 1])
            arm = pt[:, 0] * n[:, 1] - pt[:, 1] * n[:, 0]  # (R x n)_z in S_1: the pinion axis
            moment += float(np.sum(r.pressure_mpa[j, k, on] * r.cell_area_mm2[j, k] * arm))
        assert abs(abs(moment) / (200.0e3) - 1.0) < 1e-6


def test_pressures_nonnegative_and_all_pairs_share_one_rotation(loaded200):
    r = loaded200
    assert np.all(r.pressure_mpa >= 0)
    # the loaded TE exceeds the rigid envelope (the gear lags under load) at every position
    assert np.all(np.abs(r.loaded_te) > np.abs(r.unloaded_te))
    # more than one pair carries load somewhere in the cycle (contact ratio > 1), never a negative load
    assert np.all(r.pair_load_n >= 0)
    assert ((r.pair_load_n > 0).sum(axis=1) >= 2).any()
    assert np.all(r.converged)
    assert np.all(r.complementarity_residual <= 1e-10)


def _loaded_patch(result, j, k):
    """(across, along semi-axes from the pressure moments, p_max) of pair k at position j."""
    nx, ny = result.grid.across_cells, result.grid.along_cells
    p = result.pressure_mpa[j, k].reshape(nx, ny)
    x, y = _cell_coordinates(result, j, k)
    w = p / p.sum()
    mx, my = (w * x).sum(), (w * y).sum()
    return math.sqrt(5 * (w * (x - mx) ** 2).sum()), math.sqrt(5 * (w * (y - my) ** 2).sum()), p.max()


@pytest.mark.parametrize("case, flank, torque_nm", [("case1", "left", 2.0), ("case2", "left", 2.0)])
def test_hertz_limit_on_the_point_contact_flank(case, flank, torque_nm):
    """Light load on a point-contact flank (case 1 left: xi_L = 7.57 deg), one tooth pair, middle
    position: the loaded patch's semi-axes and p_max within 5% of Hertz.

    Reference: Hertz (closed form, beveloid.ltca.mechanics.hertz) for the gap 1/2 x^T H x, H the relative
    curvature of the two flanks at the pair's rigid-body tangency (beveloid.curvature, from the
    generated fundamental forms), with the pair's normal force.  Semi-axes from the pressure
    moments, a = sqrt(5 <x^2>) (exact for Hertz).  The gap itself, built by Newton on the
    generated surfaces, must carry the same quadratic form (fitted over the cells near contact).
    """
    from beveloid import curvature

    geom = Pair.example(case).geometry
    r = ltca.analyze(geom, ltca.LoadCase(torque_nm), ltca.Options(flank=flank, positions=3, pairs=1, tooth_model="plate"))
    nx, ny = r.grid.across_cells, r.grid.along_cells
    j, k = 1, 0
    rc = curvature.relative_curvature(geom, flank, r.tangency_unknowns[j, k], r.pair_pinion_angle[j, k],
                                      np.zeros(5))
    a_small, a_large = np.linalg.eigvalsh(rc.H) / 2
    ref = hertz.hertz_point_contact(a_small, a_large, float(r.pair_load_n[j, k]), ltca.Material().e_star_mpa)
    across, along, p_max = _loaded_patch(r, j, k)
    assert np.allclose(r.patch_semi_axes_mm()[j, k], [across, along], rtol=1e-12)  # what the JSON reports
    assert abs(across / ref.semi_minor_mm - 1) < 0.05
    assert abs(along / ref.semi_major_mm - 1) < 0.05
    assert abs(p_max / ref.max_pressure_mpa - 1) < 0.05
    assert ref.semi_major_mm / ref.semi_minor_mm > 3  # an elongated ellipse: the test means something
    # the gap's own quadratic form agrees with the curvature API
    h = r.gap.gap_mm[j, k].reshape(nx, ny)
    inside = r.gap.in_flank[j, k].reshape(nx, ny)
    x, y = _cell_coordinates(r, j, k)
    fit = inside & (h <= np.percentile(h[inside], 60))
    m = np.stack([x[fit] ** 2, x[fit] * y[fit], y[fit] ** 2, x[fit], y[fit], np.ones(fit.sum())], axis=-1)
    c = np.linalg.lstsq(m, h[fit], rcond=None)[0]
    fitted = np.linalg.eigvalsh(np.array([[c[0], c[1] / 2], [c[1] / 2, c[2]]]))
    assert abs(fitted[1] / a_large - 1) < 0.02


def test_light_load_pattern_follows_the_unloaded_path(geom1):
    """At 5 N m each loaded patch is centred on its pair's rigid-body tangency (within a cell)."""
    r = ltca.analyze(geom1, ltca.LoadCase(5.0), ltca.Options(flank="right", positions=5, pairs=3, tooth_model="plate"))
    origin = r.gap.pinion_point  # cells; the tangency is the grid origin
    for j in range(5):
        for k in range(3):
            p = r.pressure_mpa[j, k]
            if p.sum() == 0 or not r.converged[j]:
                continue
            x, y = _cell_coordinates(r, j, k)
            w = (p / p.sum()).reshape(x.shape)
            cx, cy = (w * x).sum(), (w * y).sum()
            hx = r.grid.across_half_mm[j, k] / r.grid.across_cells
            assert abs(cx) < 2 * hx + 0.02 and abs(cy) < 0.25 * r.grid.along_half_mm[j, k]
    assert origin.shape[-1] == 3


def test_misaligned_pair_solves_and_balances(geom1):
    """A vertical angular error shifts the patch: still converged, balanced, loads only on the flanks."""
    r = ltca.analyze(geom1, ltca.LoadCase(100.0, errors=(0, 0, 0, math.radians(0.05), 0)), ltca.Options(flank="right", positions=4, pairs=3, tooth_model="plate"))
    assert all(s == "ok" for s in r.status)
    assert np.all(np.abs(r.pinion_moment_nmm / 100e3 - 1) < 1e-6)
    assert not np.any((r.pressure_mpa > 0) & ~r.gap.in_flank)


def _run(capsys, argv):
    rc = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


def test_ltca_json_contract(capsys):
    rc, out, err = _run(capsys, ["ltca", CASE1, "--torque-nm", "150", "--positions", "4", "--json",
                                 "--tooth-model", "plate"])
    assert rc == 0, err
    data = json.loads(out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
    n, pairs = 4, data["tooth_pairs"]
    assert data["torque_nm"] == 150.0 and pairs == [-1, 0, 1]
    assert data["tooth_model"] == "plate" and data["pair_root_stress_mpa"] is None
    assert len(data["mesh_stiffness_n_per_um"]) == n
    for key in ("pinion_angle_rad", "loaded_transmission_error_urad", "contact_area_mm2", "status"):
        assert len(data[key]) == n, key
    for key in ("pair_normal_load_n", "pair_max_pressure_mpa"):
        assert len(data[key]) == n and all(len(row) == len(pairs) for row in data[key])
    for j, st in enumerate(data["status"]):
        numbers = [data["loaded_transmission_error_urad"][j], data["contact_area_mm2"][j]]
        assert (st == "ok") == all(v is not None for v in numbers)
    assert set(data["pattern_area_fraction"]) == {"pinion", "gear"}
    assert all(0 < v <= 1 for v in data["pattern_area_fraction"].values())
    assert {"iterations", "complementarity_residual", "load_residual", "moment_residual"} <= set(data["solver"])
    axes = data["pair_patch_semi_axes_mm"]
    for j in range(n):
        for k, load in enumerate(data["pair_normal_load_n"][j]):
            # an axis pair exactly where a converged pair carries load; across <= along (the ellipse's minor axis)
            assert (axes[j][k] is not None) == bool(load)
            assert axes[j][k] is None or 0 < axes[j][k][0] < axes[j][k][1]
    assert all(m is None or m < 1e-6 for m in data["solver"]["moment_residual"])
    # the tooth height the Hertz note measures a patch's length against: (h_a + h_f) m_n of each member
    assert set(data["tooth_height_mm"]) == {"pinion", "gear"}
    assert all(2.0 * 6.0 < h < 2.6 * 6.0 for h in data["tooth_height_mm"].values())  # case 1: m_n = 6


@pytest.mark.parametrize("flags, needle", [
    (["--torque-nm", "0"], "--torque-nm = 0: must be"),  # the value as typed
    (["--torque-nm", "nan"], "--torque-nm = nan: must be"),
    (["--torque-nm", "10", "--grid", "2x40"], "--grid = 2x40: must be"),
    (["--torque-nm", "10", "--positions", "0"], "--positions = 0: must be"),
    (["--torque-nm", "10", "--pairs", "2"], "--pairs = 2: must be"),
    (["--torque-nm", "10", "--grid", "201x201"], "--grid = 201x201: needs about"),
    (["--torque-nm", "10", "--vertical", "9"], "--vertical = 9"),
])
def test_ltca_bad_input_one_line(capsys, flags, needle):
    rc, out, err = _run(capsys, ["ltca", CASE1, *flags])
    assert rc == 2 and needle in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_ltca_plot_target_checked_before_computing(capsys, tmp_path):
    rc, out, err = _run(capsys, ["ltca", CASE1, "--torque-nm", "10", "--plot", str(tmp_path)])
    assert rc == 2 and "--plot" in err


def test_material_section_reaches_the_compliance(geom1, tmp_path, capsys):
    """A softer gear (the [material] section) lowers E* and the mesh stiffness: larger loaded TE."""
    from beveloid.spec import load_spec

    text = CASE1.read_text() + "\n[material]\ngear_youngs_modulus_gpa = 103.0\ngear_poisson_ratio = 0.3\n"
    soft_file = tmp_path / "soft.toml"
    soft_file.write_text(text)
    mat = ltca.Material.from_spec(load_spec(soft_file))
    assert mat.gear_e_mpa == 103e3 and mat.e_star_mpa < ltca.Material().e_star_mpa
    stiff = ltca.analyze(geom1, ltca.LoadCase(100.0), ltca.Options(flank="right", positions=3, pairs=3, tooth_model="plate"))
    soft = ltca.analyze(geom1, ltca.LoadCase(100.0), ltca.Options(flank="right", positions=3, pairs=3, material=mat, tooth_model="plate"))
    assert np.all(np.abs(soft.loaded_te - soft.unloaded_te) > np.abs(stiff.loaded_te - stiff.unloaded_te))
    bad = tmp_path / "bad.toml"
    bad.write_text(CASE1.read_text() + "\n[material]\npinion_poisson_ratio = 0.5\n")
    rc, out, err = _run(capsys, ["ltca", bad, "--torque-nm", "10"])
    assert rc == 2 and "material.pinion_poisson_ratio = 0.5" in err and len(err.strip().splitlines()) == 1


def test_gap_backends_agree(geom1):
    """The numpy backend interprets the same core.normal_gaps the compiled one runs: equal flags away
    from the boundary rule's threshold, gaps, rates and points within 1e-8, on a grid that reaches off
    the flanks."""
    pytest.importorskip("numba")
    from beveloid.ltca.model import gaps
    from beveloid.ltca.passes.cycle import Setup
    from beveloid.solver import Solver

    setup = Setup(geom1, "right", np.zeros(5), 4, 3, Solver("compiled"))
    q = np.array([0, 1, 2])
    frames = gaps.Frames(setup.start[1, q], setup.pair_phi1[1, q], setup.frame.origin[1, q], setup.frame.axes[1, q])
    xs, ys = np.meshgrid(np.linspace(-2, 2, 3), np.linspace(-40, 40, 9), indexing="ij")
    coords = np.broadcast_to(np.stack([xs.ravel(), ys.ravel()], axis=-1), (3, xs.size, 2))
    a = gaps.cell_gaps(geom1, "right", setup.errors, frames, coords, Solver("numpy"))
    b = gaps.cell_gaps(geom1, "right", setup.errors, frames, coords, Solver("compiled"))
    assert a.on_flanks.any() and not a.on_flanks.all()
    tol = tca.DEFAULT_OPTIONS.patch_tol_mm
    decided = np.abs(a.margin_mm + tol) > 1e-11
    assert decided.mean() > 0.9
    assert np.array_equal(a.on_flanks[decided], b.on_flanks[decided])
    on = a.on_flanks & b.on_flanks
    for name in ("gap_mm", "gap_D_gear_angle", "pinion_arm_mm", "pinion_lu", "pinion_point", "gear_point"):
        assert np.allclose(getattr(a, name)[on], getattr(b, name)[on], rtol=1e-9, atol=1e-8), name


def test_a_gap_does_not_depend_on_the_order_of_its_points(geom1):
    """normal_gaps starts each point's Newtons from the previous point's solution, extrapolated along a
    line of points: in any order the same flags and, to the Newtons' tolerance, the same gaps; and it
    reads no output row it has not written (the output arrays hold NaN and 'converged' before)."""
    from beveloid.ltca.model import gaps
    from beveloid.ltca.passes.cycle import Setup
    from beveloid.solver import Solver
    from beveloid.solver.core import on_patch
    from beveloid.solver.records import GapOutput, GapRequest

    solver = Solver()
    setup = Setup(geom1, "right", np.zeros(5), 4, 3, solver)
    xs, ys = np.meshgrid(np.linspace(-1.0, 1.0, 4), np.linspace(-30, 30, 9), indexing="ij")
    coords = np.stack([xs.ravel(), ys.ravel()], axis=-1)  # rows along the line, off the flanks at both ends
    M = coords.shape[0]
    fr = gaps.Frames(setup.start[1, 1:2], setup.pair_phi1[1, 1:2], setup.frame.origin[1, 1:2], setup.frame.axes[1, 1:2])

    def solved(order):
        rotation = gaps.placement.pinion_placement(fr.pinion_angle, geom1.placement()).rotation
        req = GapRequest(pair_of_point=np.zeros(M, dtype=np.int64), coords=np.ascontiguousarray(coords[order]),
                         start=fr.start, pinion_angle=fr.pinion_angle, origin=fr.origin, axes=fr.axes,
                         rotation=np.ascontiguousarray(rotation), errors=setup.errors, tol_mm=gaps.NEWTON_TOL_MM,
                         max_iter=gaps.NEWTON_ITERATIONS)
        out = GapOutput(pinion_lu=np.full((M, 2), np.nan), gear_lu_gap=np.full((M, 3), np.nan),
                        rates=np.full((M, 2), np.nan), margin=np.full(M, np.nan), ok=np.ones(M, dtype=np.int64),
                        pinion_point=np.full((M, 3), np.nan), gear_point=np.full((M, 3), np.nan))
        solver.core.normal_gaps(setup.problem, req, out)
        back = np.argsort(order)
        on = (out.ok == 1) & on_patch(out.margin, solver.options.patch_tol_mm)
        return on[back], out.gear_lu_gap[back, 2]

    rows = np.arange(M)
    snake = rows.reshape(xs.shape).copy()
    snake[1::2] = snake[1::2, ::-1].copy()
    ok, gap = solved(rows)
    assert ok.any() and not ok.all()
    for order in (snake.ravel(), rows[::-1], np.random.default_rng(3).permutation(M)):
        ok2, gap2 = solved(order)
        assert np.array_equal(ok, ok2)
        assert np.allclose(gap[ok], gap2[ok], rtol=0.0, atol=1e-8)


def test_the_gap_newtons_final_step_and_tangent_starts_give_the_confirmed_numbers(geom1, monkeypatch):
    """normal_gaps ends a Newton after a step too small to leave a residual above the tolerance
    (newton.FINAL_STEP_K) without evaluating again, and starts a point where no line of points leads to it
    from the previous point's derivatives: the gaps, rates and points within the Newtons' tolerance of those
    of Newtons that confirm every point (the shortcut switched off), in fewer surface evaluations."""
    from beveloid.ltca.model import gaps
    from beveloid.ltca.passes.cycle import Setup
    from beveloid.solver import Solver
    from beveloid.solver import gaps as core_gaps

    numpy = Solver("numpy")  # the interpreted core reads the module's names at each call
    setup = Setup(geom1, "right", np.zeros(5), 4, 3, numpy)
    q = np.array([1, 1])
    frames = gaps.Frames(setup.start[1, q], setup.pair_phi1[1, q], setup.frame.origin[1, q], setup.frame.axes[1, q])
    xs, ys = np.meshgrid(np.linspace(-0.4, 0.4, 8), np.linspace(-20, 20, 12), indexing="ij")
    snake = np.stack([xs, ys], axis=-1)
    snake[1::2] = snake[1::2, ::-1].copy()  # serpentine rows: a turn after each row
    coords = np.broadcast_to(snake.reshape(-1, 2), (2, xs.size, 2))
    calls = []
    jet = core_gaps.surface_jet_point

    def counted(*args):
        calls.append(1)
        return jet(*args)

    monkeypatch.setattr(core_gaps, "surface_jet_point", counted)
    a = gaps.cell_gaps(geom1, "right", setup.errors, frames, coords, numpy)
    fast = len(calls)
    monkeypatch.setattr(core_gaps, "FINAL_STEP_K", np.inf)
    calls.clear()
    b = gaps.cell_gaps(geom1, "right", setup.errors, frames, coords, numpy)
    assert fast < 0.85 * len(calls)
    assert a.on_flanks.all() and np.array_equal(a.on_flanks, b.on_flanks)
    for name in ("gap_mm", "pinion_lu", "pinion_point", "gear_point", "margin_mm"):
        assert np.allclose(getattr(a, name), getattr(b, name), rtol=0.0, atol=1e-8), name
    for name in ("gap_D_gear_angle", "pinion_arm_mm"):
        assert np.allclose(getattr(a, name), getattr(b, name), rtol=1e-6, atol=0.0), name


def test_pattern_colour_scale_is_the_surface_peak_not_the_edge_spike(geom1, loaded200):
    """Case 1 at 200 N m has edge peaks (singular, grid-dependent) far above the surface peak; the
    pattern's colour runs to the surface peak over the cycle and its colour bar says that more lies
    above it, so the pattern is not one dark cell on a pale flank."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from beveloid.ltca.results import plots

    r = loaded200
    surface = np.nanmax(r.pair_surface_max_pressure_mpa[r.converged])
    edge = np.nanmax(r.pair_edge_max_pressure_mpa[r.converged])
    assert edge > 1.5 * surface  # the premise: the spikes would dominate an automatic scale
    assert plots.surface_scale_mpa(r) == surface
    fig, ax = plt.subplots()
    try:
        sc, clipped = plots.ltca_pattern(ax, r, geom1, "pinion")
        assert sc.norm.vmax == surface and clipped
        assert np.ma.max(sc.get_array()) > surface  # the raster itself keeps the spikes
    finally:
        plt.close(fig)


@pytest.fixture
def no_patterns(monkeypatch):
    """The flank patterns (over (z, radius); the costly part of the LTCA's figures and table, 0.5 s a
    member) left out: no pattern is drawn and the table's flank shares are "-"."""
    from beveloid.ltca.results import plots
    from beveloid.ltca.results.result import LTCAResult

    monkeypatch.setattr(plots, "ltca_pattern", lambda *a, **k: (None, False))
    monkeypatch.setattr(LTCAResult, "pattern", lambda *a, **k: type("Pattern", (), {"area_fraction": None})())


@pytest.fixture
def drawn_figures(monkeypatch):
    """The figures beveloid.ltca.results.plots draws, kept open and not rendered (savefig records them)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    figs = []
    monkeypatch.setattr(Figure, "savefig", lambda fig, *a, **k: figs.append(fig))
    monkeypatch.setattr(Figure, "tight_layout", lambda fig, *a, **k: None)
    yield figs
    for fig in figs:
        plt.close(fig)


def test_the_pinion_angle_is_in_degrees_in_every_ltca_output(geom1, loaded200, tmp_path, drawn_figures, no_patterns):
    """One unit for the pinion angle across the product: the LTCA figures' axes (labelled as the TCA
    figures', their points at the angles in degrees), the per-position panels, the `ltca` table, the
    rating's text and fe-check's line all say degrees, as the TCA figures do."""
    from beveloid import plots as tca_plots
    from beveloid.cli import fe_check
    from beveloid.cli.ltca import format_summary
    from beveloid.ltca.results import plots
    from beveloid.rating.analysis import MemberRating, loaded_contact
    from beveloid.spec import load_spec

    r = loaded200
    deg = np.degrees(r.pinion_angle)
    plots.ltca_summary(r, geom1, tmp_path / "l.png")
    plots.ltca_torques([r], geom1, tmp_path / "t.png")
    angle_axes = [ax for fig in drawn_figures for ax in fig.axes if "pinion angle" in ax.get_xlabel()]
    assert len(angle_axes) == 3  # the summary's TE and load sharing, the torques' load sharing
    assert {ax.get_xlabel() for ax in angle_axes} == {tca_plots.PINION_ANGLE_LABEL} == {"pinion angle phi'_1 (deg)"}
    for ax in angle_axes:
        assert all(np.allclose(line.get_xdata(), deg) for line in ax.lines)
    titles = [ax.get_title() for ax in drawn_figures[1].axes if ax.get_title()]  # the per-position panels
    assert titles == [f"phi'_1 = {d:.2f} deg: {s}" for d, s in zip(deg, r.status)]

    table = format_summary(r, geom1, load_spec(CASE1)).splitlines()
    head = next(i for i, line in enumerate(table) if "status" in line.split())  # a word: not in the spec's path
    assert table[head].split("  ")[0].strip() == tca_plots.PINION_ANGLE_LABEL
    assert [float(row.split()[0]) for row in table[head + 1:head + 1 + len(deg)]] == pytest.approx(deg, abs=6e-4)

    ok = r.converged
    surf = r.pair_surface_max_pressure_mpa[ok]
    j, k = np.unravel_index(int(np.nanargmax(surf)), surf.shape)
    where = loaded_contact(r, geom1, geom1.pinion.face_width_mm).peak_where
    assert f"(pinion angle phi'_1 = {deg[ok][j]:.2f} deg, tooth pair {r.tooth_pairs[k]};" in where
    root = {"face_z_mm": 1.0, "height_above_root_mm": 2.0, "pinion_angle_rad": 0.1, "tooth_pair": 0}
    assert "(pinion angle phi'_1 = 5.73 deg, tooth pair 0)" in MemberRating.root_stress_where.fget(
        type("Member", (), {"root_stress_location": root})())
    block = {"loaded_transmission_error_urad": None, "root_stress_max_mpa": {"pinion": None, "gear": None},
             "moment_about_pinion_axis_nm": None}
    line = fe_check.format_summary({"position": 3, "pinion_angle_rad": -0.05, "flank": "right", "torque_nm": 200.0,
                                    "calculix_version": "2.21", "calculix": block, "ltca": block, "tooth_pairs": [],
                                    "notes": [], "files": {}}).splitlines()[0]
    assert line.startswith("fe-check at position 3 (pinion angle phi'_1 = -2.8648 deg), right flank")
    assert not any("mrad" in text for text in (*table, where, line))


def test_the_positions_span_one_cycle_and_the_output_says_how_many_states_they_are(geom1, loaded200, capsys,
                                                                                   no_patterns):
    """N positions over one mesh cycle include both its ends (one pitch apart: the same mesh state), so
    they are N - 1 distinct states: the notes (the table's footer and JSON "notes") and --help say it."""
    from beveloid.cli.ltca import format_summary
    from beveloid.spec import load_spec

    r = loaded200
    assert r.pinion_angle[-1] - r.pinion_angle[0] == pytest.approx(geom1.pitch_angles[0], rel=1e-12)
    note = "6 positions over one mesh cycle, its first and last one pitch apart (5 distinct mesh states)"
    assert note in r.notes and f"note: {note}" in format_summary(r, geom1, load_spec(CASE1)).splitlines()
    for command in ("ltca", "rating", "optimize"):
        assert cli.main([command, "--help"]) == 0
        text = " ".join(capsys.readouterr().out.split())
        assert "--positions N" in text and "one mesh cycle, its first and last one pitch apart: N positions are " \
                                           "N - 1 distinct mesh states (default" in text, command


def test_the_pattern_skips_only_nodes_neither_field_reaches(geom1, loaded200, monkeypatch):
    """Each position's field is evaluated only at the nodes its box reaches, and the sub-steps between two
    positions only at the nodes whose swept boxes reach them (``_Field.reached``): the same pattern, bit
    for bit, as every node (every node near the pair)."""
    from beveloid.ltca.results import pattern

    fast = [pattern.flank_pattern(loaded200, geom1, m) for m in ("pinion", "gear")]
    skipped = []
    real = pattern._Field.reached

    def everywhere(self, c, move):
        skipped.append(int((~real(self, c, move)).sum()))
        return np.ones(len(c), dtype=bool)

    monkeypatch.setattr(pattern._Field, "reached", everywhere)
    full = [pattern.flank_pattern(loaded200, geom1, m) for m in ("pinion", "gear")]
    assert sum(skipped) > 0  # the filter leaves nodes out
    for a, b in zip(fast, full):
        assert a.area_fraction == b.area_fraction
        np.testing.assert_array_equal(a.max_pressure_mpa, b.max_pressure_mpa)
