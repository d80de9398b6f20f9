"""optimize's objective ``loss``: the mesh power loss of ``ltca --speed-rpm`` weighted over the duty cycle,
and its refusal without a lubricant or a speed."""
import contextlib
import io

import pytest

from beveloid import ltca, tribology
from beveloid.cli import main
from beveloid.optimize import evaluate
from beveloid.optimize.request import Request, Vary
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict

KEY = "pinion.profile_crowning_um"


def test_loss_objective_is_the_weighted_mesh_power_loss(cases):
    base = cases.spec_dict(rating=dict(pinion_speed_rpm=1500.0))
    req = Request(base=base, varies=(Vary(KEY, 0.0, 10.0),), torques_nm=(100.0, 200.0), weights=(1.0, 3.0),
                  objectives=("loss",), ltca=ltca.Options(positions=6, grid=(7, 9), tooth_model="plate", flank="left"),
                  constraints="none")
    rec = evaluate.evaluate(req, {KEY: 5.0})
    got = rec["objectives"]["mesh_power_loss_w"]
    pair = Pair.from_spec(req.spec({KEY: 5.0}))
    losses = [tribology.evaluate(ltca.analyze(pair, ltca.LoadCase(t), req.ltca), pair, 1500.0).mesh_power_loss_w
              for t in (100.0, 200.0)]
    assert got == pytest.approx((losses[0] + 3 * losses[1]) / 4, rel=1e-9)
    assert losses[0] < losses[1]


@pytest.mark.parametrize("drop, fragment", [("lubricant", "[lubricant]"), ("speed", "pinion_speed_rpm")])
def test_loss_needs_a_lubricant_and_a_speed(cases, tmp_path, drop, fragment):
    spec = cases.spec_dict(rating=dict(pinion_speed_rpm=1500.0))
    if drop == "lubricant":
        del spec["lubricant"]
    else:
        del spec["rating"]
    text = "\n".join(f"[{s}]\n" + "\n".join(f"{k} = {v!r}".replace("'", '"') for k, v in d.items())
                     for s, d in spec.items())
    spec_from_dict(spec)  # the file itself is valid
    p = tmp_path / "s.toml"
    p.write_text(text)
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        rc = main(["optimize", str(p), "--vary", f"{KEY}=0:10", "--torque-nm", "200", "--objectives", "loss",
                   "--out", str(tmp_path / "o"), "--tooth-model", "plate"])
    assert rc == 2
    assert len(err.getvalue().splitlines()) == 1 and fragment in err.getvalue()


@pytest.mark.slow  # two ratings of the pair; test_rating_scuffing holds the verdict in the fast tier
def test_scuffing_constrains_the_search(cases):
    """optimize's constraint is rating's verdict: a candidate whose oil scuffs fails it (infeasible, a
    positive shortfall), whatever its strength; with a scuffing-resistant oil the same candidate's S_B
    meets S_Bmin and the verdict does not fail (this pair's unrelieved gear tip leaves it conditional)."""
    strong = dict(pinion_root_stress_limit_mpa=5000.0, gear_root_stress_limit_mpa=5000.0,
                  pinion_contact_stress_limit_mpa=10000.0, gear_contact_stress_limit_mpa=10000.0)
    safety = {}
    for stage in (4, 14):
        base = cases.spec_dict(material=strong, rating=dict(pinion_speed_rpm=1500.0, S_Bmin=1.2),
                               lubricant=dict(fzg_load_stage=stage))
        req = Request(base=base, varies=(Vary(KEY, 0.0, 10.0),), torques_nm=(200.0,), weights=(1.0,),
                      objectives=("loss",),
                      ltca=ltca.Options(positions=6, grid=(7, 9), tooth_model="plate", flank="left"))
        safety[stage] = evaluate.evaluate(req, {KEY: 5.0})["safety"]
    assert "S_B FAILS" in safety[4]["verdict"] and safety[4]["verdict_status"] == "fails"
    assert safety[4]["feasible"] is False and safety[4]["shortfall"] > 0
    assert "S_B meets" in safety[14]["verdict"] and safety[14]["verdict_status"] != "fails"
