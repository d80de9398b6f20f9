"""The mesh: the transmission-error formula and the tooth-pair envelope, shared by the TCA, the
sweep, the backlash and the loaded TCA.

* TE = phi'_2 - phi'_2,ref + (N1/N2)(phi'_1 - phi'_1,ref), the reference being the contact at
  the pitch point P of the aligned pair on the same flank (:func:`transmission_error`).
* Pair k (pinion tooth k with gear tooth k) at pinion angle phi'_1 is pair 0 at phi'_1 - k p_1,
  its gear turned by -k p_2 (:func:`pair_angles`); its TE is pair 0's TE at phi'_1 - k p_1.
* At each pinion angle the tooth pair that constrains the gear most carries the contact: the
  largest TE when the flank's first-touch sign is +1, the smallest when -1 (:func:`envelope`).
* The envelope is the mesh's TE only where every pair that can touch was solved
  (:func:`envelope_complete`); its peak-to-peak is taken there (tca and sweep alike).
* A loaded TCA samples one mesh cycle (one pinion pitch) with both its ends: the last position is the
  first one's mesh state again, so N positions are N - 1 distinct mesh states (:func:`cycle_positions_text`,
  said in the output and in ``--help``).
"""
from __future__ import annotations

import numpy as np

#: an envelope point is carried by every pair within this of the envelope (abs + rel x |env|, rad)
ACTIVE_ABS_RAD = 1e-12
ACTIVE_REL = 1e-9


def transmission_error(gear_angle_rad, pinion_angle_rad, ref_gear_angle_rad, ref_pinion_angle_rad, ratio):
    """TE (rad) = phi'_2 - phi'_2,ref + ratio (phi'_1 - phi'_1,ref), ratio = N1/N2; broadcasts."""
    return gear_angle_rad - ref_gear_angle_rad + ratio * (pinion_angle_rad - ref_pinion_angle_rad)


def pair_angles(pinion_angle_rad, pairs, pinion_pitch_rad):
    """(pair indices k (pairs,), pair 0's pinion angles (pairs, N) standing for pair k at the given angles)."""
    ks = np.arange(pairs) - pairs // 2
    phi = np.asarray(pinion_angle_rad, dtype=float)
    return ks, phi[None, :] - ks[:, None] * pinion_pitch_rad


def envelope(values_by_pair, sign):
    """(envelope (N,), active (pairs, N)) of per-pair values (pairs, N), nan where a pair has no
    contact: the largest value when ``sign`` > 0, else the smallest; nan where no pair has one.
    ``active`` marks the pairs that carry the envelope (to ACTIVE_ABS_RAD + ACTIVE_REL |env|)."""
    v = np.asarray(values_by_pair, dtype=float)
    with np.errstate(invalid="ignore"):
        if sign > 0:
            env = np.where(np.isnan(v), -np.inf, v).max(axis=0)
        else:
            env = np.where(np.isnan(v), np.inf, v).min(axis=0)
    env = np.where(np.isfinite(env), env, np.nan)
    with np.errstate(invalid="ignore"):
        active = (np.abs(v - env[None, :]) <= ACTIVE_ABS_RAD + ACTIVE_REL * np.abs(env)[None, :]) & np.isfinite(v)
    return env, active


def peak_to_peak(values):
    """max - min of the finite values (nan when there are none) along the last axis."""
    v = np.asarray(values, dtype=float)
    has = np.isfinite(v).any(axis=-1)
    with np.errstate(invalid="ignore"):
        hi = np.where(np.isfinite(v), v, -np.inf).max(axis=-1)
        lo = np.where(np.isfinite(v), v, np.inf).min(axis=-1)
    out = np.where(has, hi - lo, np.nan)
    return float(out) if out.ndim == 0 else out


def envelope_complete(pinion_angle_rad, ks, active, pinion_pitch_rad, margin_rad):
    """(N,) bool: the pinion angles at which no tooth pair beyond ``ks`` can carry the contact.

    Pair k at phi is pair 0 at psi = phi - k p1.  The angles psi at which a solved pair carries the
    envelope (``active`` (pairs, N), :func:`envelope`), widened by ``margin_rad`` (their spacing),
    give pair 0's carrying interval [lo, hi]; a pair k beyond ``ks`` can carry at phi only if
    phi - k p1 lies in it.  When the interval reaches the first or last solved psi it may go on
    beyond them: then no position is known complete.
    """
    phi = np.asarray(pinion_angle_rad, dtype=float)
    ks = np.asarray(ks)
    psi = phi[None, :] - ks[:, None] * pinion_pitch_rad
    carried = psi[np.asarray(active, dtype=bool)]
    if carried.size == 0:
        return np.zeros(phi.shape, dtype=bool)
    lo, hi = carried.min() - margin_rad, carried.max() + margin_rad
    if lo <= psi.min() or hi >= psi.max():
        return np.zeros(phi.shape, dtype=bool)
    complete = np.ones(phi.shape, dtype=bool)
    k_lo = int(np.floor((phi.min() - hi) / pinion_pitch_rad))  # every k whose psi can fall in [lo, hi]
    k_hi = int(np.ceil((phi.max() - lo) / pinion_pitch_rad))
    for k in [*range(k_lo, int(ks.min())), *range(int(ks.max()) + 1, k_hi + 1)]:
        shifted = phi - k * pinion_pitch_rad
        complete &= ~((shifted >= lo) & (shifted <= hi))
    return complete


def cycle_positions_text(positions: int) -> str:
    """N positions over one mesh cycle in words, with the N - 1 distinct mesh states they are (one
    position: the reference contact alone)."""
    if positions == 1:
        return "1 position: the reference contact"
    states = positions - 1
    return (f"{positions} positions over one mesh cycle, its first and last one pitch apart ({states} distinct "
            f"mesh state{'' if states == 1 else 's'})")


def cycle_positions_help(default: int) -> str:
    """The ``--positions`` help of the commands that run a loaded TCA over one mesh cycle."""
    return (f"pinion positions over one mesh cycle, its first and last one pitch apart: N positions are N - 1 "
            f"distinct mesh states (default {default})")
