"""The virtual cylindrical gear of a transverse section of a beveloid member (docs/rating.md, 2).

A beveloid's rack is the cylindrical gear's rack tilted by the cone angle gamma about its pitch-line
direction (Eqs 1-3, derivations/eq01_03_rack_cutter.py).  In every transverse section z of S_i the
tilted rack is a planar rack rolling on the same pitch circle r: each flank is an involute of one
base circle, so each flank of the tooth is an involute helicoid, the same along the face; what
changes along the face is how far the rack sits out of the pitch circle, the radial shift

    e(z) = x_t m_t + z tan(gamma)     (z from the reference section, S_i; the root cone's slope),

and the tip cone.  The flank sigma (left +1, right -1) has on the pitch cylinder

    tan(beta_sigma)    = tan(beta) cos(gamma) - sigma tan(alpha_n) sin(gamma) / cos(beta)
    tan(alpha_t,sigma) = (tan(alpha_n) cos(gamma) + sigma sin(beta) sin(gamma)) / cos(beta)

(the rack line's direction in the pitch plane and its transverse normal; the second is the
generated ``tooth_sections`` pressure angle, which a test holds).  The virtual gear of the section
for the loaded flank sigma is the helical gear with the same teeth and pitch circle whose flank is
that involute helicoid: helix beta_v = |beta_sigma|, normal module m_t cos(beta_v), normal pressure
angle atan(tan(alpha_t,sigma) cos(beta_v)), normal profile shift x_n = e(z) / m_n,v, the section's
tip diameter, the rack's dedendum in the section (r + e - root radius = a / cos(gamma)) and tip
round.  With gamma = 0 it is the cylindrical gear itself, in every section.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..tooth import sections
from .iso6336 import CylindricalGear

__all__ = ["SectionGear", "flank_angles", "section_gear", "FLANK_SIGN"]

FLANK_SIGN = {"left": 1.0, "right": -1.0}


def flank_angles(helix_angle, cone_angle, normal_pressure_angle, flank):
    """(beta_sigma, alpha_t,sigma) of a flank on the pitch cylinder (rad; beta signed like the rack's)."""
    s = FLANK_SIGN[flank]
    b, g, a = helix_angle, cone_angle, normal_pressure_angle
    beta = math.atan(math.tan(b) * math.cos(g) - s * math.tan(a) * math.sin(g) / math.cos(b))
    alpha_t = math.atan((math.tan(a) * math.cos(g) + s * math.sin(b) * math.sin(g)) / math.cos(b))
    return beta, alpha_t


@dataclass(frozen=True)
class SectionGear:
    """A member's section: where it is and its virtual helical gear."""

    member: str
    section: str  # "toe", "middle", "heel" or "" for a point of a face scan
    face_z_mm: float
    radial_shift_mm: float
    gear: CylindricalGear
    helix_angle_signed: float


def _radial_shift(geometry, member, z_face):
    m = geometry.member(member)
    z = float(sections.member_z(geometry, member, z_face))
    transverse_module = geometry.normal_module_mm / math.cos(m.helix_angle)
    # rack_shift_mm = x_t m_n cos(gamma)/cos(beta) along the tilted depth axis: x_t m_t radially
    x_t = m.rack_shift_mm / (geometry.normal_module_mm * math.cos(m.cone_angle) / math.cos(m.helix_angle))
    return x_t * transverse_module + z * math.tan(m.cone_angle), z


def section_gear(geometry, member: str, z_face: float, flank: str, section: str = "") -> SectionGear:
    """The virtual helical gear of ``member``'s section at face coordinate z_face (mm) for ``flank``."""
    m = geometry.member(member)
    beta_s, alpha_ts = flank_angles(m.helix_angle, m.cone_angle, geometry.normal_pressure_angle, flank)
    beta_v = abs(beta_s)
    mt = 2 * m.pitch_radius_mm / m.teeth
    mn_v = mt * math.cos(beta_v)
    an_v = math.atan(math.tan(alpha_ts) * math.cos(beta_v))
    e, _ = _radial_shift(geometry, member, z_face)
    sec = sections.section(geometry, member, z_face)
    tip_r, root_r = float(sec.tip_radius), float(sec.root_radius)
    gear = CylindricalGear(
        teeth=m.teeth, normal_module_mm=mn_v, normal_pressure_angle=an_v, helix_angle=beta_v,
        profile_shift=e / mn_v, tip_diameter_mm=2 * tip_r,
        rack_dedendum_mm=m.pitch_radius_mm + e - root_r, rack_tip_radius_mm=m.cutter_tip_radius_mm)
    return SectionGear(member, section, float(z_face), e, gear, beta_s)


def mate_gear(geometry, rated: SectionGear, flank: str) -> CylindricalGear:
    """The rated section's mate: the other member at its middle section, recut with the rated
    section's normal module, pressure angle and helix (a parallel-axis mate; docs/rating.md 2.2)."""
    other = "gear" if rated.member == "pinion" else "pinion"
    own = section_gear(geometry, other, 0.0, flank)
    g = rated.gear
    d = own.gear.teeth * g.normal_module_mm / math.cos(g.helix_angle)
    m = geometry.member(other)
    addendum = own.gear.tip_diameter_mm / 2 - m.pitch_radius_mm  # e + tip height, radially
    return CylindricalGear(
        teeth=own.gear.teeth, normal_module_mm=g.normal_module_mm, normal_pressure_angle=g.normal_pressure_angle,
        helix_angle=g.helix_angle, profile_shift=own.radial_shift_mm / g.normal_module_mm,
        tip_diameter_mm=d + 2 * addendum, rack_dedendum_mm=own.gear.rack_dedendum_mm,
        rack_tip_radius_mm=own.gear.rack_tip_radius_mm)
