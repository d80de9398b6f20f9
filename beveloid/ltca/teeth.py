"""The teeth the loaded contact bends: the plate (equivalent spur tooth) or the FE tooth (issue 31),
and the root stress the FE tooth gives under the solved pressure."""
from __future__ import annotations

import sys

import numpy as np

from .compliance import member_tooth

MEMBERS = ("pinion", "gear")


def _progress(stream=None):
    """A line writer on stderr when it is a terminal (the FE data of a new design takes a minute)."""
    stream = stream or sys.stderr
    if not getattr(stream, "isatty", lambda: False)():
        return None
    return lambda text: print(f"beveloid: {text}", file=stream, flush=True)


def member_teeth(pair, geom, options, material) -> tuple:
    """((pinion, gear) tooth objects with ``line_compliance(points)``: the options' tooth model, notes).
    The FE tooth is each member's body (:mod:`beveloid.tooth.body`), loaded at the modified flank's
    points; a note names a member whose flank departs from its body enough to matter."""
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    if options.tooth_model == "plate":
        return tuple(member_tooth(geom, m, *moduli[m]) for m in MEMBERS), ()
    from ..fe.cache import cached_tooth_data
    from ..fe.contact import FeTooth
    from ..tooth.body import flank_departure

    source = pair if pair is not None else geom
    out, notes = [], []
    for m in MEMBERS:
        data, _ = cached_tooth_data(source, m, *moduli[m], options.fe_refinement, progress=_progress(),
                                    coarsen=options.fe_coarsen)
        out.append(FeTooth(data, options.flank))
        note = flank_departure(source, m, data.points_mm, data.normals).note(m)
        if note:
            notes.append(note)
    return tuple(out), tuple(notes)


def root_stresses(teeth, sol, ok) -> dict:
    """{"tension": {member: (N, P)}, "compression": {...}, "where": {member: (N, P, 2)}, "along": {member:
    (z, stress)}} (MPa, mm) for FE teeth, each pair's tooth under its own cells' forces ("along": the
    loaded fillet along the face at the largest root stress); empty for the plate."""
    out = {"tension": {}, "compression": {}, "where": {}, "along": {}}
    if not all(hasattr(t, "root_stress") for t in teeth):
        return out
    N, P = sol.pressure_mpa.shape[:2]
    area = sol.grid.cell_area_mm2()
    for tooth, m in zip(teeth, MEMBERS):
        ten, comp, where = np.full((N, P), np.nan), np.full((N, P), np.nan), np.full((N, P, 2), np.nan)
        points = sol.gap.pinion_point if m == "pinion" else sol.gap.gear_point
        for j in np.flatnonzero(ok):
            for k in range(P):
                f = np.where(sol.gap.in_flank[j, k], sol.pressure_mpa[j, k] * area[j, k], 0.0)
                if f.sum() <= 0:
                    ten[j, k], comp[j, k] = 0.0, 0.0
                    continue
                r = tooth.root_stress(points[j, k], f)
                ten[j, k], comp[j, k], where[j, k] = r.tension_mpa, r.compression_mpa, (r.z_mm, r.height_mm)
        out["tension"][m], out["compression"][m], out["where"][m] = ten, comp, where
        if np.isfinite(ten).any() and np.nanmax(ten) > 0:
            j, k = np.unravel_index(int(np.nanargmax(ten)), ten.shape)
            f = np.where(sol.gap.in_flank[j, k], sol.pressure_mpa[j, k] * area[j, k], 0.0)
            out["along"][m] = tooth.along_face(points[j, k], f)
    return out
