"""The rating's result: its JSON contract (issue 32), the verdict and the table."""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..result import Result

__all__ = ["RatingResult", "SEC_KEYS"]

#: the keys of one section in the JSON, in order; from "normal_module_mm" on, every input of method B
#: (issue 57.8): the virtual gear's own normal module and flank-specific normal pressure angle (not the
#: rack's), its diameters and rack, the face length in contact (eps_beta) and the mate's (the same m_n,
#: alpha_n and helix as the rated section's virtual gear)
SEC_KEYS = ("virtual_teeth", "normal_profile_shift", "helix_angle_deg", "s_Fn_mm", "rho_F_mm", "h_Fe_mm",
            "alpha_Fen_deg", "Y_F", "Y_S", "Y_beta", "f_eps", "sigma_F0_mpa", "Z_H", "Z_E", "Z_eps", "Z_beta",
            "sigma_H0_mpa", "normal_module_mm", "normal_pressure_angle_deg", "reference_diameter_mm",
            "tip_diameter_mm", "rack_dedendum_mm", "rack_tip_radius_mm", "loaded_face_width_mm", "mate_teeth",
            "mate_normal_profile_shift", "mate_tip_diameter_mm", "mate_rack_dedendum_mm", "mate_rack_tip_radius_mm")


def _num(v):
    """A finite float, else None (strict JSON)."""
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def section_json(s) -> dict:
    b, c, g, m = s.bending, s.contact, s.virtual, s.mate
    nan = math.nan
    gear = ((nan,) * 6 if g is None else
            (g.normal_module_mm, math.degrees(g.normal_pressure_angle), g.reference_diameter_mm, g.tip_diameter_mm,
             g.rack_dedendum_mm, g.rack_tip_radius_mm))
    mate = (nan,) * 5 if m is None else (m.teeth, m.profile_shift, m.tip_diameter_mm, m.rack_dedendum_mm,
                                         m.rack_tip_radius_mm)
    values = (s.virtual_teeth, s.normal_profile_shift, s.helix_angle_deg, b.s_Fn_mm, b.rho_F_mm, b.h_Fe_mm,
              math.degrees(b.alpha_Fen), b.Y_F, b.Y_S, s.Y_beta, b.f_eps, s.sigma_F0_mpa, c.Z_H, c.Z_E, c.Z_eps,
              c.Z_beta, s.sigma_H0_mpa, *gear, s.loaded_length_mm, *mate)
    return {k: _num(v) for k, v in zip(SEC_KEYS, values)}


@dataclass(frozen=True)
class RatingResult(Result):
    """The rating of ``pair`` under ``options``: per member its ratings, the loaded contact, the factors;
    deep-frozen, its JSON by :meth:`to_json`."""

    torque_nm: float
    flank: str
    members: dict  # "pinion" | "gear" -> analysis.MemberRating
    loaded: object  # analysis.LoadedContact
    factors: object  # factors.Factors
    notes: tuple
    dynamic: object = None  # dynamic.DynamicFactor when K_v came from ISO 6336-1 method B
    #: tribology.TribologyResult at K_A K_v T and [rating] pinion_speed_rpm when the file has a [lubricant]
    #: (the scuffing criterion of the verdict; docs/tribology.md), else None
    tribology: object = None
    #: analysis.tolerance_face_load's dict when the rating took K_Hbeta from the tolerance box, else None
    tolerance_box: object = None

    def to_json(self) -> dict:
        """The JSON of ``beveloid rating --json`` (issue 32's contract)."""
        return _json(self)

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

    def edge_contact(self) -> dict | None:
        """The edge-contact rule applied (None without edge contact): ``verdict.edge_criterion``."""
        from .verdict import edge_criterion

        return edge_criterion(self)

    def verdict(self) -> dict:
        """The verdict: :func:`beveloid.rating.verdict.verdict` of this result."""
        from .verdict import verdict

        return verdict(self)


def _thawed(v):
    """Plain dicts and lists, finite floats (or None) of a nested mapping."""
    if hasattr(v, "items"):
        return {k: _thawed(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_thawed(x) for x in v]
    if isinstance(v, bool):
        return v
    if isinstance(v, (int, str)) or v is None:
        return v
    return _num(v)


def _face_load_json(fl) -> dict:
    return {"peak_line_load_n_per_mm": _num(fl.peak_line_load_n_per_mm),
            "mean_line_load_n_per_mm": _num(fl.mean_line_load_n_per_mm), "face_z_mm": _num(fl.face_z_mm),
            "loaded_length_mm": _num(fl.loaded_length_mm)}


def _convergence_json(e) -> dict | None:
    """A member's root-stress convergence estimate (rating.root_convergence), null without the FE tooth."""
    return None if e is None else _thawed(e)


def _json(r: RatingResult) -> dict:
    f = r.factors
    out = {"torque_nm": float(r.torque_nm), "flank": r.flank, "K_A": float(f.K_A), "K_v": _num(f.K_v),
           "K_v_source": f.K_v_source,
           "dynamic_factor": None if r.dynamic is None else {k: (list(v) if isinstance(v, tuple) else
                                                                 (v if isinstance(v, str) else _num(v)))
                                                             for k, v in r.dynamic.as_dict().items()}}
    for name, m in r.members.items():
        fl = r.loaded.face_load[name]
        out[name] = {
            "sections": {k: section_json(s) for k, s in m.sections.items()},
            "root_stress_max_mpa": _num(m.root_stress_max_mpa),
            "root_stress_location": None if m.root_stress_location is None else dict(m.root_stress_location),
            "root_stress_convergence": _convergence_json(r.loaded.root_stress_convergence.get(name)),
            "contact_pressure_max_mpa": _num(m.contact_pressure_max_mpa),
            "safety_bending": _num(m.safety_bending),
            "safety_pitting": _num(m.safety_pitting),
            "safety_bending_iso": _num(m.safety_bending_iso),
            "safety_pitting_iso": _num(m.safety_pitting_iso),
            "K_H_beta": _num(m.sections["middle"].K_H_beta),
            "K_F_beta": _num(m.sections["middle"].K_F_beta),
            "face_load": _face_load_json(fl),
            "material": {k: (_num(v) if isinstance(v, float) else v) for k, v in f.material_json(name).items()},
            "strength_factors": _thawed(f.strength[name].as_json()) if name in f.strength else None,
            "edge_pressure_max_mpa": _num(r.loaded.edge_pressure_max_mpa),
        }
    out["positions_check"] = _thawed(r.loaded.positions_check)
    out["tolerance_box"] = None if r.tolerance_box is None else _thawed(r.tolerance_box)
    out["tribology"] = None if r.tribology is None else r.tribology.to_json()
    out["verdict"] = r.verdict()
    out["notes"] = list(r.notes)
    return out


def _fmt(v, spec="{:.1f}", unit=""):
    """A number with its unit, or "null" (never "null MPa")."""
    v = _num(v)
    return "null" if v is None else spec.format(v) + (f" {unit}" if unit else "")


def table(r: RatingResult) -> str:
    f = r.factors
    k_v = {"method B": " (ISO 6336-1 method B)", "user": " (user's)", "static": " (static: no speed)",
           "not computed": " (method B not computed)"}[f.K_v_source]
    rows = [f"rating at pinion torque {r.torque_nm:g} N m ({r.flank} flank); K_A = {f.K_A:g}, "
            f"K_v = {f.K_v:.4g}{k_v}"]
    head = ("member", "section", "z_n", "x_n", "beta", "s_Fn", "rho_F", "h_Fe", "Y_F", "Y_S", "Y_b", "K_Fb", "sF0",
            "sF", "S_F", "Z_H", "Z_eps", "K_Hb", "sH0", "sH", "S_H")
    units = ("", "", "", "", "deg", "mm", "mm", "mm", "", "", "", "", "MPa", "MPa", "", "", "", "", "MPa", "MPa", "")
    rows.append(" ".join(f"{h:>7}" for h in head))
    rows.append(" ".join(f"{'[' + u + ']' if u else '':>7}" for u in units))
    for name, m in r.members.items():
        for k, s in m.sections.items():
            b, c = s.bending, s.contact
            vals = (s.virtual_teeth, s.normal_profile_shift, s.helix_angle_deg, b.s_Fn_mm, b.rho_F_mm, b.h_Fe_mm,
                    b.Y_F, b.Y_S, s.Y_beta, s.K_F_beta, s.sigma_F0_mpa, s.sigma_F_mpa, s.safety_bending_iso, c.Z_H,
                    c.Z_eps, s.K_H_beta, s.sigma_H0_mpa, s.sigma_H_mpa, s.safety_pitting_iso)
            rows.append(f"{name:>7} {k:>7} " + " ".join(
                f"{'null':>7}" if _num(v) is None else (f"{v:7.3f}" if abs(v) < 100 else f"{v:7.1f}") for v in vals))
    rows.append("local (loaded contact at K_A K_v T):")
    for name, m in r.members.items():
        at = "" if m.root_stress_location is None else f" ({m.root_stress_where})"
        fl = r.loaded.face_load[name]
        mat = f.material[name]
        rows.append(f"  {name}: root stress max {_fmt(m.root_stress_max_mpa, unit='MPa')}{at}, S_F "
                    f"{_fmt(m.safety_bending, '{:.3f}')}; contact pressure max "
                    f"{_fmt(m.contact_pressure_max_mpa, unit='MPa')}, S_H {_fmt(m.safety_pitting, '{:.3f}')}; "
                    f"ISO min S_F {_fmt(m.safety_bending_iso, '{:.3f}')}, S_H {_fmt(m.safety_pitting_iso, '{:.3f}')}")
        rows.append(f"    line load along the face: peak {_fmt(fl.peak_line_load_n_per_mm, unit='N/mm')} at face z "
                    f"{_fmt(fl.face_z_mm, unit='mm')}, mean {_fmt(fl.mean_line_load_n_per_mm, unit='N/mm')}: "
                    f"K_H_beta {_fmt(m.sections['middle'].K_H_beta, '{:.3f}')}, K_F_beta "
                    f"{_fmt(m.sections['middle'].K_F_beta, '{:.3f}')}")
        rows.append(f"    material: {mat['type']} {mat['quality']}, sigma_Hlim {f.contact_limit_mpa[name]:g} MPa, "
                    f"sigma_Flim {f.root_limit_mpa[name]:g} MPa, Z_NT {f.Z_NT(name):.3f}, Y_NT {f.Y_NT(name):.3f}")
    rows.append("verdict: " + r.verdict()["line"])
    rows += [f"note: {n}" for n in r.notes]
    return "\n".join(rows)
