"""Film, friction, power loss and flash temperature on every contact cell of a loaded analysis, at
one speed (:func:`evaluate`), from the speed-independent :class:`cells.Cells`."""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..ltca.model.gaps import principal_frame
from ..tca.reference import reference_contact
from . import laws
from .cells import STRAIGHT_CURVATURE, Cells, scatter
from .lubricant import Lubricant
from .result import Location, TribologyResult


def rpm_to_rad_s(rpm):
    return rpm * 2.0 * math.pi / 60.0


@dataclass(frozen=True)
class PitchPoint:
    """The aligned pair at its pitch point, per rad/s of the pinion: ISO/TR 14179-2's global quantities."""

    sum_velocity_m_s: float  #: per rad/s: the sum velocity's part across the contact line (ISO's v_sum,C)
    reduced_radius_mm: float  #: relative radius of curvature across the contact line (ISO's rho_C, normal section)
    pinion_arm_mm: float  #: moment arm of the normal about the pinion axis (the base radius of a spur pinion)
    face_width_mm: float  #: the smaller face width


@functools.lru_cache(maxsize=64)
def pitch_point(geom, flank) -> PitchPoint:
    """The pitch-point kinematics and curvature (the TE reference contact, aligned); cached per geometry
    and flank (every torque and speed of a map shares it).  ISO's sum velocity 2 v_t sin(alpha_wt) is the
    part of the sum velocity across the contact line (its part along a helical pair's line does not
    entrain); its radius is the relative radius across the line (docs/tribology.md, "Directions")."""
    from ..generated import contact_kinematics

    ref = reference_contact(geom, flank)
    x = np.asarray(ref.x, dtype=float)
    zero = np.zeros(5)
    fr = principal_frame(geom, flank, x[None], np.array([ref.pinion_angle]), zero)
    s = geom.surface("pinion", flank, x[0], x[1])
    kin = contact_kinematics.contact_velocities(s.point, s.normal, ref.pinion_angle, 1.0, float(geom.pinion.teeth),
                                                float(geom.gear.teeth), zero, geom.placement())
    from ..generated import placement

    rot = placement.pinion_placement(ref.pinion_angle, geom.placement()).rotation
    across = rot @ fr.axes[0, 0]  # in S_f, like the velocities
    k = float(fr.curvature_across[0])
    return PitchPoint(abs(float(kin.sum_velocity @ across)), 1.0 / max(k, STRAIGHT_CURVATURE),
                      float(fr.pinion_arm_mm[0]), float(min(geom.pinion.face_width_mm, geom.gear.face_width_mm)))


def global_friction(pp: PitchPoint, lub: Lubricant, torque_nm, speed_rpm, ra_mean_um):
    """ISO/TR 14179-2's mean coefficient of friction of the pair from its pitch-point quantities."""
    f_bt = abs(torque_nm) * 1e3 / pp.pinion_arm_mm
    return float(laws.schlenk_mu(f_bt / pp.face_width_mm, pp.sum_velocity_m_s * rpm_to_rad_s(speed_rpm),
                                 pp.reduced_radius_mm, lub.dynamic_viscosity_mpa_s, ra_mean_um,
                                 lub.lubricant_factor_xl))


def evaluate_cells(cells: Cells, result, pp: PitchPoint, lub: Lubricant, speed_rpm, roughness_ra_um,
                   e_star_mpa, pair=None) -> TribologyResult:
    """The tribology of one loaded analysis (``result``, its ``cells``) at ``speed_rpm``."""
    w = rpm_to_rad_s(speed_rpm)
    torque = float(result.torque_nm)
    ra = 0.5 * (roughness_ra_um[0] + roughness_ra_um[1])
    e_prime_mpa = 2.0 * e_star_mpa
    c = cells
    loaded = c.loaded
    # every law on the loaded cells only (a fraction of the grid), scattered back at the end
    q = c.line_load_n_per_mm[loaded]
    p = c.pressure_mpa[loaded]
    norm = lambda v: np.linalg.norm(v[loaded], axis=-1) * w  # noqa: E731
    vs, vsum, v1, v2 = (norm(v) for v in (c.sliding_velocity, c.sum_velocity, c.pinion_velocity, c.gear_velocity))
    # a line contact is entrained, and its band crossed, only across the line: there the speeds are the
    # velocities' parts across it and the radius the principal one across it (docs/tribology.md, "Directions")
    line = np.broadcast_to(c.line_contact[..., None], loaded.shape)[loaded]
    rx = np.where(line, c.radius_across_mm[loaded], c.radius_sum_mm[loaded])
    vsum = np.where(line, c.sum_across[loaded] * w, vsum)
    v1 = np.where(line, c.pinion_across[loaded] * w, v1)
    v2 = np.where(line, c.gear_across[loaded] * w, v2)
    area = np.broadcast_to(c.area_mm2[..., None], loaded.shape)[loaded]
    with np.errstate(all="ignore"):
        if lub.friction_coefficient is not None:
            mu = np.full(p.shape, lub.friction_coefficient)
        else:
            mu = laws.schlenk_mu(q, vsum, rx, lub.dynamic_viscosity_mpa_s, ra, lub.lubricant_factor_xl)
        force = p * area  # N per cell
        loss_density = mu * p * vs  # W/mm^2
        oil = (lub.dynamic_viscosity_pa_s, lub.pressure_viscosity_1_per_pa, e_prime_mpa * 1e6)
        hc, hm = laws.hamrock_dowson(0.5 * vsum, rx, c.radius_side_mm[loaded], c.pair_load_n[loaded], *oil)
        lc, lm = laws.line_contact_film(0.5 * vsum, rx, q, *oil)
        hc, hm = np.where(line, lc, hc), np.where(line, lm, hm)
        b = laws.hertz_half_width_mm(q, rx, e_prime_mpa)
        flash = laws.blok_flash_c(mu, q, vs, v1, v2, b)
    full = lambda a: scatter(a, loaded)  # noqa: E731
    cell_loss = full(loss_density * area)
    mu_f, hc, hm, flash = full(mu), full(hc), full(hm), full(flash)
    lam = hm / ra
    ok = np.asarray(result.converged)
    pos_loss = np.where(ok, np.nansum(cell_loss, axis=(1, 2)), np.nan)
    mean_loss = cycle_mean(pos_loss)
    p_in = abs(torque) * w
    total = float(np.sum(force))
    mu_mean = float(np.sum(mu * force) / total) if total > 0 else math.nan
    with np.errstate(invalid="ignore"):
        sv = c.sliding_velocity[loaded]
        unit = sv / np.linalg.norm(sv, axis=-1, keepdims=True)
    f_cells = np.zeros(loaded.shape + (3,))
    f_cells[loaded] = np.nan_to_num((mu * force)[:, None] * unit)
    f_pinion = -f_cells.sum(axis=(1, 2))  # (N, 3)
    friction_force = np.where(ok, np.linalg.norm(f_pinion, axis=-1), np.nan)
    any_loaded = loaded.any(axis=-1)
    with np.errstate(all="ignore"):
        pair_hc = np.where(any_loaded, np.nanmin(np.where(loaded, hc, np.inf), axis=-1), np.nan)
        pair_hm = np.where(any_loaded, np.nanmin(np.where(loaded, hm, np.inf), axis=-1), np.nan)
    flash_max, flash_at = _extreme(flash, c, np.nanargmax)
    lam_min, lam_at = _extreme(lam, c, np.nanargmin)
    bulk = laws.bulk_temperature_c(lub.temperature_c, flash_max) if math.isfinite(flash_max) else math.nan
    contact_max = bulk + flash_max
    scuff_t = (laws.scuffing_temperature_c(lub.fzg_load_stage, lub.lubricant_factor_xl)
               if lub.fzg_load_stage is not None else None)
    safety = (laws.scuffing_safety(scuff_t, contact_max, lub.temperature_c)
              if scuff_t is not None and math.isfinite(contact_max) and contact_max > lub.temperature_c else None)
    mu_global = global_friction(pp, lub, torque, speed_rpm, ra)
    return TribologyResult(
        torque_nm=torque, speed_rpm=float(speed_rpm), input_power_w=p_in, position_power_loss_w=pos_loss,
        mesh_power_loss_w=mean_loss, efficiency=1.0 - mean_loss / p_in if p_in > 0 else math.nan,
        friction_coefficient_global=mu_global, friction_coefficient_mean=mu_mean,
        loss_factor_hv=mean_loss / (p_in * mu_mean) if p_in > 0 and mu_mean > 0 else math.nan,
        friction_force_n=friction_force, pair_film_thickness_central_um=pair_hc, pair_film_thickness_min_um=pair_hm,
        lambda_min=lam_min, lambda_min_at=lam_at, flash_temperature_max_c=flash_max, flash_temperature_at=flash_at,
        bulk_temperature_c=bulk, contact_temperature_max_c=contact_max, scuffing_temperature_c=scuff_t,
        scuffing_safety=safety, oil_temperature_c=lub.temperature_c,
        dynamic_viscosity_mpa_s=lub.dynamic_viscosity_mpa_s,
        cell_mu=mu_f, cell_film_central_um=hc, cell_film_min_um=hm, cell_lambda=lam, cell_flash_c=flash,
        cell_loss_density_w_mm2=full(loss_density), cell_sliding_m_s=full(vs), cell_sum_m_s=full(vsum), cells=c, tooth_pairs=np.asarray(result.tooth_pairs),
        fixed_friction=lub.friction_coefficient is not None, pair=pair, options=lub)


def cycle_mean(per_position):
    """The mean over one mesh cycle of a value at the N positions (the first and last one pitch apart:
    the same mesh state, each weighted half); positions that did not converge (nan) left out."""
    a = np.asarray(per_position, dtype=float)
    wts = np.ones(a.size)
    if a.size > 1:
        wts[[0, -1]] = 0.5
    ok = np.isfinite(a)
    return float(np.sum(wts[ok] * a[ok]) / np.sum(wts[ok])) if ok.any() else math.nan


def _extreme(a, c: Cells, pick):
    """(value, Location) of ``pick`` (nanargmax / nanargmin) over the loaded cells; (nan, None) if none."""
    if not np.isfinite(a).any():
        return math.nan, None
    idx = np.unravel_index(int(pick(a)), a.shape)
    return float(a[idx]), Location(position=int(idx[0]), pair=int(idx[1]), cell=int(idx[2]),
                                   point_mm=tuple(float(v) for v in c.point[idx]),
                                   pinion_lu_mm=tuple(float(v) for v in c.pinion_lu[idx]))
