"""Tooth bending, shear and root (foundation) compliance as influence coefficients.

Model (derivation and limits in docs/loaded_contact.md):

* **Thin slice.**  A slice of the tooth of width dz (along the face) is a cantilever
  along the tooth centreline, clamped at the root section (radius r_f), of thickness s(r)
  (chordal thickness at radius r), in plane strain (E' = E/(1 - nu^2), G = E/(2(1 + nu))).
  A unit normal force at flank point j acts along its line of action, which crosses the
  centreline at radius r_Fj under the angle alpha_j to the centreline's normal (bending
  component cos alpha_j, compressive component sin alpha_j).  By the unit-load method
  (Castigliano, hence Maxwell-symmetric) the deflection at point i, along its own normal,
  per unit force at j and per unit face width is

      g_ij = cos a_i cos a_j [ int 12 (r_Fi - r)(r_Fj - r) / (E' s^3) dr + int k / (G s) dr ]
             + sin a_i sin a_j int 1 / (E' s) dr
             + cos a_i cos a_j l_i l_j 16 / (pi E' s_f^2)

  with the integrals from r_f to min(r_Fi, r_Fj), k = 1.2 (shear coefficient of a
  rectangle), l = r_F - r_f the lever arm and s_f the root thickness.  The last term is
  the rotation of the root section taken as a rigid strip on an elastic half-plane
  (theta = 16 M / (pi E' s_f^2); Weber's fillet-foundation term has 16.67/pi).

* **Face coupling.**  Neighbouring slices are not independent: the tooth is a plate, and a
  point load bends it over a length of the order of its height h.  Per Fourier mode cos(k z)
  along the face, a Kirchhoff cantilever plate strip (clamped root, free tip edge, edge load)
  has the slice's compliance times R(k h) (derivations/tooth_plate_coupling.py, generated
  tooth_plate_coupling.py; R(0) = 1, R ~ 6 / ((1 - nu)(3 + nu)(k h)^3) for short waves).  On a
  face 0 <= z <= L with free ends the Green's function is the cosine series

      G(z, z') = (1/L) sum_n eps_n R(k_n h) cos(k_n z) cos(k_n z'),  k_n = n pi / L,

  (eps_0 = 1, else 2): int G dz' = 1, so a uniform line load gives exactly the thin-slice
  deflection, and a load at a free end deflects more than in mid-face.  h is the tooth height
  (the plate from root to tip; the load's own height is in the slice compliance, not in R).
  ``plate_height_mm = 0`` is the uncoupled thin slice.  It replaced (issue 23) a string on an
  elastic foundation, R = 1 / (1 + lambda^2 k^2), whose k^-2 tail made the tooth too soft to
  short waves and flattened long Hertz ellipses (docs/loaded_contact.md section 5).

Cells of a contact grid are the tensor product of profile points (on the flank, outer
index) and face cells (inner index), the order of ``halfspace.tensor_grid`` with x along
the profile and y along the face.  Units: mm, N, MPa.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from . import checks
from ...generated import tooth_plate_coupling
from .halfspace import STEEL_E_MPA, STEEL_NU

__all__ = [
    "SHEAR_COEFFICIENT",
    "ToothSection",
    "LoadPoints",
    "involute_tooth_section",
    "involute_load_points",
    "slice_compliance_mm2_per_n",
    "PLATE_SERIES_BELOW",
    "plate_edge_compliance_ratio",
    "face_coupling_per_mm",
    "face_couplings_per_mm",
    "mode_cosines",
    "plate_modes",
    "tooth_influence_mm_per_mpa",
]

SHEAR_COEFFICIENT = 1.2  # rectangular cross-section


@dataclass(frozen=True)
class ToothSection:
    """A tooth slice as a cantilever: chordal thickness (mm) at radii (mm) from the root section up."""

    radius_mm: np.ndarray
    thickness_mm: np.ndarray

    @property
    def root_radius_mm(self) -> float:
        return float(self.radius_mm[0])


@dataclass(frozen=True)
class LoadPoints:
    """Where each flank point's normal line crosses the centreline, and its angle to the centreline's normal."""

    centreline_radius_mm: np.ndarray
    load_angle_rad: np.ndarray


def _involute(alpha):
    return np.tan(alpha) - alpha


def _half_angle(module_mm, teeth, alpha_n, shift, r_mm):
    """Half the angular tooth thickness at radius r >= r_b (involute, standard rack)."""
    r_p = 0.5 * module_mm * teeth
    r_b = r_p * math.cos(alpha_n)
    alpha_r = np.arccos(np.clip(r_b / r_mm, -1.0, 1.0))
    half_pitch_thickness = (math.pi / 2 + 2 * shift * math.tan(alpha_n)) / teeth
    return half_pitch_thickness + _involute(alpha_n) - _involute(alpha_r)


def _check_gear(module_mm, teeth, pressure_angle_rad, profile_shift):
    m = checks.positive("module_mm", module_mm)
    if not (isinstance(teeth, int) and 6 <= teeth <= 400):
        raise ValueError(f"teeth = {teeth!r}: must be an integer from 6 to 400")
    a = float(pressure_angle_rad)
    if not (math.radians(10) <= a <= math.radians(35)):
        raise ValueError(f"pressure_angle_rad = {pressure_angle_rad!r}: must be from 0.1745 to 0.6109 (10 to 35 deg)")
    x = float(profile_shift)
    if not (math.isfinite(x) and -1.5 <= x <= 1.5):
        raise ValueError(f"profile_shift = {profile_shift!r}: must be a number from -1.5 to 1.5")
    return m, a, x


def involute_tooth_section(
    module_mm: float,
    teeth: int,
    pressure_angle_rad: float = math.radians(20.0),
    profile_shift: float = 0.0,
    addendum_coefficient: float = 1.0,
    dedendum_coefficient: float = 1.25,
    stations: int = 2000,
) -> ToothSection:
    """Transverse section of a standard external spur tooth (no fillet).

    Involute above the base circle; below it (down to the root circle) the flank is taken
    radial (constant angular thickness): the trochoidal fillet is not modelled, which
    makes the root a little thinner, hence the tooth a little softer, than the real one.
    """
    m, a, x = _check_gear(module_mm, teeth, pressure_angle_rad, profile_shift)
    ha = checks.positive("addendum_coefficient", addendum_coefficient)
    hf = checks.positive("dedendum_coefficient", dedendum_coefficient)
    if not (isinstance(stations, int) and stations >= 20):
        raise ValueError(f"stations = {stations!r}: must be an integer >= 20")
    r_p = 0.5 * m * teeth
    r_b = r_p * math.cos(a)
    r_a = r_p + (ha + x) * m
    r_f = r_p - (hf - x) * m
    if not r_f > 0.0:
        raise ValueError(f"dedendum_coefficient = {dedendum_coefficient!r}: root radius {r_f!r} mm must be > 0")
    r = np.linspace(r_f, r_a, stations)
    psi = _half_angle(m, teeth, a, x, np.maximum(r, r_b))
    if np.any(psi <= 0.0):
        raise ValueError(f"addendum_coefficient = {addendum_coefficient!r}: the tooth comes to a point below the tip")
    thickness = 2.0 * r * np.sin(psi)
    return ToothSection(radius_mm=r, thickness_mm=thickness)


def involute_load_points(
    module_mm: float, teeth: int, radius_mm, pressure_angle_rad: float = math.radians(20.0), profile_shift: float = 0.0
) -> LoadPoints:
    """Load lines of involute flank points at the given radii (each >= the base radius).

    The normal of the involute at radius r is tangent to the base circle; it makes the
    angle alpha' = alpha_r - psi_r with the normal of the tooth centreline (alpha_r the
    pressure angle at r, psi_r the half angular thickness) and crosses the centreline at
    r_F = r_b / cos(alpha').
    """
    m, a, x = _check_gear(module_mm, teeth, pressure_angle_rad, profile_shift)
    r = checks.finite_array("radius_mm", np.atleast_1d(radius_mm))
    r_b = 0.5 * m * teeth * math.cos(a)
    if np.any(r < r_b * (1 - 1e-12)):
        raise ValueError(f"radius_mm has minimum {float(r.min())!r}: every radius must be >= the base radius {r_b!r} mm")
    alpha_r = np.arccos(np.clip(r_b / r, -1.0, 1.0))
    load_angle = alpha_r - _half_angle(m, teeth, a, x, r)
    return LoadPoints(centreline_radius_mm=r_b / np.cos(load_angle), load_angle_rad=load_angle)


def _cumulative(y: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Cumulative trapezoid integral of f over y, starting at 0."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(y))])


def slice_compliance_mm2_per_n(
    section: ToothSection, load: LoadPoints, e_mpa: float = STEEL_E_MPA, nu: float = STEEL_NU
) -> np.ndarray:
    """g[i, j]: deflection (mm) along normal i per unit force (N) per unit face width (mm) at j.

    Symmetric.  Load lines must cross the centreline between the root and the tip radius.
    """
    e = checks.positive("e_mpa", e_mpa)
    v = checks.poisson("nu", nu)
    e_ps = e / (1.0 - v * v)
    g_mod = e / (2.0 * (1.0 + v))
    r, s = section.radius_mm, section.thickness_mm
    rf = load.centreline_radius_mm
    if np.any(rf <= r[0]) or np.any(rf > r[-1]):
        raise ValueError(
            f"load centreline radii from {float(rf.min())!r} to {float(rf.max())!r} mm: "
            f"must lie in ({r[0]!r}, {r[-1]!r}] (root to tip)"
        )
    y = r - r[0]
    inv_i = 12.0 / (e_ps * s**3)
    j0, j1, j2 = (_cumulative(y, y**k * inv_i) for k in (0, 1, 2))
    shear = _cumulative(y, SHEAR_COEFFICIENT / (g_mod * s))
    axial = _cumulative(y, 1.0 / (e_ps * s))
    yf = rf - r[0]  # lever arms
    ym = np.minimum(yf[:, None], yf[None, :])

    def at(table):
        return np.interp(ym, y, table)

    c, sn = np.cos(load.load_angle_rad), np.sin(load.load_angle_rad)
    bending = yf[:, None] * yf[None, :] * at(j0) - (yf[:, None] + yf[None, :]) * at(j1) + at(j2)
    foundation = 16.0 * yf[:, None] * yf[None, :] / (math.pi * e_ps * s[0] ** 2)
    cc = c[:, None] * c[None, :]
    return cc * (bending + at(shear) + foundation) + sn[:, None] * sn[None, :] * at(axial)


PLATE_SERIES_BELOW = 0.03  # k h below which R is taken from its series (the closed form cancels)
PLATE_MODES_PER_HEIGHT = 400.0  # modes up to k h = 400: the tail beyond holds < 1e-5 of G(z, z)


def plate_edge_compliance_ratio(kh, nu: float = STEEL_NU) -> np.ndarray:
    """R(k h): the plate strip's edge compliance of mode k over the beam's (generated)."""
    t = np.asarray(kh, dtype=float)
    small = t < PLATE_SERIES_BELOW
    with np.errstate(divide="ignore", invalid="ignore"):
        closed = tooth_plate_coupling.edge_compliance_ratio(np.where(small, 1.0, t), nu).ratio
    return np.where(small, tooth_plate_coupling.edge_compliance_ratio_series(t, nu).ratio, closed)


@functools.lru_cache(maxsize=64)
def plate_modes(face_width_mm: float, plate_height_mm: float, nu: float) -> tuple:
    """(k (1/mm), weight (1/mm)) of the plate's cosine series over a face: the wave numbers n pi / L,
    n = 1 .. L :data:`PLATE_MODES_PER_HEIGHT` / (pi h), and 2 R(k h) / L (:func:`plate_edge_compliance_ratio`);
    kept per (L, h, nu): they depend on the tooth, not on the points (read-only arrays)."""
    length, h = float(face_width_mm), float(plate_height_mm)
    n = np.arange(1, int(math.ceil(PLATE_MODES_PER_HEIGHT * length / (math.pi * h))) + 1)
    k = n * math.pi / length
    weight = 2.0 * plate_edge_compliance_ratio(k * h, nu) / length
    k.flags.writeable = False
    weight.flags.writeable = False
    return k, weight


def face_couplings_per_mm(z_mm, half_dz_mm: float, face_width_mm: float, plate_height_mm: float,
                          nu: float = STEEL_NU) -> np.ndarray:
    """(Q, n, n) :func:`face_coupling_per_mm` of Q sets of n points z (Q, n), all cells of the one
    half-width ``half_dz_mm`` and inside the face (z - hz >= 0, z + hz <= L: no cell clipped), in one
    product: a cell's mean of cos(k z') is then cos(k z_b) sin(k hz) / (k hz), so that
    K = 1/L + sum_k weight_k cos(k z_a) cos(k z_b) sin(k hz) / (k hz) (the same sum; one cosine per
    point and mode instead of a cosine and two sines; the cosines by :func:`mode_cosines`)."""
    z = np.asarray(z_mm, dtype=float)
    hz, length = float(half_dz_mm), float(face_width_mm)
    if not (np.all(z - hz >= -1e-9 * length) and np.all(z + hz <= length * (1 + 1e-9))):
        raise ValueError(f"z_mm +- half_dz_mm spans {float((z - hz).min())!r} to {float((z + hz).max())!r}: must "
                         f"lie in [0, {length!r}]")
    k, weight = plate_modes(length, plate_height_mm, nu)
    c = mode_cosines(math.pi * z / length, k.size)  # (Q, n, modes): cos(k z), k = n pi / L
    # (the mode factors on one side: half the time of c weight @ (c sin(k hz) / (k hz))^T, the same to 1e-16)
    return 1.0 / length + (c * (weight * (np.sin(k * hz) / (k * hz)))) @ np.swapaxes(c, -1, -2)


def mode_cosines(theta, modes: int) -> np.ndarray:
    """(..., modes) cos(n theta) for n = 1 .. modes from 2 sqrt(modes) complex exponentials a point instead of
    ``modes`` cosines: n = a B + b (B = ceil(sqrt(modes + 1)); a, b < B) and cos(n theta) = Re(e^(i a B theta)
    e^(i b theta)) (exact; round-off ~5e-13 against the cosines of the rounded arguments, whose own is ~n
    theta 1e-16).  The plate's ~500 modes (472 and 566 for case 1's members) made the cosines ~60 % of
    :func:`face_couplings_per_mm`'s time (issue 59); this is ~2x faster."""
    theta = np.asarray(theta, dtype=float)[..., None]
    B = int(math.ceil(math.sqrt(modes + 1)))
    low = np.exp(1j * (theta * np.arange(B)))
    high = np.exp(1j * (theta * (B * np.arange(B))))
    both = (high[..., :, None] * low[..., None, :]).real
    return both.reshape(theta.shape[:-1] + (B * B,))[..., 1:modes + 1]


def face_coupling_per_mm(z_mm, half_dz_mm, face_width_mm: float, plate_height_mm: float,
                         nu: float = STEEL_NU) -> np.ndarray:
    """K[a, b] = (1/dz_b) int over face cell b of G(z_a, z') dz' (1/mm), the plate's cosine series.

    z in [0, face_width_mm]; cells must lie inside the face.  Multiplied by a slice
    compliance g (mm^2/N) and a force on cell b it gives the deflection at z_a.
    ``plate_height_mm = 0`` gives uncoupled slices (K = diag(1/dz)).
    """
    z = checks.finite_array("z_mm", z_mm)
    hz = checks.finite_array("half_dz_mm", half_dz_mm, z.size, positive_only=True)
    length = checks.positive("face_width_mm", face_width_mm)
    h = float(plate_height_mm)
    if not (math.isfinite(h) and h >= 0.0):
        raise ValueError(f"plate_height_mm = {plate_height_mm!r}: must be a finite number >= 0")
    lo, hi = z - hz, z + hz
    if np.any(lo < -1e-9 * length) or np.any(hi > length * (1 + 1e-9)):
        raise ValueError(f"z_mm +- half_dz_mm spans {float(lo.min())!r} to {float(hi.max())!r}: must lie in [0, {length!r}]")
    if h == 0.0:
        return np.diag(1.0 / (2.0 * hz))
    k, weight = plate_modes(length, h, nu)
    at = np.cos(np.outer(z, k)) * weight
    cell_mean = (np.sin(np.outer(np.clip(hi, 0, length), k)) - np.sin(np.outer(np.clip(lo, 0, length), k))) \
        / (np.outer(2.0 * hz, k))
    return 1.0 / length + at @ cell_mean.T


def tooth_influence_mm_per_mpa(slice_mm2_per_n: np.ndarray, coupling_per_mm: np.ndarray, area_mm2) -> np.ndarray:
    """Deflection (mm) at cell (i, a) per MPa on cell (j, b): g[i, j] K[a, b] area[(j, b)].

    Cells ordered profile-major (cell = i * n_face + a).  Add the matrices of both
    teeth of a pair to the half-space matrix of its contact grid.
    """
    g = np.asarray(slice_mm2_per_n, dtype=float)
    k = np.asarray(coupling_per_mm, dtype=float)
    a = checks.finite_array("area_mm2", area_mm2, g.shape[0] * k.shape[0], positive_only=True)
    return np.kron(g, k) * a[None, :]
