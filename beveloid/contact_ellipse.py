"""Instantaneous contact ellipses and the bearing pattern of an unloaded TCA (issue 11).

At a contact the two flanks separate by ``1/2 x^T H x`` along the contact normal, x in the
common tangent plane (:func:`beveloid.curvature.relative_curvature`).  For an elastic
approach delta (default 0.00632 mm, the paint-layer value of Litvin's TCA) the contact
ellipse is where that separation equals delta:

* semi-axes ``a = sqrt(2 delta / lambda_min) >= b = sqrt(2 delta / lambda_max)``, lambda the
  eigenvalues of H, untruncated;
* the major axis: the eigenvector of lambda_min, given as an angle in degrees in (-90, 90] from
  ``e1`` toward ``e2`` of the tangent basis (``e1`` = the pinion axis +z_1 projected on the
  tangent plane, ``e2 = n_1 x e1``, n_1 the pinion's outward normal, all in S_f);
* the truncated length: the chord of the major axis that lies inside both flanks (each
  member's surface points over the axis, held against the generated flank margins), at most 2a.

Near line contact lambda_min -> 0.  When ``lambda_min <= FLAT_RATIO * lambda_max`` the
semi-axes are not reported (status "line contact"); the truncated length is then the whole
chord across both flanks.  When lambda_max <= 0 the flanks do not bear on each other to second
order, or they cross (lambda_min < -FLAT_RATIO lambda_max: status "no ellipse").  Nothing here is ever NaN or inf in the JSON: a missing number is
null with its status beside it.
"""
from __future__ import annotations

import math
import typing
from dataclasses import dataclass, replace

import numpy as np

from . import curvature
from .result import Frozen
from .solver.core import GEAR_ANGLE, GEAR_L, GEAR_U, PINION_L, PINION_U
from .solver.records import ChordRequest
from .status import EllipseStatus, Status, carries_numbers

DEFAULT_APPROACH_MM = 0.00632
#: lambda_min / lambda_max below this is a line contact: the major semi-axis would be more than
#: ~3e4 minor semi-axes, beyond any flank, and lambda_min is at the round-off level of H.
FLAT_RATIO = 1e-9
APPROACH_RANGE_MM = (1e-6, 1.0)
STATUSES = tuple(EllipseStatus)
#: the chord search's samples along the cap and its halvings of the last bracket
CHORD_SAMPLES = 40
CHORD_BISECTIONS = 30


def check_approach(approach_mm, name="approach_mm", scale=1.0, unit="mm"):
    """The approach in mm, or :class:`beveloid.errors.OptionError` naming ``name`` and what is valid (the
    value shown times ``scale``, in ``unit``)."""
    from .errors import OptionError

    lo, hi = APPROACH_RANGE_MM
    v = float(approach_mm)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise OptionError(name, v * scale, f"must be a number from {lo * scale:g} to {hi * scale:g} {unit}")
    return v


@dataclass(frozen=True)
class ContactEllipses(Frozen):
    """Contact ellipses at n points (NaN where a number is not defined; ``status`` says why);
    frozen, its JSON by :meth:`to_json`."""

    approach_mm: float
    errors: np.ndarray  # (n, 5) the error sets of the points
    status: tuple  # one of STATUSES per point
    semi_axes_mm: np.ndarray  # (n, 2) [a, b], untruncated
    major_axis_deg: np.ndarray  # (n,) from e1 toward e2
    major_axis: np.ndarray  # (n, 3) unit major-axis direction in S_f
    truncated_mm: np.ndarray  # (n, 2) chord inside both flanks along -major / +major from the contact
    eigenvalues: np.ndarray  # (n, 2) lambda_min, lambda_max of H [1/mm]
    point: np.ndarray  # (n, 3) contact point in S_f [mm]
    basis: np.ndarray  # (n, 2, 3) tangent basis e1, e2 in S_f

    @property
    def truncated_length_mm(self):
        return self.truncated_mm.sum(axis=-1)

    def to_json(self) -> dict:
        num = lambda v: float(v) if np.isfinite(v) else None  # noqa: E731
        ab = [[float(a), float(b)] if np.isfinite(a) and np.isfinite(b) else None for a, b in self.semi_axes_mm]
        return {
            "contact_ellipse_semi_axes_mm": ab,
            "contact_ellipse_major_axis_deg": [num(v) for v in self.major_axis_deg],
            "contact_ellipse_truncated_length_mm": [num(v) for v in self.truncated_length_mm],
            "contact_ellipse_status": list(self.status),
        }


class MemberFrame(typing.NamedTuple):
    """A member at n contacts: its placement in S_f and its flank parameters there."""

    rotation: np.ndarray  # (n, 3, 3) L
    translation: np.ndarray  # (n, 3) t
    l: np.ndarray  # noqa: E741  (n,) mm
    u: np.ndarray  # (n,) mm

    def rows(self, idx) -> "MemberFrame":
        return self._make(a[idx] for a in self)  # every field, the same rows


def _member_frames(geom, x, pinion_angle, errors):
    """Per member: its :class:`MemberFrame` at the contacts x (n, 5) (tca_kernels.UNKNOWNS)."""
    from .generated import placement

    pair = geom.placement()
    p1 = placement.pinion_placement(pinion_angle, pair)
    p2 = placement.gear_placement(x[:, GEAR_ANGLE], errors, pair)
    return {"pinion": MemberFrame(rotation=p1.rotation, translation=p1.translation, l=x[:, PINION_L], u=x[:, PINION_U]),
            "gear": MemberFrame(rotation=p2.rotation, translation=p2.translation, l=x[:, GEAR_L], u=x[:, GEAR_U])}


def chords(geom, flank, frames, points, bases, directions, caps, solver):
    """Distances (n,) from the contacts ``points`` (n, 3) along the tangent directions ``directions``
    (n, 2) in the bases ``bases`` (n, 2, 3) to the first flank boundary of either member, each at most
    ``caps`` (n,): the solver core's chord search (:func:`beveloid.solver.chord.ellipse_chords`) on
    ``solver``'s backend.  ``frames``: each member's :class:`MemberFrame` at the contacts."""
    members = ("pinion", "gear")
    out = np.empty(points.shape[0])
    c = np.ascontiguousarray
    request = ChordRequest(
        rotations=c(np.stack([frames[w].rotation for w in members]), dtype=float),
        translations=c(np.stack([frames[w].translation for w in members]), dtype=float),
        start_lu=c(np.stack([np.stack((frames[w].l, frames[w].u), axis=-1) for w in members]), dtype=float),
        points=c(points, dtype=float), bases=c(bases, dtype=float), directions=c(directions, dtype=float),
        caps=c(caps, dtype=float), samples=np.linspace(0, 1, CHORD_SAMPLES + 1)[1:], bisections=CHORD_BISECTIONS)
    solver.core.ellipse_chords(geom.problem(flank), request, out)
    return out


def classify(lmin, lmax, valid):
    """One of STATUSES per point from the eigenvalues of H (see the module docstring)."""
    return np.where(~np.asarray(valid, bool), EllipseStatus.NO_CONTACT,
                    np.where((lmax <= 0) | (lmin < -FLAT_RATIO * lmax), EllipseStatus.NO_ELLIPSE,
                             np.where(lmin <= FLAT_RATIO * lmax, EllipseStatus.LINE_CONTACT, EllipseStatus.ELLIPSE)))


def ellipses(geom, flank, x, pinion_angle, errors, valid=None, approach_mm=DEFAULT_APPROACH_MM,
             solver=None) -> ContactEllipses:
    """Contact ellipses at solved contacts x (n, 5) (tca_kernels.UNKNOWNS) for pinion angles (n,)
    and errors (5,) or (n, 5); ``valid`` (n,) marks the points that are contacts.  The chords are
    searched by the solver core on ``solver``'s backend (a :class:`beveloid.solver.Solver`, None: the
    default)."""
    from .solver import Solver

    solver = Solver.of(solver)
    x = np.atleast_2d(np.asarray(x, dtype=float))
    n = x.shape[0]
    phi1 = np.broadcast_to(np.asarray(pinion_angle, dtype=float), (n,))
    errors = np.broadcast_to(np.asarray(errors, dtype=float), (n, 5))
    valid = np.ones(n, bool) if valid is None else np.asarray(valid, bool) & np.all(np.isfinite(x), axis=-1)
    xs = np.where(valid[:, None], x, x[valid][0] if valid.any() else 0.0)  # placeholders keep the kernels finite
    rc = curvature.relative_curvature(geom, flank, xs, phi1, errors)
    lam, V = np.linalg.eigh(rc.H)  # ascending
    lmin, lmax = lam[:, 0], lam[:, 1]
    status = classify(lmin, lmax, valid)
    ok = status == EllipseStatus.ELLIPSE
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(ok, np.sqrt(2 * approach_mm / lmin), np.nan)
        b = np.where(ok | (status == EllipseStatus.LINE_CONTACT), np.sqrt(2 * approach_mm / lmax), np.nan)
    v2 = V[:, :, 0]
    v2 = np.where((v2[:, 0] < 0)[:, None] | ((v2[:, 0] == 0) & (v2[:, 1] < 0))[:, None], -v2, v2)
    ang = np.degrees(np.arctan2(v2[:, 1], v2[:, 0]))
    ang = np.where(ang <= -90, ang + 180, ang)
    has_axis = ok | (status == EllipseStatus.LINE_CONTACT)
    ang = np.where(has_axis, ang, np.nan)
    major = np.einsum("na,nai->ni", v2, rc.basis)
    # the chord: at most a; a line contact is cut by the flanks alone
    reach = 2.0 * (geom.pinion.face_width_mm + geom.gear.face_width_mm)
    cap = np.where(ok, np.minimum(a, reach), reach)
    trunc = np.full((n, 2), np.nan)
    if has_axis.any():
        idx = np.nonzero(has_axis)[0]
        frames = {k: fr.rows(idx) for k, fr in _member_frames(geom, xs, phi1, errors).items()}
        for col, sign in ((0, -1.0), (1, 1.0)):
            trunc[idx, col] = chords(geom, flank, frames, rc.point[idx], rc.basis[idx], sign * v2[idx], cap[idx],
                                     solver)
    return ContactEllipses(approach_mm, np.array(errors), [str(s) for s in status], np.stack([a, b], axis=-1), ang,
                           np.where(has_axis[:, None], major, np.nan), trunc, lam, rc.point, rc.basis)


def flank_ellipses(geom, fr, errors, approach_mm=DEFAULT_APPROACH_MM, solver=None) -> ContactEllipses:
    """Contact ellipses at every point of a :class:`beveloid.tca.FlankResult` (pair 0's unknowns at
    the shifted pinion angles: the configuration in S_f is the same as pair k's)."""
    phi1 = fr.pinion_angle - fr.tooth_pair * geom.pitch_angles[0]
    valid = carries_numbers(np.asarray([Status[s.upper()] for s in fr.status]))
    return ellipses(geom, fr.flank, fr.unknowns, phi1, errors, valid, approach_mm, solver)


def with_ellipses(result, approach_mm=DEFAULT_APPROACH_MM, *, solver=None):
    """A new :class:`beveloid.tca.TCAResult` whose flanks carry their contact ellipses at the
    elastic approach (mm), their chords searched by ``solver``; ``result`` is not changed."""
    flanks = {k: replace(fr, contact_ellipse=flank_ellipses(result.geometry, fr, result.errors, approach_mm, solver))
              for k, fr in result.flanks.items()}
    return replace(result, flanks=flanks, approach_mm=approach_mm)


def ellipse_outline(ce: ContactEllipses, i, n=48, truncate=True):
    """Points (n, 3) in S_f of ellipse i's outline (semi-axes a, b about the contact point in the
    tangent plane), its major axis clipped to the truncated chord when ``truncate``."""
    a, b = ce.semi_axes_mm[i]
    lo, hi = ce.truncated_mm[i]
    if not np.isfinite(b):
        return None
    if not np.isfinite(a):  # line contact: the chord with the minor width
        a = max(lo, hi)
    t = np.linspace(0, 2 * np.pi, n)
    s = a * np.cos(t)
    if truncate and np.isfinite(lo):
        s = np.clip(s, -lo, hi)
    w = b * np.sin(t)
    major = ce.major_axis[i]
    minor = np.cross(np.cross(ce.basis[i, 0], ce.basis[i, 1]), major)
    return ce.point[i] + s[:, None] * major + w[:, None] * minor
