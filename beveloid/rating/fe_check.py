"""The FE tooth under ISO 6336-3's own load case: the yardstick's check of the local root stress
(docs/rating.md 5; tests/rating/test_rating_fe.py, benchmarks/rating_fe_vs_iso.py).

ISO method B puts the whole normal force at the outer point of single pair contact (d_en of the
virtual spur gear), uniform along the face.  The same load on the member's FE tooth
(beveloid.fe: the fillet stress per unit flank load) gives a root stress to set beside sigma_F0.
"""
from __future__ import annotations

import math

import numpy as np

from ..tooth import profile, sections
from . import iso6336
from .virtual import mate_gear, section_gear

__all__ = ["iso_load_case"]


def iso_load_case(pair, member: str = "pinion", flank: str = "right", tangential_load_n: float = 1000.0,
                  refinement: int = 1) -> tuple:
    """(FE root stress, ISO sigma_F0) in MPa of ``member`` under ISO's load case on its middle section's
    virtual gear: F_t at d_en along the flank normal, spread evenly over 41 points across 98 % of the face."""
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
    points = np.array([profile.flank_at_radius(g, member, flank, float(zz), bend.d_en_mm / 2)[0] for zz in z])
    normal = tangential_load_n / (math.cos(sg.gear.normal_pressure_angle) * math.cos(sg.gear.base_helix_angle))
    fe = FeTooth(data, flank).root_stress(points.reshape(-1, 3), np.full(len(z), normal / len(z)))
    return fe.tension_mpa, sigma_f0
