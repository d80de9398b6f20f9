"""docs/loaded_contact.md 5 and 7: the contact layer on a spur pair against ISO 6336-1's stiffness.

    python benchmarks/ltca_spur_pair_stiffness.py      # a few seconds

A 20 deg spur pair, m = 4 mm, z = 30 / 30, face 20 mm, a uniform line load q = 300 N/mm at the pitch
point (the problem of tests/ltca/test_ltca_tooth_compliance.py's `spur_pair_stiffness`): a contact
grid of 17 (profile, +-2.2 Hertz half-widths) x 20 (face) cells.  Per model: the pair's stiffness
q / delta (N/(mm um)), the largest mid-face cell pressure over line-contact Hertz and the largest
face-end cell pressure over line-contact Hertz and over the mid-face one.  "two teeth only" has no
contact problem: the teeth's deflection at the pitch point under the line load there.  Not a test.
"""
import math

import numpy as np

from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, tensor_grid, tensor_influence_matrix_mm_per_mpa
from beveloid.ltca.mechanics.hertz import hertz_line_contact
from beveloid.ltca.mechanics.lcp import solve_contact
from beveloid.rating import iso6336
from beveloid.ltca.mechanics.tooth_compliance import (face_coupling_per_mm, involute_load_points, involute_tooth_section,
                                            slice_compliance_mm2_per_n, tooth_influence_mm_per_mpa)

MODULE_MM, TEETH, FACE_MM, LINE_LOAD_N_PER_MM = 4.0, 30, 20.0, 300.0
ACROSS, ALONG = 17, 20


def problem():
    """(profile edges, face edges, cells, centre radius of curvature rho, Hertz, the two teeth's slice
    compliances, the reduced modulus)."""
    r_p = MODULE_MM * TEETH / 2
    r_b, rho = r_p * math.cos(math.radians(20)), r_p * math.sin(math.radians(20))
    e_star = reduced_modulus_mpa()
    hertz = hertz_line_contact(rho / 2, LINE_LOAD_N_PER_MM, e_star)
    xe = np.linspace(-2.2 * hertz.half_width_mm, 2.2 * hertz.half_width_mm, ACROSS + 1)
    ze = np.linspace(0.0, FACE_MM, ALONG + 1)
    xc = 0.5 * (xe[1:] + xe[:-1])
    section = involute_tooth_section(MODULE_MM, TEETH)
    slices = [slice_compliance_mm2_per_n(section, involute_load_points(MODULE_MM, TEETH, np.sqrt(r_b**2 + (rho + s * xc) ** 2)))
              for s in (1.0, -1.0)]  # pinion, gear
    return xe, ze, tensor_grid(xe, ze), rho, hertz, slices, e_star


def teeth_matrix(ze, cells, slices, plate_height_mm):
    k = face_coupling_per_mm(0.5 * (ze[1:] + ze[:-1]), 0.5 * np.diff(ze), FACE_MM, plate_height_mm)
    return sum(tooth_influence_mm_per_mpa(g, k, cells.area_mm2) for g in slices)


def main():
    xe, ze, cells, rho, hertz, slices, e_star = problem()
    load_n = LINE_LOAD_N_PER_MM * FACE_MM
    half_space = tensor_influence_matrix_mm_per_mpa(xe, ze, e_star)
    pitch_row = np.zeros((ACROSS, ALONG))  # the whole load on the pitch point's row of cells
    pitch_row[ACROSS // 2] = load_n / cells.area_mm2.reshape(ACROSS, ALONG)[ACROSS // 2].sum()
    teeth_only = (teeth_matrix(ze, cells, slices, 0.0) @ pitch_row.ravel()).reshape(ACROSS, ALONG)[ACROSS // 2]
    print(f"reduced modulus E* = {e_star:.0f} MPa; line-contact Hertz p0 = {hertz.max_pressure_mpa:.1f} MPa")
    gear = iso6336.CylindricalGear(TEETH, MODULE_MM, math.radians(20), 0.0, 0.0, MODULE_MM * (TEETH + 2), 1.25 * MODULE_MM, 0.0)
    c_th = iso6336.theoretical_single_stiffness_n_per_mm_um(iso6336.CylindricalPair(gear, gear, FACE_MM))
    print(f"ISO 6336-1 method B: c'_th = {c_th:.2f}, C_M c'_th = {iso6336.STIFFNESS_CORRECTION * c_th:.2f} N/(mm um)")
    print("compliance included | c (N/(mm um)) | mid-face p_max / Hertz | face-end p_max / Hertz | face end / mid-face")
    print(f"two teeth only (thin slice, no contact) | {LINE_LOAD_N_PER_MM / (teeth_only.mean() * 1e3):.2f} | - | - | -")
    for label, c in (("half-space only", half_space),
                     ("both, uncoupled slices (h = 0)", half_space + teeth_matrix(ze, cells, slices, 0.0)),
                     (f"both, plate-coupled (h = {2.25 * MODULE_MM:g} mm)",
                      half_space + teeth_matrix(ze, cells, slices, 2.25 * MODULE_MM))):
        sol = solve_contact(c, cells.x_mm**2 / rho, cells.area_mm2, load_n)
        assert sol.converged, sol.message
        p = sol.pressure_mpa.reshape(ACROSS, ALONG)
        mid, end = p[:, ALONG // 2].max(), p[:, [0, -1]].max()
        print(f"{label} | {LINE_LOAD_N_PER_MM / (sol.approach_mm * 1e3):.2f} | {mid / hertz.max_pressure_mpa:.3f} | "
              f"{end / hertz.max_pressure_mpa:.3f} | {end / mid:.3f}")


if __name__ == "__main__":
    main()
