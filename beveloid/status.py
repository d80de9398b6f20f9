"""The statuses of the package: one :class:`enum.StrEnum` per kind of status, and the integer codes of
the two that arrays carry.

Each kind has its own enum because the same word means different things in two of them: "no contact"
of a loaded position (the load finds no touching cell) is not "no contact" of a contact ellipse (the
rigid point is not a contact) nor that of the whole-tooth checks (no path of contact on a flank).  A
member is its JSON string (``PointStatus.OK == "ok"``, ``json.dumps`` and ``f"{s}"`` write ``ok``),
so outputs read the same and readers may compare with either; code builds a status from the enum
only (tests/test_architecture.py).

* :class:`Status` (codes) and :class:`PointStatus` (labels): a solved point of the rigid TCA, the
  sweep, explore's aligned contact and the backlash;
* :class:`LoadedStatus`: a position of the loaded TCA;
* :class:`EllipseStatus`: the contact ellipse of a TCA point;
* :class:`ToothStatus`: a finding of the whole-tooth checks;
* :class:`Outcome` (codes) and :class:`DesignStatus` (labels): what a design came to;
* :class:`ExploreStatus`: explore's own statuses of a row, besides the ones above that it reuses;
* :class:`Validity` and :class:`Verdict`: an ISO section's factors, a member's rating;
* :class:`EvaluationStatus`: one design evaluated by the optimiser.
"""
from __future__ import annotations

import enum

__all__ = ["Status", "PointStatus", "carries_numbers", "LoadedStatus", "EllipseStatus", "ToothStatus", "Outcome",
           "DesignStatus", "ExploreStatus", "Validity", "Verdict", "EvaluationStatus"]


class PointStatus(enum.StrEnum):
    """What a solved point is, by name (the labels of :class:`Status`)."""

    OK = "ok"
    EDGE = "edge"
    OUTSIDE = "outside"
    FAILED = "failed"


class Status(enum.IntEnum):
    """What a solved point is, as the code arrays carry it.  Only OK and EDGE points carry numbers."""

    OK = 0  #: surface contact inside both flanks
    EDGE = 1  #: edge or corner contact: a boundary curve (tip, toe, heel, form limit) bears on the mating flank
    OUTSIDE = 2  #: the two bounded flank patches cannot touch at this position: no numbers
    FAILED = 3  #: the solver did not converge: no number

    @property
    def label(self) -> PointStatus:
        """The name used in JSON, tables and plots: "ok", "edge", "outside", "failed"."""
        return PointStatus[self.name]

    @classmethod
    def labels(cls, codes) -> list[PointStatus]:
        """Labels of a sequence of codes (one lookup per code: a mesh study has ~1200)."""
        table = {int(s): s.label for s in cls}
        return [table[c] if c in table else cls(c).label for c in map(int, codes)]  # cls(c): the enum's error


def carries_numbers(codes):
    """Boolean mask (array-like codes): points with a contact (OK or EDGE)."""
    import numpy as np

    return np.asarray(codes) <= Status.EDGE


class LoadedStatus(enum.StrEnum):
    """A position of the loaded TCA."""

    OK = "ok"
    NO_CONTACT = "no contact"  #: the load closes no gap: no cell touches at this position
    NOT_CONVERGED = "not converged"  #: the contact problem did not settle


class EllipseStatus(enum.StrEnum):
    """The contact ellipse of a TCA point."""

    ELLIPSE = "ellipse"
    LINE_CONTACT = "line contact"  #: a principal relative curvature ~ 0: the patch is a line
    NO_ELLIPSE = "no ellipse"  #: the relative curvature is not positive definite
    NO_CONTACT = "no contact"  #: the point is no surface contact (its status is not ok)


class ToothStatus(enum.StrEnum):
    """A finding of the whole-tooth checks (``tooth_status`` of the design JSON)."""

    UNDERCUT = "undercut"
    POINTED = "pointed"
    INTERFERENCE = "interference"
    TIP_INSIDE_BASE_CIRCLE = "tip inside base circle"
    NO_CONTACT = "no contact"  #: the contact ratio of a flank found no path of contact
    NO_FORM_LIMIT = "no form limit"
    #: the unmodified aligned pair's contact ratio on a flank is below 1: no continuous mesh on that flank
    CONTACT_RATIO_BELOW_ONE = "contact ratio below 1"
    #: `beveloid export` refuses the member's tooth (in both formats, or in STEP only), and why
    NOT_EXPORTABLE = "not exportable"


class DesignStatus(enum.StrEnum):
    """What the design of one spec came to, by name (the labels of :class:`Outcome`)."""

    OK = "ok"
    ZERO_CONE_ANGLE = "zero_cone_angle"
    NO_WORKING_PRESSURE_ANGLE = "no_working_pressure_angle"
    GEAR_HELIX_ANGLE_OUT_OF_RANGE = "gear_helix_angle_out_of_range"
    TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE = "transverse_pressure_angle_not_positive"
    NON_FINITE_DESIGN = "non_finite_design"
    NON_PHYSICAL_PITCH_RADIUS = "non_physical_pitch_radius"
    TIP_INSIDE_BASE_CIRCLE = "tip_inside_base_circle"
    POINTED_TEETH = "pointed_teeth"
    PITCH_POINT_OFF_ACTIVE_PROFILE = "pitch_point_off_active_profile"


class Outcome(enum.IntEnum):
    """What the design of one spec came to, as the code arrays carry it: OK, or the first check it fails
    (in the order checked)."""

    OK = 0
    ZERO_CONE_ANGLE = 1
    NO_WORKING_PRESSURE_ANGLE = 2
    GEAR_HELIX_ANGLE_OUT_OF_RANGE = 3
    TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE = 4
    NON_FINITE_DESIGN = 5
    NON_PHYSICAL_PITCH_RADIUS = 6
    TIP_INSIDE_BASE_CIRCLE = 7
    POINTED_TEETH = 8
    PITCH_POINT_OFF_ACTIVE_PROFILE = 9

    @property
    def label(self) -> DesignStatus:
        """The name in tables, CSV and JSON: "ok", "pointed_teeth", ..."""
        return DesignStatus[self.name]


class ExploreStatus(enum.StrEnum):
    """explore's own statuses of a row (its ``status`` is otherwise a :class:`DesignStatus` or the
    whole-tooth flag that took it off ok, its ``mc_status`` a :class:`PointStatus`)."""

    DESIGN_REFUSED = "design_refused"  #: the design of the row's own spec refused it without an outcome
    TOOTH_CHECK_FAILED = "tooth_check_failed"  #: the whole-tooth checks stopped with an error
    NOT_CHECKED = "not checked"  #: ``tooth_status`` of a run that leaves the tooth unchecked
    NO_ALIGNED_CONTACT = "no_aligned_contact"  #: ``mc_status``: no surface contact of the aligned pair


class Validity(enum.StrEnum):
    """An ISO 6336 section's factors: OK, else the status is the text saying where they hold no longer."""

    OK = "ok"


class Verdict(enum.StrEnum):
    """A member's rating against the minimum safety factors."""

    PASSES = "passes"
    FAILS = "fails"
    CONDITIONAL = "conditional"  #: passes only if an edge contact is relieved


class EvaluationStatus(enum.StrEnum):
    """One design evaluated by the optimiser."""

    OK = "ok"
    REFUSED = "refused"  #: the spec or the design refused the values (a user error)
    FAILED = "failed"  #: an analysis stopped with an error
    INCOMPLETE = "incomplete"  #: analysed, but an objective is missing at some torque or error set
