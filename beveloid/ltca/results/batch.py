"""Many loaded analyses of one pair in one call: N positions x T torques x K assembly error sets.

    from beveloid import ltca
    batch = ltca.analyze_many(pair, ltca.LoadCase([50, 100, 200, 400],
                                                  errors=[(0, 0, 0, 0, 0), (0.02, 0, 0, 0, 0)]))
    batch.te_peak_to_peak_urad  # (K, T)
    batch.results[k][t]         # the LTCAResult of error set k at torque t

The one engine of :func:`beveloid.ltca.analyze` (:func:`beveloid.ltca.passes.analysis.run_many`): the FE data
and the teeth once per pair, the rigid reference once per error set, every contact problem of a pass
of every case in one compiled call.  ``results[k][t]`` equals ``analyze`` with that torque and that
error set.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import OptionError
from ...names import MEMBERS
from ...result import Result, num

__all__ = ["Batch", "summary"]


@dataclass(frozen=True)
class Batch(Result):
    """K error sets x T torques of one pair (``results[k][t]``) and their arrays (module docstring);
    deep-frozen, its JSON by :meth:`to_json` (each run's :meth:`LTCAResult.to_json` with the map's numbers)."""

    torque_nm: np.ndarray  # (T,)
    errors: np.ndarray  # (K, 5) dx, dy, dz mm; vertical, horizontal rad
    results: tuple  # K tuples of T LTCAResults
    extra: tuple = ()  # the LTCAResult of each extra case of analyze_many(..., extra=)

    def _each(self, fn) -> np.ndarray:
        return np.array([[fn(r) for r in row] for row in self.results], dtype=float)

    @property
    def loaded_te_rad(self) -> np.ndarray:
        """(K, T, N) the loaded TE (rad), nan where a position did not converge."""
        return np.array([[r.loaded_te for r in row] for row in self.results])

    @property
    def te_peak_to_peak_urad(self) -> np.ndarray:
        """(K, T) the loaded TE peak-to-peak (urad), nan with fewer than 3 converged positions."""
        return self._each(lambda r: r.loaded_te_peak_to_peak * 1e6)

    @property
    def max_pressure_mpa(self) -> np.ndarray:
        """(K, T) the largest entry of each run's pair_max_pressure_mpa (edge peaks included)."""
        return self._each(lambda r: summary(r)["max_pressure_mpa"])

    def root_stress_max_mpa(self, member: str) -> np.ndarray:
        """(K, T) the member's largest root stress (MPa; nan with the plate tooth)."""
        return self._each(lambda r: summary(r)["root_stress_max_mpa"][member])

    def to_json(self) -> dict:
        """``torque_nm`` (T,), ``errors`` (K, 5), ``te_peak_to_peak_urad`` and ``max_pressure_mpa`` (K, T) (null
        where not known), and ``results``: K lists of T :meth:`LTCAResult.to_json`."""
        rows = lambda a: [[num(v) for v in row] for row in a]  # noqa: E731
        return {"torque_nm": [float(t) for t in self.torque_nm], "errors": [[float(v) for v in e] for e in self.errors],
                "te_peak_to_peak_urad": rows(self.te_peak_to_peak_urad), "max_pressure_mpa": rows(self.max_pressure_mpa),
                "results": [[r.to_json() for r in row] for row in self.results]}


def _finite_max(a) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.nanmax(a)) if np.isfinite(a).any() else math.nan


def summary(result) -> dict:
    """The per-run numbers of the torque map and the tolerance box: ``te_peak_to_peak_urad``,
    ``max_pressure_mpa`` (the largest pair_max_pressure_mpa, edge peaks included),
    ``root_stress_max_mpa`` {member} (nan with the plate tooth), ``mesh_stiffness_mean_n_per_um``,
    ``mesh_stiffness_peak_to_peak_n_per_um`` (nan where not known), ``edge_contact`` (an edge peak anywhere),
    ``loaded_contact_ratio`` (:func:`loaded_contact_ratio`).
    The stiffness statistics are over the cycle's N - 1 distinct states, as :func:`te_harmonics`: the
    last position is the first one a pitch later, counted once."""
    k = np.asarray(result.mesh_stiffness_n_per_um if result.mesh_stiffness_n_per_um is not None else [], float)[:-1]
    k = k[np.isfinite(k)]
    root = result.root_stress_max_mpa()
    return {"te_peak_to_peak_urad": result.loaded_te_peak_to_peak * 1e6,
            "max_pressure_mpa": _finite_max(result.pair_max_pressure_mpa),
            "root_stress_max_mpa": {m: (math.nan if root.get(m) is None else root[m]) for m in MEMBERS},
            "mesh_stiffness_mean_n_per_um": float(k.mean()) if k.size else math.nan,
            "mesh_stiffness_peak_to_peak_n_per_um": float(k.max() - k.min()) if k.size >= 3 else math.nan,
            "edge_contact": bool(np.isfinite(result.pair_edge_max_pressure_mpa).any()),
            "loaded_contact_ratio": loaded_contact_ratio(result)}


#: a tooth pair carries load at a position when its normal load exceeds this share of the position's total
LOADED_SHARE = 1e-6


def loaded_contact_ratio(result) -> float:
    """The loaded contact ratio: the mean number of tooth pairs that carry load (more than
    :data:`LOADED_SHARE` of the position's total) over the converged positions among the cycle's N - 1
    distinct states (the last position is the first a pitch later); its resolution is 1 / (N - 1).
    nan without a converged position."""
    ok = np.asarray(result.converged, dtype=bool)[:-1]
    loads = np.nan_to_num(np.asarray(result.pair_load_n, dtype=float)[:-1][ok])
    if not loads.size:
        return math.nan
    carrying = loads > LOADED_SHARE * loads.sum(axis=1, keepdims=True)
    return float(carrying.sum(axis=1).mean())


def check_torques(values, key="torques_nm") -> np.ndarray:
    """(T,) the torques, each as ltca.Options checks it; at least one."""
    from ..options import check_torque

    vals = list(np.atleast_1d(np.asarray(values, dtype=object)).ravel())
    if not vals:
        raise OptionError(key, values, "must hold one torque at least (N m, > 0)")
    number = lambda v: float(v) if isinstance(v, (int, float, np.number)) and not isinstance(v, bool) else v  # noqa: E731
    return np.array([check_torque(number(v), key=key) for v in vals], dtype=float)


def check_error_sets(values, key="error_sets") -> np.ndarray:
    """(K, 5) finite assembly error sets (dx, dy, dz mm; vertical, horizontal rad); at least one."""
    try:
        e = np.asarray(values, dtype=float).reshape(-1, 5) if np.size(values) else np.zeros((0, 5))
    except (TypeError, ValueError):
        e = None
    if e is None or e.shape[0] == 0 or not np.all(np.isfinite(e)):
        raise OptionError(key, values, "must be one or more sets of 5 finite numbers (dx, dy, dz mm; vertical, "
                                       "horizontal rad)")
    return e


#: the mesh orders of te_harmonics_urad
MESH_ORDERS = tuple(range(1, 7))


def gear_base_radius_mm(geom) -> float:
    """The gear's base radius at its reference section (r_b2 = r_2 cos alpha_t, tan alpha_t = tan alpha_n /
    cos beta_2): a gear rotation (rad) times it is a displacement along the line of action (mm)."""
    g = geom.gear
    alpha_t = math.atan(math.tan(geom.normal_pressure_angle) / math.cos(g.helix_angle))
    return g.pitch_radius_mm * math.cos(alpha_t)


def te_harmonics(result) -> np.ndarray:
    """(6,) the amplitudes (rad) of mesh orders 1-6 of the loaded TE over the cycle: the LTCA's positions
    span exactly one mesh cycle with the end point repeated, which is counted once (the first N - 1
    positions are the samples of one period); amplitude of order h = 2 |DFT_h| / (N - 1).  nan for every
    order when a position did not converge, and for an order at or above half the samples (aliased)."""
    te = np.asarray(result.loaded_te, dtype=float)[:-1]
    out = np.full(len(MESH_ORDERS), np.nan)
    M = te.size
    if M < 2 or not np.all(np.isfinite(te)):
        return out
    spectrum = np.fft.rfft(te - te.mean())
    for i, h in enumerate(MESH_ORDERS):
        if h < M / 2:
            out[i] = 2.0 * abs(spectrum[h]) / M
    return out
