"""Gear materials of the rating (docs/rating.md 4.1): the material types that ISO 6336-2/-3's life
curves tell apart, their default strength limits from ISO 6336-5 by quality, and their life factors.

Pure data and small functions; the spec's ``[material]`` keys name a type and quality per member
(``validate`` checks them with :func:`check_member`), ``factors.Factors`` reads the rest.

* **Types** (ISO 6336-5's designations):  ``case-hardened`` (Eh, wrought), ``through-hardened``
  (V, wrought alloy steel), ``nitrided`` (NT nitr., nitriding steel), ``nitrocarburised``
  (NV nitrocar., wrought), ``grey-cast-iron`` (GG), ``nodular-cast-iron`` (GGG, pearlitic or
  bainitic).  Each pair of (Z_NT curve, Y_NT curve) of ISO 6336-2/-3 has one of them.
* **Limits:** sigma_lim = A x + B with x the surface hardness (HV for steels, HBW for cast irons),
  ISO 6336-5:2016 Table 1 by type and quality ML / MQ / ME.
* **Life factors** (no limited pitting): log-log between the tabulated points, constant beyond.
* **Groups of Y_X and Y_RrelT** (ISO 6336-3): ``size_group`` and ``surface_group`` of each type.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..spec.keys import MATERIAL_QUALITIES, MATERIAL_TYPES

__all__ = ["MATERIALS", "QUALITIES", "DEFAULT_MATERIAL", "DEFAULT_QUALITY", "Material", "check_member",
           "life_factor", "limits_mpa"]

QUALITIES = MATERIAL_QUALITIES
DEFAULT_QUALITY = "MQ"
DEFAULT_MATERIAL = "case-hardened"

#: Z_NT of ISO 6336-2:2019 Table 2 (no limited pitting): (load cycles, Z_NT) points
Z_NT_EH_V = ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85))  # St, V, GGG (perl., bai.), GTS (perl.), Eh, IF
Z_NT_NT_GG = ((1e5, 1.3), (2e6, 1.0), (1e10, 0.85))  # GG, GGG (ferr.), NT (nitr.), NV (nitr.)
Z_NT_NV_NITROCAR = ((1e5, 1.1), (2e6, 1.0), (1e10, 0.85))  # NV (nitrocar.)
#: Y_NT of ISO 6336-3:2019 Table 3: (load cycles, Y_NT) points
Y_NT_V = ((1e4, 2.5), (3e6, 1.0), (1e10, 0.85))  # V, GGG (perl., bai.), GTS (perl.)
Y_NT_EH = ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85))  # Eh, IF (root)
Y_NT_NT_GG = ((1e3, 1.6), (3e6, 1.0), (1e10, 0.85))  # St, NT (nitr.), NV (nitr.), GG, GGG (ferr.)
Y_NT_NV_NITROCAR = ((1e3, 1.1), (3e6, 1.0), (1e10, 0.85))  # NV (nitrocar.)


@dataclass(frozen=True)
class Material:
    """One material type: ISO 6336-5 Table 1 rows and the ISO 6336-2/-3 life curves."""

    name: str
    iso: str  # ISO 6336-5's designation
    hardness_unit: str  # "" (limits independent of hardness), "hv" or "hbw"
    default_hardness: float | None  # mid-range (this work's choice) where the limits depend on it
    contact: dict  # quality -> (A, B, hardness from, hardness to)
    root: dict  # quality -> (A, B, hardness from, hardness to)
    z_nt: tuple
    y_nt: tuple
    running_in: str  # ISO 6336-1's running-in allowance group: "hardened", "through-hardened", "cast-iron"
    density_kg_per_mm3: float = 7.83e-6
    #: ISO 6336-3's groups of the size factor Y_X and the relative surface factor Y_RrelT (keys of
    #: iso6336.SIZE_FACTOR and iso6336.SURFACE_FACTOR)
    size_group: str = "Eh, IF, NT, NV"
    surface_group: str = "V, GGG (perl., bai.), Eh, IF"


def _rows(ml, mq, me):
    return {"ML": ml, "MQ": mq, "ME": me}


#: ISO 6336-5:2016 Table 1: sigma_lim = A x + B on [x_from, x_to]
MATERIALS = {m.name: m for m in (
    Material("case-hardened", "Eh (wrought, case-hardened)", "", None,
             _rows((0.0, 1300.0, 600, 800), (0.0, 1500.0, 660, 800), (0.0, 1650.0, 660, 800)),
             # MQ: 500 for a core hardness of at least 30 HRC (ISO: 425 / 461 for lower core hardness)
             _rows((0.0, 312.0, 600, 800), (0.0, 500.0, 660, 800), (0.0, 525.0, 660, 800)),
             Z_NT_EH_V, Y_NT_EH, "hardened"),
    Material("through-hardened", "V (wrought alloy steel, through-hardened)", "hv", 300.0,
             _rows((1.313, 188.0, 200, 360), (1.313, 373.0, 200, 360), (2.213, 260.0, 200, 390)),
             _rows((0.423, 104.0, 200, 360), (0.425, 187.0, 200, 360), (0.358, 231.0, 200, 390)),
             Z_NT_EH_V, Y_NT_V, "through-hardened", size_group="St, V, GGG (perl., bai.), GTS"),
    Material("nitrided", "NT nitr. (nitriding steel, nitrided)", "", None,
             _rows((0.0, 1125.0, 650, 900), (0.0, 1250.0, 650, 900), (0.0, 1450.0, 650, 900)),
             _rows((0.0, 270.0, 650, 900), (0.0, 420.0, 650, 900), (0.0, 468.0, 650, 900)),
             Z_NT_NT_GG, Y_NT_NT_GG, "hardened", surface_group="GG, GGG (ferr.), NT, NV"),
    Material("nitrocarburised", "NV nitrocar. (wrought steel, nitrocarburised)", "hv", 400.0,
             _rows((0.0, 650.0, 300, 650), (1.167, 425.0, 300, 450), (1.167, 425.0, 300, 450)),
             _rows((0.0, 224.0, 300, 650), (0.653, 94.0, 300, 450), (0.653, 94.0, 300, 450)),
             Z_NT_NV_NITROCAR, Y_NT_NV_NITROCAR, "hardened", surface_group="GG, GGG (ferr.), NT, NV"),
    Material("grey-cast-iron", "GG (grey cast iron)", "hbw", 200.0,
             _rows((1.033, 132.0, 150, 240), (1.033, 132.0, 150, 240), (1.465, 122.0, 175, 275)),
             _rows((0.256, 8.0, 150, 240), (0.256, 8.0, 150, 240), (0.200, 53.0, 175, 275)),
             Z_NT_NT_GG, Y_NT_NT_GG, "cast-iron", 7.2e-6, size_group="GG, GGG (ferr.)",
             surface_group="GG, GGG (ferr.), NT, NV"),
    Material("nodular-cast-iron", "GGG (nodular cast iron, pearlitic or bainitic)", "hbw", 250.0,
             _rows((1.434, 211.0, 175, 300), (1.434, 211.0, 175, 300), (1.500, 250.0, 200, 300)),
             _rows((0.350, 119.0, 175, 300), (0.350, 119.0, 175, 300), (0.380, 134.0, 200, 300)),
             # ISO 6336-1 groups GGG (perl., bai.) with St and V for the running-in allowances (issue 57.7)
             Z_NT_EH_V, Y_NT_V, "through-hardened", 7.1e-6, size_group="St, V, GGG (perl., bai.), GTS"),
)}

assert tuple(MATERIALS) == MATERIAL_TYPES, "beveloid/spec/keys.py MATERIAL_TYPES and the table here differ"


def hardness_key(member: str, unit: str) -> str:
    return f"{member}_surface_hardness_{unit}"


def check_member(member: str, material: str, quality: str, hardness_hv, hardness_hbw) -> float | None:
    """The hardness the limits use (None where they do not depend on it); a ValueError of one line
    naming the key for a hardness the type does not take or outside ISO 6336-5's range."""
    m = MATERIALS[material]
    given = {"hv": hardness_hv, "hbw": hardness_hbw}
    for unit, value in given.items():
        if value is not None and unit != m.hardness_unit:
            takes = (f"it takes material.{hardness_key(member, m.hardness_unit)}" if m.hardness_unit
                     else "its ISO 6336-5 limits do not depend on the hardness")
            raise ValueError(f"material.{hardness_key(member, unit)} = {value:g}: not used with "
                             f"material.{member}_material = \"{material}\" ({takes}); remove it")
    if not m.hardness_unit:
        return None
    x = given[m.hardness_unit]
    if x is None:
        return m.default_hardness
    lo = max(m.contact[quality][2], m.root[quality][2])
    hi = min(m.contact[quality][3], m.root[quality][3])
    if not lo <= x <= hi:
        raise ValueError(f"material.{hardness_key(member, m.hardness_unit)} = {x:g}: must be from {lo:g} to {hi:g} "
                         f"{m.hardness_unit.upper()}, the range of ISO 6336-5 for \"{material}\" of quality {quality}")
    return float(x)


def limits_mpa(material: str, quality: str, hardness: float | None) -> tuple:
    """(sigma_Hlim, sigma_Flim) in MPa of ISO 6336-5:2016 Table 1 for a type, quality and hardness."""
    m = MATERIALS[material]
    x = 0.0 if hardness is None else hardness
    a_h, b_h = m.contact[quality][:2]
    a_f, b_f = m.root[quality][:2]
    return a_h * x + b_h, a_f * x + b_f


def life_factor(points, cycles: float | None) -> float:
    """The life factor at ``cycles`` load cycles (None: long life, 1): the static value up to the first
    point, log-log between the points (ISO's (N_0 / N_L)^exponent), the last value beyond."""
    if cycles is None:
        return 1.0
    if cycles <= points[0][0]:
        return points[0][1]
    for (n0, f0), (n1, f1) in zip(points[:-1], points[1:]):
        if cycles <= n1:
            t = math.log(cycles / n0) / math.log(n1 / n0)
            return math.exp(math.log(f0) + t * (math.log(f1) - math.log(f0)))
    return points[-1][1]
