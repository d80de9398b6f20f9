"""Design input specification for a crossed beveloid gear pair.

A design is described by a TOML file with the sections ``[pair]``,
``[pinion]``, ``[gear]`` and (optionally) ``[misalignment]``; see
``examples/case1.toml``.  This module reads such a file (or an equivalent
``dict``), validates every value, and returns frozen dataclasses.

Every problem is reported as a :class:`SpecError` whose message is a single
line naming the offending key, its value and what would be valid, e.g.::

    examples/bad.toml: pinion.teeth = 5: must be an integer from 6 to 400

All valid ranges, units, defaults and descriptions live in one table,
:data:`KEY_DOCS`; the error messages and :func:`key_docs_markdown` (a README
table) are generated from it.

Only the standard library is used (``tomllib``, ``dataclasses``, ``difflib``).
"""

from __future__ import annotations

import dataclasses
import datetime
import difflib
import math
import os
import stat
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import assembly_errors
from .generated import layouts, root_fillet, surface_models

__all__ = [
    "SpecError",
    "PairSpec",
    "MemberSpec",
    "MisalignmentSpec",
    "DesignSpec",
    "KeyDoc",
    "KEY_DOCS",
    "SECTIONS",
    "REQUIRED_SECTIONS",
    "spec_from_dict",
    "load_spec",
    "spec_to_dict",
    "misalignment_with",
    "key_docs_markdown",
    "key_schema_text",
    "spec_from_toml_bytes",
    "MAX_SPEC_BYTES",
    "EXAMPLES",
    "example_text",
    "load_example",
]

#: A spec file larger than this (bytes) is refused: real specs are about 2 kB.
MAX_SPEC_BYTES = 1_000_000

#: Example specs shipped in the package (beveloid/data/<name>.toml): the paper's Table 1 cases.
EXAMPLES: dict[str, str] = {
    "case1": "Case 1 of the paper's Table 1",
    "case2": "Case 2 of the paper's Table 1",
}

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
        detail = _one_line(str(message))
        full = f"{_one_line(source)}: {detail}" if source and source != DEFAULT_SOURCE else detail
        super().__init__(full)
        self.detail = detail
        self.key = key
        self.source = source


def _one_line(text: str) -> str:
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
    #: Radius of the rack's tip round / mn (0: the paper's sharp rack); issue 22.
    cutter_tip_radius_coefficient: float = 0.0
    #: bc: distance from the working pitch circle to the reference transverse section.
    reference_section_offset_mm: float = 0.0
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
    """Elastic constants of both members (the loaded TCA, ``beveloid ltca``)."""

    pinion_youngs_modulus_gpa: float = 206.0
    pinion_poisson_ratio: float = 0.3
    gear_youngs_modulus_gpa: float = 206.0
    gear_poisson_ratio: float = 0.3


@dataclass(frozen=True)
class DesignSpec:
    pair: PairSpec
    pinion: MemberSpec
    gear: MemberSpec
    misalignment: MisalignmentSpec = field(default_factory=MisalignmentSpec)
    material: MaterialSpec = field(default_factory=MaterialSpec)
    #: Where the spec came from (file path or "<dict>"); not part of equality.
    source: str = field(default=DEFAULT_SOURCE, compare=False)


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
            noun = "a finite integer" if self.kind == "integer" else "a finite number"
        return f"{noun} {' and '.join(parts)}{self.unit_suffix}".replace("  ", " ")

    def in_range(self, x: float) -> bool:
        if not math.isfinite(x):
            return False
        if self.lo is not None and (x <= self.lo if self.lo_open else x < self.lo):
            return False
        if self.hi is not None and (x >= self.hi if self.hi_open else x > self.hi):
            return False
        return True


_PAIR_DOCS: dict[str, KeyDoc] = {
    "normal_module_mm": KeyDoc("normal module", "mm", lo=0.0, lo_open=True, hi=100.0),
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
        "cone_angle_deg": KeyDoc("cone angle (signed)", "deg", lo=-15.0, hi=15.0),
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
        "face_width_mm": KeyDoc("face width", "mm", lo=0.0, lo_open=True, hi=1000.0),
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
            out[key] = KeyDoc(f"{doc} (tooth_surface = \"{model}\")", unit, lo=lo, hi=hi, requirement="optional",
                              default=default, model=model)
    return out


def _mis_doc(description: str, unit: str, limit: float) -> KeyDoc:
    return KeyDoc(description, unit, lo=-limit, hi=limit, requirement="optional", default=0.0)


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
    return out


#: section -> key -> KeyDoc.  The single source of truth for validation and docs.
KEY_DOCS: dict[str, dict[str, KeyDoc]] = {
    "pair": _PAIR_DOCS,
    "pinion": _member_docs("pinion"),
    "gear": _member_docs("gear"),
    "misalignment": _MIS_DOCS,
    "material": _material_docs(),
}

#: Valid top-level sections, in canonical order, with a description.
SECTIONS: dict[str, str] = {
    "pair": "data shared by both members",
    "pinion": "its helix angle and profile shift are design inputs",
    "gear": "its helix angle and profile shift are results of the direct design",
    "misalignment": "assembly errors for tooth contact analysis; optional, default 0",
    "material": "elastic constants of both members for the loaded TCA; optional, default steel",
}
REQUIRED_SECTIONS: tuple[str, ...] = ("pair", "pinion", "gear")



def key_docs_markdown() -> str:
    """A Markdown table of every key (for the README), generated from :data:`KEY_DOCS`."""
    lines = [
        "| key | required | default | valid values | description |",
        "|---|---|---|---|---|",
    ]
    for section, docs in KEY_DOCS.items():
        for key, d in docs.items():
            if d.requirement == "result":
                req, valid = "no (design result)", "must not be given"
            else:
                req = "yes" if d.requirement == "required" else "no"
                valid = d.valid_text
            default = d.default_text
            cells = [f"`{section}.{key}`", req, default, valid, d.description]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines)


# --------------------------------------------------------------------------
# Validation helpers
# --------------------------------------------------------------------------


def _fmt(value: Any) -> str:
    """Render an offending value on one line, TOML-like."""
    if value is None:
        return "None"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        text = str(value)
        return text if len(text) <= 30 else text[:12] + "..." + text[-6:]
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        text = value if len(value) <= 40 else value[:37] + "..."
        return '"' + text.encode("unicode_escape").decode("ascii").replace('"', '\\"') + '"'
    if isinstance(value, (datetime.date, datetime.time)):  # datetime is a date too
        kind = ("a date-time" if isinstance(value, datetime.datetime)
                else "a date" if isinstance(value, datetime.date) else "a time")
        return f"{value.isoformat()} ({kind})"
    if isinstance(value, Mapping):
        return "a table {" + ", ".join(_name(k) for k in list(value)[:5]) + ("...}" if len(value) > 5 else "}")
    if isinstance(value, (list, tuple)):
        text = "[" + ", ".join(_fmt(v) for v in list(value)[:5]) + (", ...]" if len(value) > 5 else "]")
        return text
    text = repr(value)
    return _one_line(text if len(text) <= 40 else text[:37] + "...")


def printable(text: str, limit: int | None = None) -> str:
    """``text`` with every non-printable character escaped (NUL, ESC, newlines ...), optionally shortened."""
    text = str(text)
    if limit is not None and len(text) > limit:
        text = text[: limit - 3] + "..."
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


def _name(key: Any) -> str:
    """A key or section name as it may appear in a message: printable, at most 40 characters."""
    return printable(str(key), 40)


def _closest(name: str, candidates: list[str]) -> str | None:
    """Most likely intended key: a close spelling, else a unique key starting with ``name``."""
    lowered = {c.lower(): c for c in candidates}
    close = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.6)
    if close:
        return lowered[close[0]]
    prefixed = [c for c in candidates if name and c.lower().startswith(name.lower())]
    return prefixed[0] if len(prefixed) == 1 else None


def _hint(name: str, candidates: list[str]) -> str:
    match = _closest(name, candidates)
    return f" (did you mean {match}?)" if match else ""


def _check_value(dotted: str, value: Any, doc: KeyDoc) -> float | int:
    """Type- and range-check one value; return it as int (integer keys) or float."""
    bad = f"{dotted} = {_fmt(value)}: must be {doc.valid_text_in(dotted.split('.')[0])}"
    if doc.kind == "choice":
        if not isinstance(value, str) or value not in doc.choices:
            raise SpecError(bad, key=dotted)
        return value
    if isinstance(value, bool):
        raise SpecError(bad, key=dotted)
    if doc.kind == "integer":
        if not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                bad += f" (write {int(value)}, not {value!r})"
            raise SpecError(bad, key=dotted)
        try:
            ok = doc.in_range(value)
        except OverflowError:  # int too large for a float
            ok = False
        if not ok:
            raise SpecError(bad, key=dotted)
        return int(value)
    if not isinstance(value, (int, float)):
        raise SpecError(bad, key=dotted)
    try:
        x = float(value)
    except OverflowError:  # huge int from a dict
        raise SpecError(bad, key=dotted) from None
    if not doc.in_range(x):
        raise SpecError(bad, key=dotted)
    return x


def _check_section(name: str, raw: Any) -> dict[str, Any]:
    """Validate one section's keys and values; return converted values incl. defaults."""
    docs = KEY_DOCS[name]
    accepted = [k for k, d in docs.items() if d.requirement != "result"]
    if not isinstance(raw, Mapping):
        raise SpecError(
            f"{name} = {_fmt(raw)}: must be a table ([{name}] section) with keys: {', '.join(accepted)}",
            key=name,
        )
    # 1. unknown keys and design results, in the order given
    for key, value in raw.items():
        key_s = str(key)
        dotted = f"{name}.{_name(key_s)}"
        doc = docs.get(key_s) if isinstance(key, str) else None
        if doc is None:
            match = _closest(key_s, list(docs))
            hint = f" (did you mean {match}?)" if match else ""
            if match and docs[match].requirement == "result":
                hint = f" (did you mean {match}? note: {name}.{match} is a design result; do not give it)"
            raise SpecError(
                f"{dotted}: unknown key; valid keys are: {', '.join(accepted)}{hint}", key=dotted
            )
        if doc.requirement == "result" and value is not None:
            raise SpecError(
                f"{dotted} = {_fmt(value)}: {dotted} is a result of the direct design; remove it",
                key=dotted,
            )
    # 2. missing required keys
    for key, doc in docs.items():
        if doc.requirement == "required" and key not in raw:
            what = f"{doc.description}, {doc.unit}" if doc.unit else doc.description
            raise SpecError(f"{name}: missing required key '{key}' ({what})", key=f"{name}.{key}")
    # 3. types and ranges
    out: dict[str, Any] = {}
    for key, doc in docs.items():
        if doc.requirement == "result":
            continue
        if key in raw:
            out[key] = _check_value(f"{name}.{key}", raw[key], doc)
        else:
            out[key] = float(doc.default) if doc.kind == "number" else doc.default
    if any(d.model for d in docs.values()):
        _resolve_surface_model(name, raw, out, docs)
    # 4. bounds that depend on another key of the same section
    for key, doc in docs.items():
        if doc.bound_key is not None and abs(out[key]) > out[doc.bound_key]:
            dotted = f"{name}.{key}"
            bound = f"{name}.{doc.bound_key}"
            raise SpecError(
                f"{dotted} = {_fmt(out[key])}: must be a finite number with"
                f" |value| <= {bound} = {_fmt(out[doc.bound_key])}{doc.unit_suffix}",
                key=dotted,
            )
    return out


def _resolve_surface_model(name: str, raw: Mapping, out: dict[str, Any], docs: dict[str, KeyDoc]) -> None:
    """Choose the member's tooth-surface model and gather its own keys into ``surface_options``."""
    given = {k for k in raw if isinstance(k, str) and k in docs and docs[k].model}
    if "tooth_surface" in raw:
        model = out["tooth_surface"]
    else:
        chosen = [m for m, keys in surface_models.SELECTED_BY.items() if any(out.get(k) for k in keys)]
        model = chosen[0] if chosen else surface_models.DEFAULT_MODEL
        out["tooth_surface"] = model
    for key in sorted(given):
        if docs[key].model != model and out[key] != docs[key].default:  # another model's key at its default is moot
            raise SpecError(
                f"{name}.{key} = {_fmt(raw[key])}: the tooth surface \"{model}\" takes no such key; set"
                f" {name}.tooth_surface = \"{docs[key].model}\" or remove {name}.{key}", key=f"{name}.{key}")
    opts = {k: out.pop(k) for k in list(out) if k in docs and docs[k].model}
    out["surface_options"] = tuple(sorted((k, v) for k, v in opts.items() if docs[k].model == model))


def _check_clearance(members: dict[str, dict[str, Any]]) -> None:
    for member, mate in (("pinion", "gear"), ("gear", "pinion")):
        cutter = members[member]["cutter_addendum_coefficient"]
        tip = members[mate]["addendum_coefficient"]
        if not cutter > tip:
            dotted = f"{member}.cutter_addendum_coefficient"
            raise SpecError(
                f"{dotted} = {_fmt(cutter)}: must exceed {mate}.addendum_coefficient = {_fmt(tip)}"
                f" (root clearance: the {member}'s dedendum must be larger than the {mate}'s addendum)",
                key=dotted,
            )


def _check_tip_round(values: dict[str, dict[str, Any]]) -> None:
    """The rack's tip round must fit its tooth (generated root_fillet.tip_round: max_radius)."""
    alpha = math.radians(values["pair"]["normal_pressure_angle_deg"])
    for member in ("pinion", "gear"):
        rho = values[member]["cutter_tip_radius_coefficient"]
        cutter = values[member]["cutter_addendum_coefficient"]
        top = root_fillet.tip_round(np.asarray(layouts.FilletParams.pack(dict(
            normal_pressure_angle=alpha, helix_angle=0.0, cone_angle=0.0, cutter_addendum_mm=cutter,
            half_thickness_mm=math.pi / 4, rack_shift_mm=0.0, pitch_radius_mm=1.0, cutter_tip_radius_mm=rho,
            normal_module_mm=1.0, profile_crowning_um=0.0, lead_crowning_um=0.0, face_width_mm=1.0)), dtype=float)).max_radius
        if rho > top:
            dotted = f"{member}.cutter_tip_radius_coefficient"
            raise SpecError(
                f"{dotted} = {_fmt(rho)}: must be at most {float(top):.4g}, the largest round that fits the rack"
                f" tooth with {member}.cutter_addendum_coefficient = {_fmt(cutter)} and"
                f" pair.normal_pressure_angle_deg = {_fmt(values['pair']['normal_pressure_angle_deg'])}",
                key=dotted)


def _build(data: Any) -> DesignSpec:
    if not isinstance(data, Mapping):
        raise SpecError(
            f"spec = {_fmt(data)}: must be a table with sections {', '.join(f'[{s}]' for s in SECTIONS)}"
        )
    for name, value in data.items():
        if name not in SECTIONS:
            if isinstance(value, Mapping):
                raise SpecError(
                    f"{_name(name)}: unknown section; valid sections are: {', '.join(SECTIONS)}"
                    f"{_hint(str(name), list(SECTIONS))}",
                    key=_name(name),
                )
            homes = [f"[{sec}]" for sec, docs in KEY_DOCS.items() if name in docs]
            where = (f"; {name} belongs in {' or '.join(homes)}" if homes
                     else f"; keys go in the sections {', '.join(f'[{sec}]' for sec in SECTIONS)}")
            raise SpecError(f"{_name(name)} = {_fmt(value)}: unknown top-level key{where}", key=_name(name))
    for name in REQUIRED_SECTIONS:
        if name not in data:
            needs = [k for k, d in KEY_DOCS[name].items() if d.requirement == "required"]
            raise SpecError(
                f"{name}: missing required section [{name}] ({SECTIONS[name]}); it needs keys: {', '.join(needs)}",
                key=name,
            )
    values = {name: _check_section(name, data.get(name, {})) for name in SECTIONS}
    _check_clearance(values)
    _check_tip_round(values)
    return DesignSpec(
        pair=PairSpec(**values["pair"]),
        pinion=MemberSpec(**values["pinion"]),
        gear=MemberSpec(**values["gear"]),
        misalignment=MisalignmentSpec(**values["misalignment"]),
        material=MaterialSpec(**values["material"]),
    )


# --------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------


def spec_from_dict(data: dict, source: str = DEFAULT_SOURCE) -> DesignSpec:
    """Validate a nested dict (as produced by ``tomllib``) and build a :class:`DesignSpec`.

    Error messages are prefixed with ``source`` unless it is ``"<dict>"``.
    Integers given for float keys are converted to float.  In the ``[gear]``
    section, ``helix_angle_deg``/``profile_shift`` set to ``None`` are treated
    as absent (so ``dataclasses.asdict(member)`` output is accepted).
    """
    try:
        spec = _build(data)
    except SpecError as err:
        raise SpecError(err.detail, key=err.key, source=source) from None
    return dataclasses.replace(spec, source=source)


def _read_spec_bytes(path: str | os.PathLike, source: str) -> bytes:
    """The file's bytes: only a regular file of at most :data:`MAX_SPEC_BYTES` (no device, FIFO, folder)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise SpecError("cannot read spec file: no such file", source=source) from None
    except (OSError, ValueError) as err:  # ValueError: embedded NUL in the path
        reason = getattr(err, "strerror", None) or str(err)
        raise SpecError(f"cannot read spec file: {reason}", source=source) from None
    if not stat.S_ISREG(st.st_mode):
        kind = ("a folder" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(st.st_mode)
                else "a device" if (stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode))
                else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise SpecError(f"cannot read spec file: it is {kind}; give a regular TOML file"
                        " (`beveloid example case1` prints one)", source=source)
    if st.st_size > MAX_SPEC_BYTES:
        raise SpecError(f"cannot read spec file: {st.st_size} bytes, more than the {MAX_SPEC_BYTES} bytes a"
                        " spec may have", source=source)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_SPEC_BYTES + 1)  # bounded, in case the file grows meanwhile
    except OSError as err:
        raise SpecError(f"cannot read spec file: {err.strerror or err}", source=source) from None
    if len(data) > MAX_SPEC_BYTES:
        raise SpecError(f"cannot read spec file: more than the {MAX_SPEC_BYTES} bytes a spec may have",
                        source=source)
    return data


def spec_from_toml_bytes(data: bytes, source: str = DEFAULT_SOURCE) -> DesignSpec:
    """Parse and validate the bytes of a TOML spec; a leading UTF-8 byte-order mark is accepted."""
    if data.startswith(b"\xef\xbb\xbf"):  # written by some Windows editors; TOML itself has no BOM
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SpecError(f"cannot read spec file: not valid UTF-8 ({err.reason} at byte {err.start})",
                        source=source) from None
    try:
        parsed = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SpecError(f"TOML syntax error: {printable(str(err))}", source=source) from None
    return spec_from_dict(parsed, source=source)


def load_spec(path: str | os.PathLike) -> DesignSpec:
    """Read and validate a TOML design file.

    A missing/unreadable file, anything that is not a regular file (folder, device, FIFO), a file
    over :data:`MAX_SPEC_BYTES` or a TOML syntax error raises :class:`SpecError` whose one-line
    message starts with the path.
    """
    source = printable(os.fsdecode(path))
    return spec_from_toml_bytes(_read_spec_bytes(path, source), source=source)


def example_text(name: str) -> str:
    """The TOML text of a packaged example (a key of :data:`EXAMPLES`), as shipped in beveloid/data/."""
    from importlib import resources

    if name not in EXAMPLES:
        raise SpecError(f"example = {_fmt(name)}: must be one of {', '.join(EXAMPLES)}")
    return (resources.files("beveloid") / "data" / f"{name}.toml").read_text(encoding="utf-8")


def load_example(name: str) -> DesignSpec:
    """A packaged example spec (``"case1"`` or ``"case2"``); works from any working directory."""
    return spec_from_toml_bytes(example_text(name).encode("utf-8"), source=f"{name}.toml")


def key_schema_text() -> str:
    """Every key of a spec file, one line each: section.key, required or default, valid values, meaning."""
    lines = ["# Keys of a beveloid spec file (TOML). Sections: "
             + "; ".join(f"[{s}] {d}" for s, d in SECTIONS.items())]
    for section, docs in KEY_DOCS.items():
        lines.append("")
        lines.append(f"[{section}]")
        for key, d in docs.items():
            if d.requirement == "result":
                need = "do not give: a result of the direct design"
            elif d.requirement == "required":
                need = f"required, {d.valid_text_in(section)}"
            else:
                need = f"optional (default {d.default_text}), {d.valid_text_in(section)}"
            lines.append(f"{key}: {need}; {d.description}")
    return "\n".join(lines)


def spec_to_dict(spec: DesignSpec) -> dict:
    """Inverse of :func:`spec_from_dict`: nested dict with every key (defaults included).

    ``None`` values (the gear's helix angle / profile shift) are omitted, so
    ``spec_from_dict(spec_to_dict(s)) == s`` and the result can be written as TOML.
    """
    out: dict[str, dict[str, Any]] = {}
    for name in SECTIONS:
        obj = getattr(spec, name)
        section: dict[str, Any] = {}
        options = dict(getattr(obj, "surface_options", ()))
        for key, doc in KEY_DOCS[name].items():
            value = options.get(key) if doc.model else getattr(obj, key)
            if value is not None:
                section[key] = value
        out[name] = section
    return out


def misalignment_with(spec: DesignSpec, **overrides: float | None) -> DesignSpec:
    """Copy of ``spec`` with misalignment fields overridden (``None`` values ignored).

    The result is validated exactly like a loaded spec; an unknown field name
    or an out-of-range value raises :class:`SpecError` (without a file prefix,
    since the value did not come from the file).  ``source`` is preserved.
    """
    data = spec_to_dict(spec)
    for key, value in overrides.items():
        if value is not None:
            data["misalignment"][key] = value
    new = spec_from_dict(data)
    return dataclasses.replace(new, source=spec.source)
