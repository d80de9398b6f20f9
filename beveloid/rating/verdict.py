"""The rating's verdict (docs/rating.md 6): one public function, :func:`verdict`, that every command
judging a design calls (``beveloid rating``, ``optimize --constraints rating``).

The verdict is a list of criteria, each a dict with the same keys (:data:`CRITERION_KEYS`): the
bending and pitting safeties of each member, from the local stresses of the loaded contact where they
exist and from ISO 6336 otherwise (``"governs": true`` on the ones that decide), the ISO ones beside
them, and the edge-contact rule.  A new criterion (scuffing, say) is one more entry; the status is
"fails" when a governing criterion that decides pass or fail fails, "conditional" when the only
failing ones are conditions (the edge rule: a relief fixes it), else "passes".

Besides the status, the verdict says which method governs each safety and whether ISO fails where
the local value governs (issue 60.5), where ISO and the local value disagree by more than
:data:`DISAGREEMENT_FACTOR` and why (issue 57.6), and what it assumes (issue 57.7); and the governing lowest
safety's margin over its minimum, with a flag (``on_minimum``) where that margin is within the verdict's
numerical uncertainty (:func:`minimum_band`): there the status depends on the numerical settings (issue 57).
"""
from __future__ import annotations

import math

import numpy as np

from ..status import Validity, Verdict
from .root_convergence import VALIDATED_SOURCE, describe_outside

__all__ = ["CRITERION_KEYS", "DISAGREEMENT_FACTOR", "EDGE_SHARE", "EDGE_SETTINGS_BAND", "EXIT_STATUS", "SETTINGS_BAND",
           "verdict", "exit_status", "limit_band", "minimum_band", "on_limit"]

#: ISO and local safeties further apart than this factor are reported with the reasons found (the
#: ISO/FE agreement commonly reported is +-10 %; beyond 2 the two are not rating the same thing)
DISAGREEMENT_FACTOR = 2.0
#: ``beveloid rating``'s exit status by verdict status (docs/commands.md): 2 is bad input, 1 an output error
EXIT_STATUS = {Verdict.PASSES: 0, Verdict.FAILS: 3, Verdict.CONDITIONAL: 4, None: 5}
#: the edge-contact rule's limit: the largest share of the mesh's load within the edge band at any instant
#: (measured: 0.05-0.11 on unrelieved pairs whose pattern runs onto a tip, under 0.002 with the tip relieved,
#: 0.011-0.022 at the ends of an uncrowned line contact, design K; docs/rating.md 6)
EDGE_SHARE = 0.02
#: the numerical settings' uncertainty of the governing lowest safety, relative (docs/rating.md 6, "A safety on its
#: minimum"): over ``benchmarks/rating_invariance.py``'s six settings (grid 7x11 / default / 15x25, positions 10 /
#: 20 / 30) the lowest safety moved from the default by at most 2.0 % in 85 of the 91 rows of docs/validation.md
#: 10.1's summary tables (by 2.5-4.0 % in six: K at 130 N m, M at both torques, R2-3 and R2-8 at their higher
#: torque, R5701-4 at 1110 N m); the two draws whose status flipped between settings sat within 0.9 %
#: (R1313-1, S_H 0.991-1.004) and 0.5 % (R1313-2, S_F 1.399-1.406) of their minimum
SETTINGS_BAND = 0.02
#: the numerical settings' uncertainty of the edge rule's load share, relative to the rule's limit (docs/rating.md 6,
#: "An edge share on its limit"): design K's uncrowned gear toe on the plate tooth, whose share sits on the limit at
#: every torque, read 0.019-0.023 over ``benchmarks/rating_invariance.py``'s six settings at 130 / 300 / 450 N m
#: (within 15 % of 0.02) and 0.0188-0.0220 over the grids 7x11 / 11x17 / 15x25 / 21x33 of
#: ``benchmarks/edge_band_convergence.py``; the tips that carry 8-40 % move by 1-4 % of their share
EDGE_SETTINGS_BAND = 0.15
#: the edge-contact rule (docs/rating.md 6), quoted in the JSON
EDGE_RULE = ("edge contact: a pair whose loaded pattern puts more than 2 % of the mesh's load within 0.05 m_n of a "
             "flank edge (toe, heel or tip of either member) at K_A K_v T does not pass cleanly; it passes only if "
             "every such edge is relieved (more, where it already is: end relief at a toe or heel, tip relief at a "
             "tip), and fails if it would fail anyway")
#: the keys of one criterion
CRITERION_KEYS = ("criterion", "kind", "member", "source", "where", "value", "required", "meets", "governs",
                  "condition")
#: the safeties a verdict rates, in the order of the line
KINDS = (("S_F", "bending"), ("S_H", "pitting"))


def _num(v):
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _criterion(what: tuple, where, value, required, governs, condition=False) -> dict:
    """One criterion: ``what`` = (criterion, kind, member, source); ``meets`` for a minimum ``required``."""
    criterion, kind, member, source = what
    value = _num(value)
    return {"criterion": criterion, "kind": kind, "member": member, "source": source, "where": where,
            "value": value, "required": required, "meets": None if value is None else bool(value >= required),
            "governs": governs, "condition": condition}


def safety_criteria(result) -> list:
    """The bending and pitting criteria of both members: each member's local safety (where computed) and
    its lowest ISO safety over the sections; the local one governs where it exists."""
    f = result.factors
    required = {"S_F": f.S_Fmin, "S_H": f.S_Hmin}
    out = []
    for kind, name in KINDS:
        local = {m: (mr.safety_bending if kind == "S_F" else mr.safety_pitting) for m, mr in result.members.items()}
        has_local = any(_num(v) is not None for v in local.values())
        for member, mr in result.members.items():
            if _num(local[member]) is not None:
                where = mr.root_stress_where if kind == "S_F" else result.loaded.peak_where
                out.append(_criterion((name, kind, member, "local"), where, local[member], required[kind], True))
            secs = [s for s in mr.sections.values()
                    if _num(s.safety_bending_iso if kind == "S_F" else s.safety_pitting_iso) is not None]
            if secs:
                low = min(secs, key=lambda s: s.safety_bending_iso if kind == "S_F" else s.safety_pitting_iso)
                v = low.safety_bending_iso if kind == "S_F" else low.safety_pitting_iso
                out.append(_criterion((name, kind, member, "iso"), low.section, v, required[kind], not has_local))
    return out


def edge_criterion(result) -> dict | None:
    """The edge-contact rule (docs/rating.md 6) as a criterion: the share of the mesh's load within the band
    of the most loaded edge against :data:`EDGE_SHARE` (a maximum), a condition (a relief of that edge
    fixes it); the band's mean pressure beside sigma_Hlim Z_NT Z_L Z_v Z_R / S_Hmin of the weaker member."""
    e = result.loaded.edge
    if e is None:
        return None
    also = [o for o in getattr(result.loaded, "edges", ()) if (o.member, o.edge) != (e.member, e.edge)
            and o.share > EDGE_SHARE]
    f = result.factors
    strength = min(f.contact_strength_mpa(m) for m in result.members)
    c = _criterion(("edge contact", "edge_load_share", e.member, "local"), e.where, e.share, EDGE_SHARE, True,
                   condition=True)
    c["meets"] = None if c["value"] is None else bool(c["value"] <= EDGE_SHARE)
    share = _num(e.share)
    band = limit_band(result, e)
    margin = None if not share else EDGE_SHARE / share - 1.0
    c.update(margin=margin, on_limit=on_limit(share, band["band"]), limit_band=band)
    c.update(rule=EDGE_RULE, limit="maximum", load_share=share, share_limit=EDGE_SHARE,
             safety=None if not share else EDGE_SHARE / share, exceeds=c["meets"] is False,
             pressure_mpa=_num(e.pressure_mpa), permissible_mpa=_num(strength / f.S_Hmin),
             band_mm=_num(e.band_mm), force_n=_num(e.force_n), edge=e.edge, relief=e.relief,
             relief_now_um=_num(e.relief_now_um), pinion_angle_rad=_num(e.pinion_angle_rad), tooth_pair=e.tooth_pair,
             also=[{"member": o.member, "edge": o.edge, "where": o.where, "load_share": _num(o.share),
                    "force_n": _num(o.force_n), "band_mm": _num(o.band_mm), "relief": o.relief,
                    "relief_now_um": _num(o.relief_now_um)} for o in also])
    return c


def on_limit(share, band: float) -> bool | None:
    """Whether an edge share lies within a factor 1 + ``band`` of :data:`EDGE_SHARE` either way,
    |ln(share / limit)| <= ln(1 + band): the same distance above and below the limit as the criterion's
    ``margin`` (limit / share - 1) reads it, so that a share and its reading at other settings, one on each
    side of the limit, are both flagged or neither; None without a share, False for none (0)."""
    if share is None:
        return None
    return bool(share > 0 and abs(math.log(share / EDGE_SHARE)) <= math.log1p(band))


def scuffing_criterion(result) -> dict | None:
    """The scuffing safety S_B (ISO/TS 6336-20's flash-temperature form on the loaded contact's cells,
    docs/tribology.md) against [rating] S_Bmin; None without a tribology (no [lubricant] or speed) or
    without the oil's FZG load stage."""
    t = getattr(result, "tribology", None)
    if t is None or t.scuffing_safety is None:
        return None
    at = t.flash_temperature_at
    where = "the hottest cell" if at is None else f"position {at.position}, pair {int(t.tooth_pairs[at.pair])}"
    c = _criterion(("scuffing", "S_B", "pair", "local"), where, t.scuffing_safety,
                   result.pair.spec.rating.S_Bmin, True)
    c.update(contact_temperature_max_c=_num(t.contact_temperature_max_c),
             scuffing_temperature_c=_num(t.scuffing_temperature_c), flash_temperature_max_c=_num(t.flash_temperature_max_c),
             lambda_min=_num(t.lambda_min), speed_rpm=t.speed_rpm)
    return c


def film_criterion(result) -> dict | None:
    """The smallest specific film thickness lambda = h_min / Ra of the rated contact (micropitting's
    quantity, ISO/TS 6336-22's lambda_GF form), reported, not judged: its permissible value needs the oil's
    micropitting test (no key for it); None without a tribology."""
    t = getattr(result, "tribology", None)
    if t is None or t.lambda_min_at is None:
        return None
    at = t.lambda_min_at
    where = f"position {at.position}, pair {int(t.tooth_pairs[at.pair])}"
    value = _num(t.lambda_min)
    return {"criterion": "micropitting film", "kind": "lambda", "member": "pair", "source": "local",
            "where": where, "value": value, "required": None, "meets": None, "governs": False, "condition": False}


def _disagreements(result, criteria) -> list:
    """Where a member's local and ISO safety of one kind differ by more than DISAGREEMENT_FACTOR, with the
    reasons the rating can name."""
    out = []
    for kind, _ in KINDS:
        for member, mr in result.members.items():
            pair = {c["source"]: c for c in criteria if c["kind"] == kind and c["member"] == member}
            if "local" not in pair or "iso" not in pair or not pair["local"]["value"] or not pair["iso"]["value"]:
                continue
            ratio = pair["local"]["value"] / pair["iso"]["value"]
            if max(ratio, 1 / ratio) <= DISAGREEMENT_FACTOR:
                continue
            why = [f"ISO out of its range at the {k}: {s.status}" for k, s in mr.sections.items()
                   if s.status != Validity.OK]
            k_hb = mr.sections["middle"].K_H_beta
            if _num(k_hb) is not None and k_hb > 2.0:
                why.append(f"K_H_beta = {k_hb:.2f} from the loaded line load: a contact much shorter than the face, "
                           "which ISO's nominal stress spreads over b")
            if kind == "S_H":
                why.append("the local S_H divides by the loaded contact's peak pressure (a crowned, eased contact), "
                           "ISO's by sigma_H0 sqrt(K_H_beta) of a line contact over the face")
            else:
                why.append("the local S_F divides by the FE tooth's largest root stress at one instant and place, "
                           "ISO's by sigma_F0 K_F_beta at the outer point of single pair contact")
            out.append({"kind": kind, "member": member, "local": pair["local"]["value"], "iso": pair["iso"]["value"],
                        "ratio_local_to_iso": ratio, "factor": DISAGREEMENT_FACTOR, "why": why})
    return out


def assumptions(result) -> list:
    """What the verdict leaves out (issue 57.7), in words, each with its direction: K_Hbeta of the load
    case's errors alone (unless the tolerance box ran), each strength factor left at 1 with the
    input it lacks (Z_L, Z_v, Z_R, Y_RrelT; rating.strength), and each member whose local S_F rests on an FE
    root stress the rating's own check does not show converged (its error estimate; issue 57)."""
    f = result.factors
    pair = getattr(result, "pair", None)
    errors = getattr(pair, "errors", None)
    aligned = errors is None or not np.any(np.asarray(errors, dtype=float))
    box = getattr(result, "tolerance_box", None)
    if box is None:
        out = [("K_H_beta of the " + ("aligned pair" if aligned else "pair's [misalignment]")
                + " only (no f_ma, f_sh or lead deviations; rating --samples K takes the tolerance box's p90)")]
    else:
        out = [f"K_H_beta at the p{box['percentile']:g} of {box['sets']} error sets of the tolerance box about the "
               "load case's errors (no lead deviations; the local stresses at the load case's errors)"]
    left = {}
    for member, s in f.strength.items():
        for factor in s.contact + s.root:
            if not factor.computed:
                left.setdefault((factor.name, factor.why), []).append(member)
    direction = {"Z_L": "S_H high for a thin oil, low for a thick one", "Z_v": "S_H high at low speed",
                 "Z_R": "S_H up to ~15 % high for unground flanks", "Y_RrelT": "S_F as for the reference test gear"}
    for (name, why), members in left.items():
        whose = "" if len(members) == len(f.strength) else f" on the {members[0]}"
        out.append(f"{name} = 1{whose} ({why}; {direction[name]})")
    if not f.strength:
        out.append("Z_L = Z_v = Z_R = Y_X = Y_RrelT = 1 (no strength factors computed)")
    out.append("Y_deltarelT = Z_W = Z_X = 1")
    for member, e in sorted(getattr(result.loaded, "root_stress_convergence", {}).items()):
        m = result.members.get(member)
        if m is None or m.safety_bending is None or e.get("converged") is None:
            continue
        if e["converged"]:
            low, high = e["error_band"]
            out.append(f"the {member}'s local S_F on an FE root stress within {low:+.1%} ... {high:+.1%} of a refined "
                       f"mesh's (the band {VALIDATED_SOURCE} validated; root_stress_convergence, docs/rating.md 5)")
        else:
            out.append(f"the {member}'s local S_F on an FE root stress not shown converged (outside the range "
                       f"{VALIDATED_SOURCE} validated: " + "; ".join(describe_outside(o) for o in e.get("outside_range") or ())
                       + "; root_stress_convergence, docs/rating.md 5)")
    if f.K_v_source == "static":
        out.append("K_v = 1 (no pinion speed)")
    return out


#: the maximum over the mesh cycle each governing safety divides by (``positions_check``'s quantity) and the power
#: of it the safety goes with: the local S_H by the contact pressure, the local S_F by the root stress, ISO's by
#: K_H_beta (S_H by its square root; S_F by K_F_beta = K_H_beta^N_F, N_F <= 1: at most its change)
_DIVIDES_BY = {("S_H", "local"): ("contact_pressure_max_mpa", 1.0), ("S_F", "local"): ("root_stress_max_mpa", 1.0),
               ("S_H", "iso"): ("K_H_beta", 0.5), ("S_F", "iso"): ("K_H_beta", 1.0)}


def minimum_band(result, low: dict) -> dict:
    """The numerical uncertainty of the governing lowest safety ``low`` (a criterion), relative:
    {"band": the larger of :data:`SETTINGS_BAND` and the positions part, "settings": SETTINGS_BAND, "positions":
    the move of the maximum it divides by in the rating's last refinement round between positions
    (``positions_check``'s ``change``, times the power the safety goes with; None when not refined or not a
    maximum the check follows)}."""
    quantity, power = _DIVIDES_BY.get((low["kind"], low["source"]), (None, 0.0))
    check = getattr(getattr(result, "loaded", None), "positions_check", None) or {}
    c = (check.get("quantities", {}).get(quantity) or {}).get(low["member"]) if quantity else None
    change = None if c is None or c.get("change") is None else power * abs(float(c["change"]))
    return {"band": max(SETTINGS_BAND, change or 0.0), "settings": SETTINGS_BAND, "positions": change}


def limit_band(result, edge) -> dict:
    """The numerical uncertainty of an edge's load share (``edge``: an ``EdgeLoad``), relative to the edge rule's
    limit: {"band": the larger of :data:`EDGE_SETTINGS_BAND` and the positions part, "settings":
    EDGE_SETTINGS_BAND, "positions": the larger of the move of that edge's share in the rating's last refinement
    round between positions (``positions_check``'s ``change`` of ``edge_load_share["MEMBER EDGE"]``) and how far
    above the share read the top of its cell passage's sawtooth lies (its ``at_edge`` over its ``all`` less 1, at
    least 0: ``edge.edge_shares(..., at_edge=True)``, the share the positions would read had one fallen on the
    last instant before the loaded cell nearest the edge leaves the flank); None without either}."""
    check = getattr(getattr(result, "loaded", None), "positions_check", None) or {}
    c = (check.get("quantities", {}).get("edge_load_share") or {}).get(f"{edge.member} {edge.edge}")
    moves = [abs(float(c["change"]))] if c is not None and c.get("change") is not None else []
    top, share = (None, None) if c is None else (_num(c.get("at_edge")), _num(c.get("all")))
    if top is not None and share:
        moves.append(max(top / share - 1.0, 0.0))
    change = max(moves) if moves else None
    return {"band": max(EDGE_SETTINGS_BAND, change or 0.0), "settings": EDGE_SETTINGS_BAND, "positions": change}


def verdict(result) -> dict:
    """The verdict of a :class:`RatingResult` (module docstring): status ("passes" | "conditional" | "fails"
    | None), the criteria, the governing lowest safety, which method governs each safety and whether ISO
    fails, the ISO/local disagreements, the assumptions, the condition and one line in words."""
    f = result.factors
    criteria = safety_criteria(result)
    edge = edge_criterion(result)
    if edge is not None:
        criteria.append(edge)
    scuffing = scuffing_criterion(result)
    if scuffing is not None:
        criteria.append(scuffing)
    film = film_criterion(result)
    if film is not None:
        criteria.append(film)
    deciding = [c for c in criteria if c["governs"] and c["value"] is not None and not c["condition"]]
    governs = {kind: ("local" if any(c["source"] == "local" and c["kind"] == kind for c in deciding)
                      else ("iso" if any(c["kind"] == kind for c in deciding) else None)) for kind, _ in KINDS}
    iso_fails = {kind: [c["member"] for c in criteria if c["kind"] == kind and c["source"] == "iso"
                        and c["meets"] is False] for kind, _ in KINDS}
    out = {"lowest": None, "value": None, "source": None, "member": None, "where": None, "required": None,
           "meets_S_Fmin": None, "meets_S_Hmin": None, "governs": governs, "iso_fails": iso_fails,
           "edge_contact": edge, "criteria": criteria, "disagreements": [], "assumptions": assumptions(result),
           "margin": None, "on_minimum": None, "minimum_band": None, "edge_on_limit": None,
           "status": None, "condition": None, "passes": None, "exit_status": EXIT_STATUS[None],
           "line": "no safety factor could be computed (see notes)"}
    if scuffing is None:
        out["assumptions"].append("no scuffing check (it needs a [lubricant] with fzg_load_stage and [rating] "
                                  "pinion_speed_rpm: docs/tribology.md)")
    if not deciding:
        return out
    low = min(deciding, key=lambda c: c["value"] / c["required"])
    ok = {kind: all(c["meets"] for c in deciding if c["kind"] == kind) for kind, _ in KINDS}
    parts = []
    for kind, _ in KINDS:
        text = f"{kind} {'meets' if ok[kind] else 'FAILS'} {kind}min = {f.S_Fmin if kind == 'S_F' else f.S_Hmin:g}"
        if governs[kind] == "local":
            text += " (local governs"
            if iso_fails[kind]:
                iso = min((c for c in criteria if c["kind"] == kind and c["source"] == "iso" and c["meets"] is False),
                          key=lambda c: c["value"])
                text += f"; ISO {kind} FAILS: {iso['value']:.3f} on the {iso['member']} at the {iso['where']}"
            text += ")"
        elif governs[kind] == "iso":
            text += " (ISO governs: no local value)"
        parts.append(text)
    line = (f"lowest safety {low['kind']} = {low['value']:.3f} ({low['source']}) on the {low['member']} at "
            f"{low['where']}; " + ", ".join(parts))
    margin = low["value"] / low["required"] - 1.0
    band = minimum_band(result, low)
    on_minimum = abs(margin) <= band["band"]
    if on_minimum:
        line += (f"; ON ITS MINIMUM: {low['kind']} is {abs(margin):.1%} {'above' if margin >= 0 else 'below'} "
                 f"{low['kind']}min = {low['required']:g}, within the verdict's numerical uncertainty of "
                 f"{band['band']:.1%}: the status there depends on the numerical settings (--grid, --positions)")
    status = Verdict.PASSES if all(ok.values()) else Verdict.FAILS
    if scuffing is not None and scuffing["value"] is not None:
        line += (f"; S_B {'meets' if scuffing['meets'] else 'FAILS'} S_Bmin = {scuffing['required']:g} "
                 f"(scuffing: {scuffing['value']:.3f}, contact temperature {scuffing['contact_temperature_max_c']:.0f} C "
                 f"against {scuffing['scuffing_temperature_c']:.0f} C)")
        if not scuffing["meets"]:
            status = Verdict.FAILS
    condition = None
    if edge is not None and edge["meets"] is False:
        condition = _edge_condition(edge)
        line += (f"; edge contact at {edge['where']}: {edge['load_share']:.1%} of the mesh's load within "
                 f"{edge['band_mm']:.2g} mm of the edge > {EDGE_SHARE:.0%} (edge-contact rule; mean pressure there "
                 f"{edge['pressure_mpa']:.0f} MPa, sigma_HP = sigma_Hlim Z_NT Z_L Z_v Z_R / S_Hmin = {edge['permissible_mpa']:.0f} MPa)")
        if edge.get("also"):
            line += ", and at " + ", ".join(f"{o['where']} ({o['load_share']:.1%})" for o in edge["also"])
        line += ": "
        if status == Verdict.PASSES:
            status = Verdict.CONDITIONAL
            line += f"CONDITIONAL, {condition}"
        else:
            line += "FAILS also without it"
    edge_on_limit = None if edge is None else edge["on_limit"]
    if edge_on_limit and status != Verdict.FAILS:
        line += (f"; the edge rule ON ITS LIMIT: {edge['where']} carries {edge['load_share']:.1%} of the mesh's "
                 f"load within its band, within the numerical uncertainty (a factor {1 + edge['limit_band']['band']:.2f} "
                 f"either way) of the rule's {EDGE_SHARE:.0%}: passes or conditional there depends on the numerical "
                 "settings (--grid, --positions)")
    out["disagreements"] = _disagreements(result, criteria)
    for d in out["disagreements"]:
        line += (f"; ISO and local {d['kind']} of the {d['member']} differ {max(d['ratio_local_to_iso'], 1 / d['ratio_local_to_iso']):.1f}x "
                 f"(> {DISAGREEMENT_FACTOR:g}x: {d['why'][0]})")
    line += "; assumes " + "; ".join(out["assumptions"])
    out.update(lowest=low["kind"], value=low["value"], source=low["source"], member=low["member"], where=low["where"],
               required=low["required"], margin=margin, on_minimum=on_minimum, minimum_band=band,
               edge_on_limit=edge_on_limit,
               meets_S_Fmin=ok["S_F"], meets_S_Hmin=ok["S_H"], status=status,
               condition=condition if status == Verdict.CONDITIONAL else None, passes=status == Verdict.PASSES,
               exit_status=EXIT_STATUS[status], line=line)
    return out


def _edge_condition(edge) -> str:
    """Which edges to relieve (every edge over the rule's limit, the most loaded first), and how the relief
    already there counts (issue 57.3)."""
    def relieved(e):
        now = e.get("relief_now_um")
        if now:
            return (f"{e['where']} is relieved more: its {e['relief']} of {now:g} um still leaves {e['force_n']:.0f} N "
                    f"({e['load_share']:.1%} of the mesh's load) within {e['band_mm']:.2g} mm of the edge (more relief, "
                    "or a longer one)")
        return f"{e['where']} is relieved ({e['relief']})"

    return "passes only if " + ", and ".join(relieved(e) for e in [edge, *edge.get("also", ())])


def exit_status(result) -> int:
    """``beveloid rating``'s exit status for the verdict: :data:`EXIT_STATUS`."""
    return verdict(result)["exit_status"]
