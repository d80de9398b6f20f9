"""The results of a pitch-cone design: :class:`MemberDesign` per member, :class:`DesignResult`,
and :class:`DesignError`; radians and mm."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..errors import ErrorCode, UserError
from ..spec import DEFAULT_SOURCE, DesignSpec


class DesignError(UserError):
    """A design request that has no (physical) solution; one line naming key(s) and a direction.

    Attributes: ``detail`` (message without the ``source:`` prefix), ``keys`` (tuple of the
    dotted spec keys concerned, may be empty), ``source`` (the spec's file, if any) and ``outcome``
    (the :class:`beveloid.design.Outcome` refused, None for a request the design cannot read).
    """

    code = ErrorCode.DESIGN_REFUSED

    def __init__(self, message: str, *, keys: tuple[str, ...] = (), source: str | None = None, outcome=None):
        detail = " ".join(str(message).split())
        full = f"{source}: {detail}" if source and source != DEFAULT_SOURCE else detail
        super().__init__(full)
        self.detail = detail
        self.keys = tuple(keys)
        self.source = source
        self.outcome = outcome


# ---------------------------------------------------------------------------
# Result types
# ---------------------------------------------------------------------------

#: dataclass field metadata of an angle in radians.
RAD = {"unit": "rad"}


@dataclass(frozen=True)
class MemberDesign:
    """Reference and working data of one member (pinion or gear); radians and mm.

    The single list of a member's design fields: fields marked ``RAD`` are angles (reported in
    degrees with a ``_deg`` suffix by beveloid.design.report.design_json), ``_mm`` fields lengths, the rest
    dimensionless.
    """

    name: str
    teeth: int
    normal_module_mm: float
    helix_angle: float = field(metadata=RAD)
    cone_angle: float = field(metadata=RAD)
    profile_shift: float
    transverse_angular_factor: float
    mounting_distance_mm: float
    working_mounting_distance_mm: float
    working_cone_angle: float = field(metadata=RAD)
    working_helix_angle: float = field(metadata=RAD)
    working_pitch_radius_mm: float
    reference_pitch_radius_mm: float
    transverse_pressure_angle_left: float = field(metadata=RAD)
    transverse_pressure_angle_right: float = field(metadata=RAD)
    working_transverse_pressure_angle_left: float = field(metadata=RAD)
    working_transverse_pressure_angle_right: float = field(metadata=RAD)
    fpd_angle_left: float = field(metadata=RAD)
    fpd_angle_right: float = field(metadata=RAD)
    pitch_point_angle: float = field(metadata=RAD)
    face_width_mm: float
    addendum_coefficient: float
    cutter_addendum_coefficient: float
    reference_section_offset_mm: float

    @property
    def transverse_module_mm(self) -> float:
        """m_t = m_n / cos(beta)."""
        return self.normal_module_mm / math.cos(self.helix_angle)

    @property
    def rack_shift_mm(self) -> float:
        """Rack shift along its own (tilted) depth axis: x_t m_n cos(gamma) / cos(beta)."""
        return self.profile_shift * self.normal_module_mm * math.cos(self.cone_angle) / math.cos(self.helix_angle)

    @property
    def cutter_addendum_mm(self) -> float:
        """Cutter addendum a = cutter_addendum_coefficient * m_n (this member's dedendum)."""
        return self.cutter_addendum_coefficient * self.normal_module_mm

    @property
    def hand(self) -> str:
        """'RH', 'LH' or '' (spur) from the sign of the helix angle."""
        return "RH" if self.helix_angle > 0 else ("LH" if self.helix_angle < 0 else "")


@dataclass(frozen=True)
class DesignResult:
    """Result of :func:`design` or :func:`indirect_design`; radians and mm.

    ``spec`` is the input spec (direct design) or a spec carrying the computed reference data
    (indirect design; its gear helix angle / profile shift stay unset).  The pair-level FPD
    angles are the sums of the members' (Eq 18).
    """

    spec: DesignSpec
    working_normal_pressure_angle: float
    normal_angular_factor: float
    fpd_angle_left: float
    fpd_angle_right: float
    offset_mm: float
    shaft_angle: float
    normal_module_mm: float
    normal_pressure_angle: float
    pinion: MemberDesign
    gear: MemberDesign
    notes: tuple[str, ...] = ()
    #: E(alpha_nw) from Eq 17 minus the required offset (0 for the indirect design).
    offset_residual_mm: float = 0.0
    #: "direct" or "indirect".
    procedure: str = "direct"

    def member(self, name: str) -> MemberDesign:
        """``"pinion"`` or ``"gear"`` (also 1 / 2)."""
        key = {"1": "pinion", "2": "gear"}.get(str(name), str(name).lower())
        if key not in ("pinion", "gear"):
            raise KeyError(f"member {name!r}: must be 'pinion' or 'gear'")
        return getattr(self, key)

    def to_json_dict(self) -> dict[str, Any]:
        """The JSON contract of :func:`beveloid.design.report.design_json`."""
        from .report import design_json

        return design_json(self)
