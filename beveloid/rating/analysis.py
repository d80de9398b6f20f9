"""The rating of a designed pair at a pinion torque: ISO per section and the loaded contact's
local stresses (docs/rating.md).

    from beveloid import ltca, rating
    result = rating.analyze(Pair.example("case1"), ltca.LoadCase(torque_nm=1000.0))
    rating.analyze(pair, ltca.LoadCase(1000.0), rating.Options(ltca.Options(positions=20, tooth_model="plate")))
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..names import MEMBERS
from ..plots import pinion_angle_text
from ..status import Validity
from ..tooth import sections
from . import dynamic, iso6336, materials
from .face_load import face_load, line_loads
from .factors import Factors, face_factor_exponent
from .strength import pitch_line_velocity_m_s
from .virtual import mate_gear, section_gear
from .root_convergence import convergence_notes, prepare, root_stress_convergence

__all__ = ["LoadedContact", "Options", "SectionRating", "MemberRating", "analyze", "loaded_contact", "ltca_case",
           "rate_section"]



#: the rating's default positions over the mesh cycle: 20 distinct mesh states (issue 57.4: at 10 the root
#: stress maximum read 7-8.5 % low against 20); the rating then refines where each maximum lies
#: (:func:`refine_positions`)
POSITIONS = 21
#: a maximum whose last refinement round still moved it more than this is reported as not resolved by the
#: positions
POSITIONS_TOLERANCE = 0.03
#: the refinement of the maxima between positions (:func:`refine_positions`) halves the spacing beside each
#: maximum down to this share of the mesh cycle (that of 81 positions): a maximum before a drop (a pair
#: leaving) is missed by a midpoint just past the drop, which reads no move (case 1 at 1500 N m, FE tooth)
REFINE_SPACING = 1.0 / 80.0
#: and on below it while the maximum still moved more than this in its last round
REFINE_TOLERANCE = 0.01
#: the local maxima over the cycle within this of the largest one are refined too (a peak between two
#: positions may lie beside a sampled local maximum lower than the largest sample)
REFINE_BAND = 0.1
#: the most pinion angles the refinement adds to the asked positions for the stresses and K_Hbeta (the maxima
#: the safeties divide by)
MAX_ADDED_POSITIONS = 24
#: and, on a budget of their own, for the edges' load shares (an edge rule's share needs its peak within a few
#: percent of 2 %; sharing the stresses' budget, the edges of case 1 at 1500 N m took the angles that its
#: pinion's root stress maximum needed: 161.2 against 163.7 MPa on the coarse FE tooth, docs/rating.md 6)
MAX_ADDED_EDGE_POSITIONS = 8
#: the maxima the refinement follows (each member's; the edge load share each edge's, keyed "member edge"): the
#: quantities the verdict reads per position
REFINED = ("contact_pressure_max_mpa", "root_stress_max_mpa", "K_H_beta", "edge_load_share")
#: an edge's load share is refined about its maxima where its largest share reaches this fraction of the edge
#: rule's limit (``verdict.EDGE_SHARE``): below it (0.2 % of the mesh's load) are the edges the pattern does
#: not run onto (a pair whose tip is relieved reads under 0.2 % on every edge, docs/rating.md 6), whose
#: refinement would spend added angles on nothing the rule judges; design J of ``benchmarks/rating_invariance.py``
#: at 560 N m reads 0.8 % on its pinion tip at 10 positions, 13-16 % at 20 and 30 (the pinion tip's peak lies
#: between two of the 10)
EDGE_REFINE_FLOOR = 0.1


def _default_ltca():
    from ..ltca.options import Options as LTCAOptions

    return LTCAOptions(positions=POSITIONS)


#: the percentile of the tolerance box's K_Hbeta that the rating takes (``tolerance_samples`` > 0)
BOX_PERCENTILE = 90.0
#: the most error sets of the rating's tolerance box (the [rating] key's range)
MAX_TOLERANCE_SAMPLES = 10_000


@dataclass(frozen=True)
class Options:
    """How a rating is computed: the LTCA it runs (an ``ltca.Options``: flank, positions, pairs, grid,
    tooth model, refinement; default: :data:`POSITIONS` positions).  The torque and the
    assembly errors are the load case (``ltca.LoadCase``).

    ``tolerance_samples`` > 0 rates K_Hbeta at the :data:`BOX_PERCENTILE` th percentile over that many
    error sets of the tolerance box under load (``ltca.studies.box_results`` on the draws of
    ``sweep.draw_errors`` about the load case's errors, half-widths ``tolerances``: keys of
    ``assembly_errors.DEFAULT_RANGES``, missing ones its defaults; seed ``tolerance_seed``); None: the
    spec's ``[rating] tolerance_samples``; 0: the load case's errors alone.

    ``root_stress_check``: with the FE tooth, estimate whether its root stress is converged
    (:mod:`beveloid.rating.root_convergence`: the FE tooth coarsened twice, its data computed once per
    design); False leaves ``root_stress_convergence`` empty (the verdict does not read it).

    ``refine_positions``: after the LTCA at the asked positions, refine where each maximum the verdict uses
    lies (:func:`refine_positions`: the LTCA again at pinion angles between the maximum and its neighbours,
    the maxima over all of them); False: the maxima over the asked positions alone.

    ``grid_check``: the LTCA's grid-convergence indicator (a once-coarsened grid solved again, its warning in
    the notes); False leaves it out with the root stress along the face and the compressive root stress,
    every other number the same to the last bit (``ltca.analyze_many(..., convergence=False, along_face=False,
    compression=False)``: the verdict reads none of them)."""

    ltca: object = field(default_factory=_default_ltca)
    tolerance_samples: int | None = None
    tolerance_seed: int = 0
    tolerances: dict | None = None
    root_stress_check: bool = True
    grid_check: bool = True
    refine_positions: bool = True

    def __post_init__(self):
        from ..assembly_errors import BY_KEY
        from ..errors import OptionError
        from ..ltca.options import Options as LTCAOptions

        if not isinstance(self.ltca, LTCAOptions):
            raise OptionError("ltca", self.ltca, "must be an ltca.Options")
        for key in ("root_stress_check", "grid_check", "refine_positions"):
            if not isinstance(getattr(self, key), bool):
                raise OptionError(key, getattr(self, key), "must be True or False")
        n = self.tolerance_samples
        if n is not None and (isinstance(n, bool) or not isinstance(n, (int, np.integer))
                              or not 0 <= n <= MAX_TOLERANCE_SAMPLES):
            raise OptionError("tolerance_samples", n, f"must be an integer from 0 to {MAX_TOLERANCE_SAMPLES} (or None: "
                                                      "the spec's [rating] tolerance_samples)")
        if isinstance(self.tolerance_seed, bool) or not isinstance(self.tolerance_seed, (int, np.integer)) \
                or not 0 <= self.tolerance_seed < 2 ** 63:
            raise OptionError("tolerance_seed", self.tolerance_seed, "must be an integer from 0 to 2**63 - 1")
        for key, half in (self.tolerances or {}).items():
            if key not in BY_KEY:
                raise OptionError("tolerances", {key: half}, f"unknown error {key!r}; valid: {', '.join(BY_KEY)}")
            if not (isinstance(half, (int, float)) and 0 <= half <= BY_KEY[key].limit):
                raise OptionError("tolerances", {key: half}, f"{key} must be a number from 0 to {BY_KEY[key].limit:g} "
                                                             f"({BY_KEY[key].unit})")

    @property
    def flank(self) -> str:
        return self.ltca.flank


def _one_torque(load):
    """The rating's load case: one torque (N m), its errors (None: the pair's)."""
    from ..errors import OptionError
    from ..ltca.load import LoadCase

    if not isinstance(load, LoadCase):
        raise TypeError(f"rating.analyze(pair, load, options=None, *, solver=None) needs an ltca.LoadCase as load, "
                        f"not {type(load).__name__}")
    if load.is_map:
        raise OptionError("torque_nm", load.torque_nm, "a rating takes one torque and one error set")
    return load


@dataclass(frozen=True)
class EdgeContact:
    """The most loaded flank edge of the loaded contact (``edge.edge_loads``): the mean pressure within
    ``band_mm`` of the edge, the force there, and the relief the edge already has."""

    pressure_mpa: float
    member: str  # whose edge: "pinion" | "gear"
    edge: str  # "toe" | "heel" | "tip"
    pinion_angle_rad: float
    tooth_pair: int
    force_n: float = math.nan
    share: float = math.nan  # force_n over the pair's load
    band_mm: float = math.nan
    relief_now_um: float = 0.0  # the spec's tip relief (tip) or end relief (toe, heel) of that member

    @property
    def where(self) -> str:
        return f"the {self.edge} of the {self.member}"

    @property
    def relief(self) -> str:
        return "tip relief" if self.edge == "tip" else "end relief"


@dataclass(frozen=True)
class LoadedContact:
    """What the rating takes from the LTCA (at K_A K_v T)."""

    surface_pressure_max_mpa: float | None  # None: no converged position with a surface peak
    edge_pressure_max_mpa: float | None  # None: no edge contact
    face_load: dict  # member -> FaceLoad (K_Hbeta from the line load along the face)
    root_stress_max_mpa: dict  # member -> FE root stress max over the cycle, None when not computed
    root_stress_location: dict  # member -> {face_z_mm, height_above_root_mm, pinion_angle_rad, tooth_pair} or None
    notes: tuple = ()
    peak_where: str = "mesh cycle peak"  # where the surface peak pressure is (pinion angle, tooth pair)
    peak_face_z_mm: dict = field(default_factory=dict)  # member -> face coordinate of that pair's patch centre
    edge: EdgeContact | None = None
    mesh_stiffness_n_per_um: float | None = None  # mean over the converged positions
    positions_check: dict = field(default_factory=dict)  # positions_check(): the maxima against every other position
    #: member -> the FE root stress's convergence estimate (root_convergence.root_stress_convergence)
    root_stress_convergence: dict = field(default_factory=dict)
    #: every edge that carries load within its band, largest share first (``edge`` is the first)
    edges: tuple = ()


def loaded_contact(ltca_result, geometry, face_width_mm: float, solve_at=None) -> LoadedContact:
    """Peak surface / edge pressure, the line load along each face (K_Hbeta) and the mean mesh
    stiffness from an ``LTCAResult``; ``face_width_mm`` the b of the mean line load.  ``solve_at(angles)``:
    the same LTCA at those pinion angles (rad), an ``LTCAResult``; given, the maxima the verdict uses (contact
    pressure, root stress, K_Hbeta) are refined between the positions (:func:`refine_positions`) and taken
    over the asked and the added positions, and so are the edge contacts (the refinement follows each edge's
    load share too); the mesh stiffness stays the asked positions' (their mean over the cycle's distinct
    states: the added angles are not evenly spaced)."""
    ok = ltca_result.converged
    notes = list(ltca_result.warnings())
    from .edge import EdgeDistances, surface_peaks

    distances = EdgeDistances(ltca_result, geometry)  # read by the surface peaks and the edge rule
    surface = surface_peaks(ltca_result, geometry, distances=distances)
    lines = {m: line_loads(ltca_result, geometry, m) for m in MEMBERS}  # read by K_Hbeta and the refinement
    check, added = refine_positions(ltca_result, geometry, face_width_mm, solve_at, surface, lines, distances)
    runs = ((ltca_result, surface, lines, distances), *added)
    p_surf, where, face, at = None, "mesh cycle peak", {}, None
    for r, surf, _, _ in runs:
        s_ok = surf[r.converged]
        if np.isfinite(s_ok).any() and (p_surf is None or float(np.nanmax(s_ok)) > p_surf):
            p_surf, at = float(np.nanmax(s_ok)), (r, s_ok)
    if at is not None:
        r, s_ok = at
        j, k = np.unravel_index(int(np.nanargmax(s_ok)), s_ok.shape)
        phi = r.pinion_angle[r.converged][j]
        face = _patch_centre_face_z(geometry, r.flank, r.tangency_unknowns[r.converged][j, k])
        where = (f"mesh cycle peak ({pinion_angle_text(phi)}, tooth pair {int(r.tooth_pairs[k])}; "
                 f"patch centre at face z {face['pinion']:.1f} mm on the pinion, {face['gear']:.1f} mm on the gear)")
    p_edge = _peak(np.concatenate([r.pair_edge_max_pressure_mpa[r.converged].ravel() for r, *_ in runs]))
    loads = {}
    for m in MEMBERS:
        each = [face_load(r, geometry, m, face_width_mm, lines=ls[m]) for r, _, ls, _ in runs]
        loads[m] = max(each, key=lambda f: -math.inf if f.K_H_beta is None else f.K_H_beta)
    if not ok.any():
        notes.append("no LTCA position converged: local stresses are null")
    root = {m: None for m in MEMBERS}
    root_where = {m: None for m in MEMBERS}
    if getattr(ltca_result, "tooth_model", "plate") == "fe":
        top, at, of = {}, {}, {}
        for r, *_ in runs:
            r_top, r_at = r.root_stress_max_mpa(), r.root_stress_location()
            for m in MEMBERS:
                v = r_top.get(m)
                if v is not None and (top.get(m) is None or v > top[m]):
                    top[m], at[m], of[m] = v, r_at.get(m), r
        for m in MEMBERS:
            root[m] = top.get(m)
            if root[m] is not None and not root[m] > 0.0:  # nothing to divide a strength by
                notes.append(f"{m}: the FE tooth reads no tensile root stress over the mesh cycle "
                             f"({root[m]:g} MPa): the local root stress and S_F are null")
                root[m] = None
                continue
            if at.get(m) is not None:
                # a location the FE tooth does not know (a reading node's height or z not finite) stays null
                z, h = at[m]["z_mm"], at[m]["height_mm"]
                root_where[m] = {"face_z_mm": None if z is None else float(sections.face_z(geometry, m, z)),
                                 "height_above_root_mm": None if h is None else float(h),
                                 "pinion_angle_rad": float(of[m].pinion_angle[at[m]["position"]]),
                                 "tooth_pair": int(at[m]["pair"])}
        notes.append("local root stress: the FE tooth's largest maximum principal stress in the loaded side's "
                     "root fillet over the mesh cycle (LTCA tooth_model = fe)")
    else:
        notes.append("local root stress: not computed (the LTCA ran with the plate tooth, which has no root "
                     "fillet; --tooth-model fe): root_stress_max_mpa and safety_bending are null, the ISO "
                     "bending values stand alone")
    from ..ltca.results.batch import summary as ltca_summary

    # the mean over the cycle's distinct states, as the LTCA's JSON and the torque map give it
    k_mesh = ltca_summary(ltca_result)["mesh_stiffness_mean_n_per_um"]
    k_mesh = float(k_mesh) if np.isfinite(k_mesh) else None
    notes += _positions_notes(check)
    edges = _edge_contacts([(r, d) for r, _, _, d in runs], geometry)
    return LoadedContact(p_surf, p_edge, loads, root, root_where, tuple(notes), where, face,
                         edges[0] if edges else None, k_mesh, check, edges=edges)


def _positions_notes(check) -> list:
    """The notes of :func:`refine_positions`' check: a maximum still moving more than
    :data:`POSITIONS_TOLERANCE` (an edge's load share only between half and twice the edge rule's limit, where
    the positions may decide the rule), added angles that did not converge."""
    from .verdict import EDGE_SHARE

    notes = []
    for q, by_member in check.get("quantities", {}).items():
        for m, c in by_member.items():
            if q == "edge_load_share" and not 0.5 * EDGE_SHARE <= (c["all"] or 0.0) <= 2.0 * EDGE_SHARE:
                continue  # far from the rule's limit the positions do not decide it (its change is in the JSON)
            top = c.get("at_edge")
            if top is not None and c["all"] and top / c["all"] - 1.0 > POSITIONS_TOLERANCE:
                notes.append(f"{m}: its edge load share {c['all']:.2%} is read where the contact grid's cells cross "
                             f"the edge one by one: at the last instant of a cell's passage it reads up to "
                             f"{top:.2%} ({top / c['all'] - 1.0:+.0%}; the edge rule's band takes it in)")
            if c["change"] is not None and abs(c["change"]) > POSITIONS_TOLERANCE:
                notes.append(f"{m}: {q} moved {c['change']:+.1%} in its last refinement round between positions "
                             f"({check['added_positions']} pinion angles added to the {check['positions']} "
                             f"asked, at most {MAX_ADDED_POSITIONS} + {MAX_ADDED_EDGE_POSITIONS} for the edges): its maximum over the cycle is not resolved "
                             f"to {POSITIONS_TOLERANCE:.0%} (more --positions)")
    if check.get("added_not_converged"):
        notes.append(f"{check['added_not_converged']} of the {check['added_positions']} pinion angles added between "
                     "positions did not converge: the maxima leave them out")
    return notes


def _peak(values):
    v = np.asarray(values, dtype=float)
    return float(np.nanmax(v)) if np.isfinite(v).any() else None


def _position_maxima(result, geometry, face_width_mm, surface, lines, distances=None) -> dict:
    """{(quantity, member): (N,) its largest value at each position of ``result``, nan where the position did
    not converge or has none}: the contact pressure (``surface``: ``edge.surface_peaks``, the same for both
    members), the FE tooth's root stress, K_Hbeta (``face_load`` of that position alone; ``lines``
    {member: ``line_loads``}), and each edge's load share (``edge.edge_shares``, keyed ("edge_load_share",
    "member edge"); ``distances``: the result's ``edge.EdgeDistances``)."""
    from .edge import edge_shares

    ok = np.asarray(result.converged)

    def by_position(a):
        a = np.where(ok[:, None], np.asarray(a, dtype=float), np.nan)
        return np.array([np.nanmax(row) if np.isfinite(row).any() else np.nan for row in a])

    out = {}
    for m in MEMBERS:
        out["contact_pressure_max_mpa", m] = by_position(surface)
        kh = (face_load(result, geometry, m, face_width_mm, [j], lines[m]).K_H_beta for j in range(ok.size))
        out["K_H_beta", m] = np.array([np.nan if k is None else k for k in kh], dtype=float)
    for m, a in (result.pair_root_stress_mpa or {}).items():
        out["root_stress_max_mpa", m] = by_position(a)
    for (m, edge), a in edge_shares(result, geometry, distances=distances).items():
        out["edge_load_share", f"{m} {edge}"] = a
    return out


def _around_maxima(phase, values, spacing: float = 0.0) -> list:
    """[(phase, weight)]: the midpoints between each local maximum of ``values`` at the cycle's ``phase``
    (0-1, one pinion pitch; the cycle wraps: the last phase's neighbour is the first's, and phase 1 is
    phase 0) within :data:`REFINE_BAND` of the largest and each of its two neighbours farther from it than
    ``spacing``; weight: its value over the largest."""
    ph = np.round(np.mod(phase, 1.0), 12) % 1.0
    uniq, inv = np.unique(ph, return_inverse=True)
    w = np.full(uniq.size, -np.inf)
    np.maximum.at(w, inv, np.where(np.isfinite(values), values, -np.inf))
    top = w.max(initial=-np.inf)
    if not (np.isfinite(top) and top > 0):
        return []
    m = uniq.size
    if m == 1:
        return [((uniq[0] + 0.5) % 1.0, 1.0)]
    out = []
    for i in range(m):
        if w[i] >= max(w[i - 1], w[(i + 1) % m]) and w[i] >= (1.0 - REFINE_BAND) * top:
            left = uniq[i - 1] - (1.0 if i == 0 else 0.0)
            right = uniq[(i + 1) % m] + (1.0 if i == m - 1 else 0.0)
            out += [(((uniq[i] + side) / 2) % 1.0, w[i] / top) for side in (left, right)
                    if abs(uniq[i] - side) > spacing]
    return out


def refine_positions(ltca_result, geometry, face_width_mm: float, solve_at=None, surface=None, lines=None,
                     distances=None):
    """(check, added): the maxima over the cycle that the verdict uses (contact pressure, each member's root
    stress and K_Hbeta, each edge's load share), refined between the LTCA's positions (issue 57.4).
    ``solve_at(angles)`` runs the same LTCA at pinion angles (rad); each round adds, for every quantity, the
    midpoints between each local maximum within :data:`REFINE_BAND` of the largest and those of its two
    neighbours farther from it than :data:`REFINE_SPACING` of the cycle (or any, while the maximum moved more
    than :data:`REFINE_TOLERANCE` in its last round), all in one LTCA; it stops when nothing is to be added or
    :data:`MAX_ADDED_POSITIONS` are for the stresses and K_Hbeta and :data:`MAX_ADDED_EDGE_POSITIONS` for the
    edges (two budgets: an edge's angles do not take a stress maximum's).  The cycle wraps: the last position
    is the first's mesh state (one pinion pitch on), so the neighbour of either end is the other's, and every
    added angle lies within the asked window.  An added angle that did not converge gives nothing (its values null), as an asked one.

    ``check`` (the JSON's ``positions_check``): the asked ``positions``, whether it was ``refined`` (a
    ``solve_at`` and at least 3 positions), the ``added_positions``, their ``added_pinion_angles_rad``, how
    many of them did not converge, the ``rounds``, and per quantity and member ``asked`` (the maximum over
    the asked positions), ``all`` (over every position) and ``change``: the maximum's relative move in its
    last round, the estimate's uncertainty from the positions (None: not refined); an edge's also ``at_edge``,
    the largest share of ``edge.edge_shares(..., at_edge=True)`` over every position (the top of the sawtooth
    its cells' passage over the edge makes).  An edge's load share is
    followed where its largest reaches :data:`EDGE_REFINE_FLOOR` of the edge rule's limit.  ``added``: (result,
    surface peaks, line loads, edge distances) of each round's LTCA.  ``surface`` (``edge.surface_peaks``),
    ``lines`` ({member: ``face_load.line_loads``}) and ``distances`` (``edge.EdgeDistances``) of
    ``ltca_result`` where known."""
    from .edge import EdgeDistances, surface_peaks
    from .verdict import EDGE_SHARE

    distances = distances or EdgeDistances(ltca_result, geometry)
    if surface is None:
        surface = surface_peaks(ltca_result, geometry, distances=distances)
    if lines is None:
        lines = {m: line_loads(ltca_result, geometry, m) for m in MEMBERS}
    phi = np.asarray(ltca_result.pinion_angle, dtype=float)
    n = phi.size
    values = _position_maxima(ltca_result, geometry, face_width_mm, surface, lines, distances)
    at_edge = _at_edge(ltca_result, geometry, distances, {})
    asked = {key: _peak(v) for key, v in values.items()}
    best, change = dict(asked), dict.fromkeys(values)
    refined = solve_at is not None and n >= 3
    start, pitch = (phi[0], phi[-1] - phi[0]) if n > 1 else (0.0, 1.0)
    angles, added, failed, rounds = [phi], [], 0, 0
    used = {"stresses": 0, "edge_shares": 0}  # the added angles on each budget
    while refined:
        phase = np.mod((np.concatenate(angles) - start) / pitch, 1.0)
        have = np.round(phase, 12) % 1.0
        weight, todo = {"stresses": {}, "edge_shares": {}}, set()
        for key in sorted(values):
            budget = "edge_shares" if key[0] == "edge_load_share" else "stresses"
            if budget == "edge_shares" and not (best[key] or 0.0) >= EDGE_REFINE_FLOOR * EDGE_SHARE:
                continue
            moving = change[key] is not None and change[key] > REFINE_TOLERANCE
            for ph, w in _around_maxima(phase, values[key], 1e-6 if moving else REFINE_SPACING):
                if np.min(np.abs((have - ph + 0.5) % 1.0 - 0.5)) > 1e-9:
                    weight[budget][ph] = max(weight[budget].get(ph, 0.0), w)
                    todo.add(key)
        # each budget its largest weights first; an angle both want is the stresses'
        new = sorted(weight["stresses"], key=lambda p: (-weight["stresses"][p], p))[:MAX_ADDED_POSITIONS - used["stresses"]]
        edge = [p for p in sorted(weight["edge_shares"], key=lambda p: (-weight["edge_shares"][p], p)) if p not in set(new)]
        edge = edge[:MAX_ADDED_EDGE_POSITIONS - used["edge_shares"]]
        used["stresses"] += len(new)
        used["edge_shares"] += len(edge)
        new = np.sort(np.asarray(new + edge, dtype=float))
        if new.size == 0:
            break
        r = solve_at(start + pitch * new)
        rounds += 1
        r_distances = EdgeDistances(r, geometry)
        r_surface = surface_peaks(r, geometry, distances=r_distances)
        r_lines = {m: line_loads(r, geometry, m) for m in MEMBERS}
        added.append((r, r_surface, r_lines, r_distances))
        angles.append(np.asarray(r.pinion_angle, dtype=float))
        failed += int((~np.asarray(r.converged)).sum())
        more = _position_maxima(r, geometry, face_width_mm, r_surface, r_lines, r_distances)
        at_edge = _at_edge(r, geometry, r_distances, at_edge)
        for key in more.keys() - values.keys():  # an edge loaded at an added angle only: 0 at the others
            before = np.concatenate(angles[:-1]).size
            values[key] = np.zeros(before)
            asked[key], best[key], change[key] = 0.0, 0.0, None
        for key in values:
            fill = np.zeros(new.size) if key[0] == "edge_load_share" else np.full(new.size, np.nan)
            values[key] = np.concatenate([values[key], more.get(key, np.where(r.converged, fill, np.nan))])
            now = _peak(values[key])
            d = None if now is None or not best[key] else now / best[key] - 1.0
            if key in todo or (d is not None and d > REFINE_TOLERANCE):
                change[key] = d
            best[key] = now
    quantities = {}
    for (q, m) in values:
        quantities.setdefault(q, {})[m] = {"asked": asked[q, m], "all": best[q, m], "change": change[q, m]}
        if q == "edge_load_share":
            quantities[q][m]["at_edge"] = at_edge.get(m)
    extra = np.concatenate(angles[1:]) if added else np.zeros(0)
    check = {"positions": int(n), "refined": bool(refined), "added_positions": int(extra.size),
             "added_pinion_angles_rad": [float(a) for a in np.sort(extra)], "added_not_converged": failed,
             "rounds": rounds, "tolerance": POSITIONS_TOLERANCE, "refine_tolerance": REFINE_TOLERANCE,
             "refine_spacing": REFINE_SPACING,
             "quantities": quantities}
    return check, tuple(added)


def _at_edge(result, geometry, distances, tops: dict) -> dict:
    """``tops`` ({"member edge": share}) with the largest ``edge.edge_shares(..., at_edge=True)`` of ``result``
    taken in: the top of the cell passage's sawtooth each position estimates (the edge share's positions
    uncertainty, ``verdict.limit_band``)."""
    from .edge import edge_shares

    out = dict(tops)
    for (m, edge), a in edge_shares(result, geometry, distances=distances, at_edge=True).items():
        v = _peak(a)
        key = f"{m} {edge}"
        if v is not None and (out.get(key) is None or v > out[key]):
            out[key] = v
    return out


def _edge_contacts(runs, geometry) -> tuple:
    """Every flank edge whose band carries load (``edge.edge_loads`` by edge) over the ``runs`` ((LTCA result,
    its ``edge.EdgeDistances``): the asked positions and those added between them), each edge's largest share,
    largest first."""
    from .edge import edge_loads

    best = {}
    for result, distances in runs:
        for e in edge_loads(result, geometry, by_edge=True, distances=distances):
            if (e.member, e.edge) not in best or e.share > best[e.member, e.edge].share:
                best[e.member, e.edge] = e
    return tuple(EdgeContact(e.pressure_mpa, e.member, e.edge, e.pinion_angle_rad, e.tooth_pair, e.force_n, e.share,
                             e.band_mm) for e in sorted(best.values(), key=lambda e: -e.share))


def edge_relief_um(spec, member: str, edge: str) -> float:
    """The relief the spec gives that edge (um): tip relief at a tip, end relief at a toe or heel (0 without)."""
    opts = dict(getattr(spec, member).surface_options)
    return float(opts.get("tip_relief_um" if edge == "tip" else "end_relief_um", 0.0) or 0.0)


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
    K_H_beta: float
    K_F_beta: float
    sigma_F_mpa: float
    sigma_H_mpa: float
    safety_bending_iso: float
    safety_pitting_iso: float
    status: str = Validity.OK
    #: method B's inputs (issue 57.8): the section's virtual gear, its mate and the loaded face length
    #: (eps_beta), None where method B had no answer
    virtual: iso6336.CylindricalGear | None = None
    mate: iso6336.CylindricalGear | None = None
    loaded_length_mm: float = math.nan


@dataclass(frozen=True)
class RateInput:
    """What :func:`rate_section` needs besides the section: loads, widths, materials, factors."""

    geometry: object
    flank: str
    torque_nm: float
    face_width_mm: float
    face_load: dict  # member -> FaceLoad
    factors: Factors
    elastic: tuple  # (E_pinion MPa, nu_pinion, E_gear MPa, nu_gear)
    #: member -> K_Hbeta of the tolerance box's percentile (:func:`tolerance_face_load`), None: the face load's
    K_H_beta_box: dict | None = None

    @property
    def face_exponent(self) -> float:
        """N_F of the pair: ISO 6336-1 takes the smaller b/h of the two members."""
        g = self.geometry
        depth = max(g.member(m).tip_height_mm + g.member(m).cutter_addendum_mm for m in MEMBERS)
        return face_factor_exponent(self.face_width_mm, depth)

    def K_H_beta(self, member: str) -> float:
        """K_Hbeta of the member's line load (1 without a loaded position; at least 1), or the tolerance
        box's percentile of it where the rating ran the box."""
        box = None if self.K_H_beta_box is None else self.K_H_beta_box.get(member)
        if box is not None:
            return max(box, 1.0)
        fl = self.face_load[member]
        return 1.0 if fl.K_H_beta is None else max(fl.K_H_beta, 1.0)

    def loaded_length_mm(self, member: str) -> float:
        """The face length the line load covers where it peaks, at most b (the eps_beta of a point contact)."""
        fl = self.face_load[member]
        b = self.face_width_mm
        return b if fl.loaded_length_mm is None else min(fl.loaded_length_mm, b)


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
    loaded = inp.loaded_length_mm(member)
    k_hb = inp.K_H_beta(member)
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
    k_fb = k_hb ** inp.face_exponent
    f = inp.factors
    s_f = sf0 * f.K_A * f.K_v * k_fb
    s_h = sh0 * math.sqrt(f.K_A * f.K_v * k_hb)
    return SectionRating(
        name, float(z_face), bend.virtual_teeth, gear.profile_shift, math.degrees(sg.helix_angle_signed), bend,
        y_beta, sf0, cf, sh0, k_hb, k_fb, s_f, s_h, f.root_strength_mpa(member) / s_f,
        f.contact_strength_mpa(member) / s_h, _validity(bend, pair_loaded), gear, mate, loaded)


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
    return "; ".join(out) if out else Validity.OK


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
        z = "at an unknown face z" if w["face_z_mm"] is None else f"at face z {w['face_z_mm']:.1f} mm"
        h = ("" if w["height_above_root_mm"] is None
             else f", {w['height_above_root_mm']:.2f} mm above the root cone")
        return f"root fillet {z}{h} ({pinion_angle_text(w['pinion_angle_rad'])}, tooth pair {w['tooth_pair']})"

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


def _loaded(pair, load, options: Options, solver):
    """The rating's LTCA of ``load`` (one torque), without the grid-convergence indicator, the root stress
    along the face and the compressive root stress unless ``options.grid_check``.  With the indicator, a grid
    coarser than the default (:data:`ltca.options.DEFAULT_GRID`) either way that the indicator finds not
    converged is raised to the default's counts and solved again (:func:`raised_grid`): the verdict is not taken
    on a grid the run itself shows too coarse (issue 57: 7x11 moved K_Hbeta and the surface peak by 3-6 % from
    every finer grid on random designs, and flipped their status)."""
    from .. import ltca

    if not options.grid_check:
        return ltca.analyze_many(pair, load, options.ltca, solver=solver, convergence=False, along_face=False,
                                 compression=False).results[0][0]
    result = ltca.analyze(pair, load, options.ltca, solver=solver)
    grid = raised_grid(result)
    if grid is None:
        return result
    asked = options.ltca.cells
    raised = ltca.analyze(pair, load, replace(options.ltca, grid=grid), solver=solver)
    why = next((w for w in result.warnings() if w.startswith("grid not converged")), "grid not converged")
    note = (f"{RAISED_GRID_NOTE} from the asked {asked[0]}x{asked[1]} to {grid[0]}x{grid[1]} cells per tooth pair "
            f"(the default's counts): the LTCA's grid-convergence indicator found {asked[0]}x{asked[1]} "
            + why.split(": use a finer")[0].removeprefix("grid "))
    return replace(raised, notes=tuple(raised.notes) + (note,))


#: the start of the note a rating whose grid :func:`raised_grid` raised carries (in its LTCA's notes and its own)
RAISED_GRID_NOTE = "the rating's contact grid raised"


def raised_grid(result) -> tuple | None:
    """The grid (across, along) the rating solves again on when the LTCA ``result``'s grid is coarser than the
    default's counts either way and its grid-convergence indicator finds a converged position not converged:
    each count raised to at least the default's; None where the grid stands (converged, or as fine as the
    default either way)."""
    from ..ltca.options import DEFAULT_GRID

    cells = tuple(result.options.cells)
    raised = tuple(max(c, d) for c, d in zip(cells, DEFAULT_GRID))
    if raised == cells:
        return None
    converged = result.convergence.converged() | ~result.converged
    return None if converged.all() else raised


def ltca_case(pair, load, options: Options | None = None):
    """(error set (5,), torque N m) of the LTCA :func:`analyze` runs for ``load`` (one torque) with ``options``
    of ``grid_check=False``: the load case's errors at K_A K_v T, with the leave-outs of the tolerance box's
    calls (``ltca.studies.box_results``), so that a caller may run it in a batch of its own and pass it as
    ``ltca_result`` (optimize's candidate: in its box's call); None where the rating's LTCA is not one such
    case: with the grid check, or where K_v is ISO's method B (the LTCA at K_A T gives the mesh stiffness that
    sets K_v: two LTCAs, the second's torque known after the first)."""
    load = _one_torque(load)
    options = Options() if options is None else options
    spec = pair.spec
    factors = Factors.from_spec(spec).with_strength(spec, pair.geometry, options.flank)
    if options.grid_check or factors.K_v_source == "method B":
        return None
    return load.error_sets(pair)[0], load.torque_nm * (factors.K_A * factors.K_v)


def analyze(pair, load, options: Options | None = None, *, solver=None, ltca_result=None, face_points: int = 0,
            progress=None):
    """Rate ``pair`` under ``load`` (an ``ltca.LoadCase``: one pinion torque, N m, and the assembly errors,
    None: the pair's); ``options`` a :class:`Options` (None: the defaults); ``ltca_result``: an LTCA already
    run at K_A K_v T (else it is run here); ``face_points`` > 0 adds that many ISO sections along each face
    (plot); ``progress(done, total, what)`` after each chunk of the tolerance box, if it runs."""
    from .. import ltca
    from .report import RatingResult

    load = _one_torque(load)
    options = Options() if options is None else options
    if not isinstance(options, Options):
        raise TypeError(f"rating.analyze(pair, load, options=None, *, solver=None) needs a rating.Options or None, "
                        f"not {type(options).__name__}")

    spec, geom = pair.spec, pair.geometry
    factors = Factors.from_spec(spec).with_strength(spec, geom, options.flank)
    b = min(geom.pinion.face_width_mm, geom.gear.face_width_mm)
    mat = ltca.Material.from_spec(spec)
    elastic = (mat.pinion_e_mpa, mat.pinion_nu, mat.gear_e_mpa, mat.gear_nu)
    dyn = None
    if ltca_result is None:
        from ..solver import Solver

        solver = solver or Solver()
        if options.root_stress_check:  # the FE data of the LTCA and of the check's same window from one solve
            prepare(pair, options.ltca, getattr(options.ltca, "material", None) or mat)
        if factors.K_v_source == "method B":
            # the mesh stiffness at K_A T (ISO's c' is that of the load K_A F_t), then the local stresses at K_A K_v T
            first = _loaded(pair, load.at(load.torque_nm * factors.K_A), options, solver)
            dyn, factors = _with_dynamic_factor(pair, load, options, factors, loaded_contact(first, geom, b), elastic)
        ltca_result = _loaded(pair, load.at(load.torque_nm * (factors.K_A * factors.K_v)), options, solver)
    solve_at = None
    if options.refine_positions:
        def solve_at(angles):
            return ltca.analyze_many(pair, load.at(ltca_result.torque_nm), replace(ltca_result.options, angles=angles),
                                     solver=solver, convergence=False, along_face=False, compression=False).results[0][0]
    lc = loaded_contact(ltca_result, geom, b, solve_at)
    conv = (root_stress_convergence(pair, ltca_result, getattr(ltca_result.options, "material", None) or mat)
            if options.root_stress_check else {})
    if conv:
        lc = replace(lc, root_stress_convergence=conv, notes=lc.notes + tuple(convergence_notes(conv)))
    if lc.edges:
        edges = tuple(replace(e, relief_now_um=edge_relief_um(spec, e.member, e.edge)) for e in lc.edges)
        lc = replace(lc, edge=edges[0], edges=edges)
    if factors.K_v_source == "method B" and dyn is None:  # the caller's LTCA: its own stiffness
        dyn, factors = _with_dynamic_factor(pair, load, options, factors, lc, elastic)
    samples = spec.rating.tolerance_samples if options.tolerance_samples is None else options.tolerance_samples
    box = None
    if samples:
        kh = lc.positions_check.get("quantities", {}).get("K_H_beta", {})
        refinement = {m: kh[m]["all"] / kh[m]["asked"] for m in kh if kh[m]["asked"] and kh[m]["all"]}
        box = tolerance_face_load(pair, load.at(load.torque_nm * (factors.K_A * factors.K_v)), options, samples,
                                  lc.face_load, solver=solver, progress=progress, refinement=refinement)
    inp = RateInput(geom, options.flank, load.torque_nm, b, lc.face_load, factors, elastic,
                    None if box is None else {m: box["members"][m]["rated"] for m in MEMBERS})
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
            None if p is None or not p > 0.0 else factors.contact_strength_mpa(member) / p, face)
    notes = factors.notes() + [n for n in ltca_result.notes if n.startswith(RAISED_GRID_NOTE)] + list(lc.notes)
    notes += [f"{m.member} {k}: {s.status}" for m in members.values() for k, s in m.sections.items() if s.status != Validity.OK]
    for member in MEMBERS:
        fl = lc.face_load[member]
        if fl.K_H_beta is None:
            notes.append(f"{member}: no loaded position in the LTCA: K_H_beta = K_F_beta = 1 on the full face width")
        elif fl.K_H_beta < 1.0:
            notes.append(f"{member}: the line load's peak is {fl.K_H_beta:.3f} of its mean over b = {b:g} mm (the "
                         "contact is longer than the common face width): K_H_beta = 1")
    if dyn is not None:
        notes += dynamic_notes(dyn)
    if lc.edge_pressure_max_mpa is not None:
        notes.append(f"edge contact: the largest edge cell pressure is {lc.edge_pressure_max_mpa:.0f} MPa (singular, "
                     "grid-dependent; not in S_H); the edge-contact rule of the verdict judges the load within a "
                     "band of the edge instead" + ("" if lc.edge is None else f" ({lc.edge.where})"))
    if box is not None:
        notes.append(f"K_H_beta (and K_F_beta = K_H_beta^N_F) of the ISO sections: the {BOX_PERCENTILE:g}th percentile "
                     f"of {box['sets']} error sets of the tolerance box (seed {box['seed']}) about the load case's "
                     "errors; the local stresses and the loaded face length stay those of the load case's errors")
    return RatingResult(load.torque_nm, options.flank, members, lc, factors, tuple(notes), dyn,
                        scuffing_tribology(pair, ltca_result), pair=pair, options=options, tolerance_box=box)


def tolerance_face_load(pair, load, options: Options, samples: int, nominal_face_load: dict, *, solver=None,
                        progress=None, refinement=None) -> dict:
    """K_Hbeta over the tolerance box under load: ``samples`` error sets drawn by ``sweep.draw_errors``
    (half-widths ``options.tolerances`` over ``assembly_errors.DEFAULT_RANGES``, seed
    ``options.tolerance_seed``) about ``load``'s errors (the pair's where it has none), each a full LTCA
    at ``load``'s torque through ``ltca.studies.box_results`` (the one loop of the box, chunk by chunk
    for ``progress``), and each member's :func:`face_load` of it.  Returns {"samples", "sets" (with a
    K_Hbeta), "seed", "percentile", "tolerances", "members": member -> {"nominal", "p50", "p90", "max",
    "rated" (the percentile times "refinement_factor", None without a set), "refinement_factor", "K_H_beta" per
    set (None where no position loaded)}}.  Each set's K_Hbeta is read at the asked positions alone (a
    refinement between positions per set would cost a rating each); ``refinement`` {member: the load case's
    K_Hbeta refined over asked, :func:`refine_positions`} scales the percentile the ISO sections take (1 where
    not given)."""
    from .. import assembly_errors, sweep
    from ..errors import OptionError
    from ..ltca import studies

    geom = pair.geometry
    b = min(geom.pinion.face_width_mm, geom.gear.face_width_mm)
    nominal = assembly_errors.from_layout(load.error_sets(pair)[0])
    ranges = dict(assembly_errors.DEFAULT_RANGES, **(options.tolerances or {}))
    for key, half in ranges.items():
        limit = assembly_errors.BY_KEY[key].limit
        if abs(nominal[key]) + half > limit:
            raise OptionError("tolerances", {key: half}, f"about the errors' {key} = {nominal[key]:g} it reaches "
                                                         f"{abs(nominal[key]) + half:g}; |nominal| + half-width must "
                                                         f"be <= {limit:g}")
    draws = sweep.draw_errors(samples, ranges=ranges, seed=options.tolerance_seed, nominal=nominal)
    rows = []
    for start in range(0, samples, studies.CHUNK_SETS):
        rows += studies.box_results(pair, load.at(errors=draws[start:start + studies.CHUNK_SETS]), options.ltca,
                                    solver=solver)
        if progress is not None:
            progress(len(rows), samples, "error sets")
    members = {}
    for m in MEMBERS:
        per_set = [face_load(row[0], geom, m, b).K_H_beta for row in rows]
        values = np.asarray([k for k in per_set if k is not None and math.isfinite(k)], dtype=float)
        factor = float((refinement or {}).get(m, 1.0))
        stats = ({"p50": None, "p90": None, "max": None, "rated": None} if values.size == 0 else
                 {"p50": float(np.percentile(values, 50)), "p90": float(np.percentile(values, 90)),
                  "max": float(values.max()), "rated": float(np.percentile(values, BOX_PERCENTILE)) * factor})
        members[m] = {"nominal": nominal_face_load[m].K_H_beta, **stats, "refinement_factor": factor,
                      "K_H_beta": [None if k is None or not math.isfinite(k) else float(k) for k in per_set]}
    sets = min(sum(k is not None for k in members[m]["K_H_beta"]) for m in MEMBERS)
    return {"samples": int(samples), "sets": int(sets), "seed": int(options.tolerance_seed),
            "percentile": BOX_PERCENTILE, "tolerances": {k: float(v) for k, v in ranges.items()},
            "nominal_errors": nominal, "members": members}


def scuffing_tribology(pair, ltca_result):
    """The tribology of the rated loaded contact (K_A K_v T) at [rating] pinion_speed_rpm when the file
    has a [lubricant] (the verdict's scuffing criterion), else None."""
    spec = pair.spec
    if not spec.lubricant.given or spec.rating.pinion_speed_rpm is None:
        return None
    from .. import tribology

    return tribology.evaluate(ltca_result, pair, spec.rating.pinion_speed_rpm)


def _with_dynamic_factor(pair, load, options, factors, lc, elastic):
    """(DynamicFactor or None, factors with its K_v); K_v = 1 ("not computed") without a mesh stiffness."""
    if lc.mesh_stiffness_n_per_um is None:
        return None, replace(factors, K_v=1.0, K_v_source="not computed")
    dyn = dynamic_factor(pair, load, options, factors, lc, elastic)
    return dyn, replace(factors, K_v=dyn.K_v)


def mesh_stiffness_per_face_width(mesh_stiffness_n_per_um: float, pinion: iso6336.CylindricalGear,
                                  face_width_mm: float) -> float:
    """ISO's c_gamma_alpha from the LTCA, N/(mm um): the normal mesh stiffness (normal load over normal
    approach) k cos^2 beta_b1 / b, ``pinion`` the pinion's middle virtual gear (the normal's moment arm
    about its axis is r_b1 cos beta_b1: load and approach both go to its transverse plane)."""
    return mesh_stiffness_n_per_um * math.cos(pinion.base_helix_angle) ** 2 / face_width_mm


def dynamic_factor(pair, load, options: Options, factors: Factors, lc: LoadedContact, elastic) -> dynamic.DynamicFactor:
    """K_v by ISO 6336-1 method B (docs/rating.md 4.2) from the pinion speed and the LTCA's mesh stiffness:
    c_gamma_alpha = (mean normal mesh stiffness) cos^2 beta_b1 / b on the pinion's middle virtual gear (its
    transverse plane), the gear's mass referred to it through the ratio (d_b2 -> u d_b1)."""
    spec, geom = pair.spec, pair.geometry
    flank = options.flank
    b = min(geom.pinion.face_width_mm, geom.gear.face_width_mm)
    inp = RateInput(geom, flank, load.torque_nm, b, lc.face_load, factors, elastic)
    p_sec, g_sec = section_gear(geom, "pinion", 0.0, flank), section_gear(geom, "gear", 0.0, flank)
    p1 = p_sec.gear
    pair_v = iso6336.CylindricalPair(p1, mate_gear(geom, p_sec, flank), inp.loaded_length_mm("pinion"))
    eps_a, eps_b = pair_v.transverse_contact_ratio, pair_v.overlap_ratio
    c_gamma = mesh_stiffness_per_face_width(lc.mesh_stiffness_n_per_um, p1, b)
    c_prime = c_gamma / iso6336.mesh_to_single_stiffness(eps_a)
    z1, z2 = geom.pinion.teeth, geom.gear.teeth
    u = z2 / z1
    d_m, rho, q = {}, {}, {}
    for m, sec in (("pinion", p_sec), ("gear", g_sec)):
        root_d = 2 * float(sections.section(geom, m, 0.0).root_radius)
        d_m[m] = (sec.gear.tip_diameter_mm + root_d) / 2
        q[m] = getattr(spec, m).bore_diameter_mm / d_m[m]
        rho[m] = materials.MATERIALS[factors.material[m]["type"]].density_kg_per_mm3
    d_b1 = p1.base_diameter_mm
    m_red = dynamic.reduced_mass_kg_per_mm(d_m["pinion"], d_b1, q["pinion"], rho["pinion"],
                                           d_m["gear"], u * d_b1, q["gear"], rho["gear"])
    d1 = p1.reference_diameter_mm
    f_t = 1000.0 * load.torque_nm / (d1 / 2)
    n1 = spec.rating.pinion_speed_rpm
    v, _ = pitch_line_velocity_m_s(geom, flank, n1)  # the v of Z_v too
    f_pt, f_fa = dynamic.accuracy_deviations_um(spec.rating.accuracy_grade, geom.normal_module_mm,
                                                max(d1, g_sec.gear.reference_diameter_mm))
    f_pb = f_pt * math.cos(p1.transverse_pressure_angle)
    y_p = y_f = 0.0
    for m in MEMBERS:
        group = materials.MATERIALS[factors.material[m]["type"]].running_in
        y_p += dynamic.running_in_um(group, f_pb, factors.contact_limit_mpa[m], v) / 2
        y_f += dynamic.running_in_um(group, f_fa, factors.contact_limit_mpa[m], v) / 2
    relief = max(dict(getattr(spec, m).surface_options).get("tip_relief_um", 0.0) for m in MEMBERS)
    c_a = relief if relief > 0 else sum(dynamic.tip_relief_running_in_um(factors.contact_limit_mpa[m])
                                        for m in MEMBERS) / 2
    return dynamic.dynamic_factor(dynamic.MeshDynamics(n1, z1, c_gamma, c_prime, m_red, factors.K_A * f_t / b,
                                                       f_pb - y_p, f_fa - y_f, c_a, eps_a + eps_b))


def dynamic_notes(d: dynamic.DynamicFactor) -> list:
    out = [f"K_v = {d.K_v:.4f} (ISO 6336-1 method B, {d.region}: N = {d.resonance_ratio:.3f}, n_E1 = "
           f"{d.resonance_speed_rpm:.0f} rpm, c_gamma_alpha = {d.c_gamma_alpha_n_per_mm_um:.2f} N/(mm um) from the "
           "LTCA's mesh stiffness)"]
    if d.region == "main resonance":
        out.append("the pinion speed is in the main resonance range of ISO 6336-1 (N_S < N <= 1.15): avoid it")
    if d.K_v < 1.0:
        out.append(f"K_v = {d.K_v:.3f} < 1 (super-critical range, ISO 6336-1 method B as it stands)")
    return out
