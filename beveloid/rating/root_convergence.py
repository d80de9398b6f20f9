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
FE field's change at a fixed filter.  The default's own reading d lies above w by the narrower window's
effect (a sharper view of the same peak, 1.6-7.5 % on docs/validation.md 10.2's members: ``window_effect``,
reported, not an error); before, the estimate compared d with c and so counted that effect as the mesh's.
The estimate is Roache's grid convergence index for two meshes, refinement ratio 2, safety factor
:data:`SAFETY_FACTOR` = 3 and an assumed order of 1:

    error_estimate = 3 |w / c - 1| / (2^1 - 1)

Order 1, not the P2 element's 2: where the root stress is read (the bottom of a sharp rack's trochoid,
docs/rating.md 8) the coarsened mesh's fillet elements are as large as the fillet's smallest radius or larger
(the fillet rule sets the default's at rho_F / 1.5 where it binds), so the step from it to the default is
not in the asymptotic range: on 17 of docs/validation.md 10.2's 18 members w / c - 1 is +2.5 to +11 %, while
the default lies -4.4 to +0.8 % from the same tooth with every size / 1.5, without a relation between the two
(R3's pinion +7.2 % against -0.4 %, its gear +2.5 % against -2.1 %): the estimate bounds that distance on each
and is within the tolerance on none.  On the eighteenth, R5701-4's gear (its radius 1.14 of its elements), the
coarsened mesh reads 1.0 % above the default's: an estimate of 2.96 % against a distance of -6.1 %, which the
fillet-radius condition below catches.  A mesh twice as coarse as the default cannot show a sharp rack's
notch stress converged to 3 %.

Two readings the estimate cannot judge are not called converged whatever it says:

* a maximum within the load grid's end span of a face end (the last :data:`beveloid.fe.tooth.FACE_FRACTIONS`
  step before its second column, 1/16 of the face): there the LTCA's contact is lumped onto the grid's end
  columns and the reading depends on their spacing, not on the mesh (``benchmarks/fe_load_grid.py``;
  case 1's pinion at 1500 N m reads 1.7 mm from its heel, the coarsened mesh reads the same loads within
  0.1 %, refinement 2 3.1 % higher);
* a fillet whose smallest radius is below :data:`RESOLVED_RADIUS_ELEMENTS` times its element size: below
  one element it is a notch the mesh does not resolve; below four, the two meshes can agree while the
  mesh refined once reads more (with the nodal maximum read before the smoothing, case 1's pinion at
  1500 N m: 209.0 / 210.1 / 224.2 MPa at coarsen 2 / the default / refinement 2, a fillet radius of 0.42 mm
  on 0.24 mm elements; with today's read-out R5701-4's gear, above).

``converged``: the estimate within :data:`TOLERANCE`, the maximum clear of the face ends, the fillet
radius resolved.

Beside it the fillet's smallest radius of curvature (mid-face section, the root of the FE tooth's
mesh rule) and the fillet's element size: a radius below the element size is a notch the mesh does
not resolve, whose peak stress grows with every refinement.
"""
from __future__ import annotations


import numpy as np

from ..fe.tooth import FACE_FRACTIONS
from ..names import MEMBERS

__all__ = ["CHECK_COARSEN", "RESOLVED_RADIUS_ELEMENTS", "SAFETY_FACTOR", "ORDER", "TOLERANCE", "error_estimate",
           "prepare", "root_stress_convergence", "convergence_notes"]

#: the check's mesh: every element size of the LTCA's FE tooth times this
CHECK_COARSEN = 2.0
#: Roache's safety factor for a two-mesh estimate
SAFETY_FACTOR = 3.0
#: the order assumed (module docstring)
ORDER = 1.0
#: the root stress counts as converged when the estimate is within this
TOLERANCE = 0.03
#: and the fillet's smallest radius spans at least this many of its elements (module docstring)
RESOLVED_RADIUS_ELEMENTS = 4.0


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


def error_estimate(same_window_mpa: float, coarse_mpa: float) -> float:
    """The estimate of the module docstring: Roache's grid convergence index of the change between
    ``coarse_mpa`` and ``same_window_mpa``, the coarsened and the default mesh read through the same window."""
    change = same_window_mpa / coarse_mpa - 1.0
    return SAFETY_FACTOR * abs(change) / (CHECK_COARSEN ** ORDER - 1.0)


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
    ``error_estimate``, ``converged``, ``fillet_radius_mm``, ``fillet_element_mm``, ``check_coarsen``,
    ``face_end_distance_mm`` (from the maximum to the nearer face end) and ``end_span_mm``; the values null
    where the LTCA has no root stress or the coarsened mesh would exceed the FE tooth's largest coarsening
    (then ``why``)."""
    from ..fe.contact import readout_window_mm
    from ..ltca.model.teeth import root_stresses
    from ..ltca.options import RANGES

    options = getattr(ltca_result, "options", None)
    if options is None or getattr(options, "tooth_model", None) != "fe" or not ltca_result.pair_root_stress_mpa:
        return {}
    coarsen = options.fe_coarsen * CHECK_COARSEN
    top = ltca_result.root_stress_max_mpa()
    out = {}
    for m in MEMBERS:
        rho, h = _fillet(pair, m, options.fe_refinement, options.fe_coarsen)
        one = _sizes(pair, m, 1, 1.0).fillet_mm
        m_n = getattr(getattr(pair, "geometry", pair), "normal_module_mm")
        ratio = readout_window_mm(m_n, one, CHECK_COARSEN * h)[1] / readout_window_mm(m_n, one, h)[1]
        out[m] = {"default_mpa": top.get(m), "coarse_mpa": None, "same_window_mpa": None, "window_ratio": float(ratio),
                  "change": None, "window_effect": None, "error_estimate": None,
                  "converged": None, "fillet_radius_mm": float(rho), "fillet_element_mm": float(h),
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
        err = error_estimate(w, c)
        end = e["face_end_distance_mm"] is not None and e["face_end_distance_mm"] < e["end_span_mm"]
        e.update(change=float(w / c - 1.0), window_effect=float(d / w - 1.0), error_estimate=float(err),
                 converged=bool(err <= TOLERANCE and not end
                                and e["fillet_radius_mm"] >= RESOLVED_RADIUS_ELEMENTS * e["fillet_element_mm"]))
    return out


def convergence_notes(estimate: dict) -> list:
    """One note per member whose root stress is not shown converged (:func:`root_stress_convergence`)."""
    notes = []
    for m, e in estimate.items():
        if e.get("converged") is not False:
            continue
        why = (f"{m}: the FE root stress is not shown converged: {e['default_mpa']:.0f} MPa at the default mesh; "
               f"through the read-out's window of a mesh with every element {e['check_coarsen']:g} times larger, "
               f"{e['same_window_mpa']:.0f} MPa at the default mesh and {e['coarse_mpa']:.0f} MPa at that mesh (change "
               f"{e['change']:+.1%}, estimated error {e['error_estimate']:.0%}, tolerance {TOLERANCE:.0%}); S_F "
               "rests on it")
        d = e.get("face_end_distance_mm")
        if d is not None and d < e["end_span_mm"]:
            why += (f"; its maximum lies {d:.1f} mm from a face end, within the load grid's end span "
                    f"({e['end_span_mm']:.1f} mm), where the reading depends on how the contact is lumped onto the grid")
        if e["fillet_radius_mm"] < e["fillet_element_mm"]:
            why += (f"; the fillet's smallest radius ({e['fillet_radius_mm']:.3f} mm, the bottom of the trochoid) is "
                    f"below its elements ({e['fillet_element_mm']:.3f} mm): a notch the mesh does not resolve, whose "
                    "peak grows with refinement (a rack tip radius, cutter_tip_radius_coefficient, rounds it)")
        elif e["fillet_radius_mm"] < RESOLVED_RADIUS_ELEMENTS * e["fillet_element_mm"]:
            why += (f"; the fillet's smallest radius ({e['fillet_radius_mm']:.3f} mm) spans fewer than "
                    f"{RESOLVED_RADIUS_ELEMENTS:g} of its elements ({e['fillet_element_mm']:.3f} mm): the two meshes can "
                    "agree while a finer one reads more (--fe-refinement 2 shows it)")
        notes.append(why)
    return notes
