"""The rating's result: its JSON contract (issue 32), the verdict and the table."""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["RatingResult", "SEC_KEYS", "to_json_dict"]

#: the keys of one section in the JSON, in order
SEC_KEYS = ("virtual_teeth", "normal_profile_shift", "helix_angle_deg", "s_Fn_mm", "rho_F_mm", "h_Fe_mm",
            "alpha_Fen_deg", "Y_F", "Y_S", "Y_beta", "f_eps", "sigma_F0_mpa", "Z_H", "Z_E", "Z_eps", "Z_beta",
            "sigma_H0_mpa")


def _num(v):
    """A finite float, else None (strict JSON)."""
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def section_json(s) -> dict:
    b, c = s.bending, s.contact
    values = (s.virtual_teeth, s.normal_profile_shift, s.helix_angle_deg, b.s_Fn_mm, b.rho_F_mm, b.h_Fe_mm,
              math.degrees(b.alpha_Fen), b.Y_F, b.Y_S, s.Y_beta, b.f_eps, s.sigma_F0_mpa, c.Z_H, c.Z_E, c.Z_eps,
              c.Z_beta, s.sigma_H0_mpa)
    return {k: _num(v) for k, v in zip(SEC_KEYS, values)}


@dataclass(frozen=True)
class RatingResult:
    torque_nm: float
    flank: str
    members: dict  # "pinion" | "gear" -> analysis.MemberRating
    loaded: object  # analysis.LoadedContact
    factors: object  # factors.Factors
    notes: tuple

    def safeties(self) -> list:
        """Every safety factor as (value, kind, source, member, where, required)."""
        f = self.factors
        out = []
        for name, m in self.members.items():
            for sec in m.sections.values():
                out.append((sec.safety_bending_iso, "S_F", "iso", name, sec.section, f.S_Fmin))
                out.append((sec.safety_pitting_iso, "S_H", "iso", name, sec.section, f.S_Hmin))
            where = m.root_stress_where
            if m.safety_bending is not None:
                out.append((m.safety_bending, "S_F", "local", name, where, f.S_Fmin))
            if m.safety_pitting is not None:
                out.append((m.safety_pitting, "S_H", "local", name, self.loaded.peak_where, f.S_Hmin))
        return out

    def verdict(self) -> dict:
        """The lowest safety relative to its minimum, and whether every safety meets its minimum; the
        local values decide where they exist, the ISO ones otherwise."""
        all_ = [s for s in self.safeties() if _num(s[0]) is not None]
        local_kinds = {s[1] for s in all_ if s[2] == "local"}
        deciding = [s for s in all_ if s[2] == "local" or s[1] not in local_kinds]
        if not deciding:
            return {"lowest": None, "value": None, "source": None, "member": None, "where": None, "required": None,
                    "meets_S_Fmin": None, "meets_S_Hmin": None, "passes": None,
                    "line": "no safety factor could be computed (see notes)"}
        low = min(deciding, key=lambda s: s[0] / s[5])
        ok_f = all(s[0] >= s[5] for s in deciding if s[1] == "S_F")
        ok_h = all(s[0] >= s[5] for s in deciding if s[1] == "S_H")
        return {"lowest": low[1], "value": _num(low[0]), "source": low[2], "member": low[3], "where": low[4],
                "required": low[5], "meets_S_Fmin": ok_f, "meets_S_Hmin": ok_h, "passes": ok_f and ok_h,
                "line": (f"lowest safety {low[1]} = {low[0]:.3f} ({low[2]}) on the {low[3]} at {low[4]}; "
                         f"S_F {'meets' if ok_f else 'FAILS'} S_Fmin = {self.factors.S_Fmin:g}, "
                         f"S_H {'meets' if ok_h else 'FAILS'} S_Hmin = {self.factors.S_Hmin:g}")}


def to_json_dict(r: RatingResult) -> dict:
    out = {"torque_nm": float(r.torque_nm), "flank": r.flank}
    for name, m in r.members.items():
        out[name] = {
            "sections": {k: section_json(s) for k, s in m.sections.items()},
            "root_stress_max_mpa": _num(m.root_stress_max_mpa),
            "root_stress_location": None if m.root_stress_location is None else dict(m.root_stress_location),
            "contact_pressure_max_mpa": _num(m.contact_pressure_max_mpa),
            "safety_bending": _num(m.safety_bending),
            "safety_pitting": _num(m.safety_pitting),
            "safety_bending_iso": _num(m.safety_bending_iso),
            "safety_pitting_iso": _num(m.safety_pitting_iso),
            "K_Hbeta": _num(m.sections["middle"].K_Hbeta),
            "K_Fbeta": _num(m.sections["middle"].K_Fbeta),
            "edge_pressure_max_mpa": _num(r.loaded.edge_pressure_max_mpa),
        }
    out["verdict"] = r.verdict()
    out["notes"] = list(r.notes)
    return out


def table(r: RatingResult) -> str:
    rows = [f"rating at pinion torque {r.torque_nm:g} N m ({r.flank} flank); K_A = {r.factors.K_A:g}, "
            f"K_v = {r.factors.K_v:g}"]
    head = ("member", "section", "z_n", "x_n", "beta", "s_Fn", "rho_F", "h_Fe", "Y_F", "Y_S", "Y_b", "sF0",
            "sF", "S_F", "Z_H", "Z_eps", "sH0", "sH", "S_H")
    rows.append(" ".join(f"{h:>7}" for h in head))
    for name, m in r.members.items():
        for k, s in m.sections.items():
            b, c = s.bending, s.contact
            vals = (s.virtual_teeth, s.normal_profile_shift, s.helix_angle_deg, b.s_Fn_mm, b.rho_F_mm, b.h_Fe_mm,
                    b.Y_F, b.Y_S, s.Y_beta, s.sigma_F0_mpa, s.sigma_F_mpa, s.safety_bending_iso, c.Z_H, c.Z_eps,
                    s.sigma_H0_mpa, s.sigma_H_mpa, s.safety_pitting_iso)
            rows.append(f"{name:>7} {k:>7} " + " ".join(f"{v:7.3f}" if abs(v) < 100 else f"{v:7.1f}" for v in vals))
    rows.append("local (loaded contact at K_A K_v T):")
    for name, m in r.members.items():
        def fmt(v, f="{:.1f}"):
            return "null" if v is None else f.format(v)
        at = "" if m.root_stress_location is None else f" ({m.root_stress_where})"
        rows.append(f"  {name}: root stress max {fmt(m.root_stress_max_mpa)} MPa{at}, S_F {fmt(m.safety_bending, '{:.3f}')}"
                    f"; contact pressure max {fmt(m.contact_pressure_max_mpa)} MPa, S_H "
                    f"{fmt(m.safety_pitting, '{:.3f}')}; ISO min S_F {m.safety_bending_iso:.3f}, "
                    f"S_H {m.safety_pitting_iso:.3f}")
    rows.append("verdict: " + r.verdict()["line"])
    rows += [f"note: {n}" for n in r.notes]
    return "\n".join(rows)
