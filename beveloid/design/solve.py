"""The direct design's unknown: the working normal pressure angle alpha_nw, the root of Eq 17, for
arrays of designs (one design is the array of one).

``offset_residual(alpha_nw) = E(alpha_nw) - E`` is scanned on a grid of each design's admissible
interval (see the package docstring) for sign changes; each bracket is solved to ``|residual| <``
the tolerance by a safeguarded Newton/bisection; the root closest to alpha_n is taken.  Every step
is one call of a generated kernel (``beveloid.generated.design_equations``, numpy, broadcasting)
over all designs (or all brackets) still at that step.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .kernels import equations, pair_kwargs, single

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
#: designs per block of the alpha_nw scan (keeps the (designs x 1200) temporaries in cache)
SCAN_BLOCK = 4


def constants(values: dict) -> dict:
    """Per-design constants by the paper's symbols (radians, mm; (n,) arrays) from spec values by dotted key."""
    rad = np.radians
    return dict(m_n=values["pair.normal_module_mm"], alpha_n=rad(values["pair.normal_pressure_angle_deg"]),
                delta=rad(values["pair.shaft_angle_deg"]), E=values["pair.offset_mm"],
                N1=values["pinion.teeth"], N2=values["gear.teeth"], x_t1=values["pinion.profile_shift"],
                gamma1=rad(values["pinion.cone_angle_deg"]), gamma2=rad(values["gear.cone_angle_deg"]),
                beta1=rad(values["pinion.helix_angle_deg"]))


def scan(alpha, c: dict, idx, column: bool = False, offset=None):
    """Residual E(alpha_nw) - E (``offset`` in place of E when given) and the admissibility mask (all
    real, positive working radii) of the designs idx at alpha (k,) or (k, m) with ``column``."""
    E = c["E"][idx] if offset is None else offset
    if single(c) and offset is None:
        E = c["E"].item()
    with np.errstate(all="ignore"):
        res, r1, r2 = equations.offset_scan(alpha_nw=alpha, offset=(E[:, None] if column and offset is None and not single(c) else E),
                                            **pair_kwargs(c, idx, column))
    return res, np.isfinite(res) & (r1 > 0) & (r2 > 0)


def _residual(alpha, c, idx):
    """E(alpha_nw) - E and its derivative (Eq 17) at alpha (k,) of the designs idx (one design: each
    bracket's alpha_nw a Python scalar)."""
    with np.errstate(all="ignore"):
        if not single(c):
            return equations.offset_residual(alpha_nw=alpha, offset=c["E"][idx], **pair_kwargs(c, idx))
        kw = pair_kwargs(c)
        outs = [equations.offset_residual(alpha_nw=float(x), offset=c["E"].item(), **kw) for x in alpha]
    return (np.array([float(o.residual) for o in outs]), np.array([float(o.residual_D_alpha_nw) for o in outs]))


def tolerance(E):
    """The residual tolerance (mm) at offsets E: 1e-11 mm, relaxed to 8 ulp of E for large E."""
    return np.maximum(RESIDUAL_TOLERANCE_MM, 8.0 * _EPS * np.abs(E))


def _refine(c, did, a, b):
    """Multisection of admissibility transitions [a, b] (design did): the admissible end of each.
    Each pass cuts every bracket into _SECTIONS and keeps the piece where the admissibility changes
    first (10 passes of 64 = 60 halvings, in 10 kernel calls, not 60)."""
    fa = scan(a, c, did)[1]
    frac = np.arange(_SECTIONS + 1) / _SECTIONS
    rows = np.arange(a.size)
    for _ in range(_SECTION_PASSES):
        pts = a[:, None] + (b - a)[:, None] * frac[None, :]
        pts[:, -1] = b
        differs = scan(pts, c, did, True)[1] != fa[:, None]
        j = np.where(differs.any(axis=1), differs.argmax(axis=1), _SECTIONS)
        j = np.maximum(j, 1)
        a, b = pts[rows, j - 1], pts[rows, j]
    return np.where(fa, a, b)


class Grids(NamedTuple):
    """The alpha_nw grids of several designs, flat and in design order: design index, alpha_nw (rad),
    residual (mm), admissible."""

    design: np.ndarray
    alpha_nw: np.ndarray
    residual_mm: np.ndarray
    admissible: np.ndarray


def grids(c: dict, todo: np.ndarray) -> Grids:
    """Each design's alpha_nw grid on (lower Eq 25 bound, 60 deg], plus the refined admissible ends of
    its admissible runs, and the scan there.

    Admissible: the kernel is real (Eqs 16, 25, 26 defined) and both working pitch radii are positive
    (|beta_w| < 90 deg; beyond, Eq 17 passes through a pole and changes sign).
    """
    lo = np.array([math.asin(min(1.0, max(abs(math.sin(float(g1))), abs(math.sin(float(g2)))) * math.sin(float(an))))
                   for g1, g2, an in zip(c["gamma1"][todo], c["gamma2"][todo], c["alpha_n"][todo])])
    grid = np.linspace(lo, MAX_WORKING_PRESSURE_ANGLE, _GRID_POINTS, axis=-1)[:, 1:]
    res = np.empty_like(grid)
    ok = np.empty(grid.shape, dtype=bool)
    for k in range(0, todo.size, SCAN_BLOCK):
        sl = slice(k, k + SCAN_BLOCK)
        res[sl], ok[sl] = scan(grid[sl], c, todo[sl], True)
    # transitions and the open lower end, refined
    i, j = np.nonzero(ok[:, :-1] != ok[:, 1:])
    did = np.concatenate([todo[i], todo[ok[:, 0]]])
    left = np.concatenate([grid[i, j], lo[ok[:, 0]]])
    right = np.concatenate([grid[i, j + 1], grid[ok[:, 0], 0]])
    extra = _refine(c, did, left, right) if did.size else np.empty(0)
    e_res, e_ok = scan(extra, c, did) if did.size else (np.empty(0), np.empty(0, dtype=bool))
    # the union of grid and extra points per design, sorted: the rows are sorted, so insert the few extra
    m = grid.shape[1]
    row = np.searchsorted(todo, did)  # todo is ascending
    pos = np.empty(0, dtype=np.int64)
    if did.size:
        o = np.lexsort((extra, row))
        row, extra, e_res, e_ok = row[o], extra[o], e_res[o], e_ok[o]
        first = np.ones(row.size, dtype=bool)
        first[1:] = (row[1:] != row[:-1]) | (extra[1:] != extra[:-1])
        pos = np.array([np.searchsorted(grid[r], x) for r, x in zip(row, extra)], dtype=np.int64)
        new = first & ~((pos < m) & (grid[row, np.minimum(pos, m - 1)] == extra))
        row, extra, e_res, e_ok, pos = row[new], extra[new], e_res[new], e_ok[new], pos[new]
    at = row * m + pos
    return Grids(np.insert(np.repeat(todo, m), at, todo[row]), np.insert(grid.ravel(), at, extra),
                 np.insert(res.ravel(), at, e_res), np.insert(ok.ravel(), at, e_ok))


def _brackets(g: Grids):
    """Sign changes of the residual between neighbouring admissible grid points (and exact zeros):
    (design, a, b, fa, fb), per design in grid order (an exact zero at the grid's end last)."""
    D, A, R, K = g
    same = D[1:] == D[:-1]
    pair = same & K[:-1] & K[1:]
    ra, rb = R[:-1], R[1:]
    zero = pair & (ra == 0.0)
    change = pair & ~zero & ((ra < 0.0) != (rb < 0.0)) & (rb != 0.0)  # signs, not the product: no overflow
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
    rank = np.concatenate([i, e + 0.5])
    order = np.lexsort((rank, did))
    return did[order], a[order], b[order], fa[order], fb[order]


def _solve(c, did, a, b, fa, fb):
    """Safeguarded Newton (exact derivative) / bisection on every bracket at once: (alpha_nw, residual;
    nan if the bracket holds a pole rather than a zero: the iteration did not bring |residual| down).

    Kept rather than scipy.optimize.brentq, which finds the same roots within 1.0e-13 rad (252
    brackets of 300 random designs): that difference alone turns one position of the crowned case 1
    (4 um, 31 positions, right flank) into a diverging TCA point whose TE spoils the TE peak-to-peak
    (tests/tca/test_tca_crowned.py::test_aligned_te_grows_in_proportion_to_small_crowning); the TCA's
    sensitivity is the defect, and the design keeps its numbers until it is fixed.
    """
    n = did.size
    tol = tolerance(c["E"][did])
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
        outside = ~((a[k] < xn) & (xn < b[k])) | (np.abs(xn - x[k]) > 0.5 * (b[k] - a[k]))  # or not faster
        x[k] = np.where(outside, mid, xn)
    fallback |= active  # 300 iterations without convergence
    k = np.nonzero(fallback)[0]
    if k.size:  # converged to floating-point resolution of alpha_nw (E(alpha_nw) very steep), not a pole?
        xb = best_x[k]
        r, dr = _residual(xb, c, did[k])
        with np.errstate(all="ignore"):
            resolution = np.where(np.isfinite(dr), 8.0 * np.abs(dr) * _EPS * np.abs(xb), 0.0)
        ok = (np.abs(r) <= np.maximum(1e3 * tol[k], resolution)) & (np.abs(r) <= 1e-6 * np.maximum(1.0, np.abs(c["E"][did[k]])))
        out_x[k] = xb
        out_r[k] = np.where(ok, r, np.nan)
    return out_x, out_r


class Roots(NamedTuple):
    """Every root of Eq 17 found, per design (ascending design index), the closest to alpha_n first."""

    design: np.ndarray
    alpha_nw: np.ndarray
    residual_mm: np.ndarray


def roots(c: dict, todo: np.ndarray) -> Roots:
    """The roots of Eq 17 of the designs todo (ascending indices)."""
    if todo.size == 0:
        return Roots(np.empty(0, dtype=np.int64), np.empty(0), np.empty(0))
    did, a, b, fa, fb = _brackets(grids(c, todo))
    x, r = _solve(c, did, a, b, fa, fb)
    good = np.isfinite(r)
    did, x, r = did[good], x[good], r[good]
    order = np.lexsort((np.abs(x - c["alpha_n"][did]), did))  # stable: equal distances keep the bracket order
    return Roots(did[order], x[order], r[order])


def closest(found: Roots, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per design: alpha_nw and the Eq 17 residual of the root closest to alpha_n (nan: no root)."""
    alpha = np.full(n, np.nan)
    resid = np.full(n, np.nan)
    did = found.design
    first = np.ones(did.size, dtype=bool)
    first[1:] = did[1:] != did[:-1]
    alpha[did[first]] = found.alpha_nw[first]
    resid[did[first]] = found.residual_mm[first]
    return alpha, resid
