"""Names as enums that still read as the strings (beveloid.names), and errors decided by type and code
(beveloid.errors), not by their message text."""
from __future__ import annotations

import json

import pytest

from beveloid import tca
from beveloid.design import DesignError, Outcome, design
from beveloid.errors import ErrorCode, OptionError, UserError
from beveloid.names import FLANKS, MEMBERS, Flank, Member
from beveloid.spec import load_example, spec_from_dict, spec_to_dict


def test_members_and_flanks_are_their_strings(pair1):
    assert Member.PINION == "pinion" and Flank.RIGHT == "right"
    assert f"{Member.GEAR}.teeth" == "gear.teeth" and json.dumps({Flank.LEFT: Member.PINION}) == '{"left": "pinion"}'
    assert [str(m) for m in MEMBERS] == ["pinion", "gear"] and list(FLANKS) == list(tca.FLANKS)
    assert (Member.PINION.index, Member.GEAR.index) == (1, 2)
    assert (Flank.LEFT.sigma, Flank.RIGHT.sigma) == (1, -1)
    # string code and enum code reach the same member
    assert pair1.geometry.member(Member.GEAR) is pair1.geometry.member("gear")
    assert {"pinion": 1}[Member.PINION] == 1


def test_errors_carry_codes_and_fields():
    assert UserError("x").code is ErrorCode.BAD_INPUT
    err = OptionError("positions", 0, "must be an integer from 1 to 100000")
    assert isinstance(err, UserError) and err.code is ErrorCode.OUT_OF_RANGE
    assert str(err) == "positions = 0: must be an integer from 1 to 100000"
    assert err.for_flag("--positions") == "--positions = 0: must be an integer from 1 to 100000"
    assert err.for_flag("--grid", shown="2x40") == "--grid = 2x40: must be an integer from 1 to 100000"
    with pytest.raises(OptionError) as info:
        tca.Options(positions=0)
    assert info.value.key == "positions" and info.value.value == 0


def test_a_refused_design_names_its_outcome():
    d = spec_to_dict(load_example("case1"))
    d["pair"]["offset_mm"] = 1.0  # Eq 17 has a root, but P falls off the active profile
    with pytest.raises(DesignError) as info:
        design(spec_from_dict(d))
    assert info.value.code is ErrorCode.DESIGN_REFUSED
    assert info.value.outcome is Outcome.PITCH_POINT_OFF_ACTIVE_PROFILE
    assert info.value.outcome.label == "pitch_point_off_active_profile"
