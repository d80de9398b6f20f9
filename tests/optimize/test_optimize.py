"""beveloid optimize: the optimiser's best against a brute-force scan, a Pareto spec reproduced by `ltca`,
the safeties by `rating`, resume and determinism, and the one-line refusals of bad --vary keys and ranges.

Cheap by construction: case 1 tilted by vertical_deg = 0.05, the plate tooth, a 7x7 grid, 3 positions,
one torque, budgets of a few candidates (one run shared by the tests of the group "optimize")."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from beveloid import ltca
from beveloid.cli import main
from beveloid.optimize import evaluate, search
from beveloid.optimize.request import Request, Vary

pytestmark = pytest.mark.xdist_group("optimize")

CASE1 = Path(__file__).resolve().parents[2] / "beveloid" / "data" / "case1.toml"
KEY = "pinion.lead_crowning_um"
LOW, HIGH = 0.0, 40.0
#: the analysis of every test here (cheap: plate tooth, 7x7 cells, 3 positions)
QUICK = ["--tooth-model", "plate", "--grid", "7x7", "--positions", "3"]
TORQUE = 200.0
#: the shared run's candidates (4 generations of 4)
BUDGET = 16


@pytest.fixture(scope="module")
def tilted(tmp_path_factory):
    """Case 1 with vertical_deg = 0.05: its contact runs onto one face end (an edge peak) unless a lead crowning
    pulls it back; more crowning than that only narrows the patch and raises the pressure."""
    text = CASE1.read_text().replace("vertical_deg = 0.0 ", "vertical_deg = 0.05")
    assert "vertical_deg = 0.05" in text
    path = tmp_path_factory.mktemp("optimize") / "tilted.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def run(tilted, tmp_path_factory):
    """One optimisation of the pinion's lead crowning for the peak pressure (8 candidates, population 4)."""
    out = tmp_path_factory.mktemp("optimize") / "out"
    args = [str(tilted), "--vary", f"{KEY}={LOW:g}:{HIGH:g}", "--torque-nm", f"{TORQUE:g}", "--objectives", "pressure",
            "--budget", str(BUDGET), "--population", "4", "--seed", "1", "--constraints", "none", "--workers", "1",
            "--out", str(out), "--json", *QUICK]
    return out, args


@pytest.fixture(scope="module")
def result(run):
    out, args = run
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
        assert main(["optimize", *args]) == 0
    return json.loads(buf.getvalue())


def test_the_best_candidate_is_the_brute_force_optimum_within_the_scan_resolution(tilted, run, result):
    """A scan over the range (step 5 um) through the same evaluation: the optimiser's best lies within one
    step of the scan's best and is no worse than the scan's points beside it."""
    import tomllib

    base = tomllib.loads(tilted.read_text())
    req = Request(base=base, varies=(Vary(KEY, LOW, HIGH),), torques_nm=(TORQUE,), weights=(1.0,),
                  objectives=("pressure",), ltca=ltca.Options(positions=3, grid=(7, 7), tooth_model="plate"), constraints="none")
    xs = np.linspace(LOW, HIGH, 9)
    f = np.array([evaluate.evaluate(req, {KEY: x})["objectives"]["max_pressure_mpa"] for x in xs])
    i = int(np.argmin(f))
    assert 0 < i < len(xs) - 1, f"the scan's optimum is not inside the range: {f}"  # a real interior optimum
    best = result["pareto"][0]
    assert len(result["pareto"]) == 1  # one objective: the front is the best
    x_best, f_best = best["values"][KEY], best["objectives"]["max_pressure_mpa"]
    assert abs(x_best - xs[i]) <= xs[1] - xs[0]
    assert f_best <= min(f[i - 1], f[i + 1])
    assert result["evaluated"] == BUDGET
    # the unmodified design (no crowning: the edge peak) is beaten
    assert f_best < result["baseline"]["objectives"]["max_pressure_mpa"]
    assert len(result["baseline"]["dominated_by"]) >= 1


def test_the_first_candidate_is_the_unmodified_design(run, result):
    """The search starts from the design it is to improve (its values inside the ranges: here no
    crowning, the range's low end), taken from the baseline's record, not computed twice."""
    out, _ = run
    first = json.loads((out / "candidates" / "000000.json").read_text())
    base = json.loads((out / "candidates" / "baseline.json").read_text())
    assert first["values"] == base["values"] == {KEY: LOW} == result["baseline"]["values"]
    assert first["objectives"] == base["objectives"] and first["candidate"] == 0
    # outside the ranges it is not a candidate: the first row is the Latin hypercube's
    req = Request(base={}, varies=(Vary(KEY, 5.0, HIGH),), torques_nm=(TORQUE,), weights=(1.0,), population=4)
    assert np.array_equal(search.initial(req, {KEY: LOW}), search.initial(req))
    assert search.initial(req, {KEY: 7.0})[0, 0] == 7.0


def test_a_pareto_spec_reproduces_its_objectives_through_ltca(run, result, capsys):
    out, _ = run
    best = result["pareto"][0]
    spec = out / best["spec_file"]
    assert main(["ltca", str(spec), "--torque-nm", f"{TORQUE:g}", *QUICK, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    peak = max(v for row in d["pair_max_pressure_mpa"] for v in row if v is not None)
    assert peak == best["objectives"]["max_pressure_mpa"]  # exactly: the same analysis of the same spec
    summary = json.loads((out / "summary.json").read_text())
    entry = summary["pareto"][0]
    assert entry["per_torque"]["te_peak_to_peak_urad"][0] == d["loaded_transmission_error_peak_to_peak_urad"]
    for name in ("candidates.csv", "pareto.csv", "pareto.png", "te_vs_torque.png", "knee_pattern.png"):
        assert (out / name).is_file()


def test_resume_recomputes_the_missing_candidates_as_the_first_run_did(run, result, tmp_path, capsys):
    """The last generation removed from a copy: --resume replays the seeded search, asks for the same
    candidates and computes the same numbers (the same candidates.csv)."""
    out, _ = run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    for i in (5, 6, 7):
        (copy / "candidates" / f"{i:06d}.json").unlink()
    (copy / "candidates.csv").unlink()
    assert main(["optimize", "--resume", str(copy), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    assert f"4/{BUDGET} candidates (4 from disk)" in err and f"8/{BUDGET} candidates (1 from disk)" in err
    assert (copy / "candidates.csv").read_text() == (out / "candidates.csv").read_text()


def test_the_tolerance_box_of_ltca_reproduces_a_candidate(tilted, capsys):
    """--samples: `beveloid ltca --torque-nm T1,T2 --samples K --seed S --tolerances ...` (the command a
    front candidate's spec names) gives each torque's 90th percentile of the candidate, to the last bit."""
    import tomllib

    from beveloid.optimize import report

    req = Request(base=tomllib.loads(tilted.read_text()), varies=(Vary(KEY, LOW, HIGH),), torques_nm=(100.0, 300.0),
                  weights=(1.0, 2.0), samples=3, seed=5, tolerances={"dx_mm": 0.05, "dy_mm": 0.05, "dz_mm": 0.05,
                                                                     "vertical_deg": 0.05, "horizontal_deg": 0.02},
                  ltca=ltca.Options(positions=3, grid=(7, 7), tooth_model="plate"), constraints="none")
    rec = evaluate.evaluate(req, {KEY: 15.0})
    path = tilted.parent / "boxed.toml"
    path.write_text(report.toml_text(report.spec_to_dict(req.spec({KEY: 15.0}))))
    command = report.reproduce_commands(req, str(path))[0].split()
    assert main(command[1:]) == 0
    d = json.loads(capsys.readouterr().out)
    for t, entry in enumerate(d["map"]):
        assert entry["tolerance"]["te_peak_to_peak_urad"]["p90"] == rec["per_torque"]["te_peak_to_peak_urad"][t]
        assert entry["tolerance"]["max_pressure_mpa"]["p90"] == rec["per_torque"]["max_pressure_mpa"][t]
    assert rec["objectives"]["te_peak_to_peak_urad"] == pytest.approx(
        (rec["per_torque"]["te_peak_to_peak_urad"][0] + 2 * rec["per_torque"]["te_peak_to_peak_urad"][1]) / 3)


def test_the_ratings_ltca_is_one_more_case_of_the_boxs_call(tilted, monkeypatch):
    """--constraints rating: the candidate's rating's LTCA (``rating.ltca_case``: the file's errors at K_A K_v T,
    the box's leave-outs) runs in its box's call of the loaded engine, not a call of its own; the record (its
    quantities, safeties, verdict) is the same to the last bit as with the rating's own LTCA.  With the grid
    check, K_v by ISO's method B (two LTCAs, the second's torque set by the first), or a run whose LTCA is not
    the rating's (its --positions or --grid: the rating keeps its own), the rating runs its own."""
    import dataclasses
    import tomllib

    from beveloid import rating
    from beveloid.pair import Pair

    req = Request(base=tomllib.loads(tilted.read_text()), varies=(Vary(KEY, LOW, HIGH),), torques_nm=(150.0, TORQUE),
                  weights=(1.0, 1.0), samples=2, seed=3,
                  ltca=ltca.Options(positions=rating.POSITIONS, tooth_model="plate"), constraints="rating")
    coarse = Request.from_json(dict(req.to_json(), ltca=dict(req.to_json()["ltca"], positions=3, grid=[7, 7])))
    assert coarse.rating_options() == req.rating_options() and evaluate._rating_case(coarse, None) is None
    calls = []
    real = ltca.analyze_many

    def spy(*a, **k):  # the calls at the mesh cycle's positions (not the rating's refinement between them)
        if k.get("options", a[2] if len(a) > 2 else None).angles is None:
            calls.append(k.get("extra", ()))
        return real(*a, **k)

    monkeypatch.setattr(ltca, "analyze_many", spy)
    batched = evaluate.evaluate(req, {KEY: 15.0})
    assert len(calls) == 1 and len(calls[0]) == 1 and calls[0][0][1] == pytest.approx(TORQUE)
    monkeypatch.setattr(evaluate, "_rating_case", lambda req, pair: None)
    alone = evaluate.evaluate(req, {KEY: 15.0})
    assert len(calls) == 3 and calls[1] == calls[2] == ()  # the box, then the rating's own
    for key in ("quantities", "safety", "objectives", "per_torque", "converged_positions", "status"):
        assert batched[key] == alone[key], key
    pair = Pair.from_spec(req.spec({KEY: 15.0}))
    assert rating.ltca_case(pair, ltca.LoadCase(TORQUE), rating.Options(req.ltca)) is None  # with the grid check
    assert rating.ltca_case(pair, ltca.LoadCase(TORQUE), req.rating_options())[1] == pytest.approx(TORQUE)
    strength = rating.analysis.Factors.with_strength
    monkeypatch.setattr(rating.analysis.Factors, "with_strength",
                        lambda *a, **k: dataclasses.replace(strength(*a, **k), K_v_source="method B"))
    assert rating.ltca_case(pair, ltca.LoadCase(TORQUE), req.rating_options()) is None


def test_the_search_is_seeded():
    req = Request(base={}, varies=(Vary(KEY, LOW, HIGH), Vary("pinion.lead_slope_um", -20.0, 20.0)),
                  torques_nm=(TORQUE,), weights=(1.0,), population=6)
    a, b = search.initial(req), search.initial(req)
    c = search.initial(Request.from_json(dict(req.to_json(), seed=2)))
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert a.shape == (6, 2) and (a[:, 0] >= LOW).all() and (a[:, 0] <= HIGH).all()


def test_the_safeties_are_the_ratings(tilted, capsys):
    """--constraints rating: a candidate's local S_H and its feasibility are what `beveloid rating` gives for
    its spec (its verdict) at the rating's own defaults, whatever the run's --positions and --grid (the
    header's rating command names neither: at the defaults of optimize it is `beveloid rating FILE
    --torque-nm T`); its rating runs on the Solver of its loaded analyses."""
    import tomllib

    from beveloid import rating
    from beveloid.optimize import report
    from beveloid.spec import spec_to_dict

    solvers, refining = [], []
    req = Request(base=tomllib.loads(tilted.read_text()), varies=(Vary(KEY, LOW, HIGH),), torques_nm=(TORQUE,),
                  weights=(1.0,), ltca=ltca.Options(positions=3, grid=(7, 7), tooth_model="plate"), constraints="rating")
    with pytest.MonkeyPatch.context() as mp:
        for module, name in ((ltca, "analyze_many"), (rating, "analyze")):
            def spy(*a, _fn=getattr(module, name), **k):
                options = k.get("options", a[2] if len(a) > 2 else None)
                (refining if getattr(options, "angles", None) is not None else solvers).append(k.get("solver"))
                return _fn(*a, **k)
            mp.setattr(module, name, spy)
        rec = evaluate.evaluate(req, {KEY: 15.0})
    # the box's analyze_many, the rating's analyze and its own LTCA (the run's 3 positions are not the rating's),
    # one Solver; and the rating's refinement between positions on it too
    assert len(solvers) == 3 and solvers[0] is not None and all(s is solvers[0] for s in solvers + refining)
    path = tilted.parent / "rated.toml"
    path.write_text(report.toml_text(spec_to_dict(req.spec({KEY: 15.0}))))
    command = report.reproduce_commands(req, str(path))[1]
    assert command == f"beveloid rating {path} --torque-nm {TORQUE:g} --flank right --tooth-model plate --json"
    rc = main(command.split()[1:])  # the rating's defaults: not the run's --positions 3 --grid 7x7
    d = json.loads(capsys.readouterr().out)
    assert rc == rating.EXIT_STATUS[d["verdict"]["status"]]
    assert rec["safety"]["safety_pitting_local"] == min(d[m]["safety_pitting"] for m in ("pinion", "gear"))
    assert rec["safety"]["safety_bending_local"] is None  # the plate has no root fillet
    assert rec["safety"]["feasible"] == (d["verdict"]["status"] == "passes")  # the verdict `rating` prints
    assert rec["safety"]["verdict"] == d["verdict"]["line"]


@pytest.mark.parametrize("vary, words", [
    ("pinion.cone_angle_deg=1:3", "macro geometry"),
    ("pair.offset_mm=220:230", "macro geometry"),
    ("misalignment.vertical_deg=0:0.1", "not a flank modification"),
    ("pinion.lead_crowning=0:40", "did you mean pinion.lead_crowning_um"),
    ("pinion.lead_crowning_um=40:0", "LOW = 40 must be below HIGH = 0"),
    ("pinion.lead_crowning_um=0:500", "HIGH = 500 must be"),
    ("pinion.lead_crowning_um=0:40:5", "LOW:HIGH"),
    ("pinion.lead_crowning_um=a:40", "must be numbers"),
    ("pinion.lead_crowning_um", "KEY=LOW:HIGH"),
])
def test_bad_vary_keys_and_ranges_get_one_line_and_exit_2(tmp_path, capsys, vary, words):
    out = tmp_path / "never"
    status = main(["optimize", str(CASE1), "--vary", vary, "--torque-nm", "100", "--out", str(out), *QUICK])
    err = capsys.readouterr().err
    assert status == 2
    assert len(err.strip().splitlines()) == 1 and words in err and "Traceback" not in err
    assert not out.exists()


@pytest.mark.parametrize("extra, words", [
    (["--vary", "pinion.tip_relief_height_mm=1:20"], "pinion.tip_relief_height_mm=1:20: HIGH = 20 is refused by the"
                                                    " spec with pinion.lead_crowning_um = 0"),
    (["--weights", "1,2"], "2 weights for 1 torques"),
    (["--objectives", "root"], "needs the FE tooth"),
    (["--objectives", "noise"], "not an objective"),
    (["--budget", "0"], "--budget = 0"),
])
def test_bad_options_get_one_line_and_exit_2(tmp_path, capsys, extra, words):
    status = main(["optimize", str(CASE1), "--vary", f"{KEY}=0:10", "--vary", "pinion.tip_relief_um=1:5", "--torque-nm", "100", "--out",
                   str(tmp_path / "never"), *QUICK, *extra])
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1 and words in err


@pytest.mark.slow
def test_a_dask_cluster_gives_the_candidates_of_one_worker(run, result, cluster, tmp_path, capsys):
    """--scheduler: the same run on a real Dask cluster (two worker processes) evaluates the same
    candidates to the last digit (the search asks for them in the same order, wherever they ran)."""
    out, args = run
    remote = tmp_path / "dask"
    argv = ["optimize", *args]
    i = argv.index("--workers")
    del argv[i:i + 2]
    argv[argv.index("--out") + 1] = str(remote)
    assert main([*argv, "--scheduler", cluster]) == 0
    summary = json.loads((remote / "summary.json").read_text())
    assert "Dask cluster" in json.dumps(summary)
    assert (remote / "candidates.csv").read_text() == (out / "candidates.csv").read_text()
    capsys.readouterr()


def test_local_workers_evaluate_the_unmodified_design_with_the_first_generation(run, result, tmp_path, monkeypatch,
                                                                                capsys):
    """--workers 2 with no FE data to make (the plate tooth): the unmodified design is one more task of the first
    generation on the workers, not evaluated here first while they wait (issue 59); the same candidates and
    baseline to the last digit as one worker's run, which evaluates it here first."""
    out, args = run
    argv = ["optimize", *args]
    argv[argv.index("--workers") + 1] = "2"
    argv[argv.index("--out") + 1] = str(tmp_path / "two")

    def not_here(*a, **k):
        raise AssertionError("the unmodified design was evaluated in the main process")

    monkeypatch.setattr(search, "evaluate", not_here)
    assert main(argv) == 0
    for name in ("candidates.csv", "candidates/baseline.json"):
        a, b = (json.loads(p.read_text()) if name.endswith(".json") else p.read_text()
                for p in (tmp_path / "two" / name, out / name))
        if name.endswith(".json"):
            a.pop("seconds"), b.pop("seconds")
        assert a == b, name
    capsys.readouterr()


def test_one_solver_per_run_not_per_candidate(tilted, monkeypatch):
    """Issue 56: every candidate of a run (here two, and the same request read back by a worker) solves with
    the request's one Solver; before, each candidate made its own."""
    import tomllib

    solvers = []
    req = Request(base=tomllib.loads(tilted.read_text()), varies=(Vary(KEY, LOW, HIGH),), torques_nm=(TORQUE,),
                  weights=(1.0,), ltca=ltca.Options(positions=3, grid=(7, 7), tooth_model="plate"), constraints="none")
    real = ltca.analyze_many

    def spy(*a, **k):
        solvers.append(k.get("solver"))
        return real(*a, **k)

    from beveloid import parallel

    monkeypatch.setattr(ltca, "analyze_many", spy)
    monkeypatch.setattr(parallel, "single_threaded", lambda: None)  # a worker's setting, not this process's
    evaluate.evaluate(req, {KEY: 10.0})
    evaluate.evaluate(req, {KEY: 20.0})
    evaluate.evaluate_task((req.to_json(), 0, {KEY: 10.0}))
    evaluate.evaluate_task((req.to_json(), 1, {KEY: 20.0}))
    assert len(solvers) == 4 and solvers[0] is solvers[1] is req.solver and solvers[2] is solvers[3]


class _LosesWorker:
    """An executor that returns the first candidate's record, then loses its worker."""

    def map_unordered(self, fn, items):
        (payload, index, values), *_ = list(items)
        yield 0, {"candidate": index, "values": values, "status": "ok", "objectives": {"pressure_mpa": 1.5}}
        from beveloid import parallel

        raise parallel.WorkLost("the Dask cluster lost a candidate (KilledWorker)")


def test_the_search_returns_a_frozen_run_whose_json_is_strict(tmp_path):
    """search.run's OptimizeRun: the records by name (not a tuple's positions), frozen all the way down,
    and its JSON a dict json.dumps takes with allow_nan=False."""
    import dataclasses

    from beveloid.errors import StopReason

    req = Request(base={}, varies=(Vary(KEY, LOW, HIGH),), torques_nm=(TORQUE,), weights=(1.0,), population=4)
    out = str(tmp_path / "opt")
    (tmp_path / "opt" / search.CANDIDATES).mkdir(parents=True)
    ran = search.run(out, req, _LosesWorker())
    assert ran.stop is StopReason.WORK_LOST and "KilledWorker" in ran.why and not ran.complete
    assert [r["candidate"] for r in ran.records] == [0] and ran.options.budget == req.budget
    with pytest.raises(dataclasses.FrozenInstanceError):
        ran.records = ()
    with pytest.raises(TypeError):
        ran.records[0]["status"] = "failed"
    got = json.loads(json.dumps(ran.to_json(), allow_nan=False))
    assert got["records"] == [json.loads((tmp_path / "opt" / search.CANDIDATES / "000000.json").read_text())]
    assert got["stop"] == str(StopReason.WORK_LOST) and got["complete"] is False
    assert got["request"] == json.loads(json.dumps(req.to_json()))
