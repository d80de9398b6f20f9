"""The FE tooth under ISO 6336-3's own load case: the yardstick's check of the local root stress
(docs/rating.md 5; tests/rating/test_rating_fe.py, benchmarks/rating_fe_vs_iso.py).

ISO method B puts the whole normal force at the outer point of single pair contact (d_en of the
virtual spur gear), uniform along the face.  The same load on the member's FE tooth
(beveloid.fe: the fillet stress per unit flank load) gives a root stress to set beside sigma_F0.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..tooth import profile, sections
from . import iso6336
from .virtual import mate_gear, section_gear

__all__ = ["IsoLoadCase", "iso_load_case", "iso_load_case_detail"]


@dataclass(frozen=True)
class IsoLoadCase:
    """The FE tooth under ISO's load case beside ISO's numbers (MPa, mm)."""

    fe_max_mpa: float  # the largest max-principal stress in the loaded fillet
    fe_face_median_mpa: float  # the median over 24 face slices of each slice's largest (the mid-face level)
    fe_face_z_mm: float  # where the largest is: face z and height above the root cone
    fe_height_above_root_mm: float
    sigma_F0_mpa: float
    iso_chord_height_above_root_mm: float  # where method B reads: its 30 deg tangent chord
    Y_S: float
    notch_parameter: float  # q_s = s_Fn / (2 rho_F)


def iso_load_case(pair, member: str = "pinion", flank: str = "right", tangential_load_n: float = 1000.0,
                  refinement: int = 1) -> tuple:
    """(FE root stress, ISO sigma_F0) in MPa of ``member`` under ISO's load case on its middle section's
    virtual gear (:func:`iso_load_case_detail`)."""
    d = iso_load_case_detail(pair, member, flank, tangential_load_n, refinement)
    return d.fe_max_mpa, d.sigma_F0_mpa


def iso_load_case_detail(pair, member: str = "pinion", flank: str = "right", tangential_load_n: float = 1000.0,
                         refinement: int = 1) -> IsoLoadCase:
    """``member``'s FE tooth under ISO's load case on its middle section's virtual gear: F_t at d_en (the
    same depth below the tip on the real section) along the flank normal, spread evenly over 41 points
    across 98 % of the face; beside sigma_F0 of that virtual gear."""
    from ..fe.cache import cached_tooth_data
    from ..fe.contact import FeTooth

    g = pair.geometry
    mat = pair.spec.material
    e_mpa = getattr(mat, f"{member}_youngs_modulus_gpa") * 1e3
    data, _ = cached_tooth_data(pair, member, e_mpa, getattr(mat, f"{member}_poisson_ratio"), refinement)
    sg = section_gear(g, member, 0.0, flank)
    b = g.member(member).face_width_mm
    virtual = iso6336.CylindricalPair(sg.gear, mate_gear(g, sg, flank), b)
    bend = iso6336.bending_geometry(virtual)
    y_beta = iso6336.helix_factor_bending(virtual.overlap_ratio, sg.gear.helix_angle)
    sigma_f0 = iso6336.nominal_root_stress_mpa(tangential_load_n, b, sg.gear.normal_module_mm, bend.Y_F, bend.Y_S,
                                               y_beta)
    w = sections.half_face(g, member)
    z = sections.member_z(g, member, np.linspace(-0.98 * w, 0.98 * w, 41))
    # d_en is a diameter of the virtual spur gear (reference diameter d_n = m_n z_n): the same depth
    # below the tip on the real section is at (d_en - d_n + d) / 2
    d_n = sg.gear.normal_module_mm * bend.virtual_teeth
    radius = (bend.d_en_mm - d_n + sg.gear.reference_diameter_mm) / 2
    points = np.array([profile.flank_at_radius(g, member, flank, float(zz), radius)[0] for zz in z])
    normal = tangential_load_n / (math.cos(sg.gear.normal_pressure_angle) * math.cos(sg.gear.base_helix_angle))
    tooth, forces = FeTooth(data, flank), np.full(len(z), normal / len(z))
    fe = tooth.root_stress(points.reshape(-1, 3), forces)
    _, along = tooth.along_face(points.reshape(-1, 3), forces)
    gear = sg.gear
    mn, rho = gear.normal_module_mm, gear.rack_tip_radius_mm
    G = rho / mn - gear.rack_dedendum_mm / mn + gear.profile_shift
    chord_radius = mn / 2 * (bend.virtual_teeth * math.cos(math.pi / 3 - bend.theta) + G / math.cos(bend.theta)
                             - rho / mn)
    root_radius = d_n / 2 + mn * gear.profile_shift - gear.rack_dedendum_mm
    return IsoLoadCase(fe.tension_mpa, float(np.nanmedian(along)), fe.z_mm, fe.height_mm, sigma_f0,
                       chord_radius - root_radius, bend.Y_S, bend.s_Fn_mm / (2 * bend.rho_F_mm))
