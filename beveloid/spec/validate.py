"""Validation of a spec given as a nested mapping (as ``tomllib`` returns it) into a :class:`DesignSpec`.

Every problem is a :class:`SpecError` whose message is one line naming the key, its value and
what would be valid, all read from :data:`beveloid.spec.keys.KEY_DOCS`.  Rules between keys
(beyond one key's range) are the functions of :data:`CROSS_CHECKS`.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from ..generated import layouts, root_fillet, surface_models
from .keys import KEY_DOCS, REQUIRED_SECTIONS, SECTIONS, KeyDoc, model_takes
from .model import (DEFAULT_SOURCE, DesignSpec, LubricantSpec, MaterialSpec, RatingSpec, MemberSpec, MisalignmentSpec, PairSpec,
                    SpecError)
from .text import closest, fmt_value, hint, name_text


def _check_value(dotted: str, value: Any, doc: KeyDoc) -> float | int:
    """Type- and range-check one value; return it as int (integer keys) or float."""
    bad = f"{dotted} = {fmt_value(value)}: must be {doc.valid_text_in(dotted.split('.')[0])}"
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
            f"{name} = {fmt_value(raw)}: must be a table ([{name}] section) with keys: {', '.join(accepted)}",
            key=name,
        )
    _check_model_name(name, raw, docs)
    # 1. unknown keys and design results, in the order given
    for key, value in raw.items():
        key_s = str(key)
        dotted = f"{name}.{name_text(key_s)}"
        doc = docs.get(key_s) if isinstance(key, str) else None
        if doc is None:
            match = closest(key_s, list(docs))
            hint = f" (did you mean {match}?)" if match else ""
            if match and docs[match].requirement == "result":
                hint = f" (did you mean {match}? note: {name}.{match} is a design result; do not give it)"
            raise SpecError(
                f"{dotted}: unknown key; valid keys are: {', '.join(accepted)}{hint}", key=dotted
            )
        if doc.requirement == "result" and value is not None:
            raise SpecError(
                f"{dotted} = {fmt_value(value)}: {dotted} is a result of the direct design; remove it",
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
        if key in raw and not (raw[key] is None and doc.requirement == "optional" and doc.default is None):
            out[key] = _check_value(f"{name}.{key}", raw[key], doc)
        else:
            out[key] = float(doc.default) if doc.kind == "number" and doc.default is not None else doc.default
    if any(d.model for d in docs.values()):
        _resolve_surface_model(name, raw, out, docs)
    # 4. bounds that depend on another key of the same section
    for key, doc in docs.items():
        if doc.bound_key is not None and abs(out[key]) > out[doc.bound_key]:
            dotted = f"{name}.{key}"
            bound = f"{name}.{doc.bound_key}"
            raise SpecError(
                f"{dotted} = {fmt_value(out[key])}: must be a finite number with"
                f" |value| <= {bound} = {fmt_value(out[doc.bound_key])}{doc.unit_suffix}",
                key=dotted,
            )
    return out


def _check_model_name(name: str, raw: Mapping, docs: dict[str, KeyDoc]) -> None:
    """A tooth_surface naming no usable model, before its keys are looked at: which (unknown, or a
    user model whose generated code is stale) and how to make or regenerate it."""
    value = raw.get("tooth_surface")
    if "tooth_surface" in docs and isinstance(value, str) and value not in docs["tooth_surface"].choices:
        from ..models import catalog

        cat = catalog()
        problem = cat.problem(value)
        if problem:
            match = closest(value, [*docs["tooth_surface"].choices, *cat.stale]) if value not in cat.stale else None
            raise SpecError(f"{name}.tooth_surface = {fmt_value(value)}: {problem}"
                            + (f" (did you mean {match}?)" if match else ""), key=f"{name}.tooth_surface")


def implied_surface_model(values: Mapping[str, Any], given: Iterable[str], docs: Mapping[str, KeyDoc]) -> str:
    """The tooth-surface model of a member whose section does not name one: the first model (in
    ``SELECTED_BY`` order) that a non-zero key selects and that takes every key given away from its
    default (else the first selected), else the default model.  ``values``: the section's values with
    the defaults filled in; ``given``: the model keys the section gives; ``docs``: the section's keys.
    (``beveloid explore`` applies it to each design of a grid.)"""
    chosen = [m for m, keys in surface_models.SELECTED_BY.items() if any(values.get(k) for k in keys)]
    moved = [k for k in given if values[k] != docs[k].default]
    chosen = [m for m in chosen if all(model_takes(m, k) for k in moved)] or chosen
    return chosen[0] if chosen else surface_models.DEFAULT_MODEL


def _resolve_surface_model(name: str, raw: Mapping, out: dict[str, Any], docs: dict[str, KeyDoc]) -> None:
    """Choose the member's tooth-surface model and gather its own keys into ``surface_options``."""
    given = {k for k in raw if isinstance(k, str) and k in docs and docs[k].model}
    if "tooth_surface" in raw:
        model = out["tooth_surface"]
    else:
        model = out["tooth_surface"] = implied_surface_model(out, given, docs)
    for key in sorted(given):
        if not model_takes(model, key) and out[key] != docs[key].default:  # another model's key at its default is moot
            raise SpecError(
                f"{name}.{key} = {fmt_value(raw[key])}: the tooth surface \"{model}\" takes no such key; set"
                f" {name}.tooth_surface = \"{docs[key].model}\" or remove {name}.{key}", key=f"{name}.{key}")
    opts = {k: out.pop(k) for k in list(out) if k in docs and docs[k].model}
    out["surface_options"] = tuple(sorted((k, v) for k, v in opts.items() if model_takes(model, k)))


def check_clearance(values: dict[str, dict[str, Any]]) -> None:
    """Each member's dedendum (cutter addendum) exceeds its mate's addendum."""
    members = values
    for member, mate in (("pinion", "gear"), ("gear", "pinion")):
        cutter = members[member]["cutter_addendum_coefficient"]
        tip = members[mate]["addendum_coefficient"]
        if not cutter > tip:
            dotted = f"{member}.cutter_addendum_coefficient"
            raise SpecError(
                f"{dotted} = {fmt_value(cutter)}: must exceed {mate}.addendum_coefficient = {fmt_value(tip)}"
                f" (root clearance: the {member}'s dedendum must be larger than the {mate}'s addendum)",
                key=dotted,
            )


#: The message of a spec nested deeper than Python's recursion allows (a spec is two levels deep).
NESTED_TOO_DEEP = ("arrays or tables nested too deeply: a spec holds sections of keys"
                   " with single values (`beveloid example case1` prints one)")

#: Rules between keys, run in this order on the checked values (section -> key -> value)
#: after every key passed its own range check; each raises :class:`SpecError`.
def check_relief_extent(values: dict[str, dict[str, Any]]) -> None:
    """A tip relief's height below the working depth, an end relief's length below half the face."""
    depth = (values["pinion"]["addendum_coefficient"] + values["gear"]["addendum_coefficient"]) * \
        values["pair"]["normal_module_mm"]
    for member in ("pinion", "gear"):
        opts = dict(values[member].get("surface_options", ()))
        for amount, key, limit, what in (("tip_relief_um", "tip_relief_height_mm", depth, "the working depth"),
                                         ("end_relief_um", "end_relief_length_mm",
                                          values[member]["face_width_mm"] / 2, f"half of {member}.face_width_mm")):
            if opts.get(amount) and not opts[key] < limit:
                raise SpecError(f"{member}.{key} = {fmt_value(opts[key])}: must be below {what} = "
                                f"{fmt_value(limit)} (mm)", key=f"{member}.{key}")


def check_tip_round(values: dict[str, dict[str, Any]]) -> None:
    """The rack's tip round must fit its tooth (generated root_fillet.tip_round: max_radius)."""
    alpha = math.radians(values["pair"]["normal_pressure_angle_deg"])
    for member in ("pinion", "gear"):
        rho = values[member]["cutter_tip_radius_coefficient"]
        cutter = values[member]["cutter_addendum_coefficient"]
        top = root_fillet.tip_round(np.asarray(layouts.FilletParams.pack(dict(
            normal_pressure_angle=alpha, helix_angle=0.0, cone_angle=0.0, cutter_addendum_mm=cutter,
            half_thickness_mm=math.pi / 4, rack_shift_mm=0.0, pitch_radius_mm=1.0, cutter_tip_radius_mm=rho,
            normal_module_mm=1.0, profile_crowning_um=0.0, lead_crowning_um=0.0, face_width_mm=1.0)),
            dtype=float)).max_radius
        if top < 0.0:  # no round fits: the rack tooth is pointed (top land pi/2 - 2 c tan(alpha) < 0)
            dotted = f"{member}.cutter_addendum_coefficient"
            raise SpecError(
                f"{dotted} = {fmt_value(cutter)}: must be at most {math.pi / (4 * math.tan(alpha)):.4g} at"
                f" pair.normal_pressure_angle_deg = {fmt_value(values['pair']['normal_pressure_angle_deg'])}:"
                " a deeper rack tooth is pointed (no top land)", key=dotted)
        if rho > top:
            dotted = f"{member}.cutter_tip_radius_coefficient"
            raise SpecError(
                f"{dotted} = {fmt_value(rho)}: must be at most {float(top):.4g}, the largest round that fits the"
                f" rack tooth with {member}.cutter_addendum_coefficient = {fmt_value(cutter)} and"
                f" pair.normal_pressure_angle_deg = {fmt_value(values['pair']['normal_pressure_angle_deg'])}",
                key=dotted)


def check_rating_life(values: dict[str, dict[str, Any]]) -> None:
    """rating.life_hours needs rating.pinion_speed_rpm (the load cycles are 60 n L_h)."""
    rating = values["rating"]
    if rating["life_hours"] is not None and rating["pinion_speed_rpm"] is None:
        raise SpecError(f"rating.life_hours = {fmt_value(rating['life_hours'])}: needs rating.pinion_speed_rpm "
                        "(a number > 0, rpm) for the load cycles; give both or neither", key="rating.life_hours")


def check_material_hardness(values: dict[str, dict[str, Any]]) -> None:
    """A surface hardness only for a material type whose ISO 6336-5 limits take it, and within
    ISO 6336-5's range for that type and quality (beveloid/rating/materials.py)."""
    from ..rating.materials import check_member

    mat = values["material"]
    for member in ("pinion", "gear"):
        try:
            check_member(member, mat[f"{member}_material"], mat[f"{member}_material_quality"],
                         mat[f"{member}_surface_hardness_hv"], mat[f"{member}_surface_hardness_hbw"])
        except ValueError as exc:
            key = str(exc).split(" = ")[0]
            raise SpecError(str(exc), key=key) from None


def check_lubricant(values: dict[str, dict[str, Any]]) -> None:
    """[lubricant]: a grade or both viscosities, a temperature above the pour point, the roughness of
    both members (beveloid/tribology/lubricant.py)."""
    from ..tribology.lubricant import check_spec_values

    try:
        check_spec_values(values)
    except ValueError as exc:
        key = getattr(exc, "key", None)
        raise SpecError(str(exc), key=key) from None


CROSS_CHECKS: tuple[Callable[[dict[str, dict[str, Any]]], None], ...] = (check_clearance, check_relief_extent,
                                                                          check_tip_round, check_rating_life,
                                                                          check_material_hardness, check_lubricant)

#: section -> the dataclass holding its keys
SECTION_TYPES: dict[str, type] = {
    "pair": PairSpec,
    "pinion": MemberSpec,
    "gear": MemberSpec,
    "misalignment": MisalignmentSpec,
    "material": MaterialSpec,
    "rating": RatingSpec,
    "lubricant": LubricantSpec,
}


def check_fields_match_keys() -> None:
    """Every key of KEY_DOCS is a field of its section's dataclass with the same default, and back.

    (A tooth-surface model's own keys go to ``MemberSpec.surface_options``, not to fields.)
    """
    for section, cls in SECTION_TYPES.items():
        fields = {f.name: f for f in dataclasses.fields(cls) if f.name != "surface_options"}
        docs = {k: d for k, d in KEY_DOCS[section].items() if d.model is None}
        if set(fields) != set(docs):
            raise RuntimeError(f"spec keys of [{section}] and the fields of {cls.__name__} differ:"
                               f" {sorted(set(fields) ^ set(docs))} (beveloid/spec/keys.py and model.py)")
        for key, doc in docs.items():
            if doc.requirement == "optional" and fields[key].default != doc.default:
                raise RuntimeError(f"default of {section}.{key}: {fields[key].default!r} in {cls.__name__},"
                                   f" {doc.default!r} in KEY_DOCS (beveloid/spec/model.py and keys.py)")


check_fields_match_keys()


def _build(data: Any) -> DesignSpec:
    if not isinstance(data, Mapping):
        raise SpecError(
            f"spec = {fmt_value(data)}: must be a table with sections {', '.join(f'[{s}]' for s in SECTIONS)}"
        )
    for name, value in data.items():
        if name not in SECTIONS:
            if isinstance(value, Mapping):
                raise SpecError(
                    f"{name_text(name)}: unknown section; valid sections are: {', '.join(SECTIONS)}"
                    f"{hint(str(name), list(SECTIONS))}",
                    key=name_text(name),
                )
            homes = [f"[{sec}]" for sec, docs in KEY_DOCS.items() if name in docs]
            where = (f"; {name} belongs in {' or '.join(homes)}" if homes
                     else f"; keys go in the sections {', '.join(f'[{sec}]' for sec in SECTIONS)}")
            raise SpecError(f"{name_text(name)} = {fmt_value(value)}: unknown top-level key{where}", key=name_text(name))
    for name in REQUIRED_SECTIONS:
        if name not in data:
            needs = [k for k, d in KEY_DOCS[name].items() if d.requirement == "required"]
            raise SpecError(
                f"{name}: missing required section [{name}] ({SECTIONS[name]}); it needs keys: {', '.join(needs)}",
                key=name,
            )
    values = {name: _check_section(name, data.get(name, {})) for name in SECTIONS}
    for check in CROSS_CHECKS:
        check(values)
    return DesignSpec(**{name: SECTION_TYPES[name](**values[name]) for name in SECTIONS})


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
    except RecursionError:  # a value nested thousands deep, shown in a message
        raise SpecError(NESTED_TOO_DEEP, source=source) from None
    return dataclasses.replace(spec, source=source)


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
