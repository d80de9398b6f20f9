"""The frozen dataclasses of a design spec and its error type.

A :class:`DesignSpec` holds one dataclass per TOML section; each field is one key of
:data:`beveloid.spec.keys.KEY_DOCS` (the package checks at import that the two agree, see
``beveloid/spec/__init__.py`` for how to add a key).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..generated import surface_models

#: ``source`` used when a spec does not come from a file; errors get no prefix.
DEFAULT_SOURCE = "<dict>"

# --------------------------------------------------------------------------
# Error type
# --------------------------------------------------------------------------


class SpecError(ValueError):
    """One-line user-facing error: names the key, the value, and what would be valid.

    ``str(err)`` is the full message (prefixed with ``source: `` when the spec
    came from a file).  Attributes: ``detail`` (message without the source
    prefix), ``key`` (dotted key such as ``"pinion.teeth"``, or ``None`` for
    file-level errors) and ``source``.
    """

    def __init__(self, message: str, *, key: str | None = None, source: str | None = None):
        detail = one_line(str(message))
        full = f"{one_line(source)}: {detail}" if source and source != DEFAULT_SOURCE else detail
        super().__init__(full)
        self.detail = detail
        self.key = key
        self.source = source


def one_line(text: str) -> str:
    """``text`` on one line: line breaks become spaces."""
    return " ".join(text.splitlines()).strip() if ("\n" in text or "\r" in text) else text


# --------------------------------------------------------------------------
# Dataclasses
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class PairSpec:
    normal_module_mm: float
    normal_pressure_angle_deg: float
    shaft_angle_deg: float
    offset_mm: float


@dataclass(frozen=True)
class MemberSpec:
    teeth: int
    cone_angle_deg: float
    face_width_mm: float
    #: Required for the pinion; for the gear it is a result of the direct design (must be None).
    helix_angle_deg: float | None = None
    #: Required for the pinion; for the gear it is a result of the direct design (must be None).
    profile_shift: float | None = None
    #: Tip height above the rack pitch line, in units of normal module.
    addendum_coefficient: float = 1.0
    #: Cutter addendum a / mn (the member's dedendum).
    cutter_addendum_coefficient: float = 1.25
    #: Radius of the rack's tip round / mn (0: the paper's sharp rack).
    cutter_tip_radius_coefficient: float = 0.0
    #: bc: distance from the working pitch circle to the reference transverse section.
    reference_section_offset_mm: float = 0.0
    #: Bore of the exported solid (``beveloid export``), 0: none.
    bore_diameter_mm: float = 0.0
    #: Flank roughness Ra (um) for the tribology (None: not given).
    roughness_ra_um: float | None = None
    #: Flank roughness Rz (um) for ISO 6336-2's Z_R (None: 6 Ra, or not given).
    roughness_rz_um: float | None = None
    #: Root fillet roughness Rz (um) for ISO 6336-3's Y_RrelT (None: not given, Y_RrelT = 1).
    root_roughness_rz_um: float | None = None
    #: Tooth-surface model (generated/surface_models.py MODELS).
    tooth_surface: str = surface_models.DEFAULT_MODEL
    #: The model's own input keys and values, as sorted (key, value) pairs.
    surface_options: tuple = ()


@dataclass(frozen=True)
class MisalignmentSpec:
    dx_mm: float = 0.0
    dy_mm: float = 0.0
    dz_mm: float = 0.0
    vertical_deg: float = 0.0
    horizontal_deg: float = 0.0


@dataclass(frozen=True)
class MaterialSpec:
    """Elastic constants of both members (the loaded TCA, ``beveloid ltca``) and their strength (the
    rating: material type and quality, ISO 6336-5; explicit limits override; None: from the type)."""

    pinion_youngs_modulus_gpa: float = 206.0
    pinion_poisson_ratio: float = 0.3
    gear_youngs_modulus_gpa: float = 206.0
    gear_poisson_ratio: float = 0.3
    pinion_material: str = "case-hardened"
    pinion_material_quality: str = "MQ"
    pinion_surface_hardness_hv: float | None = None
    pinion_surface_hardness_hbw: float | None = None
    pinion_root_stress_limit_mpa: float | None = None
    pinion_contact_stress_limit_mpa: float | None = None
    gear_material: str = "case-hardened"
    gear_material_quality: str = "MQ"
    gear_surface_hardness_hv: float | None = None
    gear_surface_hardness_hbw: float | None = None
    gear_root_stress_limit_mpa: float | None = None
    gear_contact_stress_limit_mpa: float | None = None


@dataclass(frozen=True)
class RatingSpec:
    """Load factors, speed, life and minimum safeties of the strength rating (``beveloid rating``)."""

    K_A: float = 1.0
    K_v: float | None = None  # None: ISO 6336-1 method B with pinion_speed_rpm, else 1
    accuracy_grade: int = 6
    pinion_speed_rpm: float | None = None
    life_hours: float | None = None
    S_Fmin: float = 1.4
    S_Hmin: float = 1.0
    S_Bmin: float = 1.0
    tolerance_samples: int = 0  # > 0: K_H_beta at the p90 of that many error sets of the tolerance box


@dataclass(frozen=True)
class LubricantSpec:
    """The oil of the tribology (``beveloid.tribology``); every key None: no lubricant given."""

    iso_vg: int | None = None
    base_oil: str = "mineral"
    kinematic_viscosity_40_mm2_s: float | None = None
    kinematic_viscosity_100_mm2_s: float | None = None
    kinematic_viscosity_mm2_s: float | None = None
    density_15_kg_m3: float | None = None
    temperature_c: float | None = None
    pour_point_c: float | None = None
    pressure_viscosity_coefficient_1_per_gpa: float | None = None
    lubricant_factor_xl: float | None = None
    fzg_load_stage: int | None = None
    friction_coefficient: float | None = None

    @property
    def given(self) -> bool:
        """Whether the spec names an oil (a grade or viscosities)."""
        return any(v is not None for v in (self.iso_vg, self.kinematic_viscosity_40_mm2_s,
                                           self.kinematic_viscosity_100_mm2_s, self.kinematic_viscosity_mm2_s))


@dataclass(frozen=True)
class DesignSpec:
    pair: PairSpec
    pinion: MemberSpec
    gear: MemberSpec
    misalignment: MisalignmentSpec = field(default_factory=MisalignmentSpec)
    material: MaterialSpec = field(default_factory=MaterialSpec)
    rating: RatingSpec = field(default_factory=RatingSpec)
    lubricant: LubricantSpec = field(default_factory=LubricantSpec)
    #: Where the spec came from (file path or "<dict>"); not part of equality.
    source: str = field(default=DEFAULT_SOURCE, compare=False)
