"""The direct design's unknown: the working normal pressure angle alpha_nw, the root of Eq 17.

``offset_residual(alpha_nw) = E(alpha_nw) - E`` is scanned on a grid of the admissible interval
(see the package docstring) for sign changes; each bracket is solved to ``|residual| <`` the
tolerance; the root closest to alpha_n is taken.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..spec import DesignSpec
from .kernels import deg_text, direct_outputs, equations, num_text, pair_kwargs, residual
from .members import DesignError

#: Upper end of the alpha_nw search interval (rad).
MAX_WORKING_PRESSURE_ANGLE = math.radians(60.0)

#: Target |E(alpha_nw) - E| of the root finder (mm).
RESIDUAL_TOLERANCE_MM = 1e-11

_GRID_POINTS = 1201
#: the admissibility transitions of the alpha_nw grid are refined by multisection: pieces per pass
#: and passes (64**10 = 2**60: as fine as 60 bisections)
_SECTIONS = 64
_SECTION_PASSES = 10
_EPS = np.finfo(float).eps


def spec_constants(spec: DesignSpec) -> dict[str, Any]:
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


def check_cone_angles(spec: DesignSpec, gamma1: float, gamma2: float) -> None:
    for member, g in (("pinion", gamma1), ("gear", gamma2)):
        if g == 0.0:
            key = f"{member}.cone_angle_deg"
            raise DesignError(
                f"{key} = 0.0: a beveloid member needs a non-zero cone angle (with gamma = 0 the pitch cone is a"
                f" cylinder, its apex and the mounting distance of Eqs 13-14 are at infinity);"
                f" increase |{key}| above 0", keys=(key,), source=spec.source)


def scan(alpha_nw, c: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Residual E(alpha_nw) - E and the admissibility mask (all real, positive working radii)."""
    with np.errstate(all="ignore"):
        out = equations.offset_scan(alpha_nw=np.asarray(alpha_nw, dtype=float), offset=c["E"], **pair_kwargs(c))
    ok = np.isfinite(out.residual) & (out.r_w1 > 0) & (out.r_w2 > 0)
    return out.residual, ok


def _admissible_grid(c: dict[str, Any]) -> np.ndarray:
    """alpha_nw grid on (lower Eq 25 bound, 60 deg], plus the refined ends of the admissible runs.

    Admissible: the kernel is real (Eqs 16, 25, 26 defined) and both working pitch radii are
    positive (|beta_w| < 90 deg; beyond, Eq 17 passes through a pole and changes sign).
    """
    lo = math.asin(min(1.0, max(abs(math.sin(c["gamma1"])), abs(math.sin(c["gamma2"]))) * math.sin(c["alpha_n"])))
    hi = MAX_WORKING_PRESSURE_ANGLE
    grid = np.linspace(lo, hi, _GRID_POINTS)[1:]
    _, ok = scan(grid, c)
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
        fa = scan(a, c)[1]
        # multisection: each pass cuts every bracket into _SECTIONS and keeps the piece where the
        # admissibility changes first (10 passes of 64 = 60 halvings, in 10 kernel calls, not 60)
        frac = np.arange(_SECTIONS + 1) / _SECTIONS
        rows = np.arange(a.size)
        for _ in range(_SECTION_PASSES):
            pts = a[:, None] + (b - a)[:, None] * frac[None, :]
            pts[:, -1] = b
            differs = scan(pts.ravel(), c)[1].reshape(pts.shape) != fa[:, None]
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

    Kept rather than scipy.optimize.brentq, which finds the same roots within 1.0e-13 rad (252
    brackets of 300 random designs): that difference alone turns one position of the crowned case 1
    (4 um, 31 positions, right flank) into a diverging TCA point whose TE spoils the TE peak-to-peak
    (tests/test_crowned.py::test_aligned_te_grows_in_proportion_to_small_crowning); the TCA's
    sensitivity is the defect, and the design keeps its numbers until it is fixed.

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
        out = residual(x, c)
        r, dr = float(out.residual), float(out.residual_D_alpha_nw)
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
    out = residual(x, c)
    r, dr = float(out.residual), float(out.residual_D_alpha_nw)
    # converged to floating-point resolution of alpha_nw (E(alpha_nw) very steep), not a pole?
    resolution = 8.0 * abs(dr) * _EPS * abs(x) if math.isfinite(dr) else 0.0
    ok = abs(r) <= max(1e3 * tol, resolution) and abs(r) <= 1e-6 * max(1.0, abs(c["E"]))
    return (x, r) if ok else (x, math.nan)


def _infeasible_no_root(spec: DesignSpec, c: dict[str, Any], grid: np.ndarray, res: np.ndarray,
                        ok: np.ndarray) -> DesignError:
    src = spec.source
    if not ok.any():
        q = direct_outputs(grid, c)
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
    e_model = scan(grid[ok], dict(c, E=0.0))[0]  # E(alpha_nw) itself, not E(alpha_nw) - E + E
    a_ok = grid[ok]
    span = (f"Eq 17 gives E from {num_text(e_model.min())} to {num_text(e_model.max())} mm for alpha_nw from"
            f" {deg_text(a_ok.min())} to {deg_text(a_ok.max())} deg")
    head = f"pair.offset_mm = {spec.pair.offset_mm!r}: no working normal pressure angle solves Eq 17"
    if (res[ok] > 0).all():
        return DesignError(
            f"{head}: the offset is too small for the given teeth, module and helix angles ({span});"
            f" increase pair.offset_mm to at least {num_text(e_model.min())} mm or reduce the teeth or module",
            keys=("pair.offset_mm",), source=src)
    return DesignError(
        f"{head}: the offset is too large for the given teeth, module and helix angles ({span});"
        f" reduce pair.offset_mm to at most {num_text(e_model.max())} mm or increase the teeth or module",
        keys=("pair.offset_mm",), source=src)


def solve_alpha_nw(spec: DesignSpec, c: dict[str, Any]) -> tuple[float, float, list[str]]:
    grid = _admissible_grid(c)
    res, ok = scan(grid, c)
    roots = [_solve_bracket(c, *br) for br in _brackets(grid, res, ok)]
    roots = [(x, r) for x, r in roots if math.isfinite(r)]
    if not roots:
        raise _infeasible_no_root(spec, c, grid, res, ok)
    roots.sort(key=lambda xr: abs(xr[0] - c["alpha_n"]))
    notes = []
    if len(roots) > 1:
        listed = ", ".join(deg_text(x) for x, _ in sorted(roots))
        notes.append(f"Eq 17 has {len(roots)} roots alpha_nw = {listed} deg; chose {deg_text(roots[0][0])} deg,"
                     f" the one closest to alpha_n = {deg_text(c['alpha_n'])} deg")
    x, r = roots[0]
    if abs(r) >= _tolerance(c):
        notes.append(f"Eq 17 solved only to |E(alpha_nw) - E| = {abs(r):.2g} mm: alpha_nw = {deg_text(x)} deg is at"
                     f" floating-point resolution (E(alpha_nw) is very steep there, near the end of the tangency"
                     f" range)")
    return x, r, notes
