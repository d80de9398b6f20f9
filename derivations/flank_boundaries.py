"""The blank: where a generated flank ends (not in the paper; see docs/validation.md section 0).

A flank point R = (x, y, z) in the member frame S_i with rack parameter l is on the active
flank when all four signed margins (mm) are >= 0:

    form limit  l - l_f                             (start of the rack's straight edge, l_f: the junction
                                                     with the rack's tip round, root_fillet.junction_l;
                                                     0 on the paper's sharp rack)
    tip         r_tip(z) - sqrt(x^2 + y^2)           (tip cone parallel to the rack's pitch plane)
    toe, heel   the axial distance inside the face   (face centred on the working pitch circle)

with r_tip(z) = r + (h_a + s) / cos(gamma) + z tan(gamma): the tip lies h_a = addendum_coefficient
m_n above the rack pitch plane, which is shifted by s along the rack's depth axis and tilted by
the cone angle gamma.  The toe is the face end at the small end of the cone.  Each margin is a
boundary curve g(l, u) = 0 of the flank patch when composed with the tooth surface R(l, u):
edge contact (curve against surface) uses the same functions and their derivatives.
"""
import sympy as sp

from .interface import Field, Layout
from .symbols import gamma, l, r, s

x, y, z = sp.symbols("x y z", real=True)
tip_height = sp.Symbol("h_a", positive=True)
toe_z, heel_z = sp.symbols("z_toe z_heel", real=True)
form_l = sp.Symbol("l_f", nonnegative=True)

BOUNDARIES = ("form limit", "tip", "toe", "heel")
#: The boundary on the far side of the patch: the two never meet (no corner between them).
OPPOSITE = {"form limit": "tip", "tip": "form limit", "toe": "heel", "heel": "toe"}

BLANK = Layout("FlankBlank", "Where one member's flank ends (the blank), in its frame S_i.", (
    Field("pitch_radius_mm", r, "mm", "generating (reference) pitch radius r"),
    Field("tip_height_mm", tip_height, "mm", "tip above the rack pitch plane, along the rack depth axis"),
    Field("rack_shift_mm", s, "mm", "rack shift s along its depth axis"),
    Field("cone_angle", gamma, "rad", "cone angle gamma"),
    Field("toe_z_mm", toe_z, "mm", "axial position of the toe (small end) in S_i"),
    Field("heel_z_mm", heel_z, "mm", "axial position of the heel (large end) in S_i"),
    Field("form_limit_l_mm", form_l, "mm", "l where the straight edge starts: the tip round's junction l_t (0: sharp rack)"),
), trig=("cone_angle",))


def tip_radius(zz=z):
    return r + (tip_height + s) / sp.cos(gamma) + zz * sp.tan(gamma)


def margins():
    """The four signed margins (mm), positive inside: form limit, tip, toe, heel."""
    direction = (heel_z - toe_z) / sp.Abs(heel_z - toe_z)
    return sp.Matrix([l - form_l, tip_radius() - sp.sqrt(x ** 2 + y ** 2), (z - toe_z) * direction,
                      (heel_z - z) * direction])


POINT = sp.Matrix([x, y, z])
