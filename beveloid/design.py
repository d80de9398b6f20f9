"""Pitch-cone design of a crossed beveloid gear pair (Section 3.4 and Fig. 7 of the paper).

Two procedures, both built on the generated kernels of
``beveloid.generated.design_equations`` (the only place the paper's Eqs 12-27 are
evaluated at run time; this module never imports sympy):

``design(spec) -> DesignResult`` -- the *direct* design (first chart of Fig. 7).
    Inputs (from a :class:`beveloid.spec.DesignSpec`): m_n, alpha_n, delta, E
    (``[pair]``), N1, gamma1, beta1, x_t1 (``[pinion]``), N2, gamma2 (``[gear]``) and the
    blank data (face widths, addendum coefficients, b_c).  The working normal pressure
    angle alpha_nw is the root of ``offset_residual(alpha_nw, ...) = E(alpha_nw) - E``
    (Eq 17 with the working data of Eqs 16, 23, 25, 26), found by a safeguarded
    Newton/bisection iteration with the exact derivative ``residual_D_alpha_nw`` to
    ``|residual| < 1e-11 mm`` (relaxed to 8 ulp of E for E > ~5600 mm; where E(alpha_nw) is so steep
    -- next to the end of the tangency range, E -> 0 -- that alpha_nw reaches floating-point
    resolution first, the attained residual is accepted and a note says so).  The admissible
    interval of alpha_nw is where the kernel is real: ``sin(alpha_nw) > |sin(gamma_i)| sin(alpha_n)``
    (Eq 25), the Eq 26 arcsine and the Eq 16 arccosine (pitch-cone tangency) defined, and
    ``alpha_nw < 60 deg``; it is scanned on a grid for sign changes.  If Eq 17 has several roots
    the one closest to alpha_n is taken and a note says so.  ``direct_design(alpha_nw, ...)``
    then gives every other quantity: gear helix angle beta2 (Eq 26), gear profile shift x_t2
    (Eq 27, backlash free), transverse angular factors (Eqs 22-23), working cone and helix
    angles (Eqs 25, 26, 16), mounting distances (Eqs 13-14), FPD angles (Eqs 18-20).

``indirect_design(spec_like, alpha_nw, pinion_working_cone_angle, gear_working_cone_angle,
pinion_working_helix_angle) -> DesignResult`` -- the *indirect* design (second chart of Fig. 7).
    Inputs: the working data alpha_nw, gamma_w1, gamma_w2, beta_w1 (radians) and, from
    ``spec_like``, m_n, alpha_n, delta, N1, N2, x_t1 and the blank data.  The reference data
    gamma1, gamma2 (Eq 25), beta1, beta2 (Eq 26), beta_w2 (Eq 16), E (Eq 17) and x_t2 (Eq 27)
    are computed; ``spec_like``'s values of ``pair.offset_mm``, ``pinion.cone_angle_deg``,
    ``pinion.helix_angle_deg`` and ``gear.cone_angle_deg`` are ignored (they are outputs) and
    may be omitted when ``spec_like`` is a dict.  ``result.spec`` holds the computed reference
    data, so ``design(result.spec)`` repeats the design the direct way.

Units: lengths in mm, angles in radians everywhere in this module (degrees only in
``beveloid.design_report`` and in messages).  Helix angles are signed (+ right hand).

Feasibility problems raise :class:`DesignError` (a :class:`beveloid.errors.UserError`) with a
one-line message naming the key(s), the value(s), what fails and which way to move, e.g.::

    pair.offset_mm = 10.0: no working normal pressure angle solves Eq 17: the offset is too
    small for the given teeth, module and helix angles (...); increase pair.offset_mm ...

Checks besides the paper's equations (plain numpy geometry in the reference transverse
section, tip radius ``r + x_t m_t + h_a m_n / cos(gamma)``):

* pointed teeth -- transverse tooth thickness at the tip ``<= 0.2 m_n``: an error;
* undercut -- the cutter tip line ``(a - s)/cos(gamma)`` below the pitch circle lies beyond the
  interference point ``r sin^2(alpha_P)`` of a flank (a = cutter addendum, s = rack shift):
  a warning in ``result.notes``;
* a transverse pressure angle (reference or working, either flank, either member) ``<= 0``,
  from the tilted rack ``tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta)``:
  an error (the flank leans past the radial direction; the generated ``alpha_Pw = arccos(xi_t cos(alpha_P))``
  and hence Eq 27 assume ``alpha_P > 0``);
* the pitch point P off the active profile -- in the working-pitch-circle section (z = b_c) the
  working pitch radius must lie between the form circle (where the rack's straight edge starts) and the
  tip circle, for both members and both flanks (:func:`pitch_point_margins`): an error, since the
  design's defining contact at P would not be on the teeth (e.g. alpha_nw = 4.2 deg with a 1 mm offset
  on case 1).  A negative mounting distance d alone is not rejected: with signed cone angles the apex
  may lie on either side of the crossing point;
* a zero cone angle (the cone apex, hence the mounting distance, is at infinity), a gear helix
  angle ``|beta2| >= 80 deg`` and non-finite or non-positive results: errors.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import UserError
from .generated import design_equations as _eq
from .spec import DEFAULT_SOURCE, DesignSpec, SpecError, spec_from_dict, spec_to_dict

__all__ = [
    "DesignError",
    "MemberDesign",
    "DesignResult",
    "design",
    "indirect_design",
    "MAX_WORKING_PRESSURE_ANGLE",
    "MAX_GEAR_HELIX_ANGLE",
    "POINTED_TIP_FACTOR",
    "RESIDUAL_TOLERANCE_MM",
]

#: Upper end of the alpha_nw search interval (rad).
MAX_WORKING_PRESSURE_ANGLE = math.radians(60.0)
#: |beta2| at or above this (rad) is rejected.
MAX_GEAR_HELIX_ANGLE = math.radians(80.0)
#: Teeth whose transverse tip thickness is <= this times m_n are "pointed" (an error).
POINTED_TIP_FACTOR = 0.2
#: Target |E(alpha_nw) - E| of the root finder (mm).
RESIDUAL_TOLERANCE_MM = 1e-11

_GRID_POINTS = 1201
#: the admissibility transitions of the alpha_nw grid are refined by multisection: pieces per pass
#: and passes (64**10 = 2**60: as fine as 60 bisections)
_SECTIONS = 64
_SECTION_PASSES = 10
_EPS = np.finfo(float).eps


class DesignError(UserError):
    """A design request that has no (physical) solution; one line naming key(s) and a direction.

    Attributes: ``detail`` (message without the ``source:`` prefix), ``keys`` (tuple of the
    dotted spec keys concerned, may be empty) and ``source`` (the spec's file, if any).
    """

    def __init__(self, message: str, *, keys: tuple[str, ...] = (), source: str | None = None):
        detail = " ".join(str(message).split())
        full = f"{source}: {detail}" if source and source != DEFAULT_SOURCE else detail
        super().__init__(full)
        self.detail = detail
        self.keys = tuple(keys)
        self.source = source


# ---------------------------------------------------------------------------
# Result types
# ---------------------------------------------------------------------------

#: dataclass field metadata of an angle in radians.
RAD = {"unit": "rad"}


@dataclass(frozen=True)
class MemberDesign:
    """Reference and working data of one member (pinion or gear); radians and mm.

    The single list of a member's design fields: fields marked ``RAD`` are angles (reported in
    degrees with a ``_deg`` suffix by design_report.design_json), ``_mm`` fields lengths, the rest
    dimensionless.
    """

    name: str
    teeth: int
    normal_module_mm: float
    helix_angle: float = field(metadata=RAD)
    cone_angle: float = field(metadata=RAD)
    profile_shift: float
    transverse_angular_factor: float
    mounting_distance_mm: float
    working_mounting_distance_mm: float
    working_cone_angle: float = field(metadata=RAD)
    working_helix_angle: float = field(metadata=RAD)
    working_pitch_radius_mm: float
    reference_pitch_radius_mm: float
    transverse_pressure_angle_left: float = field(metadata=RAD)
    transverse_pressure_angle_right: float = field(metadata=RAD)
    working_transverse_pressure_angle_left: float = field(metadata=RAD)
    working_transverse_pressure_angle_right: float = field(metadata=RAD)
    fpd_angle_left: float = field(metadata=RAD)
    fpd_angle_right: float = field(metadata=RAD)
    pitch_point_angle: float = field(metadata=RAD)
    face_width_mm: float
    addendum_coefficient: float
    cutter_addendum_coefficient: float
    reference_section_offset_mm: float

    @property
    def transverse_module_mm(self) -> float:
        """m_t = m_n / cos(beta)."""
        return self.normal_module_mm / math.cos(self.helix_angle)

    @property
    def rack_shift_mm(self) -> float:
        """Rack shift along its own (tilted) depth axis: x_t m_n cos(gamma) / cos(beta)."""
        return self.profile_shift * self.normal_module_mm * math.cos(self.cone_angle) / math.cos(self.helix_angle)

    @property
    def cutter_addendum_mm(self) -> float:
        """Cutter addendum a = cutter_addendum_coefficient * m_n (this member's dedendum)."""
        return self.cutter_addendum_coefficient * self.normal_module_mm

    @property
    def hand(self) -> str:
        """'RH', 'LH' or '' (spur) from the sign of the helix angle."""
        return "RH" if self.helix_angle > 0 else ("LH" if self.helix_angle < 0 else "")


@dataclass(frozen=True)
class DesignResult:
    """Result of :func:`design` or :func:`indirect_design`; radians and mm.

    ``spec`` is the input spec (direct design) or a spec carrying the computed reference data
    (indirect design; its gear helix angle / profile shift stay unset).  The pair-level FPD
    angles are the sums of the members' (Eq 18).
    """

    spec: DesignSpec
    working_normal_pressure_angle: float
    normal_angular_factor: float
    fpd_angle_left: float
    fpd_angle_right: float
    offset_mm: float
    shaft_angle: float
    normal_module_mm: float
    normal_pressure_angle: float
    pinion: MemberDesign
    gear: MemberDesign
    notes: tuple[str, ...] = ()
    #: E(alpha_nw) from Eq 17 minus the required offset (0 for the indirect design).
    offset_residual_mm: float = 0.0
    #: "direct" or "indirect".
    procedure: str = "direct"

    def member(self, name: str) -> MemberDesign:
        """``"pinion"`` or ``"gear"`` (also 1 / 2)."""
        key = {"1": "pinion", "2": "gear"}.get(str(name), str(name).lower())
        if key not in ("pinion", "gear"):
            raise KeyError(f"member {name!r}: must be 'pinion' or 'gear'")
        return getattr(self, key)

    def to_json_dict(self) -> dict[str, Any]:
        """The JSON contract of :func:`beveloid.design_report.design_json`."""
        from .design_report import design_json

        return design_json(self)


# ---------------------------------------------------------------------------
# Kernel plumbing
# ---------------------------------------------------------------------------


def _pair_kwargs(c: dict[str, Any]) -> dict[str, Any]:
    """The design kernels' pair and reference arguments, by name."""
    return dict(normal_module=c["m_n"], normal_pressure_angle=c["alpha_n"], pinion_teeth=c["N1"],
                gear_teeth=c["N2"], shaft_angle=c["delta"], pinion_profile_shift=c["x_t1"],
                pinion_cone_angle=c["gamma1"], gear_cone_angle=c["gamma2"], pinion_helix_angle=c["beta1"])


def _direct(alpha_nw, c: dict[str, Any]) -> dict[str, Any]:
    with np.errstate(all="ignore"):
        return _eq.direct_design(alpha_nw=alpha_nw, **_pair_kwargs(c))._asdict()


def _residual(alpha_nw, c: dict[str, Any]):
    with np.errstate(all="ignore"):
        return _eq.offset_residual(alpha_nw=alpha_nw, offset=c["E"], **_pair_kwargs(c))


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}"


def _num(x: float) -> str:
    return f"{x:.6g}"


# ---------------------------------------------------------------------------
# Direct design
# ---------------------------------------------------------------------------


def _spec_constants(spec: DesignSpec) -> dict[str, Any]:
    p, g1, g2 = spec.pair, spec.pinion, spec.gear
    if g1.helix_angle_deg is None or g1.profile_shift is None:
        raise DesignError("pinion.helix_angle_deg and pinion.profile_shift are required for the direct design",
                          keys=("pinion.helix_angle_deg", "pinion.profile_shift"), source=spec.source)
    return dict(
        m_n=float(p.normal_module_mm), alpha_n=math.radians(p.normal_pressure_angle_deg),
        delta=math.radians(p.shaft_angle_deg), E=float(p.offset_mm),
        N1=int(g1.teeth), N2=int(g2.teeth), x_t1=float(g1.profile_shift),
        gamma1=math.radians(g1.cone_angle_deg), gamma2=math.radians(g2.cone_angle_deg),
        beta1=math.radians(g1.helix_angle_deg),
    )


def _check_cone_angles(spec: DesignSpec, gamma1: float, gamma2: float) -> None:
    for member, g in (("pinion", gamma1), ("gear", gamma2)):
        if g == 0.0:
            key = f"{member}.cone_angle_deg"
            raise DesignError(
                f"{key} = 0.0: a beveloid member needs a non-zero cone angle (with gamma = 0 the pitch cone is a"
                f" cylinder, its apex and the mounting distance of Eqs 13-14 are at infinity);"
                f" increase |{key}| above 0", keys=(key,), source=spec.source)


def _scan(alpha_nw, c: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Residual E(alpha_nw) - E and the admissibility mask (all real, positive working radii)."""
    with np.errstate(all="ignore"):
        res, r_w1, r_w2 = _eq.offset_scan(alpha_nw=np.asarray(alpha_nw, dtype=float), offset=c["E"],
                                          **_pair_kwargs(c))
    ok = np.isfinite(res) & (r_w1 > 0) & (r_w2 > 0)
    return res, ok


def _admissible_grid(c: dict[str, Any]) -> np.ndarray:
    """alpha_nw grid on (lower Eq 25 bound, 60 deg], plus the refined ends of the admissible runs.

    Admissible: the kernel is real (Eqs 16, 25, 26 defined) and both working pitch radii are
    positive (|beta_w| < 90 deg; beyond, Eq 17 passes through a pole and changes sign).
    """
    lo = math.asin(min(1.0, max(abs(math.sin(c["gamma1"])), abs(math.sin(c["gamma2"]))) * math.sin(c["alpha_n"])))
    hi = MAX_WORKING_PRESSURE_ANGLE
    grid = np.linspace(lo, hi, _GRID_POINTS)[1:]
    _, ok = _scan(grid, c)
    # refine every admissible / inadmissible transition (and the open lower end) by bisection
    lefts, rights = [], []
    for i in np.flatnonzero(ok[:-1] != ok[1:]):
        lefts.append(grid[i])
        rights.append(grid[i + 1])
    if ok[0]:
        lefts.append(lo)
        rights.append(grid[0])
    extra: list[float] = []
    if lefts:
        a = np.array(lefts)
        b = np.array(rights)
        fa = _scan(a, c)[1]
        # multisection: each pass cuts every bracket into _SECTIONS and keeps the piece where the
        # admissibility changes first (10 passes of 64 = 60 halvings, in 10 kernel calls, not 60)
        frac = np.arange(_SECTIONS + 1) / _SECTIONS
        rows = np.arange(a.size)
        for _ in range(_SECTION_PASSES):
            pts = a[:, None] + (b - a)[:, None] * frac[None, :]
            pts[:, -1] = b
            differs = _scan(pts.ravel(), c)[1].reshape(pts.shape) != fa[:, None]
            j = np.where(differs.any(axis=1), differs.argmax(axis=1), _SECTIONS)
            j = np.maximum(j, 1)
            a, b = pts[rows, j - 1], pts[rows, j]
        extra = [float(x) for x in np.where(fa, a, b)]  # the admissible end of each transition
    return np.unique(np.concatenate([grid, np.array(extra, dtype=float)]))


def _brackets(grid: np.ndarray, res: np.ndarray, ok: np.ndarray) -> list[tuple[float, float, float, float]]:
    """Sign changes of the residual between neighbouring admissible grid points."""
    out = []
    for i in range(len(grid) - 1):
        if not (ok[i] and ok[i + 1]):
            continue
        ra, rb = res[i], res[i + 1]
        if ra == 0.0:
            out.append((grid[i], grid[i], ra, ra))
        elif (ra < 0.0) != (rb < 0.0) and rb != 0.0:  # signs, not the product: no overflow for huge E
            out.append((grid[i], grid[i + 1], ra, rb))
    if len(res) and ok[-1] and res[-1] == 0.0:
        out.append((grid[-1], grid[-1], 0.0, 0.0))
    return out


def _tolerance(c: dict[str, Any]) -> float:
    return max(RESIDUAL_TOLERANCE_MM, 8.0 * _EPS * abs(c["E"]))


def _solve_bracket(c: dict[str, Any], a: float, b: float, fa: float, fb: float) -> tuple[float, float]:
    """Safeguarded Newton (exact derivative) / bisection on a sign-change bracket.

    Returns (alpha_nw, residual); the residual is NaN if the bracket holds no root
    (a pole rather than a zero: the iteration did not bring |residual| down).
    """
    if a == b:
        return a, fa
    tol = _tolerance(c)
    x = a - fa * (b - a) / (fb - fa)
    if not a < x < b:
        x = 0.5 * (a + b)
    best = (math.inf, x)
    for _ in range(300):
        r, dr = _residual(x, c)
        r, dr = float(r), float(dr)
        if not math.isfinite(r):
            x = 0.5 * (a + b)
            continue
        if abs(r) < best[0]:
            best = (abs(r), x)
        if abs(r) < tol:
            return x, r
        if (r < 0) == (fa < 0):
            a, fa = x, r
        else:
            b, fb = x, r
        if b - a <= 4.0 * _EPS * max(abs(a), abs(b)):
            break
        xn = x - r / dr if (math.isfinite(dr) and dr != 0.0) else math.nan
        if not (a < xn < b) or abs(xn - x) > 0.5 * (b - a):  # outside, or not faster than bisection
            xn = 0.5 * (a + b)
        x = xn
    x = best[1]
    r, dr = (float(v) for v in _residual(x, c))
    # converged to floating-point resolution of alpha_nw (E(alpha_nw) very steep), not a pole?
    resolution = 8.0 * abs(dr) * _EPS * abs(x) if math.isfinite(dr) else 0.0
    ok = abs(r) <= max(1e3 * tol, resolution) and abs(r) <= 1e-6 * max(1.0, abs(c["E"]))
    return (x, r) if ok else (x, math.nan)


def _infeasible_no_root(spec: DesignSpec, c: dict[str, Any], grid: np.ndarray, res: np.ndarray,
                        ok: np.ndarray) -> DesignError:
    src = spec.source
    if not ok.any():
        q = _direct(grid, c)
        gw_ok = np.isfinite(q["gamma_w1"]) & np.isfinite(q["gamma_w2"])
        bw1_ok = gw_ok & np.isfinite(q["beta_w1"])
        tangent = bw1_ok & np.isfinite(q["beta_w2"])
        if gw_ok.any() and not bw1_ok.any():
            return DesignError(
                f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}: the working helix angle of Eq 26"
                f" (sin beta_w1 = sin beta1 cos gamma1 / (xi_n cos gamma_w1)) is not real for any alpha_nw up to"
                f" 60 deg; reduce |pinion.helix_angle_deg|", keys=("pinion.helix_angle_deg",), source=src)
        if tangent.any():
            return DesignError(
                f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}, pair.shaft_angle_deg ="
                f" {spec.pair.shaft_angle_deg!r}: the gear's working helix angle beta_w2 = eta - beta_w1 (Eq 16)"
                f" reaches 90 deg for every alpha_nw up to 60 deg; move pinion.helix_angle_deg toward the shaft"
                f" angle ({'increase' if spec.pinion.helix_angle_deg < spec.pair.shaft_angle_deg else 'reduce'} it)",
                keys=("pinion.helix_angle_deg", "pair.shaft_angle_deg"), source=src)
        return DesignError(
            f"pair.shaft_angle_deg = {spec.pair.shaft_angle_deg!r}: the pitch cones cannot touch"
            f" (sin^2 delta < sin^2 gw1 + sin^2 gw2 + 2 sin gw1 sin gw2 cos delta for every alpha_nw up to 60 deg,"
            f" with pinion.cone_angle_deg = {spec.pinion.cone_angle_deg!r}, gear.cone_angle_deg ="
            f" {spec.gear.cone_angle_deg!r}); increase the shaft angle or reduce the cone angles",
            keys=("pair.shaft_angle_deg", "pinion.cone_angle_deg", "gear.cone_angle_deg"), source=src)
    e_model = _scan(grid[ok], dict(c, E=0.0))[0]  # E(alpha_nw) itself, not E(alpha_nw) - E + E
    a_ok = grid[ok]
    span = (f"Eq 17 gives E from {_num(e_model.min())} to {_num(e_model.max())} mm for alpha_nw from"
            f" {_deg(a_ok.min())} to {_deg(a_ok.max())} deg")
    head = f"pair.offset_mm = {spec.pair.offset_mm!r}: no working normal pressure angle solves Eq 17"
    if (res[ok] > 0).all():
        return DesignError(
            f"{head}: the offset is too small for the given teeth, module and helix angles ({span});"
            f" increase pair.offset_mm to at least {_num(e_model.min())} mm or reduce the teeth or module",
            keys=("pair.offset_mm",), source=src)
    return DesignError(
        f"{head}: the offset is too large for the given teeth, module and helix angles ({span});"
        f" reduce pair.offset_mm to at most {_num(e_model.max())} mm or increase the teeth or module",
        keys=("pair.offset_mm",), source=src)


def _solve_alpha_nw(spec: DesignSpec, c: dict[str, Any]) -> tuple[float, float, list[str]]:
    grid = _admissible_grid(c)
    res, ok = _scan(grid, c)
    roots = [_solve_bracket(c, *br) for br in _brackets(grid, res, ok)]
    roots = [(x, r) for x, r in roots if math.isfinite(r)]
    if not roots:
        raise _infeasible_no_root(spec, c, grid, res, ok)
    roots.sort(key=lambda xr: abs(xr[0] - c["alpha_n"]))
    notes = []
    if len(roots) > 1:
        listed = ", ".join(_deg(x) for x, _ in sorted(roots))
        notes.append(f"Eq 17 has {len(roots)} roots alpha_nw = {listed} deg; chose {_deg(roots[0][0])} deg,"
                     f" the one closest to alpha_n = {_deg(c['alpha_n'])} deg")
    x, r = roots[0]
    if abs(r) >= _tolerance(c):
        notes.append(f"Eq 17 solved only to |E(alpha_nw) - E| = {abs(r):.2g} mm: alpha_nw = {_deg(x)} deg is at"
                     f" floating-point resolution (E(alpha_nw) is very steep there, near the end of the tangency"
                     f" range)")
    return x, r, notes


def design(spec: DesignSpec) -> DesignResult:
    """Direct design (Fig. 7, first chart): solve alpha_nw from Eq 17, then evaluate Eqs 12-27.

    Raises :class:`DesignError` when the request has no physical solution.
    """
    if not isinstance(spec, DesignSpec):
        raise TypeError(f"design() needs a DesignSpec, not {type(spec).__name__} (see beveloid.spec.load_spec)")
    c = _spec_constants(spec)
    _check_cone_angles(spec, c["gamma1"], c["gamma2"])
    alpha_nw, resid, notes = _solve_alpha_nw(spec, c)
    q = {k: float(v) for k, v in _direct(alpha_nw, c).items()}
    return _finish(spec, q, alpha_nw, offset=c["E"], residual=resid, notes=notes, procedure="direct")


# ---------------------------------------------------------------------------
# Indirect design
# ---------------------------------------------------------------------------

_INDIRECT_IGNORED = {
    "pair": {"offset_mm": 1.0},
    "pinion": {"cone_angle_deg": 1.0, "helix_angle_deg": 0.0},
    "gear": {"cone_angle_deg": 1.0},
}


def _as_spec(spec_like: DesignSpec | Mapping) -> DesignSpec:
    if isinstance(spec_like, DesignSpec):
        return spec_like
    if isinstance(spec_like, Mapping):
        data = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in spec_like.items()}
        for section, keys in _INDIRECT_IGNORED.items():
            sec = data.get(section)
            if isinstance(sec, dict):
                for key, placeholder in keys.items():
                    sec.setdefault(key, placeholder)
        return spec_from_dict(data)
    raise TypeError(f"indirect_design() needs a DesignSpec or a dict, not {type(spec_like).__name__}")


def indirect_design(spec_like: DesignSpec | Mapping, alpha_nw: float, pinion_working_cone_angle: float,
                    gear_working_cone_angle: float, pinion_working_helix_angle: float) -> DesignResult:
    """Indirect design (Fig. 7, second chart): reference data from working data.

    ``spec_like`` (a :class:`DesignSpec` or a spec dict) supplies m_n, alpha_n, delta, N1, N2,
    x_t1 and the blank data; its offset, pinion cone/helix angles and gear cone angle are
    ignored.  The four working quantities are in radians (helix signed, + right hand).
    Returns a :class:`DesignResult` whose ``spec`` carries the computed gamma1, gamma2, beta1 and E.
    """
    spec = _as_spec(spec_like)
    src = spec.source
    p, g1 = spec.pair, spec.pinion
    if g1.profile_shift is None:
        raise DesignError("pinion.profile_shift is required for the indirect design",
                          keys=("pinion.profile_shift",), source=src)
    args = {"alpha_nw": alpha_nw, "pinion_working_cone_angle": pinion_working_cone_angle,
            "gear_working_cone_angle": gear_working_cone_angle,
            "pinion_working_helix_angle": pinion_working_helix_angle}
    for name, value in args.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(float(value)):
            raise DesignError(f"{name} = {value!r}: must be a finite angle in radians", keys=(name,), source=src)
    alpha_nw = float(alpha_nw)
    gw1, gw2, bw1 = float(pinion_working_cone_angle), float(gear_working_cone_angle), float(pinion_working_helix_angle)
    if not 0.0 < alpha_nw < math.pi / 2:
        raise DesignError(f"alpha_nw = {alpha_nw!r} rad: must be between 0 and pi/2", keys=("alpha_nw",), source=src)
    for name, g in (("pinion_working_cone_angle", gw1), ("gear_working_cone_angle", gw2)):
        if g == 0.0 or abs(g) >= math.pi / 2:
            raise DesignError(f"{name} = {g!r} rad: must be non-zero with |value| < pi/2 (a zero cone angle puts the"
                              f" cone apex at infinity)", keys=(name,), source=src)
    if abs(bw1) >= math.pi / 2:
        raise DesignError(f"pinion_working_helix_angle = {bw1!r} rad: |value| must be < pi/2",
                          keys=("pinion_working_helix_angle",), source=src)
    alpha_n = math.radians(p.normal_pressure_angle_deg)
    with np.errstate(all="ignore"):
        out = _eq.indirect_design(
            alpha_nw=alpha_nw, normal_module=float(p.normal_module_mm), normal_pressure_angle=alpha_n,
            pinion_teeth=int(g1.teeth), gear_teeth=int(spec.gear.teeth), shaft_angle=math.radians(p.shaft_angle_deg),
            pinion_profile_shift=float(g1.profile_shift), pinion_working_cone_angle=gw1, gear_working_cone_angle=gw2,
            pinion_working_helix_angle=bw1)
    q = {k: float(v) for k, v in out._asdict().items()}
    for member, key, gw in (("pinion", "gamma1", gw1), ("gear", "gamma2", gw2)):
        if not math.isfinite(q[key]):
            name = f"{member}_working_cone_angle"
            raise DesignError(
                f"{name} = {_deg(gw)} deg: Eq 25 has no reference cone angle (sin gamma = sin gamma_w sin alpha_nw /"
                f" sin alpha_n > 1 with alpha_nw = {_deg(alpha_nw)} deg); reduce |{name}| or alpha_nw",
                keys=(name,), source=src)
    if not math.isfinite(q["beta_w2"]):
        raise DesignError(
            f"pair.shaft_angle_deg = {p.shaft_angle_deg!r}: the pitch cones cannot touch (sin^2 delta < sin^2 gw1 +"
            f" sin^2 gw2 + 2 sin gw1 sin gw2 cos delta with gamma_w1 = {_deg(gw1)}, gamma_w2 = {_deg(gw2)} deg);"
            f" increase the shaft angle or reduce the working cone angles",
            keys=("pair.shaft_angle_deg", "pinion_working_cone_angle", "gear_working_cone_angle"), source=src)
    if not math.isfinite(q["beta1"]):
        raise DesignError(
            f"pinion_working_helix_angle = {_deg(bw1)} deg: Eq 26 has no reference helix angle"
            f" (|sin beta1| > 1); reduce |pinion_working_helix_angle|",
            keys=("pinion_working_helix_angle",), source=src)
    new_pair = dataclasses.replace(p, offset_mm=q["E"])
    new_pinion = dataclasses.replace(g1, cone_angle_deg=math.degrees(q["gamma1"]),
                                     helix_angle_deg=math.degrees(q["beta1"]))
    new_gear = dataclasses.replace(spec.gear, cone_angle_deg=math.degrees(q["gamma2"]))
    new_spec = dataclasses.replace(spec, pair=new_pair, pinion=new_pinion, gear=new_gear)
    try:  # the computed reference data must themselves form a valid spec
        spec_from_dict(spec_to_dict(new_spec))
    except SpecError as err:
        raise DesignError(f"the indirect design gives {err.detail}; change the working data",
                          keys=((err.key,) if err.key else ()), source=src) from None
    return _finish(new_spec, q, alpha_nw, offset=q["E"], residual=0.0, notes=[], procedure="indirect")


# ---------------------------------------------------------------------------
# Common finish: physical checks and assembly of the result
# ---------------------------------------------------------------------------


def _inv(t: float) -> float:
    """inv(alpha) from alpha."""
    return math.tan(t) - t


def _tooth_checks(spec: DesignSpec, m: MemberDesign, notes: list[str]) -> None:
    """Pointed or too thin tip (error) and undercut (note) in the reference transverse section."""
    m_n = m.normal_module_mm
    m_t = m.transverse_module_mm
    r = m.reference_pitch_radius_mm
    aPL, aPR = m.transverse_pressure_angle_left, m.transverse_pressure_angle_right
    s_t = math.pi * m_t / 2 + m.profile_shift * m_t * (math.tan(aPL) + math.tan(aPR))
    r_a = r + m.profile_shift * m_t + m.addendum_coefficient * m_n / math.cos(m.cone_angle)
    if m.name == "pinion":
        raise_hint = "increase pinion.profile_shift or pinion.teeth"
        lower_hint = "reduce pinion.profile_shift or pinion.addendum_coefficient"
        keys = ("pinion.profile_shift", "pinion.teeth", "pinion.addendum_coefficient")
    else:  # the gear's profile shift is a result: Eq 27 fixes the sum of the shifts for the offset
        raise_hint = ("reduce pinion.profile_shift or increase pair.offset_mm (Eq 27 then raises the gear's"
                      " profile shift), or increase gear.teeth")
        lower_hint = ("increase pinion.profile_shift or reduce pair.offset_mm (Eq 27 then lowers the gear's"
                      " profile shift), or reduce gear.addendum_coefficient")
        keys = ("pinion.profile_shift", "pair.offset_mm", "gear.teeth", "gear.addendum_coefficient")
    if m.name == "pinion":
        head = f"pinion.profile_shift = {spec.pinion.profile_shift!r}, pinion.teeth = {m.teeth}: "
    else:
        head = (f"pair.offset_mm = {spec.pair.offset_mm!r}, pinion.profile_shift ="
                f" {spec.pinion.profile_shift!r}: the gear profile shift from Eq 27 is {_num(m.profile_shift)}"
                f" and ")
    where = f"at the reference section (tip radius {_num(r_a)} mm)"
    angle = s_t / r
    for flank, aP in (("left", aPL), ("right", aPR)):
        r_b = r * math.cos(aP)
        if r_a <= r_b:
            raise DesignError(
                f"{head}{m.name} teeth: the tip circle lies inside the {flank}-flank base circle {_num(r_b)} mm {where};"
                f" {raise_hint}", keys=keys, source=spec.source)
        angle += _inv(aP) - _inv(math.acos(r_b / r_a))
    s_a = r_a * angle
    if s_a <= POINTED_TIP_FACTOR * m_n:
        hint = lower_hint if m.profile_shift > 0 else raise_hint
        raise DesignError(
            f"{head}{m.name} teeth are pointed: transverse tip thickness {_num(s_a)} mm <= {POINTED_TIP_FACTOR} m_n ="
            f" {_num(POINTED_TIP_FACTOR * m_n)} mm {where}; {hint}", keys=keys, source=spec.source)
    depth = (m.cutter_addendum_mm - m.rack_shift_mm) / math.cos(m.cone_angle)
    for flank, aP in (("left", aPL), ("right", aPR)):
        limit = r * math.sin(aP) ** 2
        if depth > limit:
            notes.append(
                f"undercut: {m.name} {flank} flank at the reference section (cutter tip {_num(depth)} mm below the"
                f" pitch circle, interference point {_num(limit)} mm below it; x_t = {_num(m.profile_shift)});"
                f" {raise_hint}")


def pitch_point_margins(m: MemberDesign) -> dict[str, tuple[float, float, float]]:
    """Where the pitch point P lies on each flank of ``m``, in its working-pitch-circle section.

    P is at the working pitch radius r_w in the transverse section z = b_c (the frame origin is in the
    reference section).  That section is a shifted spur section: base radius r cos(alpha_P), tip radius
    ``r + (h_a m_n + s)/cos(gamma) + b_c tan(gamma)``, and the rack tip (where its straight edge starts)
    at the depth ``h = (a - s)/cos(gamma) - b_c tan(gamma)`` below the pitch circle.  The profile point at
    radius rho is cut by the rack point at depth ``t = sin(alpha_P) (r sin(alpha_P) - sqrt(rho^2 - r_b^2))``;
    it is on the active profile when ``t <= h`` (above the form circle) and rho <= tip radius.

    Returns per flank (radius of the form circle, tip radius, r_w) in mm; the form radius is the
    base radius where the rack tip reaches below the interference point (undercut).
    """
    r, r_w, zc = m.reference_pitch_radius_mm, m.working_pitch_radius_mm, m.reference_section_offset_mm
    tan_g, cos_g = math.tan(m.cone_angle), math.cos(m.cone_angle)
    tip = r + (m.addendum_coefficient * m.normal_module_mm + m.rack_shift_mm) / cos_g + zc * tan_g
    depth = (m.cutter_addendum_mm - m.rack_shift_mm) / cos_g - zc * tan_g
    out = {}
    for flank, aP in (("left", m.transverse_pressure_angle_left), ("right", m.transverse_pressure_angle_right)):
        r_b = r * math.cos(aP)
        along = r * math.sin(aP) - depth / math.sin(aP)  # rack tip's point on the line of action, from T
        form = math.hypot(r_b, along) if along > 0 else r_b
        out[flank] = (form, tip, r_w)
    return out


def _check_pitch_point(spec: DesignSpec, m: MemberDesign, alpha_nw: float) -> None:
    """The designed contact at the pitch point P must lie on the active profile of both flanks.

    Otherwise the aligned pair has no contact near P (TCA finds the flanks apart or off the
    blank): typically alpha_nw is so small that the working pitch circle falls below the form
    circle, or so large that it passes the tip.
    """
    for flank, (form, tip, r_w) in pitch_point_margins(m).items():
        if form <= r_w <= tip:
            continue
        below = r_w < form
        where = (f"below the start of the active profile (form circle {_num(form)} mm)" if below
                 else f"above the tip (tip circle {_num(tip)} mm)")
        if below:
            move = (f"increase pair.offset_mm (a larger alpha_nw moves P outward) or increase"
                    f" {m.name}.cutter_addendum_coefficient (a deeper cut lowers the form circle)")
            keys = ("pair.offset_mm", f"{m.name}.cutter_addendum_coefficient")
        else:
            move = (f"reduce pair.offset_mm (a smaller alpha_nw moves P inward) or increase"
                    f" {m.name}.addendum_coefficient")
            keys = ("pair.offset_mm", f"{m.name}.addendum_coefficient")
        raise DesignError(
            f"pair.offset_mm = {spec.pair.offset_mm!r}: the design's pitch point P (working pitch radius"
            f" {_num(r_w)} mm, alpha_nw = {_deg(alpha_nw)} deg) lies {where} of the {m.name} teeth, {flank}"
            f" flank, so the pair cannot mesh at P; {move}", keys=keys, source=spec.source)


def _member(spec: DesignSpec, q: dict[str, float], i: int, name: str, m_n: float) -> MemberDesign:
    ms = getattr(spec, name)
    return MemberDesign(
        name=name,
        teeth=int(ms.teeth),
        normal_module_mm=m_n,
        helix_angle=q[f"beta{i}"],
        cone_angle=q[f"gamma{i}"],
        profile_shift=(float(ms.profile_shift) if i == 1 else q["x_t2"]),
        transverse_angular_factor=q[f"xi_t{i}"],
        mounting_distance_mm=q[f"d{i}"],
        working_mounting_distance_mm=q[f"d_w{i}"],
        working_cone_angle=q[f"gamma_w{i}"],
        working_helix_angle=q[f"beta_w{i}"],
        working_pitch_radius_mm=q[f"r_w{i}"],
        reference_pitch_radius_mm=q[f"r{i}"],
        transverse_pressure_angle_left=q[f"alpha_PL{i}"],
        transverse_pressure_angle_right=q[f"alpha_PR{i}"],
        working_transverse_pressure_angle_left=q[f"alpha_PwL{i}"],
        working_transverse_pressure_angle_right=q[f"alpha_PwR{i}"],
        fpd_angle_left=q[f"xi_L{i}"],
        fpd_angle_right=q[f"xi_R{i}"],
        pitch_point_angle=math.atan2(q[f"sin_theta{i}"], q[f"cos_theta{i}"]),
        face_width_mm=float(ms.face_width_mm),
        addendum_coefficient=float(ms.addendum_coefficient),
        cutter_addendum_coefficient=float(ms.cutter_addendum_coefficient),
        reference_section_offset_mm=float(ms.reference_section_offset_mm),
    )


def _check_transverse_pressure_angles(spec: DesignSpec, q: dict[str, float], alpha_nw: float) -> None:
    """Every transverse pressure angle, reference and working, must be positive.

    Tilted rack: tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta), and the same
    with the working data.  With alpha_P <= 0 a flank leans past the radial direction; the generated
    kernels take alpha_Pw = arccos(xi_t cos(alpha_P)) >= 0, so Eqs 22 and 27 would silently lose the sign.
    """
    src = spec.source
    alpha_n = math.radians(spec.pair.normal_pressure_angle_deg)
    for i, name in ((1, "pinion"), (2, "gear")):
        b, g = q[f"beta{i}"], q[f"gamma{i}"]
        bw, gw = q[f"beta_w{i}"], q[f"gamma_w{i}"]
        for sigma, word in ((1, "left"), (-1, "right")):
            ref = math.tan(alpha_n) * math.cos(g) + sigma * math.sin(b) * math.sin(g)
            work = math.tan(alpha_nw) * math.cos(gw) + sigma * math.sin(bw) * math.sin(gw)
            if ref > 0 and work > 0:
                continue
            which = "reference" if not ref > 0 else f"working (alpha_nw = {_deg(alpha_nw)} deg)"
            angle = math.atan2(ref if not ref > 0 else work, math.cos(b if not ref > 0 else bw))
            if name == "pinion":
                head = (f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}, pinion.cone_angle_deg ="
                        f" {spec.pinion.cone_angle_deg!r}")
                move = "reduce |pinion.helix_angle_deg| or |pinion.cone_angle_deg|"
                keys = ("pinion.helix_angle_deg", "pinion.cone_angle_deg", "pair.normal_pressure_angle_deg")
            else:
                head = f"gear.cone_angle_deg = {spec.gear.cone_angle_deg!r} (gear helix angle {_deg(b)} deg)"
                move = "reduce |gear.cone_angle_deg| or the gear helix angle (via pinion.helix_angle_deg)"
                keys = ("gear.cone_angle_deg", "pinion.helix_angle_deg", "pair.normal_pressure_angle_deg")
            raise DesignError(
                f"{head}: the {name}'s {word}-flank {which} transverse pressure angle is {_deg(angle)} deg <= 0"
                f" (tan alpha_P = (tan alpha_n cos gamma +- sin beta sin gamma) / cos beta); {move},"
                f" or increase pair.normal_pressure_angle_deg", keys=keys, source=src)


def _finish(spec: DesignSpec, q: dict[str, float], alpha_nw: float, *, offset: float, residual: float,
            notes: list[str], procedure: str) -> DesignResult:
    src = spec.source
    beta2 = q["beta2"]
    if not math.isfinite(beta2) or abs(beta2) >= MAX_GEAR_HELIX_ANGLE:
        shown = f"{_deg(beta2)} deg" if math.isfinite(beta2) else "not real (|sin beta2| > 1)"
        # beta2 ~ eta - beta_w1 with eta ~ delta: move beta1 toward delta
        bw2 = q["beta_w2"]
        direction = "increase" if (bw2 > 0 if math.isfinite(bw2) else True) else "reduce"
        raise DesignError(
            f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}: the gear helix angle beta2 (Eq 26,"
            f" beta_w2 = eta - beta_w1 of Eq 16) is {shown}, |beta2| must stay below 80 deg;"
            f" {direction} pinion.helix_angle_deg (beta2 ~ shaft angle - beta1)",
            keys=("pinion.helix_angle_deg", "pair.shaft_angle_deg"), source=src)
    _check_transverse_pressure_angles(spec, q, alpha_nw)
    bad = sorted(k for k, v in q.items() if not math.isfinite(v))
    if bad:
        raise DesignError(
            f"pinion.cone_angle_deg = {spec.pinion.cone_angle_deg!r}, gear.cone_angle_deg ="
            f" {spec.gear.cone_angle_deg!r}: the design equations give non-finite {', '.join(bad)}"
            f" at alpha_nw = {_deg(alpha_nw)} deg; increase |cone angles| or the shaft angle",
            keys=("pinion.cone_angle_deg", "gear.cone_angle_deg"), source=src)
    for i, name in ((1, "pinion"), (2, "gear")):
        if not q[f"r_w{i}"] > 0 or not q[f"r{i}"] > 0:
            raise DesignError(
                f"{name}.teeth = {getattr(spec, name).teeth}: non-physical {name} pitch radius"
                f" (r = {_num(q[f'r{i}'])}, r_w = {_num(q[f'r_w{i}'])} mm); increase {name}.teeth",
                keys=(f"{name}.teeth",), source=src)
    m_n = float(spec.pair.normal_module_mm)
    pinion = _member(spec, q, 1, "pinion", m_n)
    gear = _member(spec, q, 2, "gear", m_n)
    notes = list(notes)
    for m in (pinion, gear):
        _tooth_checks(spec, m, notes)
    for m in (pinion, gear):
        _check_pitch_point(spec, m, alpha_nw)
    return DesignResult(
        spec=spec,
        working_normal_pressure_angle=float(alpha_nw),
        normal_angular_factor=q["xi_n"],
        fpd_angle_left=q["xi_L"],
        fpd_angle_right=q["xi_R"],
        offset_mm=float(offset),
        shaft_angle=math.radians(spec.pair.shaft_angle_deg),
        normal_module_mm=m_n,
        normal_pressure_angle=math.radians(spec.pair.normal_pressure_angle_deg),
        pinion=pinion,
        gear=gear,
        notes=tuple(notes),
        offset_residual_mm=float(residual),
        procedure=procedure,
    )
