"""The contact ratio of `beveloid design` runs on the compiled solver (the default "auto") and
gives the numpy backend's numbers."""
from __future__ import annotations

import pytest

from beveloid.tca import FLANKS
from beveloid.solver import Solver, backends
from beveloid.tooth import contact


def test_the_checks_default_to_the_compiled_solver():
    assert Solver.of(None).backend == ("compiled" if backends.AVAILABLE else "numpy")


@pytest.mark.parametrize("flank", FLANKS)
def test_compiled_contact_ratio_is_the_numpy_one(pair1, compiled_solver, flank):
    g = pair1.geometry
    ref = contact.flank_contact(g, flank, solver=Solver("numpy"))
    got = contact.flank_contact(g, flank, solver=Solver("compiled"))
    # the ends are bisected to ~1e-10 rad: compare numbers, not which boundary a round-off lands on
    assert got.contact_ratio == pytest.approx(ref.contact_ratio, abs=1e-9)
    assert got.start_rad == pytest.approx(ref.start_rad, abs=1e-9)
    assert got.end_rad == pytest.approx(ref.end_rad, abs=1e-9)
    for member in ("pinion", "gear"):
        assert got.form_margin_mm[member] == pytest.approx(ref.form_margin_mm[member], abs=1e-9)
