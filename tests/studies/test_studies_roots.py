"""The studies' searches (scipy.optimize): the crowning for a target TE and the edge-contact onset."""
from __future__ import annotations

import math

import pytest

from beveloid import tca
from beveloid.studies import crowning, paper


def test_amount_for_te_hits_the_target_and_says_when_it_cannot():
    target = 7.5
    amount, te = crowning.amount_for_te("case1", target, positions=101)
    assert 0.0 < amount < crowning.MAX_AMOUNT_UM
    assert te == pytest.approx(target, rel=1e-4)
    # the returned TE is the TE of the returned amount, not a leftover of the search
    assert crowning.aligned_te_urad("case1", amount, positions=101) == te
    # more crowning, more TE: the amount is where the TE crosses the target
    assert crowning.aligned_te_urad("case1", 0.9 * amount, positions=101) < target
    assert crowning.aligned_te_urad("case1", 1.1 * amount, positions=101) > target
    assert crowning.amount_for_te("case1", 1e7, positions=101) == (None, None)


def test_amount_for_te_refuses_a_jump_across_the_target(monkeypatch):
    """A TE that steps over the target (no amount reaches it) has no answer, not the step's place."""
    monkeypatch.setattr(crowning, "aligned_te_urad", lambda case, amount, *a: 5.0 if amount < 40.0 else 10.0)
    assert crowning.amount_for_te("case1", 7.5) == (None, None)
    monkeypatch.setattr(crowning, "aligned_te_urad", lambda case, amount, *a: 0.25 * amount)
    amount, te = crowning.amount_for_te("case1", 7.5)
    assert amount == pytest.approx(30.0, rel=1e-6) and te == pytest.approx(7.5, rel=1e-6)


@pytest.mark.parametrize("direction", [+1.0, -1.0])
def test_edge_onset_is_where_a_toe_or_heel_starts_to_bear(geom1, direction):
    tol = 1e-4
    onset = paper.edge_onset_offset(geom1, "right", direction, tol=tol)
    assert 0.0 < onset < 3.0 and math.isfinite(onset)
    clear = tca.DEFAULT_OPTIONS.patch_tol_mm
    assert paper.edge_face_margin(geom1, "right", direction * (onset - 2 * tol)) > clear
    assert paper.edge_face_margin(geom1, "right", direction * (onset + 2 * tol)) <= clear
