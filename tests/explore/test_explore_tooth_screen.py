"""explore's whole-tooth statuses over a chunk at once (beveloid.tooth.screen, issue 29): the sections of
many designs equal each design's own, and the rows carry exactly the statuses and reasons of the checks
run design by design (beveloid.tooth.undercut / tip, as `beveloid design` runs them)."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.explore import contact, rows
from beveloid.explore import tooth as explore_tooth
from beveloid.explore.grid import Plan, parse_vary
from beveloid.pair import Pair
from beveloid.spec import load_example, spec_to_dict
from beveloid.sweep import DEFAULT_RANGES
from beveloid.names import MEMBERS
from beveloid.tooth import screen, sections


@pytest.fixture(scope="module")
def mixed():
    """Case 1 over pinion face width x profile shift: clear, undercut, and pointed-and-undercut designs."""
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.face_width_mm=100:1000:4"),
                                                      parse_vary("pinion.profile_shift=-0.4:0.5:3")))
    values = {k: np.full(plan.count, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, plan.count))
    return plan, values


def _batched_geometry(plan, values):
    from beveloid.design import design_arrays

    d = design_arrays(values)
    ((models, idx),) = rows.model_groups(plan, values, d.ok)
    return idx, contact.geometry(values, d.q, idx, models)


def test_sections_of_many_designs_equal_each_designs_own(mixed):
    plan, values = mixed
    idx, geom = _batched_geometry(plan, values)
    for member in MEMBERS:
        grid = sections.face_grid(geom, member, 7)
        many = sections.section(geom, member, grid)
        assert grid.shape == (idx.size, 7) and many.undercut_depth_left.shape == (idx.size, 7)
        for k, j in enumerate(idx):
            one_geom = Pair.from_spec(rows.design_spec(plan, values, j)).geometry
            one_grid = sections.face_grid(one_geom, member, 7)
            np.testing.assert_allclose(grid[k], one_grid, rtol=1e-13, atol=1e-12)
            one = sections.section(one_geom, member, one_grid)
            for name in ("tip_arc_thickness", "undercut_depth_left", "undercut_depth_right", "tip_radius"):
                np.testing.assert_allclose(getattr(many, name)[k], getattr(one, name), rtol=1e-11, atol=1e-11)


def test_the_screen_clears_only_designs_without_a_whole_tooth_status(mixed):
    plan, values = mixed
    idx, geom = _batched_geometry(plan, values)
    clear = screen.clear(geom)
    found = [explore_tooth.statuses(Pair.from_spec(rows.design_spec(plan, values, j)).geometry) for j in idx]
    assert all(not f for f, c in zip(found, clear) if c)
    assert all(not c for f, c in zip(found, clear) if f)
    assert clear.any() and not clear.all()


def test_rows_equal_the_checks_run_design_by_design(mixed, monkeypatch):
    plan, _ = mixed
    fast = rows.compute(plan, 0, plan.count, DEFAULT_RANGES)
    monkeypatch.setattr(screen, "clear", lambda geometry: np.zeros(np.shape(geometry.normal_module_mm), bool))
    slow = rows.compute(plan, 0, plan.count, DEFAULT_RANGES)  # every design through the checks themselves
    for name in ("status", "tooth_status", "reason"):
        assert fast[name].tolist() == slow[name].tolist(), name
    assert {"ok", "undercut", "pointed"} <= set(fast["status"])
