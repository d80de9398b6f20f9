"""Reports of a pitch-cone design: a table laid out like the paper's Table 1, and JSON.

``format_table1(result) -> str``
    Rows in the order of Table 1 (normal module ... FPD angles) plus the working normal
    pressure angle alpha_nw and the working mounting distance d_w; columns
    ``Parameter | Symbol | Pinion | Gear``.  Angles in degrees, six decimals (more than
    the paper prints); pair quantities (delta, E, xi_L, xi_R, alpha_nw) in the pinion column.
    Notes of the design (undercut warnings, several roots of Eq 17) follow the table.

``design_json(result) -> dict``
    A JSON-ready dict (full-precision floats, angles in degrees).  Contract -- these keys
    are always present:

    * top level: ``working_normal_pressure_angle_deg``, ``fpd_angle_left_deg``,
      ``fpd_angle_right_deg``, ``pinion``, ``gear``;
    * ``pinion`` and ``gear``: ``helix_angle_deg``, ``profile_shift``,
      ``transverse_angular_factor``, ``mounting_distance_mm``, ``working_cone_angle_deg``,
      ``working_helix_angle_deg``, ``working_pitch_radius_mm``, ``reference_pitch_radius_mm``.

    Extra keys: top level ``procedure``, ``normal_module_mm``, ``normal_pressure_angle_deg``,
    ``shaft_angle_deg``, ``offset_mm``, ``offset_residual_mm``, ``normal_angular_factor``,
    ``notes``; per member ``teeth``, ``hand``, ``cone_angle_deg``, ``face_width_mm``,
    ``working_mounting_distance_mm``, transverse pressure angles (reference and working,
    left/right), the member's FPD angles, ``pitch_point_angle_deg``,
    ``addendum_coefficient``, ``cutter_addendum_coefficient``, ``reference_section_offset_mm``,
    ``rack_shift_mm``.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

# Annotations name beveloid.design's DesignResult and MemberDesign as strings (noqa: F821 there):
# design imports this module, not the other way round.

__all__ = ["format_table1", "design_json", "TABLE1_ROWS"]

#: (parameter label, symbol) of the rows of :func:`format_table1`, in order.
TABLE1_ROWS: tuple[tuple[str, str], ...] = (
    ("Normal module (mm)", "mn"),
    ("Normal pressure angle (deg)", "αn"),
    ("Number of teeth", "N"),
    ("Shaft angle (deg)", "δ"),
    ("Offset (mm)", "E"),
    ("Cone angle (deg)", "γ"),
    ("Helix angle (deg)", "β"),
    ("Profile shifting factor", "xt"),
    ("Total face-width (mm)", "W"),
    ("Transverse angular factor", "ξt"),
    ("Mounting distance (mm)", "d"),
    ("Working cone angle (deg)", "γw"),
    ("Working helix angle (deg)", "βw"),
    ("FPD-angle (deg)", "ξL"),
    ("FPD-angle (deg)", "ξR"),
    ("Working normal pressure angle (deg)", "αnw"),
    ("Working mounting distance (mm)", "dw"),
)

_DIGITS = 6


def _f(x: float) -> str:
    return f"{x:.{_DIGITS}f}"


def _d(x: float) -> str:
    return _f(math.degrees(x))


def _helix(m: "MemberDesign") -> str:  # noqa: F821
    return f"{_d(m.helix_angle)} ({m.hand})" if m.hand else _d(m.helix_angle)


def format_table1(result: DesignResult) -> str:  # noqa: F821
    """The design as a plain-text table laid out like Table 1 of the paper."""
    p, g = result.pinion, result.gear
    values: dict[str, tuple[str, ...]] = {
        "mn": (_f(result.normal_module_mm), _f(result.normal_module_mm)),
        "αn": (_d(result.normal_pressure_angle), _d(result.normal_pressure_angle)),
        "N": (str(p.teeth), str(g.teeth)),
        "δ": ("", "", _d(result.shaft_angle)),
        "E": ("", "", _f(result.offset_mm)),
        "γ": (_d(p.cone_angle), _d(g.cone_angle)),
        "β": (_helix(p), _helix(g)),
        "xt": (_f(p.profile_shift), _f(g.profile_shift)),
        "W": (_f(p.face_width_mm), _f(g.face_width_mm)),
        "ξt": (_f(p.transverse_angular_factor), _f(g.transverse_angular_factor)),
        "d": (_f(p.mounting_distance_mm), _f(g.mounting_distance_mm)),
        "γw": (_d(p.working_cone_angle), _d(g.working_cone_angle)),
        "βw": (_d(p.working_helix_angle), _d(g.working_helix_angle)),
        "ξL": (_d(p.fpd_angle_left), _d(g.fpd_angle_left), _d(result.fpd_angle_left)),
        "ξR": (_d(p.fpd_angle_right), _d(g.fpd_angle_right), _d(result.fpd_angle_right)),
        "αnw": ("", "", _d(result.working_normal_pressure_angle)),
        "dw": (_f(p.working_mounting_distance_mm), _f(g.working_mounting_distance_mm)),
    }
    header = ("Parameter", "Symbol", "Pinion", "Gear", "Pair")
    rows = [header] + [(label, sym, *values[sym], "", "")[:5] for label, sym in TABLE1_ROWS]
    widths = [max(len(r[k]) for r in rows) for k in range(5)]

    def line(r: tuple[str, ...]) -> str:
        cells = [r[0].ljust(widths[0]), r[1].ljust(widths[1])] + [r[k].rjust(widths[k]) for k in (2, 3, 4)]
        return " | ".join(cells).rstrip(" |")

    out = [f"Crossed beveloid gear pair: {result.procedure} pitch-cone design", line(header),
           "-+-".join("-" * w for w in widths)]
    out += [line(r) for r in rows[1:]]
    out += ["", "Pair: quantities of the pair; its FPD angles are the sums of the members' (Eq 18),"
            " xi_L = xi_L1 + xi_L2, xi_R = xi_R1 + xi_R2."]
    if result.notes:
        out.append("")
        out += [f"note: {n}" for n in result.notes]
    return "\n".join(out)


def _member_json(m: "MemberDesign") -> dict[str, Any]:  # noqa: F821
    """Every field of MemberDesign: angles (metadata unit rad) in degrees as <name>_deg, the rest as
    they are; plus the derived hand and rack shift."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(m):
        value = getattr(m, f.name)
        if f.name == "name":
            continue
        if f.metadata.get("unit") == "rad":
            out[f"{f.name}_deg"] = math.degrees(value)
        else:
            out[f.name] = int(value) if isinstance(value, int) else float(value)
    out["hand"] = m.hand
    out["rack_shift_mm"] = float(m.rack_shift_mm)
    return out


def design_json(result: DesignResult) -> dict[str, Any]:  # noqa: F821
    """The design as a JSON-ready dict (see the module docstring for the key contract)."""
    deg = math.degrees
    return {
        "working_normal_pressure_angle_deg": deg(result.working_normal_pressure_angle),
        "fpd_angle_left_deg": deg(result.fpd_angle_left),
        "fpd_angle_right_deg": deg(result.fpd_angle_right),
        "pinion": _member_json(result.pinion),
        "gear": _member_json(result.gear),
        "procedure": result.procedure,
        "normal_module_mm": float(result.normal_module_mm),
        "normal_pressure_angle_deg": deg(result.normal_pressure_angle),
        "shaft_angle_deg": deg(result.shaft_angle),
        "offset_mm": float(result.offset_mm),
        "offset_residual_mm": float(result.offset_residual_mm),
        "normal_angular_factor": float(result.normal_angular_factor),
        "notes": list(result.notes),
    }
