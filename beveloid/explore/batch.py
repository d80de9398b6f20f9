"""The direct pitch-cone design of many designs at once, over the generated design equations.

:func:`design_batch` runs the algorithm of :func:`beveloid.design.design` (the same alpha_nw grid,
the same multisection of the admissibility transitions, the same brackets, the same safeguarded
Newton/bisection, the same checks in the same order) on arrays of designs instead of one design:
the generated kernels of ``beveloid.generated.design_equations`` are numpy and broadcast, so each
step is one kernel call over every design (or every bracket) still at that step.  Per design it
returns a status (``"ok"`` or the class of the refusal ``design()`` would raise, see STATUSES)
and, for the designs that are ``"ok"``, the design equations' values (radians, mm) by name.

tests/explore/test_explore_batch.py holds it equal to ``design()`` on grids with infeasible designs.
"""
from __future__ import annotations

import math

import numpy as np

from .. import design as _design
from ..generated import design_equations as eq

#: per-design status classes, in the order design() checks them (first failure wins)
STATUSES = ("ok", "zero_cone_angle", "no_working_pressure_angle", "gear_helix_angle_out_of_range",
            "transverse_pressure_angle_not_positive", "non_finite_design", "non_physical_pitch_radius",
            "tip_inside_base_circle", "pointed_teeth", "pitch_point_off_active_profile")
_EPS = np.finfo(float).eps
#: design()'s alpha_nw grid and its multisection (pieces per pass, passes): the same numbers as
#: beveloid/design.py, which keeps them private; the batch must scan exactly as design() does
_POINTS = 1201
_SECTIONS = 64
_PASSES = 10
#: designs per block of the alpha_nw scan (keeps the (designs x 1200) temporaries in cache)
SCAN_BLOCK = 4


def refusal_class(err: Exception) -> str:
    """The STATUSES class of a :class:`beveloid.design.DesignError` raised by ``design()``."""
    text = str(err)
    for needle, status in (("non-zero cone angle", "zero_cone_angle"),
                           ("no working normal pressure angle", "no_working_pressure_angle"),
                           ("for any alpha_nw up to 60 deg", "no_working_pressure_angle"),
                           ("for every alpha_nw up to 60 deg", "no_working_pressure_angle"),
                           ("the gear helix angle beta2", "gear_helix_angle_out_of_range"),
                           ("transverse pressure angle is", "transverse_pressure_angle_not_positive"),
                           ("give non-finite", "non_finite_design"),
                           ("non-physical", "non_physical_pitch_radius"),
                           ("tip circle lies inside", "tip_inside_base_circle"),
                           ("teeth are pointed", "pointed_teeth"),
                           ("pitch point P", "pitch_point_off_active_profile")):
        if needle in text:
            return status
    return "design_refused"


def _kw(c, idx=None, column=False):
    """The design kernels' pair arguments (by name) for the designs idx, as (k,) or (k, 1) arrays."""
    def pick(v):
        v = v if idx is None else v[idx]
        return v[:, None] if column else v
    return dict(normal_module=pick(c["m_n"]), normal_pressure_angle=pick(c["alpha_n"]),
                pinion_teeth=pick(c["N1"]), gear_teeth=pick(c["N2"]), shaft_angle=pick(c["delta"]),
                pinion_profile_shift=pick(c["x_t1"]), pinion_cone_angle=pick(c["gamma1"]),
                gear_cone_angle=pick(c["gamma2"]), pinion_helix_angle=pick(c["beta1"]))


def _scan(alpha, c, idx, column):
    with np.errstate(all="ignore"):
        res, r1, r2 = eq.offset_scan(alpha_nw=alpha, offset=(c["E"][idx][:, None] if column else c["E"][idx]),
                                     **_kw(c, idx, column))
    return res, np.isfinite(res) & (r1 > 0) & (r2 > 0)


def _residual(alpha, c, idx):
    with np.errstate(all="ignore"):
        return eq.offset_residual(alpha_nw=alpha, offset=c["E"][idx], **_kw(c, idx))


def constants(values: dict) -> dict:
    """Per-design constants (radians, mm) of the design from spec values by dotted key (arrays)."""
    rad = np.radians
    return dict(m_n=values["pair.normal_module_mm"], alpha_n=rad(values["pair.normal_pressure_angle_deg"]),
                delta=rad(values["pair.shaft_angle_deg"]), E=values["pair.offset_mm"],
                N1=values["pinion.teeth"], N2=values["gear.teeth"], x_t1=values["pinion.profile_shift"],
                gamma1=rad(values["pinion.cone_angle_deg"]), gamma2=rad(values["gear.cone_angle_deg"]),
                beta1=rad(values["pinion.helix_angle_deg"]))


def _refine(c, did, a, b):
    """Multisection of admissibility transitions [a, b] (design did): the admissible end of each."""
    fa = _scan(a, c, did, False)[1]
    frac = np.arange(_SECTIONS + 1) / _SECTIONS
    rows = np.arange(a.size)
    for _ in range(_PASSES):
        pts = a[:, None] + (b - a)[:, None] * frac[None, :]
        pts[:, -1] = b
        differs = _scan(pts, c, did, True)[1] != fa[:, None]
        j = np.where(differs.any(axis=1), differs.argmax(axis=1), _SECTIONS)
        j = np.maximum(j, 1)
        a, b = pts[rows, j - 1], pts[rows, j]
    return np.where(fa, a, b)


def _grids(c, todo):
    """design._admissible_grid and its scan for the designs todo: flat (design, alpha, residual, ok)."""
    s = np.maximum(np.abs(np.sin(c["gamma1"][todo])), np.abs(np.sin(c["gamma2"][todo])))
    lo = np.array([math.asin(min(1.0, float(v) * math.sin(float(an)))) for v, an in zip(s, c["alpha_n"][todo])])
    grid = np.linspace(lo, _design.MAX_WORKING_PRESSURE_ANGLE, _POINTS, axis=-1)[:, 1:]
    res = np.empty_like(grid)
    ok = np.empty(grid.shape, dtype=bool)
    for k in range(0, todo.size, SCAN_BLOCK):
        sl = slice(k, k + SCAN_BLOCK)
        res[sl], ok[sl] = _scan(grid[sl], c, todo[sl], True)
    # transitions and the open lower end, refined
    i, j = np.nonzero(ok[:, :-1] != ok[:, 1:])
    did = np.concatenate([todo[i], todo[ok[:, 0]]])
    left = np.concatenate([grid[i, j], lo[ok[:, 0]]])
    right = np.concatenate([grid[i, j + 1], grid[ok[:, 0], 0]])
    extra = _refine(c, did, left, right) if did.size else np.empty(0)
    e_res, e_ok = _scan(extra, c, did, False) if did.size else (np.empty(0), np.empty(0, dtype=bool))
    # np.unique(grid + extra) per design: the rows are sorted, so insert the few extra points
    m = grid.shape[1]
    row = np.searchsorted(todo, did)  # todo is ascending
    if did.size:
        o = np.lexsort((extra, row))
        row, extra, e_res, e_ok = row[o], extra[o], e_res[o], e_ok[o]
        first = np.ones(row.size, dtype=bool)
        first[1:] = (row[1:] != row[:-1]) | (extra[1:] != extra[:-1])
        pos = np.array([np.searchsorted(grid[r], x) for r, x in zip(row, extra)], dtype=np.int64)
        new = first & ~((pos < m) & (grid[row, np.minimum(pos, m - 1)] == extra))
        row, extra, e_res, e_ok, pos = row[new], extra[new], e_res[new], e_ok[new], pos[new]
    at = row * m + pos
    D = np.insert(np.repeat(todo, m), at, todo[row])
    A = np.insert(grid.ravel(), at, extra)
    R = np.insert(res.ravel(), at, e_res)
    K = np.insert(ok.ravel(), at, e_ok)
    return D, A, R, K


def _brackets(D, A, R, K):
    """design._brackets over the flat grids: (design, a, b, fa, fb) in the order design() lists them."""
    same = D[1:] == D[:-1]
    pair = same & K[:-1] & K[1:]
    ra, rb = R[:-1], R[1:]
    zero = pair & (ra == 0.0)
    change = pair & ~zero & ((ra < 0.0) != (rb < 0.0)) & (rb != 0.0)
    last = np.ones(D.size, dtype=bool)
    last[:-1] = ~same
    end = last & K & (R == 0.0)
    i = np.nonzero(zero | change)[0]
    e = np.nonzero(end)[0]
    z = zero[i]
    did = np.concatenate([D[i], D[e]])
    a = np.concatenate([A[i], A[e]])
    b = np.concatenate([np.where(z, A[i], A[i + 1]), A[e]])
    fa = np.concatenate([R[i], np.zeros(e.size)])
    fb = np.concatenate([np.where(z, R[i], R[i + 1]), np.zeros(e.size)])
    rank = np.concatenate([i, e + 0.5])  # within a design: pairs by position, the exact end root last
    order = np.lexsort((rank, did))
    return did[order], a[order], b[order], fa[order], fb[order]


def _solve(c, did, a, b, fa, fb):
    """design._solve_bracket on every bracket at once: (alpha_nw, residual; nan if no root)."""
    n = did.size
    tol = np.maximum(_design.RESIDUAL_TOLERANCE_MM, 8.0 * _EPS * np.abs(c["E"][did]))
    out_x = a.copy()
    out_r = fa.copy()
    active = a != b
    with np.errstate(all="ignore"):
        x = a - fa * (b - a) / (fb - fa)
    x = np.where((a < x) & (x < b), x, 0.5 * (a + b))
    best_r = np.full(n, np.inf)
    best_x = x.copy()
    fallback = np.zeros(n, dtype=bool)  # left the loop without |r| < tol: take the best point
    for _ in range(300):
        k = np.nonzero(active)[0]
        if k.size == 0:
            break
        r, dr = _residual(x[k], c, did[k])
        bad = ~np.isfinite(r)
        x[k[bad]] = 0.5 * (a[k[bad]] + b[k[bad]])
        g = ~bad
        k, r, dr = k[g], r[g], dr[g]
        better = np.abs(r) < best_r[k]
        best_r[k[better]] = np.abs(r[better])
        best_x[k[better]] = x[k[better]]
        done = np.abs(r) < tol[k]
        out_x[k[done]] = x[k[done]]
        out_r[k[done]] = r[done]
        active[k[done]] = False
        k, r, dr = k[~done], r[~done], dr[~done]
        same = (r < 0) == (fa[k] < 0)
        a[k[same]], fa[k[same]] = x[k[same]], r[same]
        b[k[~same]], fb[k[~same]] = x[k[~same]], r[~same]
        stop = b[k] - a[k] <= 4.0 * _EPS * np.maximum(np.abs(a[k]), np.abs(b[k]))
        active[k[stop]] = False
        fallback[k[stop]] = True
        k, r, dr = k[~stop], r[~stop], dr[~stop]
        with np.errstate(all="ignore"):
            xn = np.where(np.isfinite(dr) & (dr != 0.0), x[k] - r / dr, np.nan)
        mid = 0.5 * (a[k] + b[k])
        outside = ~((a[k] < xn) & (xn < b[k])) | (np.abs(xn - x[k]) > 0.5 * (b[k] - a[k]))
        x[k] = np.where(outside, mid, xn)
    fallback |= active  # 300 iterations without convergence
    k = np.nonzero(fallback)[0]
    if k.size:
        xb = best_x[k]
        r, dr = _residual(xb, c, did[k])
        with np.errstate(all="ignore"):
            resolution = np.where(np.isfinite(dr), 8.0 * np.abs(dr) * _EPS * np.abs(xb), 0.0)
        ok = (np.abs(r) <= np.maximum(1e3 * tol[k], resolution)) & (np.abs(r) <= 1e-6 * np.maximum(1.0, np.abs(c["E"][did[k]])))
        out_x[k] = xb
        out_r[k] = np.where(ok, r, np.nan)
    return out_x, out_r


def _alpha_nw(c, todo, n):
    """Per design: alpha_nw and the Eq 17 residual of the root closest to alpha_n (nan: no root)."""
    alpha = np.full(n, np.nan)
    resid = np.full(n, np.nan)
    if todo.size == 0:
        return alpha, resid
    did, a, b, fa, fb = _brackets(*_grids(c, todo))
    x, r = _solve(c, did, a, b, fa, fb)
    good = np.isfinite(r)
    did, x, r = did[good], x[good], r[good]
    dist = np.abs(x - c["alpha_n"][did])
    order = np.lexsort((dist, did))  # stable: equal distances keep the bracket order
    did, x, r = did[order], x[order], r[order]
    first = np.ones(did.size, dtype=bool)
    first[1:] = did[1:] != did[:-1]
    alpha[did[first]] = x[first]
    resid[did[first]] = r[first]
    return alpha, resid


def _fail(status, mask, code):
    """Set status code where the design is still ok and mask holds."""
    status[(status == 0) & mask] = code


def _checks(v, c, q, alpha_nw, status):
    """design._finish's checks in its order, elementwise (status codes: index into STATUSES)."""
    with np.errstate(all="ignore"):
        beta2 = q["beta2"]
        _fail(status, ~np.isfinite(beta2) | (np.abs(beta2) >= _design.MAX_GEAR_HELIX_ANGLE), 3)
        bad = np.zeros(status.size, dtype=bool)
        for i in (1, 2):
            b, g, bw, gw = q[f"beta{i}"], q[f"gamma{i}"], q[f"beta_w{i}"], q[f"gamma_w{i}"]
            for sigma in (1, -1):
                ref = np.tan(c["alpha_n"]) * np.cos(g) + sigma * np.sin(b) * np.sin(g)
                work = np.tan(alpha_nw) * np.cos(gw) + sigma * np.sin(bw) * np.sin(gw)
                bad |= ~((ref > 0) & (work > 0))
        _fail(status, bad, 4)
        _fail(status, ~np.all([np.isfinite(x) for x in q.values()], axis=0), 5)
        _fail(status, ~((q["r_w1"] > 0) & (q["r1"] > 0) & (q["r_w2"] > 0) & (q["r2"] > 0)), 6)
        m_n = c["m_n"]
        inside = np.zeros(status.size, dtype=bool)
        pointed = np.zeros(status.size, dtype=bool)
        for i, name in ((1, "pinion"), (2, "gear")):
            # a failure of the pinion's tooth checks comes before any of the gear's
            x_t = c["x_t1"] if i == 1 else q["x_t2"]
            beta, gamma, r = q[f"beta{i}"], q[f"gamma{i}"], q[f"r{i}"]
            m_t = m_n / np.cos(beta)
            aPL, aPR = q[f"alpha_PL{i}"], q[f"alpha_PR{i}"]
            s_t = math.pi * m_t / 2 + x_t * m_t * (np.tan(aPL) + np.tan(aPR))
            r_a = r + x_t * m_t + v[f"{name}.addendum_coefficient"] * m_n / np.cos(gamma)
            angle = s_t / r
            here = np.zeros(status.size, dtype=bool)
            for aP in (aPL, aPR):
                r_b = r * np.cos(aP)
                here |= r_a <= r_b
                ac = np.arccos(r_b / r_a)
                angle = angle + ((np.tan(aP) - aP) - (np.tan(ac) - ac))
            new_inside = here & ~inside & ~pointed
            new_pointed = ~here & ~inside & ~pointed & (r_a * angle <= _design.POINTED_TIP_FACTOR * m_n)
            inside |= new_inside
            pointed |= new_pointed
        status[(status == 0) & inside] = 7
        status[(status == 0) & pointed] = 8
        off = np.zeros(status.size, dtype=bool)
        for i, name in ((1, "pinion"), (2, "gear")):
            x_t = c["x_t1"] if i == 1 else q["x_t2"]
            beta, gamma, r, r_w = q[f"beta{i}"], q[f"gamma{i}"], q[f"r{i}"], q[f"r_w{i}"]
            zc = v[f"{name}.reference_section_offset_mm"]
            rack = x_t * m_n * np.cos(gamma) / np.cos(beta)
            tan_g, cos_g = np.tan(gamma), np.cos(gamma)
            tip = r + (v[f"{name}.addendum_coefficient"] * m_n + rack) / cos_g + zc * tan_g
            depth = (v[f"{name}.cutter_addendum_coefficient"] * m_n - rack) / cos_g - zc * tan_g
            for aP in (q[f"alpha_PL{i}"], q[f"alpha_PR{i}"]):
                r_b = r * np.cos(aP)
                along = r * np.sin(aP) - depth / np.sin(aP)
                form = np.where(along > 0, np.hypot(r_b, along), r_b)
                off |= ~((form <= r_w) & (r_w <= tip))
        _fail(status, off, 9)


def design_batch(values: dict) -> tuple[np.ndarray, np.ndarray, dict]:
    """The direct design of n designs given by spec values (dotted key -> (n,) float array).

    Returns (status codes (n,) into STATUSES, alpha_nw (n,) rad, q: the generated direct_design
    outputs by name plus ``offset_residual_mm``); q and alpha_nw are nan where the status is not ok.
    """
    c = constants(values)
    n = c["m_n"].size
    status = np.zeros(n, dtype=np.int64)
    _fail(status, (c["gamma1"] == 0.0) | (c["gamma2"] == 0.0), 1)
    alpha, resid = _alpha_nw(c, np.nonzero(status == 0)[0], n)
    _fail(status, ~np.isfinite(alpha), 2)
    with np.errstate(all="ignore"):
        q = {k: np.asarray(x, dtype=float) for k, x in eq.direct_design(alpha_nw=alpha, **_kw(c))._asdict().items()}
    _checks(values, c, q, alpha, status)
    none = status != 0
    for x in q.values():
        x[none] = np.nan
    alpha = np.where(none, np.nan, alpha)
    q["offset_residual_mm"] = np.where(none, np.nan, resid)
    return status, alpha, q
