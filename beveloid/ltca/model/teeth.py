"""The teeth the loaded contact bends: the plate (equivalent spur tooth) or the FE tooth (issue 31),
and the root stress the FE tooth gives under the solved pressure."""
from __future__ import annotations

import collections
import contextlib
import sys
import weakref

import numpy as np

from ...names import MEMBERS
from .compliance import member_tooth

def one_blas_thread():
    """BLAS limited to one thread: the many small factorisations run 3x slower with OpenBLAS
    threads on a busy 2-core machine (docs/performance.md), and a 91 x 91 eigendecomposition
    (the FE tooth's compliance) took 0.13 s of CPU with the default threads against 0.001 s."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional: without it BLAS keeps its own thread count
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


def fe_progress(stream=None):
    """A line a stage on stderr when it is a terminal (the FE data of a new design takes a minute)."""
    from ...progress import Lines

    stream = stream or sys.stderr
    if not getattr(stream, "isatty", lambda: False)():
        return None
    return Lines(stream, prefix="beveloid: ")


def member_teeth(pair, geom, options, material) -> tuple:
    """((pinion, gear) tooth objects with ``line_compliance(points)``: the options' tooth model, notes).
    The FE tooth is each member's body (:mod:`beveloid.tooth.body`), loaded at the modified flank's
    points; a note names a member whose flank departs from its body enough to matter."""
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    if options.tooth_model == "plate":
        return tuple(member_tooth(geom, m, *moduli[m]) for m in MEMBERS), ()
    from ...tooth.departure import flank_departure

    source = pair if pair is not None else geom
    out, notes = [], []
    for m in MEMBERS:
        tooth = fe_tooth(source, m, moduli[m], options)
        data = tooth.data
        out.append(tooth)
        # the departure of a pair's flank from its body, once per (pair, member, data): optimize's candidate
        # calls the loaded engine three times (its box's two chunks, its rating), a crowned flank 40 ms each
        key = (id(source), m, id(data))
        held = _DEPARTURES.get(key)
        if held is None or held[0]() is not source or held[1]() is not data:
            held = _DEPARTURES[key] = (weakref.ref(source), weakref.ref(data),
                                       flank_departure(source, m, data.points_mm, data.normals).note(m))
            while len(_DEPARTURES) > 2 * FE_TEETH_KEPT:
                _DEPARTURES.popitem(last=False)
        if held[2]:
            notes.append(held[2])
    return tuple(out), tuple(notes)


#: the departure notes of the last few (pair, member, FE data), the objects referenced weakly (a note keeps neither a
#: design nor its FE data in memory: the FE caches bound those; an entry whose objects died is not theirs)
_DEPARTURES: "collections.OrderedDict" = collections.OrderedDict()


#: the FE teeth of the last few FE data (by identity: beveloid.fe.cache keeps the data of a key in
#: this process) and flanks: the compliance's projection and the fillet's distances once per pair
_FE_TEETH: "collections.OrderedDict" = collections.OrderedDict()
FE_TEETH_KEPT = 4


def fe_tooth(source, member, moduli, options):
    """The :class:`beveloid.fe.contact.FeTooth` of ``member`` on the options' flank: its data from
    :func:`beveloid.fe.cache.cached_tooth_data` (the body, not the flank modifications or the
    assembly errors: computed on a miss, read once per process), the tooth built once per data from
    the arrays the cache keeps with it (:func:`beveloid.fe.cache.stored_tooth_arrays`)."""
    from ...fe import cache
    from ...fe.contact import FeTooth

    data, _ = cache.cached_tooth_data(source, member, *moduli, options.fe_refinement, progress=fe_progress(),
                                      coarsen=options.fe_coarsen)
    key = (id(data), options.flank)  # the entry holds the data: its id is not reused while it lives
    tooth = _FE_TEETH.get(key)
    if tooth is None or tooth.data is not data:
        with one_blas_thread():
            tooth = _FE_TEETH[key] = FeTooth(data, options.flank, cache.stored_tooth_arrays(data, options.flank))
        while len(_FE_TEETH) > FE_TEETH_KEPT:
            _FE_TEETH.popitem(last=False)
    _FE_TEETH.move_to_end(key)
    return tooth


def fe_data_on_disk(pair, options, material) -> bool:
    """Whether the FE data :func:`member_teeth` reads for ``pair`` (both members' bodies, at the options'
    refinement and coarsening) is in the FE cache's folder, so that no process would make it (True for the
    plate tooth, which reads none): optimize's workers then start on the candidates while the unmodified
    design is evaluated beside them."""
    if options.tooth_model != "fe":
        return True
    from ...fe import cache

    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    return all(cache.entry_path(cache.cache_key(pair, m, *moduli[m], options.fe_refinement, options.fe_coarsen)).is_file()
               for m in MEMBERS)


def root_stresses(teeth, sol, ok, along_face=True, compression=True) -> dict:
    """{"tension": {member: (N, P)}, "compression": {...}, "where": {member: (N, P, 2)}, "along": {member:
    (z, stress)}, "unread": {member: loaded pairs without a root stress}} (MPa, mm) for FE teeth, each
    pair's tooth under its own cells' forces ("along": the loaded fillet along the face at the largest
    root stress, empty where not ``along_face``; "compression" empty where not ``compression``; NaN where
    every fillet node lies within the reading depth of the pair's load); empty for the plate.  Every loaded (position, pair) of a member at once (:meth:`beveloid.fe.contact.FeTooth.root_stresses`)."""
    out = {"tension": {}, "compression": {}, "where": {}, "along": {}, "unread": {}}
    if not all(hasattr(t, "root_stress") for t in teeth):
        return out
    N, P = sol.pressure_mpa.shape[:2]
    area = sol.grid.cell_area_mm2()
    forces = np.where(sol.gap.in_flank, sol.pressure_mpa * area[..., None], 0.0)  # (N, P, cells)
    with np.errstate(invalid="ignore"):
        loaded = ok[:, None] & (np.nansum(forces, axis=-1) > 0)
    jj, kk = np.nonzero(loaded)
    for tooth, m in zip(teeth, MEMBERS):
        ten, comp, where = np.full((N, P), np.nan), np.full((N, P), np.nan), np.full((N, P, 2), np.nan)
        ten[ok], comp[ok] = 0.0, 0.0
        points = sol.gap.pinion_point if m == "pinion" else sol.gap.gear_point
        if jj.size:
            r = tooth.root_stresses(points[jj, kk], forces[jj, kk], compression)
            ten[jj, kk], comp[jj, kk] = r.tension_mpa, r.compression_mpa
            where[jj, kk] = np.stack([r.z_mm, r.height_mm], axis=-1)
            out["unread"][m] = int(np.count_nonzero(np.isnan(r.tension_mpa)))
        out["tension"][m], out["where"][m] = ten, where
        if compression:
            out["compression"][m] = comp
        if along_face and np.isfinite(ten).any() and np.nanmax(ten) > 0:
            j, k = np.unravel_index(int(np.nanargmax(ten)), ten.shape)
            out["along"][m] = tooth.along_face(points[j, k], forces[j, k])
    return out
