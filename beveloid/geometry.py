"""The designed pair as the solver sees it: each member's surface model, generating data and
blank, and where the members sit (mm, rad).

The generated kernels take their parameters as named layouts (``beveloid.generated.layouts``);
this module fills them by field name from the design, never by position.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from . import names
from .generated import flank_boundaries, layouts, root_fillet, surface_models, tca_kernels
from .solver.records import Problem

BOUNDARIES = flank_boundaries.BOUNDARIES

MEMBERS = names.MEMBERS  # Member.PINION, Member.GEAR: equal to "pinion", "gear"


@dataclass(frozen=True)
class Member:
    """One member's generating data and blank, in mm and rad."""

    teeth: int
    helix_angle: float
    cone_angle: float
    cutter_addendum_mm: float
    rack_shift_mm: float
    pitch_radius_mm: float
    working_pitch_radius_mm: float
    working_mounting_distance_mm: float
    reference_section_offset_mm: float
    face_width_mm: float
    tip_height_mm: float  # tip above the rack pitch plane, along the rack depth axis
    pitch_point_angle: float  # theta_i of the pitch point on the working pitch cone
    tooth_surface: str = "involute"  # a model of tca_kernels.MODELS
    surface_options: tuple = ()  # (name, value) pairs: the model's own parameters, by layout field name
    cutter_tip_radius_mm: float = 0.0  # the rack's tip round rho_a0 (root fillet, beveloid.tooth.fillet)
    form_limit_l_mm: float = 0.0  # l where the flank starts: the tip round's junction l_t (0: sharp rack)

    @property
    def axial_placement_mm(self) -> float:
        """d_w - b_c: where the S_i origin sits on the axis, from the common perpendicular."""
        return self.working_mounting_distance_mm - self.reference_section_offset_mm

    @property
    def face_limits(self):
        """(toe, heel) axial positions in S_i, centred on the working pitch circle (z = b_c)."""
        c = self.reference_section_offset_mm
        w = self.face_width_mm / 2
        if np.ndim(self.cone_angle):  # the members of many designs
            up = self.cone_angle >= 0
            return np.where(up, c - w, c + w), np.where(up, c + w, c - w)
        return (c - w, c + w) if self.cone_angle >= 0 else (c + w, c - w)

    @classmethod
    def from_design(cls, m, normal_module_mm, normal_pressure_angle, spec_member) -> "Member":
        """From a designed member ``m`` (a :class:`beveloid.design.MemberDesign`, or the members of many
        designs by the same field names: :class:`beveloid.design.checks.MemberArrays`) and its spec
        section (``tooth_surface``, ``surface_options``, ``cutter_tip_radius_coefficient``)."""
        mn = normal_module_mm
        rho = getattr(spec_member, "cutter_tip_radius_coefficient", 0.0) * mn
        form = junction_l(normal_pressure_angle, rho, mn)
        return cls(
            teeth=_number(m.teeth, int), helix_angle=m.helix_angle, cone_angle=m.cone_angle,
            cutter_addendum_mm=m.cutter_addendum_mm, rack_shift_mm=m.rack_shift_mm,
            pitch_radius_mm=m.reference_pitch_radius_mm, working_pitch_radius_mm=m.working_pitch_radius_mm,
            working_mounting_distance_mm=m.working_mounting_distance_mm,
            reference_section_offset_mm=m.reference_section_offset_mm, face_width_mm=m.face_width_mm,
            tip_height_mm=m.addendum_coefficient * mn, pitch_point_angle=m.pitch_point_angle,
            tooth_surface=getattr(spec_member, "tooth_surface", "involute"),
            surface_options=tuple(sorted(dict(getattr(spec_member, "surface_options", ()) or ()).items())),
            cutter_tip_radius_mm=rho, form_limit_l_mm=_number(form, float) if np.ndim(m.cone_angle) == 0 else
            np.broadcast_to(form, np.shape(m.cone_angle)))

    def tip_radius(self, z):
        """Tip cone radius at axial positions z (S_i): the generated tip margin of a point at radius r, plus r."""
        z = np.asarray(z, dtype=float)
        r = self.pitch_radius_mm
        point = np.stack(np.broadcast_arrays(r, 0.0, z), axis=-1)
        return r + flank_boundaries.flank_margins(point, 0.0, self.blank()).margins[..., BOUNDARIES.index("tip")]

    def blank(self) -> np.ndarray:
        """The FlankBlank vector (fields,), or (n, fields) for the members of n designs."""
        toe, heel = self.face_limits
        return pack_rows(layouts.FlankBlank, dict(
            pitch_radius_mm=self.pitch_radius_mm, tip_height_mm=self.tip_height_mm, rack_shift_mm=self.rack_shift_mm,
            cone_angle=self.cone_angle, toe_z_mm=toe, heel_z_mm=heel, form_limit_l_mm=self.form_limit_l_mm))


def _number(x, kind):
    """A Python int or float for one design; the arrays of many designs as they are."""
    return kind(x) if np.ndim(x) == 0 else x


def pack_rows(layout, values) -> np.ndarray:
    """A generated layout filled by field name: (fields,) for one design, (n, fields) for arrays of n."""
    return np.ascontiguousarray(np.stack(np.broadcast_arrays(*layout.pack(values)), axis=-1), dtype=float)


def junction_l(normal_pressure_angle, tip_radius_mm, normal_module_mm):
    """l_t of the rack's tip round: where the flank's straight part starts, the form limit of the
    blank (generated root_fillet.tip_round; the other fields do not enter it); float or array."""
    values = dict(normal_pressure_angle=normal_pressure_angle, helix_angle=0.0, cone_angle=0.0, cutter_addendum_mm=0.0,
                  half_thickness_mm=0.0, rack_shift_mm=0.0, pitch_radius_mm=1.0, cutter_tip_radius_mm=tip_radius_mm,
                  normal_module_mm=normal_module_mm, profile_crowning_um=0.0, lead_crowning_um=0.0, face_width_mm=1.0)
    shaped = dict(zip(values, np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values.values()))))
    params = np.moveaxis(np.asarray(layouts.FilletParams.pack(shaped), dtype=float), 0, -1)
    return root_fillet.tip_round(params).junction_l


@dataclass(frozen=True)
class PairGeometry:
    """Everything the TCA needs: the designed pair in mm and rad.

    One design (floats), or many (each field an array of n designs, one surface model per member:
    ``beveloid explore``'s batched contact at P); the parameter vectors then have a leading axis n."""

    normal_module_mm: float
    normal_pressure_angle: float
    offset_mm: float
    shaft_angle: float
    pinion: Member
    gear: Member

    @property
    def half_thickness_mm(self):
        return math.pi * self.normal_module_mm / 4

    @classmethod
    def from_design(cls, result) -> "PairGeometry":
        """From a :class:`beveloid.design.DesignResult` (surface models from its spec)."""
        mn, spec = result.normal_module_mm, result.spec
        return cls(mn, result.normal_pressure_angle, result.offset_mm, result.shaft_angle,
                   Member.from_design(result.pinion, mn, result.normal_pressure_angle, spec.pinion),
                   Member.from_design(result.gear, mn, result.normal_pressure_angle, spec.gear))

    def unmodified(self) -> "PairGeometry":
        """The pair with every flank modification of the built-in models taken off (crowning, tip and end
        relief, lead slope: the models ``surface_models.SELECTED_BY`` selects by a key, back to the
        involute); this geometry itself when it has none.  A user's own surface model is the flank, not
        a modification of it, and stays."""
        bare = {}
        for which in MEMBERS:
            m = self.member(which)
            if surface_models.SELECTED_BY.get(m.tooth_surface):
                bare[which] = replace(m, tooth_surface=surface_models.DEFAULT_MODEL, surface_options=())
        return replace(self, **bare) if bare else self

    def modifications_scaled(self, t: float) -> "PairGeometry":
        """The pair with every modification amplitude of the built-in models (their keys in um: crowning,
        relief, lead slope) times ``t``, extents and the models kept: t = 0 is the unmodified flank in the
        same model, t = 1 this pair (a path for a solve the full modification throws off)."""
        scaled = {}
        for which in MEMBERS:
            m = self.member(which)
            if surface_models.SELECTED_BY.get(m.tooth_surface):
                opts = tuple((k, v * t if k.endswith("_um") and isinstance(v, float) else v) for k, v in m.surface_options)
                scaled[which] = replace(m, surface_options=opts)
        return replace(self, **scaled) if scaled else self

    def member(self, which: str) -> Member:
        if which not in MEMBERS:
            raise ValueError(f"member must be one of {', '.join(MEMBERS)}, got {which!r}")
        return getattr(self, which)

    def surface_values(self, which: str) -> dict:
        """Every quantity a surface model may take, by layout field name."""
        m = self.member(which)
        values = dict(normal_pressure_angle=self.normal_pressure_angle, helix_angle=m.helix_angle,
                      cone_angle=m.cone_angle, cutter_addendum_mm=m.cutter_addendum_mm,
                      half_thickness_mm=self.half_thickness_mm, rack_shift_mm=m.rack_shift_mm,
                      pitch_radius_mm=m.pitch_radius_mm, face_width_mm=m.face_width_mm,
                      normal_module_mm=self.normal_module_mm, tip_height_mm=m.tip_height_mm,
                      reference_section_offset_mm=m.reference_section_offset_mm)
        choices = surface_models.MODEL_CHOICES.get(m.tooth_surface, {})  # keys given by name -> kernel values
        values.update({k: names[default] for k, (default, names, _) in choices.items()})
        values.update({k: choices[k][1][v] if k in choices else v for k, v in m.surface_options})
        return values

    def surface_params(self, which: str) -> np.ndarray:
        """The member's parameter vector for its surface model, zero-padded to tca_kernels.PARAMETER_COUNT
        ((n, PARAMETER_COUNT) for n designs)."""
        fields = pack_rows(tca_kernels.SURFACE_LAYOUTS[self.member(which).tooth_surface], self.surface_values(which))
        out = np.zeros(fields.shape[:-1] + (tca_kernels.PARAMETER_COUNT,))
        out[..., :fields.shape[-1]] = fields
        return out

    def placement(self) -> np.ndarray:
        return pack_rows(layouts.PairPlacement, dict(
            offset_mm=self.offset_mm, shaft_angle=self.shaft_angle,
            pinion_axial_placement_mm=self.pinion.axial_placement_mm,
            gear_axial_placement_mm=self.gear.axial_placement_mm))

    def problem(self, flank: str) -> Problem:
        """The solver core's problem for one flank (beveloid/solver/records.py)."""
        return Problem(pinion_model=tca_kernels.model_id(self.pinion.tooth_surface),
                       gear_model=tca_kernels.model_id(self.gear.tooth_surface), flank=tca_kernels.flank_id(flank),
                       pinion_params=self.surface_params("pinion"), gear_params=self.surface_params("gear"),
                       pair=self.placement(), pinion_blank=self.pinion.blank(), gear_blank=self.gear.blank())

    @property
    def pitch_angles(self):
        return 2 * math.pi / self.pinion.teeth, 2 * math.pi / self.gear.teeth

    def surface(self, which, flank, l, u):
        """Point, outward unit normal and roll angle of a member's flank (generated kernel)."""
        return tca_kernels.surface(self.member(which).tooth_surface, flank, l, u, self.surface_params(which))

    def surface_jet(self, which, flank, l, u):
        return tca_kernels.surface_jet(self.member(which).tooth_surface, flank, l, u, self.surface_params(which))
