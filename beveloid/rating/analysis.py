"""The rating of a designed pair at a pinion torque: ISO per section and the loaded contact's
local stresses (docs/rating.md).

    from beveloid.rating import Options, analyze
    result = analyze(Pair.example("case1"), Options(torque_nm=1000.0))
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..tooth import sections
from . import iso6336
from .factors import Factors, face_factor_exponent
from .virtual import mate_gear, section_gear

__all__ = ["LoadedContact", "Options", "SectionRating", "MemberRating", "analyze", "loaded_contact",
           "rate_section"]

MEMBERS = ("pinion", "gear")


@dataclass(frozen=True)
class Options:
    """A rating request: the nominal pinion torque (N m) and the LTCA it runs."""

    torque_nm: float
    flank: str = "right"
    positions: int = 10
    pairs: int = 3
    tooth_model: str | None = None  # the LTCA's: None = "fe" when gmsh and scikit-fem import (root stress)
    fe_refinement: int = 1
    fe_coarsen: float = 1.0  # the FE tooth's element sizes times this (ltca.Options)

    def __post_init__(self):
        self.ltca_options(1.0)  # the LTCA's own range table checks the request

    def ltca_options(self, load_factor: float):
        """The LTCA at load_factor (K_A K_v) times the torque, the pair's own errors and material."""
        from ..ltca.options import Options as LTCAOptions

        return LTCAOptions(torque_nm=self.torque_nm * load_factor, flank=self.flank, positions=self.positions,
                           pairs=self.pairs, tooth_model=self.tooth_model, fe_refinement=self.fe_refinement,
                           fe_coarsen=self.fe_coarsen)


@dataclass(frozen=True)
class LoadedContact:
    """What the rating takes from the LTCA (at K_A K_v T)."""

    surface_pressure_max_mpa: float | None  # None: no converged position with a surface peak
    edge_pressure_max_mpa: float | None  # None: no edge contact
    contact_length_mm: float | None  # the shortest loaded length along the face of the most loaded pair
    root_stress_max_mpa: dict  # member -> FE root stress max over the cycle, None when not computed
    root_stress_location: dict  # member -> {face_z_mm, height_above_root_mm, pinion_angle_rad, tooth_pair} or None
    notes: tuple = ()
    peak_where: str = "mesh cycle peak"  # where the surface peak pressure is (pinion angle, tooth pair)
    peak_face_z_mm: dict = field(default_factory=dict)  # member -> face coordinate of that pair's patch centre


def loaded_contact(ltca_result, geometry) -> LoadedContact:
    """Peak surface / edge pressure and the loaded length from an ``LTCAResult``."""
    ok = ltca_result.converged
    notes = list(ltca_result.warnings())
    surf = ltca_result.pair_surface_max_pressure_mpa[ok]
    edge = ltca_result.pair_edge_max_pressure_mpa[ok]
    p_surf = float(np.nanmax(surf)) if np.isfinite(surf).any() else None
    where, face = "mesh cycle peak", {}
    if p_surf is not None:
        j, k = np.unravel_index(int(np.nanargmax(surf)), surf.shape)
        phi = ltca_result.pinion_angle[ok][j]
        face = _patch_centre_face_z(geometry, ltca_result.flank, ltca_result.tangency_unknowns[ok][j, k])
        where = (f"mesh cycle peak (pinion angle {phi * 1e3:.2f} mrad, tooth pair {int(ltca_result.tooth_pairs[k])}; "
                 f"patch centre at face z {face['pinion']:.1f} mm on the pinion, {face['gear']:.1f} mm on the gear)")
    p_edge = float(np.nanmax(edge)) if np.isfinite(edge).any() else None
    axes = ltca_result.patch_semi_axes_mm()[ok]  # (N, P, 2): across, along
    loads = np.where(np.isfinite(ltca_result.pair_load_n[ok]), ltca_result.pair_load_n[ok], -1.0)
    lengths = []
    for j in range(loads.shape[0]):
        k = int(np.argmax(loads[j]))
        along = axes[j, k, 1]
        if loads[j, k] > 0 and np.isfinite(along):
            lengths.append(2.0 * float(along))
    length = min(lengths) if lengths else None
    if not ok.any():
        notes.append("no LTCA position converged: local stresses are null")
    root = {m: None for m in MEMBERS}
    root_where = {m: None for m in MEMBERS}
    if getattr(ltca_result, "tooth_model", "plate") == "fe":
        top, at = ltca_result.root_stress_max_mpa(), ltca_result.root_stress_location()
        for m in MEMBERS:
            root[m] = top.get(m)
            if at.get(m) is not None:
                root_where[m] = {"face_z_mm": float(sections.face_z(geometry, m, at[m]["z_mm"])),
                                 "height_above_root_mm": float(at[m]["height_mm"]),
                                 "pinion_angle_rad": float(ltca_result.pinion_angle[at[m]["position"]]),
                                 "tooth_pair": int(at[m]["pair"])}
        notes.append("local root stress: the FE tooth's largest maximum principal stress in the loaded side's "
                     "root fillet over the mesh cycle (LTCA tooth_model = fe)")
    else:
        notes.append("local root stress: not computed (the LTCA ran with the plate tooth, which has no root "
                     "fillet; --tooth-model fe): root_stress_max_mpa and safety_bending are null, the ISO "
                     "bending values stand alone")
    return LoadedContact(p_surf, p_edge, length, root, root_where, tuple(notes), where, face)


def _patch_centre_face_z(geometry, flank, tangency) -> dict:
    """Face coordinate (mm, toe < 0 < heel) on each member of a pair's rigid tangency point."""
    from ..tca import unknowns

    x = unknowns(np.asarray(tangency, dtype=float))
    out = {}
    for member, (l, u) in (("pinion", (x.pinion_l_mm, x.pinion_u_mm)), ("gear", (x.gear_l_mm, x.gear_u_mm))):
        z = geometry.surface(member, flank, np.atleast_1d(l), np.atleast_1d(u)).point[0, 2]
        out[member] = float(sections.face_z(geometry, member, z))
    return out


@dataclass(frozen=True)
class SectionRating:
    """ISO values of one section (the JSON's SEC, plus the load factors and safeties)."""

    section: str
    face_z_mm: float
    virtual_teeth: float
    normal_profile_shift: float
    helix_angle_deg: float
    bending: iso6336.BendingGeometry
    Y_beta: float
    sigma_F0_mpa: float
    contact: iso6336.ContactFactors
    sigma_H0_mpa: float
    K_Hbeta: float
    K_Fbeta: float
    sigma_F_mpa: float
    sigma_H_mpa: float
    safety_bending_iso: float
    safety_pitting_iso: float
    status: str = "ok"


@dataclass(frozen=True)
class RateInput:
    """What :func:`rate_section` needs besides the section: loads, widths, materials, factors."""

    geometry: object
    flank: str
    torque_nm: float
    face_width_mm: float
    loaded_length_mm: float | None
    factors: Factors
    elastic: tuple  # (E_pinion MPa, nu_pinion, E_gear MPa, nu_gear)


def _member_torque_nm(geometry, member, pinion_torque_nm):
    return pinion_torque_nm * (1.0 if member == "pinion" else geometry.gear.teeth / geometry.pinion.teeth)


def rate_section(inp: RateInput, member: str, z_face: float, name: str = "") -> SectionRating:
    """ISO 6336 on the virtual gear of ``member``'s section at face coordinate z_face (mm); a section
    where method B has no answer (no 30 deg tangent, a tip below the outer point of single contact)
    gets NaN values and its reason in ``status`` (null in the JSON)."""
    try:
        return _rate_section(inp, member, z_face, name)
    except (ValueError, ZeroDivisionError) as exc:
        nan = math.nan
        bend = iso6336.BendingGeometry(nan, nan, nan, nan, nan, nan, nan, nan, nan, 0, f_eps=nan)
        return SectionRating(name, float(z_face), nan, nan, nan, bend, nan, nan,
                             iso6336.ContactFactors(nan, nan, nan, nan), nan, nan, nan, nan, nan, nan, nan,
                             status=f"ISO not computed: {exc}")


def _rate_section(inp: RateInput, member: str, z_face: float, name: str) -> SectionRating:
    geom = inp.geometry
    sg = section_gear(geom, member, z_face, inp.flank, name)
    gear, mate = sg.gear, mate_gear(geom, sg, inp.flank)
    b = inp.face_width_mm
    loaded = b if inp.loaded_length_mm is None else min(inp.loaded_length_mm * math.cos(gear.base_helix_angle), b)
    k_hb = b / loaded
    pair_loaded = iso6336.CylindricalPair(gear, mate, loaded)
    bend = iso6336.bending_geometry(pair_loaded)
    ft = 1000.0 * _member_torque_nm(geom, member, inp.torque_nm) / (gear.reference_diameter_mm / 2)
    y_beta = iso6336.helix_factor_bending(pair_loaded.overlap_ratio, gear.helix_angle)
    sf0 = iso6336.nominal_root_stress_mpa(ft, b, gear.normal_module_mm, bend.Y_F, bend.Y_S, y_beta)
    e = inp.elastic
    own = (e[0], e[1]) if member == "pinion" else (e[2], e[3])
    other = (e[2], e[3]) if member == "pinion" else (e[0], e[1])
    cf = iso6336.contact_factors(pair_loaded, own[0], own[1], other[0], other[1])
    small = gear if gear.teeth <= mate.teeth else mate
    u = max(gear.teeth, mate.teeth) / min(gear.teeth, mate.teeth)
    sh0 = iso6336.nominal_contact_stress_mpa(cf, ft, small.reference_diameter_mm, b, u)
    m = geom.member(member)
    k_fb = k_hb ** face_factor_exponent(b, m.tip_height_mm + m.cutter_addendum_mm)
    f = inp.factors
    s_f = sf0 * f.K_A * f.K_v * k_fb
    s_h = sh0 * math.sqrt(f.K_A * f.K_v * k_hb)
    return SectionRating(
        name, float(z_face), bend.virtual_teeth, gear.profile_shift, math.degrees(sg.helix_angle_signed), bend,
        y_beta, sf0, cf, sh0, k_hb, k_fb, s_f, s_h, f.root_strength_mpa(member) / s_f,
        f.contact_strength_mpa(member) / s_h, _validity(bend, pair_loaded))


def _validity(bend, pair) -> str:
    """"ok", or where ISO 6336-3 says its factors hold no longer (the values are kept)."""
    out = []
    qs = bend.s_Fn_mm / (2 * bend.rho_F_mm)
    if not 1.0 <= qs < 8.0:
        out.append(f"notch parameter q_s = {qs:.3g} outside ISO 6336-3's 1 <= q_s < 8 (Y_S extrapolated)")
    eps_an = pair.transverse_contact_ratio / math.cos(pair.gear.base_helix_angle) ** 2
    if eps_an > 2.05:
        out.append(f"eps_alpha_n = {eps_an:.3g} > 2.05: deep-tooth factor Y_DT < 1 not applied")
    if eps_an < 1.0:
        out.append(f"eps_alpha_n = {eps_an:.3g} < 1: the virtual pair has no single-pair contact span")
    return "; ".join(out) if out else "ok"


@dataclass(frozen=True)
class MemberRating:
    member: str
    sections: dict  # "toe" | "middle" | "heel" -> SectionRating
    root_stress_max_mpa: float | None
    root_stress_location: dict | None  # LoadedContact.root_stress_location's entry
    contact_pressure_max_mpa: float | None
    safety_bending: float | None
    safety_pitting: float | None
    face: tuple = field(default=(), repr=False)  # SectionRating along the face (for the plot)

    @property
    def root_stress_where(self) -> str:
        """The root stress peak's place in words (the verdict's "where")."""
        w = self.root_stress_location
        if w is None:
            return "mesh cycle peak"
        return (f"root fillet at face z {w['face_z_mm']:.1f} mm, {w['height_above_root_mm']:.2f} mm above the root "
                f"cone (pinion angle {w['pinion_angle_rad'] * 1e3:.2f} mrad, tooth pair {w['tooth_pair']})")

    @property
    def safety_bending_iso(self) -> float:
        """The lowest ISO S_F of the three sections (NaN when none was computed)."""
        return _lowest(s.safety_bending_iso for s in self.sections.values())

    @property
    def safety_pitting_iso(self) -> float:
        return _lowest(s.safety_pitting_iso for s in self.sections.values())


def _lowest(values) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return min(finite) if finite else math.nan


def analyze(pair, options: Options, solver=None, ltca_result=None, face_points: int = 0):
    """Rate ``pair`` at ``options.torque_nm``; ``ltca_result``: an LTCA already run at K_A K_v T
    (else it is run here); ``face_points`` > 0 adds that many ISO sections along each face (plot)."""
    from .. import ltca
    from .report import RatingResult

    spec, geom = pair.spec, pair.geometry
    factors = Factors.from_spec(spec)
    if ltca_result is None:
        from ..solver import Solver

        ltca_result = ltca.analyze(pair, options.ltca_options(factors.K_A * factors.K_v), solver or Solver())
    lc = loaded_contact(ltca_result, geom)
    mat = ltca.Material.from_spec(spec)
    inp = RateInput(geom, options.flank, options.torque_nm, min(geom.pinion.face_width_mm, geom.gear.face_width_mm),
                    lc.contact_length_mm, factors, (mat.pinion_e_mpa, mat.pinion_nu, mat.gear_e_mpa, mat.gear_nu))
    members = {}
    for member in MEMBERS:
        w = sections.half_face(geom, member)
        secs = {name: rate_section(inp, member, at * w, name) for name, at in sections.ENDS}
        face = tuple(rate_section(inp, member, z) for z in np.linspace(-w, w, face_points)) if face_points else ()
        root = lc.root_stress_max_mpa[member]
        p = lc.surface_pressure_max_mpa
        members[member] = MemberRating(
            member, secs, root, lc.root_stress_location[member], p,
            None if root is None else factors.root_strength_mpa(member) / root,
            None if p is None else factors.contact_strength_mpa(member) / p, face)
    notes = factors.notes() + list(lc.notes)
    notes += [f"{m.member} {k}: {s.status}" for m in members.values() for k, s in m.sections.items() if s.status != "ok"]
    if lc.contact_length_mm is None:
        notes.append("no loaded contact length from the LTCA: K_Hbeta = K_Fbeta = 1 on the full face width")
    if lc.edge_pressure_max_mpa is not None:
        notes.append(f"edge contact: peak edge pressure {lc.edge_pressure_max_mpa:.0f} MPa (grid-dependent, "
                     "reported apart; not in S_H)")
    return RatingResult(options.torque_nm, options.flank, members, lc, factors, tuple(notes))
