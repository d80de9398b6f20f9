"""Is the FE tooth's root stress, the one the local S_F divides by, converged?  (issue 57.5)

That root stress is the LTCA's: the largest principal stress of the FE tooth's fillet tensors read on a grid
fixed by the geometry (``fe.tooth.tooth_data``, ``fe.contact.readout_matrix``; the coarsened tooth below is read
at the same points, over a window widened to 0.75 of its own fillet elements, which flattens the notch's peak:
its reading lies 8-12 % below the default's on docs/validation.md 10.2's designs).

The LTCA's loads (the cell forces of every converged, loaded position and pair) are read a second
time with the FE tooth of a mesh :data:`CHECK_COARSEN` times coarser (every element size doubled; its
data computed once per design and cached like the default's).  The load distribution is kept: between
the coarsened and the default tooth it moves the largest root stress by about 0.3 % (design A of
docs/validation.md 10.2: 517.3 / 589.9 MPa read this way against 518.8 / 589.2 MPa from the coarsened
tooth's own LTCA), so the two readings differ by the read-out's discretisation.

From the two values (c coarse, d default) the estimate is Roache's grid convergence index for two
meshes, refinement ratio 2, safety factor :data:`SAFETY_FACTOR` = 3 and an assumed order of 1:

    error_estimate = 3 |d / c - 1| / (2^1 - 1)

Order 1, not the P2 element's 2: where the root stress is read (the bottom of a sharp rack's
trochoid, docs/rating.md 8) the increments did not shrink with refinement on the designs of
docs/validation.md 10.2, and on them the default's distance from refinement 2 was up to 2.3 times
|d / c - 1| (design C's pinion: 6.3 % against 2.7 %).

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
  on 0.24 mm elements).  With the nodal fit read before FE_DATA_VERSION 4 no member of docs/validation.md
  10.2 did so, but only two had an estimate within the tolerance (docs/rating.md 5): the condition is kept.

``converged``: the estimate within :data:`TOLERANCE`, the maximum clear of the face ends, the fillet
radius resolved.

Beside it the fillet's smallest radius of curvature (mid-face section, the root of the FE tooth's
mesh rule) and the fillet's element size: a radius below the element size is a notch the mesh does
not resolve, whose peak stress grows with every refinement.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ..fe.tooth import FACE_FRACTIONS
from ..names import MEMBERS

__all__ = ["CHECK_COARSEN", "RESOLVED_RADIUS_ELEMENTS", "SAFETY_FACTOR", "ORDER", "TOLERANCE", "root_stress_convergence",
           "convergence_notes"]

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


def root_stress_convergence(pair, ltca_result, material) -> dict:
    """{member: {...}} the estimate of the module docstring for an LTCA run with the FE tooth (its
    ``options.tooth_model`` "fe"); {} otherwise.  ``material``: the ``ltca.Material`` the LTCA ran with.  Per member: ``default_mpa`` (the LTCA's largest root
    stress), ``coarse_mpa`` (the same loads read with the coarsened tooth), ``change`` (default /
    coarse - 1), ``error_estimate``, ``converged``, ``fillet_radius_mm``, ``fillet_element_mm``,
    ``check_coarsen``, ``face_end_distance_mm`` (from the maximum to the nearer face end) and
    ``end_span_mm``; the values null where the LTCA has no root stress or the coarsened mesh would
    exceed the FE tooth's largest coarsening (then ``why``)."""
    from ..ltca.model.teeth import fe_tooth, root_stresses
    from ..ltca.options import RANGES

    options = getattr(ltca_result, "options", None)
    if options is None or getattr(options, "tooth_model", None) != "fe" or not ltca_result.pair_root_stress_mpa:
        return {}
    coarsen = options.fe_coarsen * CHECK_COARSEN
    top = ltca_result.root_stress_max_mpa()
    out = {}
    for m in MEMBERS:
        rho, h = _fillet(pair, m, options.fe_refinement, options.fe_coarsen)
        out[m] = {"default_mpa": top.get(m), "coarse_mpa": None, "change": None, "error_estimate": None,
                  "converged": None, "fillet_radius_mm": float(rho), "fillet_element_mm": float(h),
                  "check_coarsen": float(coarsen), "face_end_distance_mm": None, "end_span_mm": None, "why": None}
    if coarsen > RANGES["fe_coarsen"][1]:
        for e in out.values():
            e["why"] = (f"not checked: the LTCA's FE tooth is already coarsened {options.fe_coarsen:g} times, and the "
                        f"check's {coarsen:g} exceeds the largest coarsening {RANGES['fe_coarsen'][1]:g}")
        return out
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    coarse_options = dataclasses.replace(options, fe_coarsen=coarsen)
    teeth = tuple(fe_tooth(pair, m, moduli[m], coarse_options) for m in MEMBERS)
    coarse = root_stresses(teeth, ltca_result, ltca_result.converged, False, False)["tension"]
    at = ltca_result.root_stress_location()
    for tooth, m in zip(teeth, MEMBERS):
        lo, hi = float(tooth.data.z_mm[0]), float(tooth.data.z_mm[-1])
        out[m]["end_span_mm"] = FACE_FRACTIONS[2] * (hi - lo)
        z = (at.get(m) or {}).get("z_mm")
        if z is not None:
            out[m]["face_end_distance_mm"] = float(min(z - lo, hi - z))
        d, a = out[m]["default_mpa"], coarse.get(m)
        c = float(np.nanmax(a)) if a is not None and np.isfinite(a).any() else None
        out[m]["coarse_mpa"] = c
        if d is None or c is None or not c > 0.0:
            out[m]["why"] = "no tensile root stress to compare"
            continue
        change = d / c - 1.0
        err = SAFETY_FACTOR * abs(change) / (2.0 ** ORDER - 1.0)
        e = out[m]
        end = e["face_end_distance_mm"] is not None and e["face_end_distance_mm"] < e["end_span_mm"]
        e.update(change=float(change), error_estimate=float(err),
                 converged=bool(err <= TOLERANCE and not end
                                and e["fillet_radius_mm"] >= RESOLVED_RADIUS_ELEMENTS * e["fillet_element_mm"]))
    return out


def convergence_notes(estimate: dict) -> list:
    """One note per member whose root stress is not shown converged (:func:`root_stress_convergence`)."""
    notes = []
    for m, e in estimate.items():
        if e.get("converged") is not False:
            continue
        why = (f"{m}: the FE root stress is not shown converged: {e['default_mpa']:.0f} MPa at the default mesh, "
               f"{e['coarse_mpa']:.0f} MPa with every element {e['check_coarsen']:g} times larger (change "
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
