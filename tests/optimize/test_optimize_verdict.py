"""beveloid optimize's constraint is `beveloid rating`'s verdict (issue 60): a candidate whose rating is
CONDITIONAL (an unrelieved tip carrying an edge pressure above the edge-contact rule) is not feasible,
and every pareto_<n>.toml passes the rating command its header names.

The pair is the issue's (m_n 3, 19/43 teeth, 8 deg shaft angle, 92 mm offset); cheap: plate tooth,
3 positions, 100 N m, where the pinion's unrelieved tip carries an edge peak of about 2600 MPa."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from beveloid import ltca
from beveloid.cli import main
from beveloid.optimize import evaluate, search
from beveloid.optimize.request import Request, Vary
from beveloid.status import Verdict

PAIR = (Path(__file__).resolve().parents[1] / "data" / "issue60_pair.toml").read_text()
KEY = "pinion.tip_relief_um"
TORQUE = 100.0
QUICK = ["--tooth-model", "plate", "--positions", "3"]


def _request(**kw):
    import tomllib

    return Request(base=tomllib.loads(PAIR), varies=(Vary(KEY, 0.0, 30.0),), torques_nm=(TORQUE,), weights=(1.0,),
                   ltca=ltca.Options(positions=3, tooth_model="plate"), constraints="rating", **kw)


def test_a_conditional_verdict_is_not_feasible():
    """Unrelieved, the pinion's tip carries an edge peak above sigma_Hlim Z_NT / S_Hmin while every safety
    is met: `rating` says CONDITIONAL, and so the optimiser must not call it feasible (it did: its
    constraint was the local safeties alone); 18 um of tip relief passes both."""
    from beveloid.pair import Pair

    req = _request()
    bare = evaluate.safeties(req, Pair.from_spec(req.spec({KEY: 0.0})))
    assert bare["safety_pitting_local"] >= bare["S_Hmin"]  # the safeties alone would pass it
    assert "CONDITIONAL, passes only if the tip of the pinion is relieved" in bare["verdict"]
    assert bare["feasible"] is False
    assert bare["verdict_status"] == Verdict.CONDITIONAL and bare["shortfall"] > 0
    rec = {"status": "ok", "objectives": {q: 1.0 for q in req.quantities}, "safety": bare}
    assert search.told(req, rec)[1][0] > 0  # the search is told it violates its constraint
    relieved = evaluate.safeties(req, Pair.from_spec(req.spec({KEY: 18.0})))
    assert relieved["verdict_status"] == Verdict.PASSES
    assert relieved["feasible"] is True and relieved["shortfall"] <= 0
    # candidates.csv says why the bare one is not feasible (its reason was empty)
    from beveloid.optimize import report

    assert report.row(req, {**rec, "candidate": 0, "values": {KEY: 0.0}, "per_torque": {}}, False)["reason"] == (
        "rating at 100 N m: CONDITIONAL, passes only if the tip of the pinion is relieved (tip relief)")
    assert report.row(req, {**rec, "candidate": 1, "values": {KEY: 18.0}, "per_torque": {}, "safety": relieved},
                      False)["reason"] == ""


@pytest.mark.slow
@pytest.mark.parametrize("high", [2.0, 30.0])
def test_every_pareto_spec_passes_the_rating_its_header_names(tmp_path, capsys, high):
    """An optimisation of the pinion's tip relief from the unrelieved design: each pareto_<n>.toml, rated
    by the command in its header (the highest torque of the duty cycle), passes.  Up to 2 um the tip still
    carries its edge peak (CONDITIONAL): no candidate passes, the front is empty and says so; up to 30 um
    the front is not empty."""
    spec = tmp_path / "my.toml"
    spec.write_text(PAIR)
    out = tmp_path / "opt"
    assert main(["optimize", str(spec), "--vary", f"{KEY}=0:{high:g}", "--torque-nm", f"50,{TORQUE:g}", "--budget",
                 "8", "--population", "4", "--workers", "1", "--grid", "7x9", "--out", str(out), "--json", *QUICK]) == 0
    front = json.loads(capsys.readouterr().out)["pareto"]
    assert bool(front) == (high > 2.0)
    for entry in front:
        text = (out / entry["spec_file"]).read_text()
        rating = next(c for c in text.splitlines()[2].split(": ", 1)[1].split("; ") if c.startswith("beveloid rating"))
        assert f"--torque-nm {TORQUE:g}" in rating
        args = rating.split()[1:]
        args[1] = str(out / entry["spec_file"])
        assert main(args) == 0
        verdict = json.loads(capsys.readouterr().out.splitlines()[0])["verdict"]
        assert verdict["status"] == Verdict.PASSES, (entry["values"], verdict["line"])
