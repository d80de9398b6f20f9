"""rating's verdict with the scuffing criterion: a pair whose scuffing safety is below [rating] S_Bmin
fails, whatever its strength."""
import pytest

from beveloid import ltca, rating
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict

STRONG = dict(pinion_root_stress_limit_mpa=5000.0, gear_root_stress_limit_mpa=5000.0,
              pinion_contact_stress_limit_mpa=10000.0, gear_contact_stress_limit_mpa=10000.0)


def rated(cases, stage):
    spec = cases.spec_dict(material=STRONG, rating=dict(pinion_speed_rpm=1500.0, S_Bmin=1.2),
                           lubricant=dict(fzg_load_stage=stage))
    pair = Pair.from_spec(spec_from_dict(spec))
    return rating.analyze(pair, ltca.LoadCase(200.0), rating.Options(ltca.Options(flank="left", tooth_model="plate")))


@pytest.fixture(scope="module")
def weak_oil(cases):
    return rated(cases, 4)  # theta_S = 80 + 2.25 X_L 16: about 111 C


def test_scuffing_fails_a_strong_pair(weak_oil):
    v = weak_oil.verdict()
    strength = [c for c in v["criteria"] if c["kind"] in ("S_F", "S_H") and c["governs"]]
    assert strength and all(c["meets"] for c in strength)  # it would pass on its strength
    scuff = [c for c in v["criteria"] if c["kind"] == "S_B"]
    assert len(scuff) == 1 and scuff[0]["value"] < 1.2 and scuff[0]["meets"] is False
    assert v["status"] == "fails" and v["passes"] is False and v["exit_status"] == 3
    assert "S_B FAILS" in v["line"]
    assert weak_oil.to_json()["tribology"]["scuffing_safety"] == pytest.approx(scuff[0]["value"])
    film = [c for c in v["criteria"] if c["kind"] == "lambda"]  # reported beside it, not judged
    assert len(film) == 1 and film[0]["value"] == pytest.approx(weak_oil.tribology.lambda_min)
    assert film[0]["governs"] is False and film[0]["meets"] is None


def test_a_scuffing_resistant_oil_passes(cases, weak_oil):
    v = rated(cases, 14).verdict()
    scuff = [c for c in v["criteria"] if c["kind"] == "S_B"]
    weak = [c for c in weak_oil.verdict()["criteria"] if c["kind"] == "S_B"][0]
    assert scuff[0]["meets"] is True and scuff[0]["value"] > weak["value"]
    assert v["status"] != "fails"
