"""Hertz on uncoupled slices: the closed form, and the contact layer that must reproduce it.

The tooth's thin slices in series with the half-space lower a long contact's peak below Hertz.
``hertz_point_contact_on_slices`` is the exact solution of that problem for a uniform slice
compliance (docs/loaded_contact.md section 5.1); here the contact layer (half-space + slices,
solved by ``lcp``) is held to it, and the plate-coupled tooth to the bracket it must lie in.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, tensor_grid, tensor_influence_matrix_mm_per_mpa
from beveloid.ltca.mechanics.hertz import hertz_point_contact, hertz_point_contact_on_slices
from beveloid.ltca.mechanics.lcp import solve_contact
from beveloid.ltca.mechanics.tooth_compliance import face_coupling_per_mm, tooth_influence_mm_per_mpa

E_STAR = reduced_modulus_mpa()
# a near-line contact: R = 20 mm across, 3000 mm along, 2 kN; g of the order of two teeth's
# slices (1 / (31 N/(mm um)), docs/loaded_contact.md section 5)
A_PER_MM, B_PER_MM, LOAD_N, G_MM2_PER_N = 1 / (2 * 20.0), 1 / (2 * 3000.0), 2000.0, 3.2e-5


def test_line_load_of_the_hertz_pressure():
    """The two facts the closed form rests on: q(y) = (pi/2) p0 a_x (1 - y^2/a_y^2), P = (4/3) q0 a_y."""
    x, y, c, ax, ay, p0 = sp.symbols("x y c a_x a_y p_0", positive=True)
    # across y = const the pressure p0 sqrt(1 - x^2/ax^2 - y^2/ay^2) is (p0/ax) sqrt(c^2 - x^2),
    # c = ax sqrt(1 - y^2/ay^2) its half-chord
    chord = sp.integrate(sp.sqrt(c**2 - x**2), (x, -c, c))
    q = (p0 / ax * chord).subs(c, ax * sp.sqrt(1 - y**2 / ay**2))
    q0 = sp.pi / 2 * p0 * ax
    assert sp.simplify(q - q0 * (1 - y**2 / ay**2)) == 0
    load = sp.integrate(q0 * (1 - y**2 / ay**2), (y, -ay, ay))
    assert sp.simplify(load - sp.Rational(2, 3) * sp.pi * ax * ay * p0) == 0
    assert sp.simplify(q0 - 3 * load / (4 * ay)) == 0


def test_closed_form_limits_and_self_consistency():
    plain = hertz_point_contact(A_PER_MM, B_PER_MM, LOAD_N, E_STAR)
    assert hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, 0.0) == plain
    soft = hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, G_MM2_PER_N)
    # its own a_y: the Hertz contact of (A, B - 3 g P / (4 a_y^3)) has that a_y
    b_eff = B_PER_MM - 0.75 * G_MM2_PER_N * LOAD_N / soft.semi_axis_y_mm**3
    again = hertz_point_contact(A_PER_MM, b_eff, LOAD_N, E_STAR)
    assert again.semi_axis_y_mm == pytest.approx(soft.semi_axis_y_mm, rel=1e-10)
    assert soft.approach_mm == pytest.approx(again.approach_mm + G_MM2_PER_N * 0.75 * LOAD_N / soft.semi_axis_y_mm)
    # the slices lengthen the contact and lower its peak; a vanishing g tends to Hertz
    assert soft.semi_axis_y_mm > 1.3 * plain.semi_axis_y_mm and soft.max_pressure_mpa < 0.9 * plain.max_pressure_mpa
    tiny = hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, 1e-12)
    assert tiny.max_pressure_mpa == pytest.approx(plain.max_pressure_mpa, rel=1e-6)
    with pytest.raises(ValueError, match="slice_compliance_mm2_per_n = -1.0"):
        hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, -1.0)


def solve_layer(plate_height_mm: float, nx: int = 15, ny: int = 41):
    """Half-space + slices of compliance g along y (the face), coupled by a plate of that height
    (0: uncoupled); the grid spans 1.3 x the closed form's ellipse on a face 20 a_y long."""
    ref = hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, G_MM2_PER_N)
    xe = np.linspace(-1.3 * ref.semi_axis_x_mm, 1.3 * ref.semi_axis_x_mm, nx + 1)
    ye = np.linspace(-1.3 * ref.semi_axis_y_mm, 1.3 * ref.semi_axis_y_mm, ny + 1)
    cells = tensor_grid(xe, ye)
    face_mm = 20.0 * ref.semi_axis_y_mm
    k = face_coupling_per_mm(0.5 * (ye[1:] + ye[:-1]) + 0.5 * face_mm, 0.5 * np.diff(ye), face_mm, plate_height_mm)
    c = tensor_influence_matrix_mm_per_mpa(xe, ye, E_STAR)
    c = c + tooth_influence_mm_per_mpa(np.full((nx, nx), G_MM2_PER_N), k, cells.area_mm2)
    sol = solve_contact(c, A_PER_MM * cells.x_mm**2 + B_PER_MM * cells.y_mm**2, cells.area_mm2, LOAD_N)
    assert sol.converged, sol.message
    f = cells.area_mm2 * sol.pressure_mpa
    a_y = float(np.sqrt(5 * (f @ cells.y_mm**2) / f.sum()))  # exact for an ellipsoidal pressure
    return sol, a_y


def test_layer_on_uncoupled_slices_is_the_closed_form():
    ref = hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, G_MM2_PER_N)
    plain = hertz_point_contact(A_PER_MM, B_PER_MM, LOAD_N, E_STAR)
    sol, a_y = solve_layer(0.0)
    assert sol.max_pressure_mpa == pytest.approx(ref.max_pressure_mpa, rel=0.01)
    assert a_y == pytest.approx(ref.semi_axis_y_mm, rel=0.02)
    assert sol.approach_mm == pytest.approx(ref.approach_mm, rel=0.02)
    assert sol.max_pressure_mpa < 0.9 * plain.max_pressure_mpa  # far from Hertz: the test can tell


def test_plate_coupled_tooth_lies_between_the_slices_and_hertz():
    """A plate spreads a slice's deflection over about its height: the peak lies between the
    uncoupled slices' (the closed form) and Hertz's, nearer Hertz the higher the plate."""
    ref = hertz_point_contact_on_slices(A_PER_MM, B_PER_MM, LOAD_N, E_STAR, G_MM2_PER_N).max_pressure_mpa
    plain = hertz_point_contact(A_PER_MM, B_PER_MM, LOAD_N, E_STAR).max_pressure_mpa
    peaks = [solve_layer(h)[0].max_pressure_mpa for h in (3.0, 6.0, 13.5, 40.0)]
    assert ref < peaks[0] and peaks[-1] < plain * 1.005
    assert np.all(np.diff(peaks) > 0)
    # a tooth as high as the contact is long (a_y = 7.9 mm here): well below Hertz
    assert peaks[1] < 0.95 * plain
