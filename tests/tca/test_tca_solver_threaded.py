"""The analysis' Solver reaches every step of the TCA (issue 42): the contact ellipses' chord search
gets the Solver itself, and the TE reference the Solver's tolerances (before: the ellipses always
took the default backend, the reference the default tolerances)."""
from __future__ import annotations

import pytest

from beveloid import contact_ellipse, tca
from beveloid.solver import Solver, SolverOptions
from beveloid.tca import flank as tca_flank


@pytest.mark.usefixtures("compiled_solver")
def test_the_ellipses_chord_search_gets_the_analysis_solver(pair1, monkeypatch):
    seen = []
    real = contact_ellipse.chords
    monkeypatch.setattr(contact_ellipse, "chords", lambda *a: seen.append(a[-1]) or real(*a))
    solver = Solver("numpy", SolverOptions(tol_mm=1e-11))
    tca.analyze(pair1, tca.Options(flanks=("right",), positions=3), solver=solver)
    assert seen and all(s is solver for s in seen)


@pytest.mark.usefixtures("compiled_solver")  # the suite's compile step runs default solvers: before the spy
@pytest.mark.parametrize("backend", ["numpy", "auto"])
def test_the_te_reference_is_solved_with_the_analysis_tolerances(pair1, monkeypatch, backend):
    seen = []
    real = tca_flank.reference_contact
    monkeypatch.setattr(tca_flank, "reference_contact", lambda geom, flank, options=None: seen.append(options)
                        or real(geom, flank, options))
    options = SolverOptions(tol_mm=1e-10, max_iter=40)
    tca.analyze(pair1, tca.Options(flanks=("left",), positions=3, approach_mm=None), solver=Solver(backend, options))
    assert seen and all(o == options for o in seen)
