"""The rating's maxima over the mesh cycle, refined between the LTCA's positions (issue 57.4,
beveloid/rating/analysis.py ``refine_positions``, docs/rating.md "The positions check")."""
from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from beveloid import ltca, rating
from beveloid.pair import Pair
from beveloid.rating.analysis import (MAX_ADDED_EDGE_POSITIONS, MAX_ADDED_POSITIONS, REFINE_BAND, _around_maxima,
                                      refine_positions)
from beveloid.spec import spec_from_toml_bytes
from beveloid.status import LoadedStatus

#: random design R3-2 of the issue-57 audits (design K of benchmarks/rating_invariance.py): its contact
#: pressure jumps up between two positions of 10 and falls off after (a line contact inclined to its grid)
DESIGN_K = Path(__file__).resolve().parents[1] / "data" / "random_r3_2.toml"


@pytest.fixture(scope="module")
def design_k():
    return Pair.from_spec(spec_from_toml_bytes(DESIGN_K.read_bytes()))


def _rate(pair, positions, refine=True, torque_nm=130.0):
    options = rating.Options(ltca.Options(positions=positions, tooth_model="plate"), refine_positions=refine)
    return rating.analyze(pair, ltca.LoadCase(torque_nm), options)


def test_ten_positions_find_the_maximum_thirty_find(design_k):
    """Design K at 130 N m (plate tooth): 10 positions read the contact pressure maximum 12 % below 30 positions
    (434 against 495 MPa: the peak lies between two of the 10), and S_H 14 % high with the FE tooth (3.665
    against 3.206-3.249 on 20 and 30, docs/validation.md 10.1).  Refined between positions, the 10 read the
    30's maximum within 2 %, and so does S_H; the peak is at an added pinion angle, every added angle strictly
    inside the asked window (the cycle wraps: its ends are one mesh state) and none on an asked position;
    ``asked`` is the maximum over the asked positions alone, ``all`` never below it."""
    from beveloid import tca
    from beveloid.plots import pinion_angle_text

    ten, thirty = _rate(design_k, 10), _rate(design_k, 30, refine=False)
    p10, p30 = ten.loaded.surface_pressure_max_mpa, thirty.loaded.surface_pressure_max_mpa
    assert p10 == pytest.approx(p30, rel=0.02)
    s10, s30 = ten.members["pinion"].safety_pitting, thirty.members["pinion"].safety_pitting
    assert s10 == pytest.approx(s30, rel=0.02)
    check = ten.loaded.positions_check
    c = check["quantities"]["contact_pressure_max_mpa"]["pinion"]
    assert c["all"] == p10 and c["asked"] < 0.95 * p10  # what 10 positions alone read (today's 434 MPa)
    assert check["refined"] and check["rounds"] >= 1 and 0 < check["added_positions"] <= MAX_ADDED_POSITIONS + MAX_ADDED_EDGE_POSITIONS
    assert abs(c["change"]) <= check["tolerance"]
    angles = np.asarray(check["added_pinion_angles_rad"])
    assert np.all(np.diff(angles) > 0)
    assert any(pinion_angle_text(a) in ten.loaded.peak_where for a in angles), ten.loaded.peak_where
    phi = tca.mesh_angles(design_k.geometry, "right", 10, 3, 1)
    assert np.all((angles > phi[0]) & (angles < phi[-1]))
    assert np.min(np.abs(angles[:, None] - phi[None, :])) > 1e-9
    for by_member in check["quantities"].values():
        for c in by_member.values():
            assert c["all"] >= c["asked"]
    assert ten.loaded.face_load["gear"].K_H_beta == check["quantities"]["K_H_beta"]["gear"]["all"]
    assert thirty.loaded.positions_check["quantities"]["contact_pressure_max_mpa"]["pinion"]["all"] == p30


def test_the_midpoints_wrap_round_the_cycle():
    """The neighbours of a maximum at the cycle's first position are the second and the one before the last
    (phase 1 is phase 0's mesh state); a local maximum within REFINE_BAND of the largest is refined too, one
    further below it is not; positions without a value (not converged) are neither maxima nor refused as
    neighbours."""
    phase = np.linspace(0.0, 1.0, 6)  # 5 mesh states, the last one the first's
    values = np.array([10.0, 5.0, 9.5, 2.0, np.nan, 9.8])
    got = sorted((round(p, 9), round(w, 9)) for p, w in _around_maxima(phase, values))
    assert got == [(0.1, 1.0), (0.3, 0.95), (0.5, 0.95), (0.9, 1.0)]  # about phase 0 (= 1): 0.1 and 0.9; about 0.4
    low = values.copy()
    low[2] = 10.0 * (1.0 - REFINE_BAND) - 0.5
    assert sorted(round(p, 9) for p, _ in _around_maxima(phase, low)) == [0.1, 0.9]
    assert _around_maxima(phase, np.full(6, np.nan)) == []
    # a maximum's neighbours nearer than the spacing asked are not split again (REFINE_SPACING)
    assert len(_around_maxima(phase, values, spacing=0.15)) == 4 and _around_maxima(phase, values, spacing=0.25) == []


def test_an_added_angle_that_does_not_converge_gives_nothing():
    """An added pinion angle whose LTCA did not converge has no values: the maxima stay those of the asked
    positions, the check counts it, and the JSON holds no NaN."""
    pair = Pair.example("case1")
    lt = ltca.analyze(pair, ltca.LoadCase(1500.0), ltca.Options(positions=5, tooth_model="plate"))
    calls = []

    def failing(angles):
        r = ltca.analyze(pair, ltca.LoadCase(1500.0), dataclasses.replace(lt.options, angles=angles))
        calls.append(len(angles))
        return dataclasses.replace(r, status=tuple(LoadedStatus.NOT_CONVERGED for _ in angles))

    check, added = refine_positions(lt, pair.geometry, 50.0, failing)
    assert calls and check["added_not_converged"] == check["added_positions"] == sum(calls)
    for by_member in check["quantities"].values():
        for c in by_member.values():
            assert c["all"] == c["asked"] and c["change"] == 0.0
    json.dumps(check, allow_nan=False)
    from beveloid.rating.analysis import _positions_notes

    assert any("did not converge: the maxima leave them out" in n for n in _positions_notes(check))


def test_refine_positions_and_angles_are_checked_options():
    from beveloid.errors import OptionError

    with pytest.raises(OptionError, match="refine_positions"):
        rating.Options(refine_positions="yes")
    assert ltca.Options(angles=[0.1, 0.2]).positions == 2 and ltca.Options(angles=(0.3,)).angles == (0.3,)
    for bad in ([], [0.1, float("nan")], "0.1", [True], [0.1] * 401):
        with pytest.raises(OptionError, match="angles = .*: must be 1 to 400 finite pinion angles"):
            ltca.Options(angles=bad)


#: design J of benchmarks/rating_invariance.py: at 560 N m its pinion tip's edge load peaks between two of 10
#: positions (0.8-0.9 % of the mesh's load at the 10, 13-16 % at 20 and 30)
DESIGN_J = Path(__file__).resolve().parents[1] / "data" / "design_j.toml"


def test_an_edge_load_between_positions_is_found():
    """The edge rule reads every position the rating analysed, and the refinement follows each edge's load
    share: on design J at 560 N m (plate tooth, grid 7x11) 10 positions alone put 0.9 % of the mesh's load on
    the pinion's tip, under the rule's 2 %, and the verdict named the gear's tip only; refined, the 10 list
    both tips, each within 5 % of what 30 positions find, the pinion tip's share at an added angle."""
    from beveloid.rating.verdict import EDGE_SHARE

    pair = Pair.from_spec(spec_from_toml_bytes(DESIGN_J.read_bytes()))

    def edges(positions):
        lt = ltca.Options(positions=positions, tooth_model="plate", grid=(7, 11))
        r = rating.analyze(pair, ltca.LoadCase(560.0), rating.Options(lt))
        return r, {(e.member, e.edge): e for e in r.loaded.edges if e.share > EDGE_SHARE}

    ten, by_ten = edges(10)
    _, by_thirty = edges(30)
    assert set(by_ten) == set(by_thirty) == {("gear", "tip"), ("pinion", "tip")}
    for key, e in by_thirty.items():
        assert by_ten[key].share == pytest.approx(e.share, rel=0.05), key
    c = ten.loaded.positions_check["quantities"]["edge_load_share"]["pinion tip"]
    assert c["asked"] < EDGE_SHARE < c["all"] == by_ten["pinion", "tip"].share
    assert by_ten["pinion", "tip"].pinion_angle_rad in ten.loaded.positions_check["added_pinion_angles_rad"]
    v = ten.verdict()
    assert [(o["member"], o["edge"]) for o in v["edge_contact"]["also"]] == [("pinion", "tip")]
    assert "the tip of the pinion" in v["line"]
