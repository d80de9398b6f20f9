"""The tribology's result at one torque and speed (immutable) and its JSON and CSV."""
from __future__ import annotations

import math
import typing
from dataclasses import dataclass

import numpy as np

from ..result import Result


class Location(typing.NamedTuple):
    """Where a cell is: position, pair index (of the LTCA's tooth_pairs), cell, its point in S_f and
    the pinion surface parameters (l, u) of its centre."""

    position: int
    pair: int
    cell: int
    point_mm: tuple
    pinion_lu_mm: tuple


def _num(v, digits=None):
    """A JSON number or None (nan, inf, None)."""
    if v is None:
        return None
    v = float(v)
    if not math.isfinite(v):
        return None
    return round(v, digits) if digits is not None else v


@dataclass(frozen=True, eq=False)
class TribologyResult(Result):
    """Film, friction, power loss and flash temperature of one loaded analysis at one speed; arrays
    (N,) per position, (N, P) per position and pair, (N, P, C) per cell (nan where no load).  ``pair``
    the analysed pair, ``options`` the :class:`~beveloid.tribology.lubricant.Lubricant`."""

    torque_nm: float
    speed_rpm: float
    input_power_w: float
    position_power_loss_w: np.ndarray  # (N,) nan where the position did not converge
    mesh_power_loss_w: float  # mean over the converged positions of the cycle
    efficiency: float
    friction_coefficient_global: float  # ISO/TR 14179-2 from the pitch-point quantities
    friction_coefficient_mean: float  # load-weighted mean of the local coefficients
    loss_factor_hv: float  # mesh_power_loss / (input_power friction_coefficient_mean)
    friction_force_n: np.ndarray  # (N,) magnitude of the friction force on each member (equal, opposite)
    pair_film_thickness_central_um: np.ndarray  # (N, P) smallest over the pair's loaded cells
    pair_film_thickness_min_um: np.ndarray  # (N, P)
    lambda_min: float
    lambda_min_at: Location | None
    flash_temperature_max_c: float
    flash_temperature_at: Location | None
    bulk_temperature_c: float
    contact_temperature_max_c: float
    scuffing_temperature_c: float | None
    scuffing_safety: float | None
    oil_temperature_c: float
    dynamic_viscosity_mpa_s: float
    cell_mu: np.ndarray
    cell_film_central_um: np.ndarray
    cell_film_min_um: np.ndarray
    cell_lambda: np.ndarray
    cell_flash_c: np.ndarray
    cell_loss_density_w_mm2: np.ndarray
    cell_sliding_m_s: np.ndarray
    cell_sum_m_s: np.ndarray
    cells: typing.Any  # cells.Cells (speed-independent)
    tooth_pairs: np.ndarray
    fixed_friction: bool = False

    def location_json(self, loc):
        if loc is None:
            return None
        return {"position": loc.position, "pair": int(self.tooth_pairs[loc.pair]),
                "point_mm": [_num(v, 6) for v in loc.point_mm],
                "pinion_l_mm": _num(loc.pinion_lu_mm[0], 6), "pinion_u_mm": _num(loc.pinion_lu_mm[1], 6)}

    def to_json(self) -> dict:
        """The keys ``beveloid ltca`` reports (docs/tribology.md): null where not computed."""
        rows = lambda a: [[_num(v) for v in row] for row in a]  # noqa: E731
        return {
            "torque_nm": self.torque_nm,
            "speed_rpm": self.speed_rpm,
            "input_power_w": _num(self.input_power_w),
            "mesh_power_loss_w": _num(self.mesh_power_loss_w),
            "efficiency": _num(self.efficiency),
            "loss_factor_hv": _num(self.loss_factor_hv),
            "friction_coefficient_global": _num(self.friction_coefficient_global),
            "friction_coefficient_mean": _num(self.friction_coefficient_mean),
            "friction_model": "fixed" if self.fixed_friction else "ISO/TR 14179-2 local",
            "position_power_loss_w": [_num(v) for v in self.position_power_loss_w],
            "friction_force_n": [_num(v) for v in self.friction_force_n],
            "pair_film_thickness_central_um": rows(self.pair_film_thickness_central_um),
            "pair_film_thickness_min_um": rows(self.pair_film_thickness_min_um),
            "lambda_min": _num(self.lambda_min),
            "lambda_min_at": self.location_json(self.lambda_min_at),
            "flash_temperature_max_c": _num(self.flash_temperature_max_c),
            "flash_temperature_at": self.location_json(self.flash_temperature_at),
            "bulk_temperature_c": _num(self.bulk_temperature_c),
            "contact_temperature_max_c": _num(self.contact_temperature_max_c),
            "scuffing_temperature_c": _num(self.scuffing_temperature_c),
            "scuffing_safety": _num(self.scuffing_safety),
            "oil_temperature_c": self.oil_temperature_c,
            "dynamic_viscosity_mpa_s": _num(self.dynamic_viscosity_mpa_s),
        }

    CSV_COLUMNS = ("position", "pair", "cell", "x_mm", "y_mm", "z_mm", "pressure_mpa", "sliding_profile_m_s",
                   "sliding_lengthwise_m_s", "sliding_speed_m_s", "sum_speed_m_s", "entrainment_angle_deg",
                   "friction_coefficient", "loss_density_w_mm2", "film_central_um", "film_min_um", "lambda",
                   "flash_temperature_c")

    def csv_rows(self) -> list:
        """One row per loaded cell and position (:attr:`CSV_COLUMNS`)."""
        c = self.cells
        w = self.speed_rpm * 2 * math.pi / 60
        out = []
        for j, k, i in zip(*np.nonzero(c.loaded)):
            x, y, z = c.point[j, k, i]
            out.append((int(j), int(self.tooth_pairs[k]), int(i), x, y, z, c.pressure_mpa[j, k, i],
                        c.sliding_profile[j, k, i] * w, c.sliding_lengthwise[j, k, i] * w,
                        self.cell_sliding_m_s[j, k, i], self.cell_sum_m_s[j, k, i],
                        c.entrainment_angle_deg[j, k, i], self.cell_mu[j, k, i],
                        self.cell_loss_density_w_mm2[j, k, i], self.cell_film_central_um[j, k, i],
                        self.cell_film_min_um[j, k, i], self.cell_lambda[j, k, i], self.cell_flash_c[j, k, i]))
        return out
