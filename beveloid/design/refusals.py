"""The one-line refusals of one design for the outcomes decided before its members exist: a zero cone
angle, no root of Eq 17, the gear helix angle, non-finite outputs, non-physical pitch radii (the
tooth and pitch-point refusals are in checks.py beside their geometry)."""
from __future__ import annotations

import math

import numpy as np

from ..names import Member
from ..spec import DesignSpec
from . import solve
from .checks import Outcome
from .kernels import deg_text, direct_outputs, member_outputs, num_text
from .members import DesignError


def zero_cone_angle(spec: DesignSpec) -> DesignError:
    for member in Member:
        if getattr(spec, member).cone_angle_deg == 0.0:
            key = f"{member}.cone_angle_deg"
            return DesignError(
                f"{key} = 0.0: a beveloid member needs a non-zero cone angle (with gamma = 0 the pitch cone is a"
                f" cylinder, its apex and the mounting distance of Eqs 13-14 are at infinity);"
                f" increase |{key}| above 0", keys=(key,), source=spec.source, outcome=Outcome.ZERO_CONE_ANGLE)
    return DesignError("a cone angle is zero", keys=("pinion.cone_angle_deg", "gear.cone_angle_deg"),
                       source=spec.source, outcome=Outcome.ZERO_CONE_ANGLE)


def no_working_pressure_angle(spec: DesignSpec, c: dict) -> DesignError:
    """No root of Eq 17 for the one design of the constants ``c``: why (from its alpha_nw grid)."""
    g = solve.grids(c, np.zeros(1, dtype=np.int64))
    grid, res, ok = g.alpha_nw, g.residual_mm, g.admissible
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
                f" 60 deg; reduce |pinion.helix_angle_deg|", keys=("pinion.helix_angle_deg",), source=src, outcome=Outcome.NO_WORKING_PRESSURE_ANGLE)
        if tangent.any():
            return DesignError(
                f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}, pair.shaft_angle_deg ="
                f" {spec.pair.shaft_angle_deg!r}: the gear's working helix angle beta_w2 = eta - beta_w1 (Eq 16)"
                f" reaches 90 deg for every alpha_nw up to 60 deg; move pinion.helix_angle_deg toward the shaft"
                f" angle ({'increase' if spec.pinion.helix_angle_deg < spec.pair.shaft_angle_deg else 'reduce'} it)",
                keys=("pinion.helix_angle_deg", "pair.shaft_angle_deg"), source=src, outcome=Outcome.NO_WORKING_PRESSURE_ANGLE)
        return DesignError(
            f"pair.shaft_angle_deg = {spec.pair.shaft_angle_deg!r}: the pitch cones cannot touch"
            f" (sin^2 delta < sin^2 gw1 + sin^2 gw2 + 2 sin gw1 sin gw2 cos delta for every alpha_nw up to 60 deg,"
            f" with pinion.cone_angle_deg = {spec.pinion.cone_angle_deg!r}, gear.cone_angle_deg ="
            f" {spec.gear.cone_angle_deg!r}); increase the shaft angle or reduce the cone angles",
            keys=("pair.shaft_angle_deg", "pinion.cone_angle_deg", "gear.cone_angle_deg"), source=src, outcome=Outcome.NO_WORKING_PRESSURE_ANGLE)
    a_ok = grid[ok]
    e_model = solve.scan(a_ok, c, np.zeros(a_ok.size, dtype=np.int64), offset=np.zeros(1))[0]  # E(alpha_nw) itself
    span = (f"Eq 17 gives E from {num_text(e_model.min())} to {num_text(e_model.max())} mm for alpha_nw from"
            f" {deg_text(a_ok.min())} to {deg_text(a_ok.max())} deg")
    head = f"pair.offset_mm = {spec.pair.offset_mm!r}: no working normal pressure angle solves Eq 17"
    # E(alpha_nw) is 0 at the grid's open lower end (Eq 25's bound): an offset below every other value
    # of the range is too small (its root, if any, lies at that end, where it cannot be resolved)
    positive = e_model[e_model > 0]
    smallest = float(positive.min()) if positive.size else float(e_model.min())
    if (res[ok] > 0).all() or spec.pair.offset_mm < smallest:
        return DesignError(
            f"{head}: the offset is too small for the given teeth, module and helix angles ({span});"
            f" increase pair.offset_mm to at least {num_text(smallest)} mm or reduce the teeth or module",
            keys=("pair.offset_mm",), source=src, outcome=Outcome.NO_WORKING_PRESSURE_ANGLE)
    return DesignError(
        f"{head}: the offset is too large for the given teeth, module and helix angles ({span});"
        f" reduce pair.offset_mm to at most {num_text(e_model.max())} mm or increase the teeth or module",
        keys=("pair.offset_mm",), source=src, outcome=Outcome.NO_WORKING_PRESSURE_ANGLE)


def root_notes(c: dict, roots: solve.Roots) -> list[str]:
    """Notes on the root taken (one design): several roots, or solved only to floating-point resolution."""
    alpha_n = float(c["alpha_n"][0])
    x, r = float(roots.alpha_nw[0]), float(roots.residual_mm[0])
    notes = []
    if roots.alpha_nw.size > 1:
        listed = ", ".join(deg_text(v) for v in sorted(roots.alpha_nw))
        notes.append(f"Eq 17 has {roots.alpha_nw.size} roots alpha_nw = {listed} deg; chose {deg_text(x)} deg,"
                     f" the one closest to alpha_n = {deg_text(alpha_n)} deg")
    if abs(r) >= float(solve.tolerance(c["E"][0])):
        notes.append(f"Eq 17 solved only to |E(alpha_nw) - E| = {abs(r):.2g} mm: alpha_nw = {deg_text(x)} deg is at"
                     f" floating-point resolution (E(alpha_nw) is very steep there, near the end of the tangency"
                     f" range)")
    return notes


def gear_helix_angle(spec: DesignSpec, q: dict) -> DesignError:
    beta2 = q["beta2"]
    shown = f"{deg_text(beta2)} deg" if math.isfinite(beta2) else "not real (|sin beta2| > 1)"
    # beta2 ~ eta - beta_w1 with eta ~ delta: move beta1 toward delta
    bw2 = q["beta_w2"]
    direction = "increase" if (bw2 > 0 if math.isfinite(bw2) else True) else "reduce"
    return DesignError(
        f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}: the gear helix angle beta2 (Eq 26,"
        f" beta_w2 = eta - beta_w1 of Eq 16) is {shown}, |beta2| must stay below 80 deg;"
        f" {direction} pinion.helix_angle_deg (beta2 ~ shaft angle - beta1)",
        keys=("pinion.helix_angle_deg", "pair.shaft_angle_deg"), source=spec.source, outcome=Outcome.GEAR_HELIX_ANGLE_OUT_OF_RANGE)


def non_finite(spec: DesignSpec, q: dict, alpha_nw: float) -> DesignError:
    bad = sorted(k for k, v in q.items() if not math.isfinite(v))
    return DesignError(
        f"pinion.cone_angle_deg = {spec.pinion.cone_angle_deg!r}, gear.cone_angle_deg ="
        f" {spec.gear.cone_angle_deg!r}: the design equations give non-finite {', '.join(bad)}"
        f" at alpha_nw = {deg_text(alpha_nw)} deg; increase |cone angles| or the shaft angle",
        keys=("pinion.cone_angle_deg", "gear.cone_angle_deg"), source=spec.source, outcome=Outcome.NON_FINITE_DESIGN)


def pitch_radius(spec: DesignSpec, q: dict) -> DesignError:
    for name in Member:
        o = member_outputs(q, name)
        if not o.working_pitch_radius_mm > 0 or not o.reference_pitch_radius_mm > 0:
            break
    return DesignError(
        f"{name}.teeth = {getattr(spec, name).teeth}: non-physical {name} pitch radius"
        f" (r = {num_text(o.reference_pitch_radius_mm)}, r_w = {num_text(o.working_pitch_radius_mm)} mm);"
        f" increase {name}.teeth", keys=(f"{name}.teeth",), source=spec.source, outcome=Outcome.NON_PHYSICAL_PITCH_RADIUS)
