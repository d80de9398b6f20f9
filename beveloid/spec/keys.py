"""The single table of a spec's keys: ranges, units, defaults and descriptions (:data:`KEY_DOCS`).

The validation (:mod:`beveloid.spec.validate`), its error messages, ``beveloid example --schema``
and the README's key table (:mod:`beveloid.spec.schema`) all read this table and nothing else.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import assembly_errors
from ..generated import surface_models

# --------------------------------------------------------------------------
# The single table of keys, ranges, units, defaults and descriptions
# --------------------------------------------------------------------------


def _num(x: float) -> str:
    """Compact number for range texts: 6 not 6.0, 0.3 stays 0.3."""
    if isinstance(x, float) and x.is_integer():
        return str(int(x))
    return repr(x)


@dataclass(frozen=True)
class KeyDoc:
    """Documentation and validation rule of one key.

    ``requirement`` is ``"required"``, ``"optional"`` (then ``default`` applies)
    or ``"result"`` (computed by the design; giving it is an error).
    ``bound_key`` names a key of the same section whose value bounds
    ``|value|`` (used for ``reference_section_offset_mm``).
    """

    description: str
    unit: str = ""  # "mm", "deg" or "" (dimensionless)
    kind: str = "number"  # "number", "integer" or "choice" (one of ``choices``)
    lo: float | None = None
    lo_open: bool = False
    hi: float | None = None
    hi_open: bool = False
    requirement: str = "required"
    default: float | int | str | None = None
    bound_key: str | None = None
    choices: tuple[str, ...] = ()
    #: 0 is not valid (inside the range)
    nonzero: bool = False
    #: for a tooth-surface model's own key: the model that takes it
    model: str | None = None

    @property
    def default_text(self) -> str:
        """The default as written in docs ('' when there is none)."""
        if self.default is None:
            return ""
        return f'"{self.default}"' if self.kind == "choice" else _num(float(self.default))

    @property
    def unit_suffix(self) -> str:
        return f" ({self.unit})" if self.unit else ""

    @property
    def valid_text(self) -> str:
        """What a valid value is, e.g. ``'an integer from 6 to 400'``."""
        return self.valid_text_in(None)

    def valid_text_in(self, section: str | None) -> str:
        """:attr:`valid_text` with ``bound_key`` qualified by ``section`` (if given)."""
        if self.kind == "choice":
            return "one of " + ", ".join(f'"{c}"' for c in self.choices)
        noun = "an integer" if self.kind == "integer" else "a number"
        if self.nonzero:
            noun = "a non-zero " + noun.split()[-1]
        if self.bound_key is not None:
            bound = f"{section}.{self.bound_key}" if section else self.bound_key
            return f"a finite number with |value| <= {bound}{self.unit_suffix}"
        if self.lo is not None and self.hi is not None and not self.lo_open and not self.hi_open:
            return f"{noun} from {_num(self.lo)} to {_num(self.hi)}{self.unit_suffix}"
        parts = []
        if self.lo is not None:
            parts.append(f"{'>' if self.lo_open else '>='} {_num(self.lo)}")
        if self.hi is not None:
            parts.append(f"{'<' if self.hi_open else '<='} {_num(self.hi)}")
        if self.lo is None or self.hi is None:
            noun = ("a finite " + noun.split()[-1]) if not self.nonzero else ("a finite, " + noun[2:])
        return f"{noun} {' and '.join(parts)}{self.unit_suffix}".replace("  ", " ")

    def in_range(self, x: float) -> bool:
        if self.nonzero and x == 0:
            return False
        if not math.isfinite(x):
            return False
        if self.lo is not None and (x <= self.lo if self.lo_open else x < self.lo):
            return False
        if self.hi is not None and (x >= self.hi if self.hi_open else x > self.hi):
            return False
        return True


_PAIR_DOCS: dict[str, KeyDoc] = {
    "normal_module_mm": KeyDoc("normal module", "mm", lo=0.001, hi=100.0),
    "normal_pressure_angle_deg": KeyDoc(
        "normal pressure angle of the generating rack", "deg", lo=10.0, hi=35.0
    ),
    "shaft_angle_deg": KeyDoc(
        "crossing angle between the shafts", "deg", lo=0.0, lo_open=True, hi=90.0, hi_open=True
    ),
    "offset_mm": KeyDoc("offset between the crossed axes", "mm", lo=0.0, lo_open=True, hi=1e6),
}


def _member_docs(member: str) -> dict[str, KeyDoc]:
    design_input = "required" if member == "pinion" else "result"
    mate = "gear" if member == "pinion" else "pinion"
    return {
        "teeth": KeyDoc("number of teeth", kind="integer", lo=6, hi=400),
        "cone_angle_deg": KeyDoc("cone angle (signed; 0 is a cylinder, whose cone apex and mounting distance"
                                 " are at infinity: not a beveloid)", "deg", lo=-15.0, hi=15.0, nonzero=True),
        "helix_angle_deg": KeyDoc(
            "helix angle, signed: + right hand, - left hand",
            "deg",
            lo=-60.0,
            lo_open=True,
            hi=60.0,
            hi_open=True,
            requirement=design_input,
        ),
        "profile_shift": KeyDoc(
            "transverse profile-shift coefficient xt",
            lo=-1.5,
            hi=1.5,
            requirement=design_input,
        ),
        # at least 1 um: a narrower face is no tooth (5e-324 mm halves to 0 and the face's ends coincide)
        "face_width_mm": KeyDoc("face width", "mm", lo=0.001, hi=1000.0),
        "addendum_coefficient": KeyDoc(
            "tip height above the rack pitch line, in units of normal module",
            lo=0.3,
            hi=2.0,
            requirement="optional",
            default=1.0,
        ),
        "cutter_addendum_coefficient": KeyDoc(
            f"cutter addendum / normal module (the {member}'s dedendum);"
            f" must exceed {mate}.addendum_coefficient",
            lo=0.5,
            hi=2.5,
            requirement="optional",
            default=1.25,
        ),
        "cutter_tip_radius_coefficient": KeyDoc(
            "radius of the rack's tip round / normal module (0: sharp rack; ISO 53 profile A: 0.38);"
            " at most the largest round that fits the rack tooth",
            lo=0.0,
            hi=1.0,
            requirement="optional",
            default=0.0,
        ),
        "reference_section_offset_mm": KeyDoc(
            "distance bc from the working pitch circle to the reference transverse section",
            "mm",
            requirement="optional",
            default=0.0,
            bound_key="face_width_mm",
        ),
        "bore_diameter_mm": KeyDoc(
            "diameter of the bore of the exported solid (beveloid export; 0: no bore); must be below the"
            " member's smallest root diameter",
            "mm",
            lo=0.0,
            hi=10000.0,
            requirement="optional",
            default=0.0,
        ),
        "roughness_ra_um": KeyDoc(
            f"arithmetic mean roughness Ra of the {member}'s flanks (tribology: friction, film parameter lambda;"
            " needed with [lubricant])", "um", lo=0.0, lo_open=True, hi=100.0, requirement="optional"),
        "roughness_rz_um": KeyDoc(
            f"mean peak-to-valley roughness Rz of the {member}'s flanks (rating: ISO 6336-2's roughness factor"
            " Z_R; without it 6 Ra from roughness_ra_um, DIN 3991's approximation)", "um", lo=0.0, lo_open=True,
            hi=400.0, requirement="optional"),
        "root_roughness_rz_um": KeyDoc(
            f"mean peak-to-valley roughness Rz of the {member}'s root fillets (rating: ISO 6336-3's relative"
            " surface factor Y_RrelT; without it Y_RrelT = 1)", "um", lo=0.0, lo_open=True, hi=400.0,
            requirement="optional"),
        "tooth_surface": KeyDoc(
            "tooth-surface model (generated/surface_models.py); by default the model whose keys below are"
            f" non-zero, else {surface_models.DEFAULT_MODEL}",
            kind="choice",
            choices=surface_models.MODELS,
            requirement="optional",
            default=surface_models.DEFAULT_MODEL,
        ),
        **_model_key_docs(),
    }


def _model_key_docs() -> dict[str, KeyDoc]:
    """The tooth-surface models' own input keys (generated from the derivation registry)."""
    out: dict[str, KeyDoc] = {}
    for model, keys in surface_models.MODEL_KEYS.items():
        for key, (unit, default, lo, hi, doc) in keys.items():
            if key in out:  # a key shared by several models: with the first, all named
                continue
            takers = " or ".join(f'"{m}"' for m, k in surface_models.MODEL_KEYS.items() if key in k)
            out[key] = KeyDoc(f"{doc} (tooth_surface = {takers})", unit, lo=lo, hi=hi, requirement="optional",
                              default=default, model=model)
        for key, (default, choices, doc) in surface_models.MODEL_CHOICES.get(model, {}).items():
            out[key] = KeyDoc(f"{doc} (tooth_surface = \"{model}\")", kind="choice", choices=tuple(choices),
                              requirement="optional", default=default, model=model)
    return out


def key_docs_for(models=()) -> dict[str, dict[str, "KeyDoc"]]:
    """:data:`KEY_DOCS` with the built-in tooth-surface models and only the user models named in
    ``models`` (the README's table: none; ``beveloid example --schema --model NAME``: those)."""
    from dataclasses import replace

    from ..models import builtin_models

    keep = set(builtin_models()) | set(models)
    out: dict[str, dict[str, KeyDoc]] = {}
    for section, docs in KEY_DOCS.items():
        out[section] = {}
        for key, doc in docs.items():
            if doc.model is not None and doc.model not in keep:
                continue
            if key == "tooth_surface":
                doc = replace(doc, choices=tuple(c for c in doc.choices if c in keep))
            out[section][key] = doc
    return out


def model_takes(model: str, key: str) -> bool:
    """Whether a tooth-surface model takes a key (numeric or by name)."""
    return key in surface_models.MODEL_KEYS[model] or key in surface_models.MODEL_CHOICES.get(model, {})


def _mis_doc(description: str, unit: str, limit: float) -> KeyDoc:
    return KeyDoc(description, unit, lo=-limit, hi=limit, requirement="optional", default=0.0)


#: the rating's material types and ISO 6336-5 qualities (beveloid/rating/materials.py holds their data)
MATERIAL_TYPES = ("case-hardened", "through-hardened", "nitrided", "nitrocarburised", "grey-cast-iron",
                  "nodular-cast-iron")
MATERIAL_QUALITIES = ("ML", "MQ", "ME")

_MIS_DOCS: dict[str, KeyDoc] = {e.key: _mis_doc(e.description, e.unit, e.limit) for e in assembly_errors.ERRORS}


def _material_docs() -> dict[str, KeyDoc]:
    out: dict[str, KeyDoc] = {}
    for member in ("pinion", "gear"):
        out[f"{member}_youngs_modulus_gpa"] = KeyDoc(
            f"Young's modulus of the {member} (loaded TCA)", "GPa", lo=1.0, hi=1000.0, requirement="optional",
            default=206.0)
        out[f"{member}_poisson_ratio"] = KeyDoc(
            f"Poisson's ratio of the {member} (loaded TCA)", lo=0.0, hi=0.5, hi_open=True, requirement="optional",
            default=0.3)
    for member in ("pinion", "gear"):
        out[f"{member}_material"] = KeyDoc(
            f"material type of the {member} (rating: ISO 6336-2/-3 life curves, ISO 6336-5 limits)", kind="choice",
            choices=MATERIAL_TYPES, requirement="optional", default="case-hardened")
        out[f"{member}_material_quality"] = KeyDoc(
            f"ISO 6336-5 material quality of the {member} (rating: the default limits)", kind="choice",
            choices=MATERIAL_QUALITIES, requirement="optional", default="MQ")
        out[f"{member}_surface_hardness_hv"] = KeyDoc(
            f"surface hardness of the {member} for the ISO 6336-5 limits of \"through-hardened\" and "
            "\"nitrocarburised\" (rating; default mid-range: 300 and 400 HV)", "HV", lo=50.0, hi=1000.0,
            requirement="optional")
        out[f"{member}_surface_hardness_hbw"] = KeyDoc(
            f"surface hardness of the {member} for the ISO 6336-5 limits of \"grey-cast-iron\" and "
            "\"nodular-cast-iron\" (rating; default mid-range: 200 and 250 HBW)", "HBW", lo=50.0, hi=700.0,
            requirement="optional")
        out[f"{member}_root_stress_limit_mpa"] = KeyDoc(
            f"nominal tooth-root stress limit sigma_Flim of the {member} (rating; overrides the ISO 6336-5 value "
            "of the material and quality)", "MPa", lo=0.0, lo_open=True, hi=5000.0, requirement="optional")
        out[f"{member}_contact_stress_limit_mpa"] = KeyDoc(
            f"allowable contact stress sigma_Hlim of the {member} (rating; overrides the ISO 6336-5 value of the "
            "material and quality)", "MPa", lo=0.0, lo_open=True, hi=10000.0, requirement="optional")
    return out


def _rating_docs() -> dict[str, KeyDoc]:
    return {
        "K_A": KeyDoc("application factor K_A (rating)", lo=1.0, hi=10.0, requirement="optional", default=1.0),
        "K_v": KeyDoc("dynamic factor K_v, the user's (rating; overrides ISO 6336-1 method B, which needs "
                      "pinion_speed_rpm; without either K_v = 1)", lo=1.0, hi=10.0, requirement="optional"),
        "accuracy_grade": KeyDoc("ISO 1328-1:1995 accuracy grade of both members (rating: the pitch and profile "
                                 "deviations of K_v method B)", kind="integer", lo=1, hi=12, requirement="optional",
                                 default=6),
        "pinion_speed_rpm": KeyDoc("pinion speed for the life factors (rating; without it and life_hours: "
                                   "long-life factors = 1)", "rpm", lo=0.0, lo_open=True, hi=1e6,
                                   requirement="optional"),
        "life_hours": KeyDoc("required life for the life factors (rating; needs pinion_speed_rpm)", "h", lo=0.0,
                             lo_open=True, hi=1e7, requirement="optional"),
        "S_Fmin": KeyDoc("required minimum bending safety S_Fmin (rating)", lo=0.0, lo_open=True, hi=100.0,
                         requirement="optional", default=1.4),
        "S_Hmin": KeyDoc("required minimum pitting safety S_Hmin (rating)", lo=0.0, lo_open=True, hi=100.0,
                         requirement="optional", default=1.0),
        "tolerance_samples": KeyDoc("error sets of the tolerance box under load (rating: K_H_beta at their 90th "
                                    "percentile instead of the file's errors alone; 0: the file's errors; beveloid "
                                    "rating --samples)", kind="integer", lo=0, hi=10000, requirement="optional",
                                    default=0),
        "S_Bmin": KeyDoc("required minimum scuffing safety S_Bmin (rating, flash-temperature method with a "
                         "[lubricant] and pinion_speed_rpm: docs/tribology.md)", lo=0.0, lo_open=True, hi=100.0,
                         requirement="optional", default=1.0),
    }


#: the base oils of [lubricant] (beveloid/tribology/lubricant.py holds their defaults)
BASE_OILS = ("mineral", "pao", "ester", "polyglycol")


def _lubricant_docs() -> dict[str, KeyDoc]:
    opt = dict(requirement="optional")
    return {
        "iso_vg": KeyDoc("ISO 3448 viscosity grade (kinematic viscosity at 40 C, mm^2/s); with base_oil it gives both "
                         "viscosities (tribology)", kind="integer", lo=2, hi=3200, **opt),
        "base_oil": KeyDoc("base oil: its viscosity index, density, pour point, X_L and pressure-viscosity defaults "
                           "(tribology)", kind="choice", choices=BASE_OILS, default="mineral", **opt),
        "kinematic_viscosity_40_mm2_s": KeyDoc("kinematic viscosity at 40 C (tribology; with the 100 C one: ASTM "
                                               "D341 between and beyond them)", "mm^2/s", lo=1.0, hi=100000.0, **opt),
        "kinematic_viscosity_100_mm2_s": KeyDoc("kinematic viscosity at 100 C (tribology)", "mm^2/s", lo=0.5,
                                                hi=10000.0, **opt),
        "kinematic_viscosity_mm2_s": KeyDoc("kinematic viscosity at temperature_c, measured (tribology; overrides "
                                            "the ASTM D341 value)", "mm^2/s", lo=0.1, hi=1e6, **opt),
        "density_15_kg_m3": KeyDoc("density at 15 C (tribology; default from base_oil)", "kg/m^3", lo=500.0,
                                   hi=2000.0, **opt),
        "temperature_c": KeyDoc("oil (inlet) temperature (tribology; needed with [lubricant]); above the pour point",
                                "C", lo=-60.0, hi=200.0, **opt),
        "pour_point_c": KeyDoc("pour point (tribology; default from base_oil)", "C", lo=-80.0, hi=50.0, **opt),
        "pressure_viscosity_coefficient_1_per_gpa": KeyDoc(
            "pressure-viscosity coefficient alpha at temperature_c (tribology; default from base_oil, ISO/TS 6336-22)",
            "1/GPa", lo=1.0, hi=60.0, **opt),
        "lubricant_factor_xl": KeyDoc("lubricant factor X_L of ISO/TR 14179-2's friction law and ISO/TS 6336-20's "
                                      "scuffing temperature (tribology; default from base_oil)", lo=0.1, hi=3.0, **opt),
        "fzg_load_stage": KeyDoc("the oil's FZG A/8.3/90 scuffing load stage (tribology: the scuffing temperature; "
                                 "without it no scuffing safety)", kind="integer", lo=1, hi=14, **opt),
        "friction_coefficient": KeyDoc("a fixed friction coefficient that overrides the friction model everywhere "
                                       "(tribology)", lo=0.0, hi=0.5, **opt),
    }


#: section -> key -> KeyDoc.  The single source of truth for validation and docs.
KEY_DOCS: dict[str, dict[str, KeyDoc]] = {
    "pair": _PAIR_DOCS,
    "pinion": _member_docs("pinion"),
    "gear": _member_docs("gear"),
    "misalignment": _MIS_DOCS,
    "material": _material_docs(),
    "rating": _rating_docs(),
    "lubricant": _lubricant_docs(),
}

#: Valid top-level sections, in canonical order, with a description.
SECTIONS: dict[str, str] = {
    "pair": "data shared by both members",
    "pinion": "its helix angle and profile shift are design inputs",
    "gear": "its helix angle and profile shift are results of the direct design",
    "misalignment": "assembly errors for tooth contact analysis; optional, default 0",
    "material": "elastic constants (loaded TCA) and strength (rating) of both members; optional, default case-hardened steel",
    "rating": "load factors, speed, life and minimum safeties of `beveloid rating`; optional",
    "lubricant": "the oil of the tribology (film, friction, power loss, scuffing: docs/tribology.md); optional",
}
REQUIRED_SECTIONS: tuple[str, ...] = ("pair", "pinion", "gear")
