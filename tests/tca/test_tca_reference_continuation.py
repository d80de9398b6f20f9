"""The TE reference (the aligned contact at the pitch point) of a flank whose modification moves the
contact far from P (issue 60.7): a full Newton from P diverged (residual 8.6e10 mm) and `tca`/`ltca`
called it the user's error "no contact at the pitch point"; now the contact is followed from the
unmodified flank along the modification's amplitude."""
from __future__ import annotations

import tomllib

import numpy as np
import pytest

from beveloid import cli, tca
from beveloid.pair import Pair
from beveloid.spec import example_text
from beveloid.tca.contact import evaluate

#: case 1 at module 2 (offset scaled with it), 30 mm faces, 8 um lead crowning and a steep lead slope
SMALL = {"pair": {"normal_module_mm": 2.0, "offset_mm": 229.0 / 3},
         "pinion": {"face_width_mm": 30.0, "lead_crowning_um": 8.0}, "gear": {"face_width_mm": 30.0}}


def _spec(slope_um):
    d = tomllib.loads(example_text("case1"))
    for sec, keys in SMALL.items():
        d[sec].update(keys)
    d["pinion"]["lead_slope_um"] = slope_um
    d["misalignment"]["vertical_deg"] = 0.06
    return d


def _toml(d, path):
    lines = []
    for sec, keys in d.items():
        lines.append(f"[{sec}]")
        lines += [f'{k} = "{v}"' if isinstance(v, str) else f"{k} = {v!r}" for k, v in keys.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_steep_lead_slope_has_its_reference_and_its_edge_contact(tmp_path, capsys):
    geom = Pair.from_spec(_spec(80.0)).geometry
    ref = tca.reference_contact(geom, "right")
    s = evaluate(geom, "right", ref.x, ref.pinion_angle, np.zeros(5))
    assert np.linalg.norm(s.residual) < 1e-6  # a contact of the modified flanks, not a diverged iterate
    assert tca.pitch_point_notes(geom, "right")  # off the active flank: said, as for any design
    assert cli.main(["tca", str(_toml(_spec(80.0), tmp_path / "s80.toml")), "--positions", "12",
                     "--flank", "right", "--json"]) == 0
    import json

    st = json.loads(capsys.readouterr().out)["flanks"]["right"]["status"]
    assert "edge" in st  # the contact the slope moves to: the face end


def test_a_modification_that_moves_it_off_the_flank_says_so(tmp_path, capsys):
    assert cli.main(["tca", str(_toml(_spec(120.0), tmp_path / "s120.toml")), "--positions", "12"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "more than a face width): reduce the modification" in err
    assert "residual" not in err


@pytest.mark.parametrize("slope", [-60.0, 60.0])
def test_moderate_slopes_are_untouched(slope, monkeypatch):
    """Where Newton from P converges, the continuation is not used."""
    from beveloid.tca import reference

    monkeypatch.setattr(reference, "_along_the_modification", lambda *a: pytest.fail("continuation used"))
    reference.reference_contact.cache_clear()
    geom = Pair.from_spec(_spec(slope)).geometry
    assert np.isfinite(tca.reference_contact(geom, "right").x).all()


#: a rotating-seed draw of the slow tier's CLI fuzz (seed 18508): case 1 with a 164 um lead slope on the pinion
#: and deeper cutters; Newton from the pitch point converged (on the machine that found it), without the
#: continuation, to a root of the right flanks' extension 3250 mm beyond the pinion's toe: the flanks' reference
#: contacts then opened the gear the same way and the backlash raised (tests/tca/test_tca_backlash_inconsistent_flanks.py)
FAR_ROOT = {"pair": {"offset_mm": 237.69778752093393},
            "pinion": {"lead_slope_um": 164.32059409845374, "cutter_tip_radius_coefficient": 0.0,
                       "cutter_addendum_coefficient": 1.4274888914824064},
            "gear": {"cutter_tip_radius_coefficient": 0.0, "cutter_addendum_coefficient": 1.2115731385778412},
            "misalignment": {"horizontal_deg": -2.00001}}


def test_the_fuzz_spec_gives_an_answer_or_one_line(tmp_path, capsys):
    import json

    d = tomllib.loads(example_text("case1"))
    for sec, keys in FAR_ROOT.items():
        d[sec].update(keys)
    rc = cli.main(["tca", str(_toml(d, tmp_path / "far.toml")), "--positions", "5", "--pairs", "1", "--json"])
    out, err = capsys.readouterr()
    if rc == 2:  # where Newton from P does not converge there: the continuation's "more than a face width"
        assert err.count("\n") == 1 and out == ""
        return
    assert rc == 0
    res = json.loads(out)  # strict JSON: no NaN
    assert res["backlash_um"] is None and res["backlash_status"] in ("failed", "outside")
    assert all(s is None or np.isfinite(s) for s in res["te_peak_to_peak_urad"].values())
