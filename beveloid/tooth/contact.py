"""Contact ratio and interference of the aligned pair, per flank, from the TCA with edge contact.

Definitions (docs/validation.md, "The whole tooth"):

* A tooth pair is **in contact** at a pinion angle phi'_1 when the TCA of that pair (surface, edge
  or corner contact, ``tca.solve_grid``, no errors) has a contact *and* that contact carries the
  envelope of the neighbouring pairs: pair k at phi'_1 is pair 0 at phi'_1 - k 2pi/N1, and the pair
  whose transmission error constrains the gear most (``tca.first_touch_sign``) carries it, within
  the tolerance ``tca.mesh_flank`` uses (1e-12 rad + 1e-9 |TE|).  Alone, a pair can always be
  brought into (edge) contact by turning the gear: only the envelope says whether it touches.
* The **contact ratio** is the length of the pinion-angle interval around the pitch point during
  which pair 0 is in contact, divided by the pinion's angular pitch 2pi/N1.  Its ends are found
  by bisection (28 halvings: ~1e-10 rad) between grid angles 2pi/(N1 ``per_pitch``) apart.
* **Interference**: the mating tip reaches the fillet, i.e. on the pair's contact (within that
  interval) a contact point lies on a member's flank below its true form limit (``profile.form_limit``:
  the junction with the fillet, or the top of an undercut; measured as l - l_form < -1e-9 mm along the
  rack edge), or a form limit of the TCA's blank carries or ends the contact.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..result import Frozen
from .. import tca
from ..generated import tca_kernels
from ..solver import Solver
from ..status import Status, carries_numbers
from . import fillet as fillet_kernels
from . import profile, sections

class NoContact(RuntimeError):
    """The contact ratio cannot be measured: no contact at the pitch point, or over too many pitches."""


#: a contact point this far (mm, along the rack edge) below the true form limit is interference
FORM_TOL_MM = 1e-9

FORM_LIMITS = tuple(i for i, n in enumerate(tca_kernels.CONTACT_BOUNDARIES) if n.endswith("form limit"))


@dataclass(frozen=True)
class FlankContact(Frozen):
    flank: str
    contact_ratio: float
    start_rad: float  # pinion angle phi'_1 where pair 0's contact starts / ends
    end_rad: float
    #: where the contact starts and ends: the boundary it crosses there (tca_kernels.CONTACT_BOUNDARIES)
    start_boundary: str
    end_boundary: str
    interference: tuple  # names of the form limits the mating tip reaches (empty: none)
    #: per member: the smallest l - l_form (mm) over the contact's points (< 0: below the form limit;
    #: None: the form limit could not be found in any of their sections)
    form_margin_mm: dict = None


def _pair0(geom, flank, phi, solver):
    sol = tca.solve_grid(geom, flank, np.zeros(5), np.asarray(phi, dtype=float), solver=solver)
    return sol.x[0], sol.status[0], sol.boundary[0], sol.active[0]


def _te(geom, flank, x, status, phi, solver):
    ref = tca.reference_contact(geom, flank, solver.options)  # the Solver's tolerances
    n1, n2 = geom.pinion.teeth, geom.gear.teeth
    te = tca.unknowns(x).gear_angle_rad - tca.unknowns(ref.x).gear_angle_rad + (n1 / n2) * (phi - ref.pinion_angle)
    return np.where(carries_numbers(status), te, np.nan)


def _carries(te0, te_k, sign):
    """Pair 0 carries the envelope of itself and the pairs whose TE are te_k (..., K)."""
    both = np.concatenate([te0[..., None], te_k], axis=-1)
    fill = -np.inf if sign > 0 else np.inf
    env = (np.max if sign > 0 else np.min)(np.where(np.isnan(both), fill, both), axis=-1)
    with np.errstate(invalid="ignore"):
        return np.isfinite(te0) & (np.abs(te0 - env) <= 1e-12 + 1e-9 * np.abs(env))


class _Path:
    """Pair 0 and its neighbours at arbitrary pinion angles."""

    def __init__(self, geom, flank, neighbours, solver):
        self.geom, self.flank, self.solver = geom, flank, solver
        self.p1 = geom.pitch_angles[0]
        self.ks = np.array([k for k in range(-neighbours, neighbours + 1) if k != 0])
        self.sign = tca.first_touch_sign(geom, flank)

    def at(self, phi):
        """(in contact, x, status, boundary, active) of pair 0 at one angle."""
        angles = np.concatenate([[phi], phi - self.ks * self.p1])
        x, st, bnd, act = _pair0(self.geom, self.flank, angles, self.solver)
        te = _te(self.geom, self.flank, x, st, angles, self.solver)
        return bool(_carries(te[:1], te[None, 1:], self.sign)[0]), x[0], st[0], bnd[0], act[0]


def _refine(path, inside, outside, steps=28):
    """Bisect between an angle in contact and one not; returns the last state in contact."""
    state = path.at(inside)
    for _ in range(steps):
        mid = 0.5 * (inside + outside)
        s = path.at(mid)
        if s[0]:
            inside, state = mid, s
        else:
            outside = mid
    return inside, state


def _end_boundary(state):
    """The boundary pair 0's contact leaves through: the carrying one at an edge contact, else the nearest."""
    _, _, status, boundary, active = state
    names = tca_kernels.CONTACT_BOUNDARIES
    if status == Status.EDGE and active[0] >= 0:
        return names[active[0]]
    return names[boundary] if boundary >= 0 else ""


def flank_contact(geom, flank, per_pitch=24, span_pitches=3, neighbours=2, *, solver=None) -> FlankContact:
    """Contact ratio and interference of one flank of the aligned pair (see the module docstring),
    solved by ``solver`` (a :class:`beveloid.solver.Solver`; None: the default)."""
    solver = Solver.of(solver)
    path = _Path(geom, flank, neighbours, solver)
    p1, ref = path.p1, tca.reference_contact(geom, flank, solver.options).pinion_angle
    n = span_pitches + neighbours
    idx = np.arange(-n * per_pitch, n * per_pitch + 1)
    phi = ref + idx * (p1 / per_pitch)
    x, st, bnd, act = _pair0(geom, flank, phi, solver)
    te = _te(geom, flank, x, st, phi, solver)
    central = np.nonzero(np.abs(idx) <= span_pitches * per_pitch)[0]
    shifts = np.array([k * per_pitch for k in path.ks])
    te_k = te[central[:, None] - shifts[None, :]]
    inc = _carries(te[central], te_k, path.sign)
    c0 = int(np.nonzero(idx[central] == 0)[0][0])
    if not inc[c0]:
        raise NoContact(f"{flank} flank: the aligned pair carries no contact at its pitch point")
    lo, hi = c0, c0
    while lo > 0 and inc[lo - 1]:
        lo -= 1
    while hi < len(central) - 1 and inc[hi + 1]:
        hi += 1
    if lo == 0 or hi == len(central) - 1:
        raise NoContact(f"{flank} flank: contact over more than {span_pitches} pinion pitches on either side")
    start, s_state = _refine(path, phi[central[lo]], phi[central[lo - 1]])
    end, e_state = _refine(path, phi[central[hi]], phi[central[hi + 1]])
    # form limits carrying contact on the interval, or where the contact ends
    carrying = act[central[lo:hi + 1]].ravel()
    reached = {tca_kernels.CONTACT_BOUNDARIES[i] for i in carrying if i in FORM_LIMITS}
    ends = (_end_boundary(s_state), _end_boundary(e_state))
    reached |= {b for b in ends if b.endswith("form limit")}
    # contact points below the true form limit (fillet junction or top of the undercut)
    xs = np.concatenate([x[central[lo:hi + 1]], [s_state[1], e_state[1]]])
    p1_pts, p2_pts = tca.contact_points(geom, flank, xs)
    margins = {}
    for member, l_col, pts in (("pinion", 0, p1_pts), ("gear", 2, p2_pts)):
        margin = xs[:, l_col] - form_limit_l(geom, member, flank, pts[:, 2])
        margins[member] = float(np.min(margin[np.isfinite(margin)])) if np.isfinite(margin).any() else None
        if margins[member] is not None and margins[member] < -FORM_TOL_MM:
            reached.add(f"{member} form limit")
    return FlankContact(flank, float((end - start) / p1), float(start), float(end), ends[0], ends[1],
                        tuple(sorted(reached)), margins)


def form_limit_l(geom, member, flank, z, samples=9):
    """l_form (mm) of the flank at axial positions z (S_i): l_t of the tip round, or, where the section is
    undercut, the top of the undercut (``profile.form_limit`` on ``samples`` sections across the contact's
    z range, interpolated); NaN where a section has no form limit (no involute up to the tip)."""
    z = np.asarray(z, dtype=float)
    l_t = float(fillet_kernels.tip_round(geom, member).junction_l)
    cut = getattr(sections.section(geom, member, sections.face_z(geom, member, z)), f"undercut_depth_{flank}")
    if not np.any(cut > 0):
        return np.full(z.shape, l_t)
    zs = np.linspace(z.min(), z.max(), samples)
    forms = [profile.form_limit(geom, member, flank, zz) for zz in zs]
    lf = np.array([np.nan if f is None else f.l_mm for f in forms])
    return np.interp(z, zs, lf) if samples > 1 and z.max() > z.min() else np.full(z.shape, lf[0])
