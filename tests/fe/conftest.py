"""The FE data of case 1's members on a coarse mesh, computed once per test run (shared by the
tests of tests/fe that need a real tooth)."""
from __future__ import annotations

import pytest

from beveloid.ltca import Material
from beveloid.pair import Pair

#: every element size times this: the cheap tooth of the suite (the default mesh is in benchmarks/)
COARSEN = 3.0


@pytest.fixture(scope="session")
def coarsen():
    """:data:`COARSEN`, for the tests that build the same tooth's data otherwise."""
    return COARSEN


@pytest.fixture(scope="session")
def case1():
    return Pair.example("case1")


@pytest.fixture(scope="session")
def coarse_teeth(case1):
    from beveloid.fe.tooth import tooth_data

    m = Material.from_spec(case1.spec)
    return {"pinion": tooth_data(case1, "pinion", m.pinion_e_mpa, m.pinion_nu, coarsen=COARSEN),
            "gear": tooth_data(case1, "gear", m.gear_e_mpa, m.gear_nu, coarsen=COARSEN)}


@pytest.fixture(scope="session")
def raw_coarse_pinion(case1):
    """The session's coarse pinion with the fillet stresses unsmoothed (the nodal means)."""
    from beveloid.fe.tooth import tooth_data

    m = Material.from_spec(case1.spec)
    return tooth_data(case1, "pinion", m.pinion_e_mpa, m.pinion_nu, coarsen=COARSEN, smooth=False)
