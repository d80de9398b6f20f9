"""beveloid.ltca.mechanics.tooth_compliance: beam closed forms, the face coupling, ISO 6336-1 stiffness."""
from __future__ import annotations

import math

import numpy as np
import pytest

from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, tensor_grid, tensor_influence_matrix_mm_per_mpa
from beveloid.ltca.mechanics.hertz import hertz_line_contact
from beveloid.ltca.mechanics.lcp import solve_contact
from beveloid.ltca.mechanics.tooth_compliance import (
    SHEAR_COEFFICIENT,
    LoadPoints,
    ToothSection,
    face_coupling_per_mm,
    involute_load_points,
    involute_tooth_section,
    plate_edge_compliance_ratio,
    slice_compliance_mm2_per_n,
    tooth_influence_mm_per_mpa,
)

E, NU = 206_000.0, 0.3
E_PS = E / (1 - NU**2)
G_MOD = E / (2 * (1 + NU))


def test_uniform_cantilever_matches_beam_closed_forms():
    """Constant thickness s, load at height L: 4 L^3/(E' s^3) + k L/(G s) + 16 L^2/(pi E' s^2)."""
    s, root = 3.0, 10.0
    section = ToothSection(np.linspace(root, root + 8.0, 4001), np.full(4001, s))
    heights = np.array([2.0, 5.0, 7.5])
    angle = np.array([0.0, 0.0, 0.4])
    g = slice_compliance_mm2_per_n(section, LoadPoints(root + heights, angle), E, NU)
    L = heights[1]
    expected = 4 * L**3 / (E_PS * s**3) + SHEAR_COEFFICIENT * L / (G_MOD * s) + 16 * L**2 / (math.pi * E_PS * s**2)
    assert g[1, 1] == pytest.approx(expected, rel=1e-6)
    # cross term by the unit-load method: deflection at a (lower) of a load at b (higher)
    a, b = heights[0], heights[1]
    bend = 12 / (E_PS * s**3) * (a * a * b / 2 - a**3 / 6)
    cross = bend + SHEAR_COEFFICIENT * a / (G_MOD * s) + 16 * a * b / (math.pi * E_PS * s**2)
    assert g[0, 1] == pytest.approx(cross, rel=1e-6)
    # an inclined load: bending, shear and root terms scale with cos^2, compression adds sin^2 L / (E' s)
    L = heights[2]
    c, sn = math.cos(0.4), math.sin(0.4)
    straight = 4 * L**3 / (E_PS * s**3) + SHEAR_COEFFICIENT * L / (G_MOD * s) + 16 * L**2 / (math.pi * E_PS * s**2)
    assert g[2, 2] == pytest.approx(c * c * straight + sn * sn * L / (E_PS * s), rel=1e-6)
    assert np.allclose(g, g.T, rtol=1e-12)


def test_involute_section_and_load_points():
    m, z = 4.0, 30
    section = involute_tooth_section(m, z)
    r_p = m * z / 2
    assert section.root_radius_mm == pytest.approx(r_p - 1.25 * m)
    # chordal thickness at the pitch circle: 2 r_p sin(pi / (2 z))
    assert np.interp(r_p, section.radius_mm, section.thickness_mm) == pytest.approx(2 * r_p * math.sin(math.pi / (2 * z)), rel=1e-6)
    lp = involute_load_points(m, z, [r_p])
    alpha = math.radians(20) - math.pi / (2 * z)
    assert lp.load_angle_rad[0] == pytest.approx(alpha, rel=1e-12)
    assert lp.centreline_radius_mm[0] == pytest.approx(r_p * math.cos(math.radians(20)) / math.cos(alpha), rel=1e-12)
    # a thicker (positively shifted) tooth is stiffer at the same load radius
    g0 = slice_compliance_mm2_per_n(section, lp)[0, 0]
    shifted = involute_tooth_section(m, z, profile_shift=0.4)
    g1 = slice_compliance_mm2_per_n(shifted, involute_load_points(m, z, [r_p], profile_shift=0.4))[0, 0]
    assert g1 < g0
    # higher load points are more compliant, and the matrix is positive definite
    r = np.linspace(r_p * math.cos(math.radians(20)) + 0.5, r_p + m, 8)
    g = slice_compliance_mm2_per_n(section, involute_load_points(m, z, r))
    assert np.all(np.diff(np.diag(g)) > 0)
    assert np.linalg.eigvalsh(g).min() > 0


def test_face_coupling_green_function():
    """The plate's cosine series on a free-ended face: int G = 1, reciprocity, the infinite plate's
    point value in mid-face (an integral of R computed here independently), mirror ends, decay."""
    from scipy.integrate import quad

    length, h = 200.0, 5.0  # mid-face far from the ends (40 h)
    # 0.2 mm cells (h / 25): measured, the mid-face peak within 5e-4 of the infinite plate's and the end
    # ratio within 2.4e-3 of 2 (0.1 mm cells: 1.5e-4, 7e-4, and 3.5x the CPU)
    cells, per_mm = 1000, 1000 / length
    edges = np.linspace(0.0, length, cells + 1)
    z, hz = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
    k = face_coupling_per_mm(z, hz, length, h, NU)
    # a uniform line load deflects uniformly (free ends, int G = 1), also at the ends
    assert np.allclose(k @ (2 * hz), 1.0, rtol=1e-10)
    # reciprocity (up to the cells' averaging)
    assert np.allclose(k * (2 * hz)[None, :], (k * (2 * hz)[None, :]).T, rtol=2e-3, atol=1e-9)

    def printed(t):  # derivations/tooth_plate_coupling.py's printed R, here by its hyperbolic form
        return 3 * (math.sinh(2 * t) - 2 * t) / (t**3 * ((1 - NU) * (3 + NU) * math.sinh(t) ** 2 + (1 - NU) ** 2 * t**2 + 4))

    # an infinite plate's point load: G(z, z) = (1 / (pi h)) int_0^inf R(t) dt (Fourier), in mid-face
    infinite = (quad(printed, 1e-6, 30.0, limit=200)[0] + quad(lambda t: 6 / ((1 - NU) * (3 + NU) * t**3), 30.0,
                                                                 math.inf)[0]) / (math.pi * h)
    mid = cells // 2
    assert k[mid, mid] == pytest.approx(infinite, rel=2e-3)  # the cell average of a cusp-free peak
    # a free end mirrors the face: twice the mid-face deflection
    assert k[0, 0] / k[mid, mid] == pytest.approx(2.0, rel=5e-3)
    # the deflection decays along the face, monotonically, to under 1 % of its peak 4 h away
    row = k[mid, mid:mid + round(4 * h * per_mm)]
    assert np.all(np.diff(row[: round(6.0 * per_mm)]) < 0) and abs(row[-1]) < 1e-2 * row[0]
    # the transfer function: 1 at k = 0, the semi-infinite plate's free edge for short waves
    assert plate_edge_compliance_ratio(0.0, NU) == 1.0
    assert plate_edge_compliance_ratio(200.0, NU) * 200.0**3 == pytest.approx(6 / ((1 - NU) * (3 + NU)), rel=1e-12)
    # height 0: uncoupled thin slices
    assert np.allclose(face_coupling_per_mm(z[:50], hz[:50], length, 0.0), np.diag(1 / (2 * hz[:50])))


def spur_pair_stiffness(coupling: bool) -> tuple[float, float]:
    """Single-pair stiffness per face width at the pitch point of a 20 deg spur pair, m = 4, z = 30/30.

    Contact grid (profile x face) with the half-space and both teeth's slice compliance;
    a uniform load q = 300 N/mm; returns (stiffness q / delta in N/(mm um), Hertz p0 ratio).
    """
    m, z, width = 4.0, 30, 20.0
    r_p = m * z / 2
    r_b, rho = r_p * math.cos(math.radians(20)), r_p * math.sin(math.radians(20))
    e_star = reduced_modulus_mpa()
    q = 300.0
    hl = hertz_line_contact(rho / 2, q, e_star)
    xe = np.linspace(-2.2 * hl.half_width_mm, 2.2 * hl.half_width_mm, 18)
    ze = np.linspace(0.0, width, 21)
    cells = tensor_grid(xe, ze)
    xc = 0.5 * (xe[1:] + xe[:-1])
    section = involute_tooth_section(m, z)
    pinion = involute_load_points(m, z, np.sqrt(r_b**2 + (rho + xc) ** 2))
    gear = involute_load_points(m, z, np.sqrt(r_b**2 + (rho - xc) ** 2))
    height = 2.25 * m if coupling else 0.0  # the tooth's height: the coupling plate
    k = face_coupling_per_mm(0.5 * (ze[1:] + ze[:-1]), 0.5 * np.diff(ze), width, height)
    c = tensor_influence_matrix_mm_per_mpa(xe, ze, e_star)
    for lp in (pinion, gear):
        c = c + tooth_influence_mm_per_mpa(slice_compliance_mm2_per_n(section, lp), k, cells.area_mm2)
    sol = solve_contact(c, cells.x_mm**2 / rho, cells.area_mm2, q * width)
    assert sol.converged, sol.message
    mid = sol.pressure_mpa.reshape(17, 20)[:, 10].max()
    return q / (sol.approach_mm * 1e3), mid / hl.max_pressure_mpa


@pytest.mark.parametrize("coupling", [False, True])
def test_spur_pair_stiffness_is_iso_6336_order_of_magnitude(coupling):
    """ISO 6336-1: c' about 14 N/(mm um) for steel spur pairs; the model must be within a factor 2.

    (For z1 = z2 = 30, x = 0 ISO's q' formula gives c'_th = 16.4 and c' = 0.8 c'_th = 13.1.)
    """
    stiffness, p_ratio = spur_pair_stiffness(coupling)
    assert 7.0 < stiffness < 28.0
    # mid-face the pressure stays near line-contact Hertz (cell resolution, tooth bending tilt-free)
    assert p_ratio == pytest.approx(1.0, rel=0.1)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: involute_tooth_section(4.0, 5), "teeth = 5"),
        (lambda: involute_tooth_section(-1.0, 30), "module_mm = -1.0"),
        (lambda: involute_load_points(4.0, 30, [50.0]), "radius_mm has minimum 50.0"),
        (lambda: face_coupling_per_mm([1.0], [0.5], 10.0, -1.0), "plate_height_mm = -1.0"),
        (lambda: face_coupling_per_mm([9.8], [0.5], 10.0, 1.0), "must lie in"),
        (lambda: slice_compliance_mm2_per_n(involute_tooth_section(4.0, 30), LoadPoints(np.array([70.0]), np.array([0.0]))),
         "load centreline radii"),
        (lambda: slice_compliance_mm2_per_n(involute_tooth_section(4.0, 30), involute_load_points(4.0, 30, [60.0]), nu=0.7),
         "nu = 0.7"),
    ],
)
def test_user_errors(call, match):
    with pytest.raises(ValueError, match=match) as err:
        call()
    assert "\n" not in str(err.value)


def test_the_batched_face_coupling_is_the_cell_mean_series():
    """face_couplings_per_mm (one cosine per point and mode, many lines at once) against the cell-mean
    series of face_coupling_per_mm (a cosine and two sines) on lines of random points inside the face,
    one reaching each end; and a point whose cell leaves the face refused."""
    from beveloid.ltca.mechanics.tooth_compliance import face_couplings_per_mm

    length, h, hz = 50.0, 6.75, 0.05
    z = np.random.default_rng(3).uniform(hz, length - hz, (4, 17))
    z[0, 0], z[1, -1] = hz, length - hz
    many = face_couplings_per_mm(z, hz, length, h, NU)
    for line, k in zip(z, many):
        one = face_coupling_per_mm(line, np.full(line.size, hz), length, h, NU)
        assert np.abs(k - one).max() <= 1e-12 * np.abs(one).max()
    with pytest.raises(ValueError, match="must lie in"):
        face_couplings_per_mm(np.array([[length]]), hz, length, h, NU)


def test_the_mode_cosines_are_the_cosines():
    """mode_cosines (cos(n theta) from products of exponentials of a B + b) against numpy's cosines of
    n theta, over the face (theta in [0, pi], both ends included) and for mode counts on both sides of
    a square (B changes)."""
    from beveloid.ltca.mechanics.tooth_compliance import mode_cosines

    theta = np.concatenate([[0.0, np.pi], np.random.default_rng(5).uniform(0.0, np.pi, 40)]).reshape(2, 21)
    for modes in (1, 3, 24, 25, 472):
        c = mode_cosines(theta, modes)
        assert c.shape == (2, 21, modes)
        assert np.abs(c - np.cos(theta[..., None] * np.arange(1, modes + 1))).max() < 2e-12
