"""The batched loaded engine (ltca.analyze_many), the torque map, the TE harmonics, the CSV and the
tolerance box of `beveloid ltca` (issue 43); the plate tooth on small grids, few positions."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, ltca, sweep
from beveloid.ltca.results.batch import MESH_ORDERS, gear_base_radius_mm, summary, te_harmonics
from beveloid.pair import Pair

CASE1 = Path(__file__).resolve().parents[2] / "examples" / "case1.toml"
SMALL = dict(positions=5, grid=(7, 9), tooth_model="plate")


@pytest.fixture(scope="module")
def pair():
    return Pair.example("case1")


def _same(a, b, rtol=1e-9):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert np.array_equal(np.isfinite(a), np.isfinite(b))
    m = np.isfinite(a)
    assert np.allclose(a[m], b[m], rtol=rtol, atol=rtol * np.max(np.abs(a[m]), initial=0.0))


def test_a_batch_entry_equals_its_single_run(pair):
    errors = [(0.0, 0.0, 0.0, 0.0, 0.0), (0.03, -0.02, 0.01, math.radians(0.02), 0.0)]
    batch = ltca.analyze_many(pair, ltca.LoadCase([60.0, 250.0], errors=errors), ltca.Options(**SMALL))
    assert batch.te_peak_to_peak_urad.shape == (2, 2)
    for k, t in ((1, 0), (0, 1)):
        one = ltca.analyze(pair, ltca.LoadCase([60.0, 250.0][t], errors=errors[k]), ltca.Options(**SMALL))
        got = batch.results[k][t]
        assert got.torque_nm == one.torque_nm
        for name in ("loaded_te", "pair_load_n", "pair_max_pressure_mpa", "mesh_stiffness_n_per_um"):
            _same(getattr(got, name), getattr(one, name))
    # the cases differ: a torque or an error set that was not applied would show here
    assert abs(batch.te_peak_to_peak_urad[0, 1] - batch.te_peak_to_peak_urad[0, 0]) > 0.1
    assert np.nanmax(np.abs(batch.results[1][0].loaded_te - batch.results[0][0].loaded_te)) > 1e-7


def test_near_zero_torque_gives_the_unloaded_te(pair):
    low = ltca.analyze(pair, ltca.LoadCase(0.01), ltca.Options(**SMALL))
    high = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(**SMALL))
    assert all(s == "ok" for s in low.status)
    gap_low = np.max(np.abs(low.loaded_te - low.unloaded_te))
    gap_high = np.max(np.abs(high.loaded_te - high.unloaded_te))
    # the elastic approach grows like F^(2/3) (Hertz) to F (beams): 2e4 times less torque, < 1/300 of it
    assert gap_low < gap_high / 300 and gap_low < 0.1e-6


class _TE:
    def __init__(self, te):
        self.loaded_te = np.asarray(te, float)


def test_harmonics_of_a_known_curve_over_one_cycle_with_the_end_repeated():
    M = 16
    x = 2 * np.pi * np.arange(M + 1) / M  # the repeated end point is the cycle's start
    te = 3e-6 + 2e-6 * np.sin(x) + 0.5e-6 * np.cos(3 * x + 0.4) + 0.25e-6 * np.sin(6 * x)
    h = te_harmonics(_TE(te))
    assert np.allclose(h, [2e-6, 0, 0.5e-6, 0, 0, 0.25e-6], atol=1e-15)
    # an order at or above half the samples is aliased: not reported
    assert np.isnan(te_harmonics(_TE(te[::4]))[1:]).all()
    assert np.isnan(te_harmonics(_TE(np.where(np.arange(M + 1) == 3, np.nan, te)))).all()  # not converged there


def test_harmonics_of_a_run_keep_its_power(pair):
    """Parseval: the TE's variance over the cycle is the power of orders 1..M/2 - 1 plus the Nyquist term."""
    r = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(positions=13, grid=(7, 9), tooth_model="plate"))
    te = r.loaded_te[:-1]
    M = te.size  # 12: orders 1-5 reported, 6 is the Nyquist order
    h = te_harmonics(r)
    assert np.all(np.isfinite(h[:5])) and np.isnan(h[5])
    nyquist = abs(np.sum(te * (-1.0) ** np.arange(M))) / M
    assert np.sum(h[:5] ** 2) / 2 + nyquist ** 2 == pytest.approx(np.var(te), rel=1e-9)
    d = r.to_json()
    assert d["te_harmonics_mesh_orders"] == list(MESH_ORDERS)
    assert d["te_harmonics_um"][0] == pytest.approx(h[0] * gear_base_radius_mm(pair.geometry) * 1e3)
    # the stiffness over the same N - 1 states as the harmonics: the end state (the first a pitch later) once
    k = r.mesh_stiffness_n_per_um
    assert k[-1] == pytest.approx(k[0], rel=1e-3) and np.all(np.isfinite(k))
    assert d["mesh_stiffness_mean_n_per_um"] == pytest.approx(np.mean(k[:-1]), rel=1e-12)
    assert d["mesh_stiffness_peak_to_peak_n_per_um"] == pytest.approx(np.ptp(k[:-1]), rel=1e-12)


class _Stiffness(_TE):
    """A run whose only numbers are its loaded TE and its mesh stiffness (what ``summary`` reads of them)."""

    def __init__(self, k):
        super().__init__(np.zeros(len(k)))
        self.mesh_stiffness_n_per_um = np.asarray(k, float)
        self.loaded_te_peak_to_peak = 0.0
        self.pair_max_pressure_mpa = self.pair_edge_max_pressure_mpa = np.full((len(k), 1), np.nan)
        self.pair_load_n, self.converged = np.ones((len(k), 1)), np.isfinite(self.mesh_stiffness_n_per_um)

    def root_stress_max_mpa(self):
        return {}


def test_mesh_stiffness_counts_the_repeated_end_state_once():
    # one cycle sampled at 4 states, the 5th the first a pitch later: mean 2.5, not (10 + 1) / 5 = 2.2
    s = summary(_Stiffness([1.0, 2.0, 3.0, 4.0, 1.0]))
    assert s["mesh_stiffness_mean_n_per_um"] == 2.5 and s["mesh_stiffness_peak_to_peak_n_per_um"] == 3.0
    assert math.isnan(summary(_Stiffness([1.0, np.nan, np.nan, 5.0]))["mesh_stiffness_peak_to_peak_n_per_um"])


def _cli(capsys, *args):
    rc = cli.main(["ltca", str(CASE1), "--positions", "4", "--grid", "7x9", "--tooth-model", "plate", *args])
    out, err = capsys.readouterr()
    return rc, out, err


def test_torque_map_entries_are_the_single_runs(capsys, tmp_path):
    rc, out, _ = _cli(capsys, "--torque-nm", "80,300", "--json", "--csv", str(tmp_path / "dyn"))
    assert rc == 0
    d = json.loads(out)
    m = d["torque_map"]
    assert m["torque_nm"] == [80.0, 300.0] and len(d["map"]) == 2
    for i, t in enumerate((80, 300)):
        rc, single, _ = _cli(capsys, "--torque-nm", str(t), "--json")
        s = json.loads(single)
        e = d["map"][i]
        assert e["loaded_transmission_error_urad"] == pytest.approx(s["loaded_transmission_error_urad"], rel=1e-9)
        assert m["te_peak_to_peak_urad"][i] == pytest.approx(s["loaded_transmission_error_peak_to_peak_urad"],
                                                             rel=1e-9)
        top = max(v for row in s["pair_max_pressure_mpa"] for v in row if v is not None)
        assert m["max_pressure_mpa"][i] == pytest.approx(top, rel=1e-9)
        assert m["mesh_stiffness_mean_n_per_um"][i] == pytest.approx(s["mesh_stiffness_mean_n_per_um"], rel=1e-9)
    assert m["root_stress_max_mpa"] == {"pinion": [None, None], "gear": [None, None]}  # the plate has no fillet
    with open(tmp_path / "dyn" / "ltca.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 4
    assert all(any(name.endswith(u) for u in ("_nm", "_rad", "_urad", "_um", "_n_per_um", "_n"))
               for name in rows[0] if name not in ("position", "status"))
    assert float(rows[5]["loaded_te_urad"]) == pytest.approx(d["map"][1]["loaded_transmission_error_urad"][1])
    assert float(rows[5]["pair_0_load_n"]) == pytest.approx(d["map"][1]["pair_normal_load_n"][1][1])


def test_tolerance_sets_are_sweeps_draws_and_equal_plain_runs(capsys, pair):
    rc, out, _ = _cli(capsys, "--torque-nm", "150", "--samples", "3", "--seed", "5", "--tolerances",
                      "dx=0.05,dy=0.05,dz=0.05,vertical=0.02,horizontal=0.01", "--json")
    assert rc == 0
    t = json.loads(out)["tolerance"]
    assert t["samples"] == 3 and t["seed"] == 5 and len(t["sets"]) == 3
    draws = sweep.draw_errors(3, ranges={"dx_mm": 0.05, "dy_mm": 0.05, "dz_mm": 0.05, "vertical_deg": 0.02,
                                         "horizontal_deg": 0.01}, seed=5, nominal={})
    for s, e in zip(t["sets"], draws):
        assert [s["errors"][k] for k in ("dx_mm", "dy_mm", "dz_mm")] == pytest.approx(e[:3], rel=1e-12)
        assert math.radians(s["errors"]["vertical_deg"]) == pytest.approx(e[3], rel=1e-12)
    one = ltca.analyze(pair, ltca.LoadCase(150.0, errors=tuple(draws[2])), ltca.Options(positions=4, grid=(7, 9), tooth_model="plate"))
    assert t["sets"][2]["te_peak_to_peak_urad"] == pytest.approx(one.loaded_te_peak_to_peak * 1e6, rel=1e-9)
    assert t["sets"][2]["max_pressure_mpa"] == pytest.approx(np.nanmax(one.pair_max_pressure_mpa), rel=1e-9)
    ptp = [s["te_peak_to_peak_urad"] for s in t["sets"]]
    assert t["te_peak_to_peak_urad"]["max"] == pytest.approx(max(ptp))
    assert t["te_peak_to_peak_urad"]["p50"] == pytest.approx(np.median(ptp))


@pytest.mark.parametrize("args, words", [
    (["--torque-nm", "100,abc"], "--torque-nm"),
    (["--torque-nm", "100,-5"], "--torque-nm"),
    (["--torque-nm", "100", "--samples", "-1"], "--samples"),
    (["--torque-nm", "100", "--samples", "2", "--tolerances", "dq=1"], "--tolerances"),
])
def test_bad_flags_are_one_line(capsys, args, words):
    try:
        rc, _, err = _cli(capsys, *args)
    except SystemExit as exc:  # argparse's own refusals
        rc, err = exc.code, capsys.readouterr().err
    assert rc == 2 and words in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_the_rigid_mesh_study_gets_the_solver_itself(monkeypatch, pair):
    """Issue 42: the Solver (backend and tolerances), not its backend's name."""
    import threading

    from beveloid.ltca.passes import cycle
    from beveloid.solver import Solver, SolverOptions

    seen = []
    real = cycle.mesh_paths
    me = threading.get_ident()

    def spy(*args, **kwargs):
        if threading.get_ident() == me:  # not conftest's warm-up of the compiled kernels on its thread
            seen.append(kwargs.get("solver"))
        return real(*args, **kwargs)

    monkeypatch.setattr(cycle, "mesh_paths", spy)
    solver = Solver(options=SolverOptions(tol_mm=1e-11, max_iter=30))
    cycle.Setup(pair.geometry, "right", np.zeros(5), 3, 3, solver)
    cycle.setups(pair.geometry, "right", [np.zeros(5)] * 2, 3, 3, solver)
    assert seen == [solver, solver]


def test_the_compiled_and_interpreted_contact_kernels_agree(monkeypatch):
    from beveloid.ltca.mechanics import halfspace, kernel
    from beveloid.ltca.mechanics.lcp import solve_contact

    cells = halfspace.tensor_grid(np.linspace(-1, 1, 8), np.linspace(-2, 2, 10))
    c = halfspace.influence_matrix_mm_per_mpa(cells, 1.1e5)
    h = 0.01 * cells.x_mm ** 2 + 0.002 * cells.y_mm ** 2

    def solved():
        return solve_contact([c, c], np.concatenate([h, h + 1e-4]), np.tile(cells.area_mm2, 2), 200.0)

    b = solved()  # the compiled twin (numba installed)
    with monkeypatch.context() as m:
        m.setattr(kernel, "kernels", lambda solver=None: kernel)  # this module, interpreted
        a = solved()
    assert a.converged and b.converged and a.iterations == b.iterations
    assert np.allclose(a.pressure_mpa, b.pressure_mpa, rtol=1e-10, atol=1e-10 * a.pressure_mpa.max())


def test_a_pass_started_from_the_previous_ones_contact_set_solves_the_same(monkeypatch, pair):
    """The result and check passes start from the previous pass's contact set mapped onto their grids
    (cycle.mapped_contact); the solution of the contact problem does not depend on the start: the same
    numbers as from the uncoupled estimate, in fewer iterations."""
    from beveloid.ltca.passes import cycle

    warm = ltca.analyze(pair, ltca.LoadCase(150.0), ltca.Options(**SMALL))
    with monkeypatch.context() as m:
        m.setattr(cycle, "mapped_contact", lambda source, grid, gap: np.zeros_like(gap.in_flank))
        cold = ltca.analyze(pair, ltca.LoadCase(150.0), ltca.Options(**SMALL))
    for name in ("loaded_te", "pair_load_n", "pair_max_pressure_mpa", "mesh_stiffness_n_per_um"):
        _same(getattr(warm, name), getattr(cold, name), rtol=1e-10)
    assert np.array_equal(warm.convergence.pressure_change, cold.convergence.pressure_change, equal_nan=True)
    assert warm.iterations.sum() < cold.iterations.sum()


def test_a_torque_starts_from_the_contact_set_of_the_torque_before(monkeypatch, pair):
    """The first and the result pass run in waves, each position started from the same error set's contact
    set at the torque before, at the first torque from the first error set's, cell for cell
    (analysis._torque_after_torque): the numbers of each (error set, torque) analysed alone, bit for bit, in
    fewer iterations."""
    from beveloid.ltca.passes import cycle

    options = ltca.Options(**SMALL)
    errors = [(0.0, 0.0, 0.0, 0.0, 0.0), (0.02, 0.0, 0.01, 0.0, 0.0)]
    spent = []
    real = cycle.kernel.kernels

    def counted(solver=None):
        k = real(solver)

        class Counting:
            def __getattr__(self, name):
                return getattr(k, name)

            def solve_positions(self, layout, cells, start, out):
                k.solve_positions(layout, cells, start, out)
                spent.append(int(out.result[:, 1].sum()))
        return Counting()

    monkeypatch.setattr(cycle.kernel, "kernels", counted)
    both = ltca.analyze_many(pair, ltca.LoadCase([100.0, 300.0], errors=errors), options, convergence=False).results
    together = sum(spent)
    spent.clear()
    for k, e in enumerate(errors):
        for t, torque in enumerate((100.0, 300.0)):
            alone = ltca.analyze_many(pair, ltca.LoadCase([torque], errors=[e]), options, convergence=False).results[0][0]
            for name in ("loaded_te", "pair_load_n", "pressure_mpa", "pair_root_stress_mpa", "mesh_stiffness_n_per_um"):
                a, b = getattr(both[k][t], name), getattr(alone, name)
                if isinstance(a, dict):
                    assert all(np.array_equal(a[m], b[m], equal_nan=True) for m in a)
                else:
                    np.testing.assert_array_equal(a, b)
    assert together < sum(spent)


def test_a_mapped_contact_set_follows_the_cells_in_the_tangent_plane():
    """The same grid maps onto itself; a grid moved across by one cell of the source maps the set moved
    by one cell; twice the cells, each source cell becomes 2 x 2 cells; off-flank cells never start."""
    from beveloid.ltca.passes import cycle
    from beveloid.ltca.model import gaps
    from beveloid.ltca.model.grid import PairGrid

    nx, ny = 5, 7
    src_grid = PairGrid(nx, ny, np.full((1, 1), 1.0), np.full((1, 1), 3.5))
    loaded = np.zeros((nx, ny), bool)
    loaded[1:3, 2:5] = True
    shift = np.linspace(-0.1, 0.1, ny)[None, None, :]

    def gap(grid, columns_shift):
        g = gaps.empty_gap(1, 1, grid.cells, grid.along_cells)
        return g._replace(in_flank=np.ones_like(g.in_flank), across_shift_mm=columns_shift + np.zeros((1, 1, 1)))

    src_gap = gap(src_grid, shift)
    src = cycle.Solution(grid=src_grid, gap=src_gap, pressure_mpa=np.where(loaded, 1.0, 0.0).reshape(1, 1, -1),
                         converged=np.ones(1, bool), no_contact=np.zeros(1, bool), rotation_rad=np.zeros(1),
                         approach_mm=np.zeros(1), iterations=np.zeros(1, int),
                         complementarity_residual=np.zeros(1), load_residual=np.zeros(1))
    same = cycle.mapped_contact(src, src_grid, src_gap).reshape(nx, ny)
    assert np.array_equal(same, loaded)
    moved = cycle.mapped_contact(src, src_grid, gap(src_grid, shift + 2.0 / nx)).reshape(nx, ny)
    assert np.array_equal(moved[:-1], loaded[1:]) and not moved[-1].any()
    fine = PairGrid(2 * nx, 2 * ny, src_grid.across_half_mm, src_grid.along_half_mm)
    fine_gap = gap(fine, np.repeat(shift, 2, axis=-1))
    got = cycle.mapped_contact(src, fine, fine_gap).reshape(2 * nx, 2 * ny)
    assert np.array_equal(got, np.repeat(np.repeat(loaded, 2, axis=0), 2, axis=1))
    off = fine_gap._replace(in_flank=np.zeros_like(fine_gap.in_flank))
    assert not cycle.mapped_contact(src, fine, off).any()
    not_converged = src._replace(converged=np.zeros(1, bool))
    assert not cycle.mapped_contact(not_converged, fine, fine_gap).any()


def test_column_offsets_resampled_onto_a_coarser_grid_of_the_same_extent():
    """The check grid's along-columns take the result grid's offsets, linearly interpolated at its own
    column centres: a linear function of the along coordinate is kept exactly; a kink is not invented."""
    from beveloid.ltca.model.grid import centres, resample_along

    y17, y11 = centres(1.0, 17), centres(1.0, 11)
    a = np.stack([0.3 - 2.0 * y17, np.abs(y17)])
    got = resample_along(a, 11)
    assert np.allclose(got[0], 0.3 - 2.0 * y11, rtol=0, atol=1e-14)
    assert np.all(got[1] >= np.abs(y11) - 1e-14) and np.all(got[1] <= np.abs(y11) + 2 / 17)


def test_the_loaded_contact_ratio_counts_the_pairs_that_carry_load(capsys):
    """issue 60: the loaded contact ratio is the mean number of tooth pairs carrying load over the cycle's
    distinct converged states, in the JSON and the table."""
    from types import SimpleNamespace

    from beveloid.ltca.results.batch import loaded_contact_ratio

    loads = [[0.0, 10.0, 0.0], [5.0, 5.0, 0.0], [0.0, 3.0, 1e-9], [1.0, 1.0, 1.0], [0.0, 10.0, 0.0]]
    r = SimpleNamespace(pair_load_n=np.array(loads), converged=np.array([True, True, True, False, True]))
    assert loaded_contact_ratio(r) == (1 + 2 + 1) / 3  # the 4th did not converge, the 5th is the 1st again
    rc, out, _ = _cli(capsys, "--torque-nm", "300", "--json")
    d = json.loads(out)
    count = [sum(1 for v in row if v and v > 1e-6 * sum(x or 0 for x in row)) for row in d["pair_normal_load_n"][:-1]]
    assert rc == 0 and d["loaded_contact_ratio"] == pytest.approx(sum(count) / len(count), abs=1e-12)
    assert 1.0 <= d["loaded_contact_ratio"] <= 3.0
    _, text, _ = _cli(capsys, "--torque-nm", "300")
    assert f"loaded contact ratio: {d['loaded_contact_ratio']:.3f}" in text


def test_the_plot_of_a_tolerance_box_draws_its_sets(capsys, tmp_path, monkeypatch):
    """issue 60: `ltca --samples K --plot` drew only the file's errors, titled "all errors 0": its title now
    says it is the file's errors and names the figure of the K sets, which is written beside it."""
    from beveloid.ltca.results import plots

    titles = []
    real = plots.ltca_summary
    monkeypatch.setattr(plots, "ltca_summary", lambda *a, title="", **k: (titles.append(title), real(*a, title=title,
                                                                                                      **k))[1])
    out = tmp_path / "box.png"
    rc, _, _ = _cli(capsys, "--torque-nm", "300", "--samples", "2", "--plot", str(out))
    assert rc == 0 and out.is_file()
    assert (tmp_path / "box_tolerance.png").read_bytes()[:4] == b"\x89PNG"
    assert "the file's errors" in titles[0] and "2 error sets: box_tolerance.png" in titles[0]


def test_the_tolerance_box_analyses_the_file_errors_as_one_task_per_torque(pair):
    """``tolerance_box(..., nominal=load)``: the analyses at the file's errors (patterns included) run as more
    tasks beside the chunks, on workers one per torque (the main process of ``ltca --samples`` runs none;
    issue 59: one task of every torque was the box's longest), without workers one task of every torque; the
    same numbers as ``analyze_many`` of all the torques at once either way (but the active-set iterations of
    a torque analysed alone: in one call a torque starts from the torque before it); the rows the same as
    without it."""
    options = ltca.Options(**SMALL)
    load = ltca.LoadCase([150.0, 300.0])
    draws = np.array([[0.01, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.02, 0.0, 0.0]])
    ran = []
    real = ltca.studies.nominal_results

    def counted(task):
        ran.append(task)
        return real(task)

    import unittest.mock

    with unittest.mock.patch.object(ltca.studies, "nominal_results", counted):
        results, rows = ltca.studies.tolerance_box(pair, load.at(errors=draws), options, nominal=load)
    # here (no workers) one task of every torque; on workers one a torque (each analysed alone: the same numbers)
    assert [task[1].torques_nm for task in ran] == [(150.0, 300.0)]
    on_workers = ltca.studies._box_tasks(pair, load.at(errors=draws), options, load, parallel=True)
    assert [t[2].torques_nm for t in on_workers if t[0] == "nominal"] == [(150.0,), (300.0,)]
    alone = [ltca.studies.nominal_results(t[1:])[0] for t in on_workers if t[0] == "nominal"]
    plain = ltca.studies.tolerance_box(pair, load.at(errors=draws), options)
    assert [[r["te_peak_to_peak_urad"] for r in row] for row in rows] == \
        [[r["te_peak_to_peak_urad"] for r in row] for row in plain]
    direct = ltca.analyze_many(pair, load, options).results[0]
    assert len(results) == len(direct) == len(alone) == 2
    for a, b in [*zip(results, direct), *zip(alone, direct)]:
        assert a.torque_nm == b.torque_nm
        np.testing.assert_array_equal(a.loaded_te, b.loaded_te)
        np.testing.assert_array_equal(a.pressure_mpa, b.pressure_mpa)
        ja, jb = a.to_json(), b.to_json()
        ja["solver"].pop("iterations"), jb["solver"].pop("iterations")
        assert json.dumps(ja) == json.dumps(jb)  # every other number it reports, to the last bit
        assert set(a.patterns) == {"pinion", "gear"}


def test_the_solver_says_which_backend_runs_the_contact_kernel_and_why():
    """The LTCA's dense kernel follows Solver.dense_backend (compiled wherever numba is installed,
    whatever the TCA backend), and the solver says why it does not follow its backend."""
    from beveloid.ltca.mechanics import kernel
    from beveloid.solver import DENSE_BACKEND_WHY, Solver, backends

    numpy_solver, default = Solver("numpy"), Solver()
    assert numpy_solver.dense_backend == default.dense_backend == ("compiled" if backends.AVAILABLE else "numpy")
    assert kernel.kernels(numpy_solver) is kernel.kernels(default)
    assert (kernel.kernels(numpy_solver) is kernel) == (numpy_solver.dense_backend == "numpy")
    assert "100x slower" in DENSE_BACKEND_WHY


def test_without_the_convergence_indicator_every_other_number_is_the_same(pair):
    """``analyze_many(..., convergence=False, along_face=False)`` (what the tolerance box and optimize run:
    they report no grid-convergence indicator and no root stress along the face) leaves out the
    once-coarsened solve and the fillet along the face: ``convergence`` nan, no "grid not converged"
    warning, ``root_stress_along_face`` empty, every other array of every result bit-identical to the full
    analysis; the box's rows are those of the full analyses' summaries.  (The plate tooth here, which has
    no fillet: the FE tooth's in tests/fe/test_fe_ltca.py.)"""
    import dataclasses

    options = ltca.Options(**SMALL)
    load = ltca.LoadCase([80.0, 300.0], errors=[(0.0, 0.0, 0.0, 0.0, 0.0), (0.02, 0.0, -0.01, 0.0, 0.0)])
    full = ltca.analyze_many(pair, load, options).results
    lean = ltca.analyze_many(pair, load, options, convergence=False, along_face=False).results
    assert any(np.isfinite(r.convergence.pressure_change).any() for row in full for r in row)
    for row_full, row_lean in zip(full, lean):
        for a, b in zip(row_full, row_lean):
            assert np.isnan(b.convergence.pressure_change).all() and np.isnan(b.convergence.load_change).all()
            assert not any("grid not converged" in w for w in b.warnings())
            assert b.root_stress_along_face == {}
            for f in dataclasses.fields(a):
                if f.name in ("convergence", "pair", "root_stress_along_face"):
                    continue
                np.testing.assert_equal(getattr(b, f.name), getattr(a, f.name), err_msg=f.name)  # nested, nan == nan
    rows = ltca.studies.tolerance_box(pair, load, options)
    assert [[r["te_peak_to_peak_urad"] for r in row] for row in rows] == \
        [[summary(r)["te_peak_to_peak_urad"] for r in row] for row in full]


def test_the_tolerance_box_hands_out_small_tasks_with_the_numbers_of_whole_batches(pair, monkeypatch):
    """Issue 59: the box's workers get TASK_SETS error sets a task, one (64 sets in tasks of 8 kept at most 8
    workers busy, in tasks of 2 the 16 workers took 3 rounds), the box without workers CHUNK_SETS; every set's
    row is bit-identical either way and to those of box_results, which batches CHUNK_SETS sets a call (a set's
    numbers do not depend on the sets analysed with it)."""
    options = ltca.Options(**SMALL)
    draws = np.array([[0.01 * k, 0.0, -0.005 * k, 0.0, 0.0] for k in range(5)])
    load = ltca.LoadCase([150.0, 300.0]).at(errors=draws)
    tasks = []
    real = ltca.studies._chunk
    monkeypatch.setattr(ltca.studies, "_chunk", lambda task: tasks.append(len(task[1].error_sets(pair))) or real(task))
    rows = ltca.studies.tolerance_box(pair, load, options)
    assert tasks == [min(5, ltca.studies.CHUNK_SETS)]  # here (no workers): CHUNK_SETS sets a task
    on_workers = ltca.studies._box_tasks(pair, load, options, parallel=True)
    assert ltca.studies.TASK_SETS < ltca.studies.CHUNK_SETS
    assert [len(t[2].error_sets(pair)) for t in on_workers] == [1, 1, 1, 1, 1]
    rows_alone = [r for t in on_workers for r in ltca.studies._chunk(t[1:])]
    whole = ltca.studies.box_results(pair, load, options)  # one call of 5 sets
    for key in ("te_peak_to_peak_urad", "max_pressure_mpa"):
        assert [[r[key] for r in row] for row in rows] == [[r[key] for r in row] for row in rows_alone] == \
            [[summary(r)[key] for r in row] for row in whole]


def test_the_setups_of_many_error_sets_are_each_sets_own(pair):
    """``cycle.setups`` (what ``analyze_many`` builds: the principal frames of every error set in one
    evaluation of the surfaces) gives every Setup array and frame of each set's own ``Setup`` bit for bit."""
    from beveloid.ltca.passes.cycle import Setup, setups
    from beveloid.solver import Solver

    sets = [(0.0, 0.0, 0.0, 0.0, 0.0), (0.02, 0.0, -0.01, 0.0, 0.0), (0.0, 0.01, 0.0, 1e-4, -1e-4)]
    together = setups(pair.geometry, "right", sets, 5, 3, Solver())
    for e, a in zip(sets, together):
        b = Setup(pair.geometry, "right", e, 5, 3, Solver())
        assert set(vars(a)) == set(vars(b))
        for key, value in vars(b).items():
            if isinstance(value, np.ndarray):
                np.testing.assert_array_equal(getattr(a, key), value, err_msg=key)
        for field, value in zip(b.frame._fields, b.frame):
            np.testing.assert_array_equal(getattr(a.frame, field), value, err_msg=field)
        assert (a.gear_sign, a.pinion_sign, a.max_along_mm) == (b.gear_sign, b.pinion_sign, b.max_along_mm)


def test_the_rigid_meshes_of_many_error_sets_are_one_call_of_the_solver_core(pair, monkeypatch):
    """``cycle.setups`` solves the rigid mesh of every error set in one call of the solver core
    (``tca.flank.mesh_paths``; it was one ``tca.mesh_flank`` a set), each set's pinion angles, unknowns,
    statuses, TE and envelope carriers those of its own ``mesh_flank`` bit for bit (also beyond
    ``tca.grid.SERIAL_MAX_SETS``, where the core runs the sets on threads)."""
    import threading

    from beveloid import tca
    from beveloid.ltca.passes.cycle import setups
    from beveloid.solver import Solver
    from beveloid.status import Status
    from beveloid.tca import flank, grid

    calls = []
    real = grid.solve_grid
    me = threading.get_ident()  # not conftest's warm-up of the compiled kernels on its thread
    monkeypatch.setattr(flank, "solve_grid", lambda *a, **k: (threading.get_ident() == me and calls.append(len(a[2])))
                        or real(*a, **k))
    sets = [(0.0, 0.0, 0.0, 0.0, 0.0), (0.02, 0.0, -0.01, 0.0, 0.0), (0.0, 0.01, 0.0, 1e-4, -1e-4)]
    setups(pair.geometry, "right", sets, 5, 3, Solver())
    assert calls == [3]
    many = np.random.default_rng(3).uniform(-1, 1, (grid.SERIAL_MAX_SETS + 2, 5)) * [0.02, 0.02, 0.02, 1e-4, 1e-4]
    many[:3] = sets
    for batch in (np.asarray(sets), many):
        m = flank.mesh_paths(pair.geometry, "right", batch, 5, 3, 1, solver=Solver())
        for k in (0, 1, 2, len(batch) - 1):
            fr = tca.mesh_flank(pair.geometry, "right", batch[k], positions=5, pairs=3, window_pitches=1, solver=Solver())
            np.testing.assert_array_equal(m.pinion_angle, fr.pinion_angle)
            np.testing.assert_array_equal(m.unknowns[k], fr.unknowns)
            np.testing.assert_array_equal(m.transmission_error[k], fr.transmission_error)
            np.testing.assert_array_equal(m.gear_angle[k], fr.gear_angle)
            np.testing.assert_array_equal(m.active[k], fr.active)
            assert tuple(Status.labels(m.code[k])) == tuple(fr.status)


def test_an_extra_case_of_a_batch_is_its_own_analysis(pair):
    """``analyze_many(..., extra=[(errors, torque)])`` (optimize's candidate: its rating's LTCA in its box's call)
    analyses each extra case in the same call, its result that case's own analysis to the last bit, the
    batch's rows unchanged."""
    import collections.abc
    import dataclasses

    options = ltca.Options(**SMALL)
    load = ltca.LoadCase([60.0, 250.0], errors=[(0.0, 0.0, 0.0, 0.0, 0.0), (0.03, -0.02, 0.01, 0.0, 0.0)])
    case = ((0.01, 0.0, 0.0, math.radians(0.02), 0.0), 400.0)
    plain = ltca.analyze_many(pair, load, options, convergence=False)
    batch = ltca.analyze_many(pair, load, options, convergence=False, extra=[case])
    alone = ltca.analyze_many(pair, ltca.LoadCase(case[1], errors=case[0]), options, convergence=False).results[0][0]
    assert plain.extra == () and len(batch.extra) == 1
    for got, want in [(batch.extra[0], alone)] + [(a, b) for ra, rb in zip(batch.results, plain.results)
                                                   for a, b in zip(ra, rb)]:
        for f in dataclasses.fields(want):
            if f.name in ("pair", "options", "iterations"):  # the active-set iterations depend on the start
                continue
            x, y = getattr(got, f.name), getattr(want, f.name)
            if isinstance(y, collections.abc.Mapping):  # the members' FrozenMaps
                assert set(x) == set(y), f.name
                for k in y:
                    np.testing.assert_equal(x[k], y[k], err_msg=f"{f.name}[{k}]")
            else:
                np.testing.assert_equal(x, y, err_msg=f.name)
