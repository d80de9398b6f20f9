"""Is the FE tooth's root stress, the one the local S_F divides by, converged?  (issue 57.5)

That root stress is the LTCA's: the largest principal stress of the FE tooth's fillet tensors read on a grid
fixed by the geometry (``fe.tooth.tooth_data``, ``fe.contact.readout_matrix``: a moving least-squares fit
of the nodes' tensors over a window of +-1 fillet element of refinement 1 along the profile).

The LTCA's loads (the cell forces of every converged, loaded position and pair) are read twice more: with
the FE tooth of a mesh :data:`CHECK_COARSEN` times coarser (every element size doubled), whose read-out's
window is widened to 0.75 of its own fillet elements (1.5 times the default's: ``fe.contact.readout_window_mm``),
and with the default's mesh read through that same wider window (``tooth_data(..., smooth=<that coarsening>)``).
Both data are computed once per design and cached like the default's; the second is a read-out of the
default's solution, so a rating computes it with the default's data from one solve (:func:`prepare`, before
its LTCA: ``fe.cache.cached_tooth_data`` with a tuple of read-outs).  The load distribution is kept:
between the coarsened and the default tooth it moves the largest root stress by about 0.3 % (design A of
docs/validation.md 10.2: 517.3 / 589.9 MPa read this way against 518.8 / 589.2 MPa from the coarsened
tooth's own LTCA).

The two readings through the same window (c coarse, w the default's mesh) differ by the mesh alone: the
FE field's change at a fixed filter (``change`` = w / c - 1).  The default's own reading d lies above w by the
narrower window's effect (a sharper view of the same peak, 0.8-7.0 % on docs/validation.md 10.2's members:
``window_effect``, reported, not an error).

**The estimate is the band docs/validation.md 10.2 validated, not a two-mesh index.**  On its 18 members (case 1,
case 2, R1, R2, R3, R5701-1, -3, -4 and U11, both members, at ``MESH_RULES_VERSION`` 8) the default reads
:data:`VALIDATED_BAND` (-2.7 ... +2.4 %) from a refined value (every size / 1.5, or the mean of refined draws).
A two-mesh estimate cannot show that: Roache's grid convergence index of the coarse check (refinement ratio 2,
safety factor :data:`SAFETY_FACTOR` 3, order :data:`ORDER` 1), ``coarse_gci`` = 3 |w / c - 1|, is 7.3-36 % on
those members, because the coarsened mesh's fillet elements are 1.0-1.14 times the fillet's smallest radius (the
notch is not resolved there, the step from it not in the asymptotic range), and a single reading scatters 1-2.6 %
with the nodes' placement (10.2, ``--jitter``), so no pair of meshes a factor 1.5-2 apart brings it under 3 % where
the truth is within it.  ``coarse_gci`` is reported and kept as an alarm only.

``converged``: the design lies inside the range 10.2 validated (:func:`outside_validated`, each parameter's
bounds those of its 18 members):

* the default mesh (``fe_refinement`` 1, ``fe_coarsen`` 1; the band is of that mesh);
* the fillet's smallest radius over the normal module, :data:`VALIDATED_RADIUS_PER_MODULE` (a sharper notch,
  design B's or C's gear, is not resolved at its elements; a rounded rack's fillet, meshed at 0.5 rho_F, moved
  +14 % under refinement on design B's gear: docs/rating.md 5);
* that radius over the fillet's elements, :data:`VALIDATED_RADIUS_ELEMENTS`;
* the coarse check's change, |change| no larger than the largest on the 18 members, :data:`VALIDATED_CHANGE`
  (the alarm: a field that moves more from the coarsened mesh than on any validated member);
* the maximum clear of the face ends: not within the load grid's end span of a face end (the last
  :data:`beveloid.fe.tooth.FACE_FRACTIONS` step before its second column, 1/16 of the face), where the LTCA's
  contact is lumped onto the grid's end columns and the reading depends on their spacing, not on the mesh
  (``benchmarks/fe_load_grid.py``; the validated members' maxima all lie mid-face).

Inside, ``error_estimate`` is the band's largest magnitude and ``error_band`` the band, their source in
``error_estimate_source``; outside, both null, ``converged`` false and ``outside_range`` names each parameter outside
with its value and the validated bounds.  The band was measured at one mesh rule: :data:`VALIDATED_MESH_RULES_VERSION`
(a test holds ``fe.mesh.MESH_RULES_VERSION`` to it, so that a new rule is validated again before it is rated).
"""
from __future__ import annotations


import numpy as np

from ..fe.tooth import FACE_FRACTIONS
from ..names import MEMBERS

__all__ = ["CHECK_COARSEN", "SAFETY_FACTOR", "ORDER", "TOLERANCE", "VALIDATED_BAND", "VALIDATED_CHANGE",
           "VALIDATED_MESH_RULES_VERSION", "VALIDATED_RADIUS_ELEMENTS", "VALIDATED_RADIUS_PER_MODULE",
           "VALIDATED_SOURCE", "coarse_gci", "describe_outside", "outside_validated", "prepare", "root_stress_convergence",
           "convergence_notes"]

#: the check's mesh: every element size of the LTCA's FE tooth times this
CHECK_COARSEN = 2.0
#: Roache's safety factor for a two-mesh estimate (``coarse_gci``)
SAFETY_FACTOR = 3.0
#: the order assumed (module docstring)
ORDER = 1.0
#: the issue's tolerance (57.5: within 3 % of a refined or extrapolated value); the validated band lies within it
TOLERANCE = 0.03
#: where the band and the range were measured
VALIDATED_SOURCE = "docs/validation.md 10.2"
#: the mesh rule they were measured at (``fe.mesh.MESH_RULES_VERSION``)
VALIDATED_MESH_RULES_VERSION = 8
#: the default's root stress (under its own LTCA) over a refined value on the 18 members, - 1: lowest (R5701-4's
#: gear, -2.64 %), highest (R2's pinion, +2.38 %), rounded outward to 0.1 % (10.2, "The rating's estimate")
VALIDATED_BAND = (-0.027, 0.024)
#: the fillet's smallest radius over the normal module on them: R5701-4's gear, R3's pinion
VALIDATED_RADIUS_PER_MODULE = (0.0284, 0.1234)
#: that radius over the fillet's elements on them (fe.mesh's rho_F / 1.75 where it binds; rho_F / 2 at the
#: largest radii); a relative 1e-6 allowed for the round-off of the sizes
VALIDATED_RADIUS_ELEMENTS = (1.75, 2.0)
#: the largest |change| of the coarse check on them (the estimate's alarm): R2's pinion, +11.95 %, rounded up
VALIDATED_CHANGE = 0.12


def _sizes(pair, member, refinement, coarsen):
    """The FE tooth's mesh sizes (``fe.mesh.MeshSizes``) of ``member`` at ``refinement`` / ``coarsen``."""
    from ..fe.mesh import mesh_sizes
    from ..tooth.body import body_pair
    from ..tooth.sampling import ToothSampler

    body = body_pair(pair, member)
    geometry = getattr(body, "geometry", body)
    return mesh_sizes(ToothSampler(geometry, member), geometry.normal_module_mm, refinement / coarsen)


def _fillet(pair, member, refinement, coarsen) -> tuple:
    """(the fillet's smallest radius of curvature mm, its element size mm) of the FE tooth's mesh."""
    sizes = _sizes(pair, member, refinement, coarsen)
    return sizes.fillet_radius_mm, sizes.fillet_mm


def coarse_gci(same_window_mpa: float, coarse_mpa: float) -> float:
    """Roache's grid convergence index of the change between ``coarse_mpa`` and ``same_window_mpa``, the
    coarsened and the default mesh read through the same window (module docstring: an alarm, not the estimate)."""
    change = same_window_mpa / coarse_mpa - 1.0
    return SAFETY_FACTOR * abs(change) / (CHECK_COARSEN ** ORDER - 1.0)


def _bound(name, value, low, high, rel=0.0) -> dict | None:
    """{"parameter", "value", "low", "high"} where ``value`` lies outside [low, high] (None: unbounded), else None."""
    if (low is not None and value < low * (1.0 - rel)) or (high is not None and value > high * (1.0 + rel)):
        return {"parameter": name, "value": float(value), "low": None if low is None else float(low),
                "high": None if high is None else float(high)}
    return None


def outside_validated(e: dict, fe_refinement, fe_coarsen, m_n_mm) -> list:
    """The parameters of one member's estimate ``e`` (:func:`root_stress_convergence`'s entry: its
    ``fillet_radius_mm``, ``fillet_element_mm``, ``change``, ``face_end_distance_mm``, ``end_span_mm``) and of the
    FE tooth's settings that lie outside the range docs/validation.md 10.2 validated (module docstring), each
    {"parameter", "value", "low", "high"}; [] inside."""
    rho, h = e["fillet_radius_mm"], e["fillet_element_mm"]
    found = [_bound("fe_refinement", fe_refinement, 1, 1), _bound("fe_coarsen", fe_coarsen, 1.0, 1.0),
             _bound("fillet_radius_per_module", rho / m_n_mm, *VALIDATED_RADIUS_PER_MODULE),
             _bound("fillet_radius_elements", rho / h, *VALIDATED_RADIUS_ELEMENTS, rel=1e-6),
             _bound("change", e["change"], -VALIDATED_CHANGE, VALIDATED_CHANGE)]
    if e["face_end_distance_mm"] is not None:
        found.append(_bound("face_end_distance_mm", e["face_end_distance_mm"], e["end_span_mm"], None))
    return [f for f in found if f is not None]


def _moduli(material) -> dict:
    return {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}


def prepare(pair, options, material) -> None:
    """Before a rating's LTCA (``options`` its ``ltca.Options``, ``material`` its ``ltca.Material``) with the FE
    tooth: each member's FE data at the LTCA's mesh, read through the LTCA's window and through the check's,
    from one solve where neither is cached (``fe.cache.cached_tooth_data`` with both read-outs), so that the
    LTCA and :func:`root_stress_convergence` read them from the cache: a design's first rating solves the
    default mesh once (and the check's coarsened mesh once)."""
    from ..fe import cache
    from ..ltca.model.teeth import fe_progress
    from ..ltca.options import RANGES

    coarsen = options.fe_coarsen * CHECK_COARSEN
    if getattr(options, "tooth_model", None) != "fe" or coarsen > RANGES["fe_coarsen"][1]:
        return
    moduli = _moduli(material)
    for m in MEMBERS:
        cache.cached_tooth_data(pair, m, *moduli[m], options.fe_refinement, progress=fe_progress(),
                                coarsen=options.fe_coarsen, smooth=(True, float(coarsen)))


def _check_teeth(pair, options, moduli, coarsen, window_coarsen):
    """The FE teeth (pinion, gear) at ``coarsen`` read through the window of the mesh at ``window_coarsen``
    (``fe.tooth.tooth_data``), their data cached like the LTCA's."""
    from ..fe import cache
    from ..fe.contact import FeTooth
    from ..ltca.model.teeth import one_blas_thread

    teeth = []
    for m in MEMBERS:
        data, _ = cache.cached_tooth_data(pair, m, *moduli[m], options.fe_refinement, coarsen=coarsen,
                                          smooth=True if window_coarsen is None else float(window_coarsen))
        with one_blas_thread():
            teeth.append(FeTooth(data, options.flank, cache.stored_tooth_arrays(data, options.flank)))
    return tuple(teeth)


def _largest(reading, m):
    a = reading.get(m)
    return float(np.nanmax(a)) if a is not None and np.isfinite(a).any() else None


def root_stress_convergence(pair, ltca_result, material) -> dict:
    """{member: {...}} the estimate of the module docstring for an LTCA run with the FE tooth (its
    ``options.tooth_model`` "fe"); {} otherwise.  ``material``: the ``ltca.Material`` the LTCA ran with.  Per
    member: ``default_mpa`` (the LTCA's largest root stress), ``coarse_mpa`` (the same loads read with the
    coarsened tooth), ``same_window_mpa`` (read with the default's mesh through the coarsened tooth's window),
    ``window_ratio`` (that window over the default's), ``change`` (same_window / coarse - 1: the mesh's change
    at a fixed window), ``window_effect`` (default / same_window - 1: the narrower window's, not an error),
    ``coarse_gci`` (3 |change|: the alarm), ``change_limit`` (:data:`VALIDATED_CHANGE`), ``converged``,
    ``error_estimate`` (the validated band's largest magnitude where converged, else null), ``error_band``
    ([lowest, highest] where converged), ``error_estimate_source``, ``outside_range`` (:func:`outside_validated`),
    ``fillet_radius_mm``, ``fillet_element_mm``, ``fillet_radius_per_module``, ``fillet_radius_elements``,
    ``check_coarsen``, ``face_end_distance_mm`` (from the maximum to the nearer face end) and ``end_span_mm``; the
    values null where the LTCA has no root stress or the coarsened mesh would exceed the FE tooth's largest
    coarsening (then ``why``)."""
    from ..fe.contact import readout_window_mm
    from ..ltca.model.teeth import root_stresses
    from ..ltca.options import RANGES

    options = getattr(ltca_result, "options", None)
    if options is None or getattr(options, "tooth_model", None) != "fe" or not ltca_result.pair_root_stress_mpa:
        return {}
    coarsen = options.fe_coarsen * CHECK_COARSEN
    top = ltca_result.root_stress_max_mpa()
    m_n = getattr(getattr(pair, "geometry", pair), "normal_module_mm")
    source = (f"the band {VALIDATED_SOURCE} validated: the default mesh's root stress {VALIDATED_BAND[0]:+.1%} ... "
              f"{VALIDATED_BAND[1]:+.1%} from a refined value on its 18 members, inside whose range this design lies")
    out = {}
    for m in MEMBERS:
        rho, h = _fillet(pair, m, options.fe_refinement, options.fe_coarsen)
        one = _sizes(pair, m, 1, 1.0).fillet_mm
        ratio = readout_window_mm(m_n, one, CHECK_COARSEN * h)[1] / readout_window_mm(m_n, one, h)[1]
        out[m] = {"default_mpa": top.get(m), "coarse_mpa": None, "same_window_mpa": None, "window_ratio": float(ratio),
                  "change": None, "window_effect": None, "coarse_gci": None, "change_limit": VALIDATED_CHANGE,
                  "converged": None, "error_estimate": None, "error_band": None, "error_estimate_source": None,
                  "outside_range": None, "fillet_radius_mm": float(rho), "fillet_element_mm": float(h),
                  "fillet_radius_per_module": float(rho / m_n), "fillet_radius_elements": float(rho / h),
                  "check_coarsen": float(coarsen), "face_end_distance_mm": None, "end_span_mm": None, "why": None}
    if coarsen > RANGES["fe_coarsen"][1]:
        for e in out.values():
            e["why"] = (f"not checked: the LTCA's FE tooth is already coarsened {options.fe_coarsen:g} times, and the "
                        f"check's {coarsen:g} exceeds the largest coarsening {RANGES['fe_coarsen'][1]:g}")
        return out
    moduli = _moduli(material)
    teeth = _check_teeth(pair, options, moduli, coarsen, None)
    coarse = root_stresses(teeth, ltca_result, ltca_result.converged, False, False)["tension"]
    same = root_stresses(_check_teeth(pair, options, moduli, options.fe_coarsen, coarsen), ltca_result,
                         ltca_result.converged, False, False)["tension"]
    at = ltca_result.root_stress_location()
    for tooth, m in zip(teeth, MEMBERS):
        lo, hi = float(tooth.data.z_mm[0]), float(tooth.data.z_mm[-1])
        out[m]["end_span_mm"] = FACE_FRACTIONS[2] * (hi - lo)
        z = (at.get(m) or {}).get("z_mm")
        if z is not None:
            out[m]["face_end_distance_mm"] = float(min(z - lo, hi - z))
        d, c, w = out[m]["default_mpa"], _largest(coarse, m), _largest(same, m)
        out[m]["coarse_mpa"], out[m]["same_window_mpa"] = c, w
        if d is None or c is None or w is None or not c > 0.0 or not w > 0.0:
            out[m]["why"] = "no tensile root stress to compare"
            continue
        e = out[m]
        e.update(change=float(w / c - 1.0), window_effect=float(d / w - 1.0), coarse_gci=float(coarse_gci(w, c)))
        e["outside_range"] = outside_validated(e, options.fe_refinement, options.fe_coarsen, m_n)
        e["converged"] = not e["outside_range"]
        if e["converged"]:
            e.update(error_estimate=float(max(abs(b) for b in VALIDATED_BAND)), error_band=list(VALIDATED_BAND),
                     error_estimate_source=source)
    return out


#: how a parameter outside the validated range is named (:func:`describe_outside`)
_NAMES = {"fe_refinement": ("fe_refinement", "{:g}"), "fe_coarsen": ("fe_coarsen", "{:g}"),
          "fillet_radius_per_module": ("the fillet's smallest radius", "{:.4f} m_n"),
          "fillet_radius_elements": ("the fillet's radius over its elements", "{:.2f}"),
          "change": ("the coarse check's change", "{:+.1%}"),
          "face_end_distance_mm": ("the maximum's distance from a face end", "{:.1f} mm")}


def describe_outside(o: dict) -> str:
    """One parameter of :func:`outside_validated` in words: its name, value and the validated bounds."""
    name, fmt = _NAMES[o["parameter"]]
    if o["low"] is not None and o["high"] is not None:
        within = (f"validated {fmt.format(o['low'])}" if o["low"] == o["high"] else
                  f"validated {fmt.format(o['low'])} ... {fmt.format(o['high'])}")
    else:
        within = f"at least {fmt.format(o['low'])}" if o["low"] is not None else f"at most {fmt.format(o['high'])}"
    return f"{name} {fmt.format(o['value'])} ({within})"


def convergence_notes(estimate: dict) -> list:
    """One note per member whose root stress is not shown converged (:func:`root_stress_convergence`)."""
    notes = []
    for m, e in estimate.items():
        if e.get("converged") is not False:
            continue
        why = (f"{m}: the FE root stress is not shown converged: {e['default_mpa']:.0f} MPa at the default mesh, "
               f"outside the range {VALIDATED_SOURCE} validated (its band {VALIDATED_BAND[0]:+.1%} ... "
               f"{VALIDATED_BAND[1]:+.1%} from a refined value): " + "; ".join(describe_outside(o) for o in e["outside_range"])
               + f"; the coarse check (every element {e['check_coarsen']:g} times larger, both read through its "
               f"window): {e['same_window_mpa']:.0f} MPa at the default mesh and {e['coarse_mpa']:.0f} MPa at that "
               f"mesh (change {e['change']:+.1%}, two-mesh GCI {e['coarse_gci']:.0%}); S_F rests on it")
        d = e.get("face_end_distance_mm")
        if d is not None and d < e["end_span_mm"]:
            why += (f"; its maximum lies {d:.1f} mm from a face end, within the load grid's end span "
                    f"({e['end_span_mm']:.1f} mm), where the reading depends on how the contact is lumped onto the grid")
        if e["fillet_radius_mm"] < e["fillet_element_mm"]:
            why += (f"; the fillet's smallest radius ({e['fillet_radius_mm']:.3f} mm, the bottom of the trochoid) is "
                    f"below its elements ({e['fillet_element_mm']:.3f} mm): a notch the mesh does not resolve, whose "
                    "peak grows with refinement (a rack tip radius, cutter_tip_radius_coefficient, rounds it)")
        notes.append(why)
    return notes
