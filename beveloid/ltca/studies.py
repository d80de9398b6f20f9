"""The studies of a loaded pair: the torque map and the tolerance box under load.

    from beveloid import ltca
    batch = ltca.analyze_many(pair, ltca.LoadCase([50, 100, 200, 400]), options)
    ltca.studies.torque_map_json(batch.results[0])       # per torque: TE p-p, peaks, root, stiffness
    box = ltca.studies.tolerance_box(pair, ltca.LoadCase([100, 200], errors=draws), options)
    ltca.studies.tolerance_json(box, 0, len(draws), seed, tolerances)   # the box at the first torque

:func:`box_results` is the one loop of the tolerance box: :func:`beveloid.ltca.analyze_many` over
:data:`CHUNK_SETS` error sets at a time, the calls that ``beveloid ltca --samples`` (here, on local
workers or a Dask cluster: :func:`tolerance_box`) and ``beveloid optimize`` both make, so that their
numbers are the same to the last bit.
"""
from __future__ import annotations

import math

import numpy as np

from ..names import MEMBERS

__all__ = ["CHUNK_SETS", "TASK_SETS", "box_results", "nominal_results", "tolerance_box", "tolerance_json", "torque_map_json"]

#: error sets per call of the batched engine (the numbers do not depend on where a chunk runs): 16, so that
#: optimize's candidate (``--samples 16``) is one call, one set-up and one cold start of the waves
#: (``ltca.passes.analysis``): 3-4 % less CPU a candidate than two calls of 8, ~70 MB more at the peak
CHUNK_SETS = 16
#: error sets per task of :func:`tolerance_box`'s workers: one, so that many workers share a box evenly (64
#: sets in tasks of 8 kept at most 8 busy; in tasks of 2, 16 workers took 3 rounds of 2 sets and the file's
#: errors); a set's numbers do not depend on the sets analysed with it (issue 59).  Without workers the box
#: runs :data:`CHUNK_SETS` sets a task and the file's errors as one task of every torque: the sets of a
#: call share its waves (``ltca.passes.analysis``: a set's first torque starts from the first set's contact
#: set, a torque from the torque before's), 5-10 % less CPU, the same numbers but the active-set iterations
TASK_SETS = 1


def box_results(pair, load, options=None, *, solver=None, extra=()) -> list:
    """``[[LTCAResult per torque] per error set]`` of ``load`` (its torques x its error sets), one
    :func:`beveloid.ltca.analyze_many` per :data:`CHUNK_SETS` sets, all with ``solver``, without the
    grid-convergence indicator, the root stress along the face and the compressive root stress
    (``convergence=False``, ``along_face=False``, ``compression=False``: neither the box, optimize nor the
    rating's box reports them; each result's ``convergence`` is nan, its ``root_stress_along_face`` and
    ``pair_root_compressive_stress_mpa`` empty, every other number that of :func:`beveloid.ltca.analyze`).
    ``extra``: more (error set, torque) cases analysed in the first call (``analyze_many(..., extra=)``: optimize's
    candidate adds its rating's LTCA), each a row of its one LTCAResult after the load's sets."""
    from . import analyze_many

    sets = load.error_sets(pair)
    out, more = [], []
    for start in range(0, len(sets), CHUNK_SETS):
        batch = analyze_many(pair, load.at(errors=sets[start:start + CHUNK_SETS]), options, solver=solver,
                             convergence=False, along_face=False, compression=False, extra=() if start else extra)
        out += batch.results
        more += [[r] for r in batch.extra]
    return out + more


def _chunk(task):
    """One chunk of the tolerance box: (pair, load, options) -> [[summary per torque] per set]."""
    from .results.batch import summary

    pair, load, options = task
    rows = box_results(pair, load, options)
    return [[dict(summary(r), errors=e) for r in row] for e, row in zip(load.error_sets(pair), rows)]


def nominal_results(task) -> list:
    """(pair, load, options) -> ``[LTCAResult per torque]`` of ``load`` (one error set: the file's) with both
    contact patterns (``with_patterns``): what ``beveloid ltca`` reports besides its tolerance box."""
    from . import analyze_many

    pair, load, options = task
    rasters = {}  # each member's flank raster once for every torque
    return [r.with_patterns(rasters) for r in analyze_many(pair, load, options).results[0]]


def _task(task):
    """What a worker of :func:`tolerance_box` runs: ("box", pair, load, options) a chunk (:func:`_chunk`),
    ("nominal", pair, load, options) the analyses at the file's errors (:func:`nominal_results`)."""
    kind, rest = task[0], task[1:]
    return nominal_results(rest) if kind == "nominal" else _chunk(rest)


def tolerance_box(pair, load, options=None, *, workers=None, scheduler=None, progress=None, nominal=None):
    """``[[summary (ltca.results.batch.summary, with "errors") per torque] per error set]`` of ``load``'s
    error sets (the draws), in tasks of :data:`TASK_SETS` on ``workers`` local processes or on the Dask
    cluster at ``scheduler`` (beveloid.parallel), of :data:`CHUNK_SETS` here (:func:`_box_tasks`);
    ``progress(done, total, "error sets")`` after each task (a :class:`beveloid.progress.Progress`).

    ``nominal``: a LoadCase (the file's errors) analysed as more tasks on the same workers, one per torque and
    the first (:func:`nominal_results`, patterns included; a torque's analysis does not depend on the torques
    analysed with it), so that the main process runs no analysis (issue 59: the serial part of ``ltca
    --samples``); here one task of every torque; then ``(its [LTCAResult per torque], the rows)``."""
    from contextlib import nullcontext

    from ..parallel import executor

    parallel = workers is not None or scheduler is not None
    tasks = _box_tasks(pair, load, options, nominal, parallel)
    first = sum(t[0] == "nominal" for t in tasks)
    sets = load.error_sets(pair)
    out = [None] * len(tasks)
    done = 0
    with (executor(workers, scheduler) if parallel else nullcontext()) as ex:
        items = ex.map_unordered(_task, tasks) if parallel else ((i, _task(t)) for i, t in enumerate(tasks))
        for i, res in items:
            out[i] = res
            if i < first:
                continue
            done += len(res)
            if progress is not None:
                progress(done, len(sets), "error sets")
    rows = [row for chunk in out[first:] for row in chunk]
    return rows if nominal is None else ([r for part in out[:first] for r in part], rows)


def _box_tasks(pair, load, options, nominal=None, parallel=True) -> list:
    """The tasks of :func:`tolerance_box` (:func:`_task`'s): on workers (``parallel``) the error sets
    :data:`TASK_SETS` a task and the file's errors (``nominal``, a LoadCase) one task per torque, first; here
    :data:`CHUNK_SETS` sets a task and the file's errors one task."""
    sets = load.error_sets(pair)
    size = TASK_SETS if parallel else CHUNK_SETS
    tasks = [("box", pair, load.at(errors=sets[i:i + size]), options) for i in range(0, len(sets), size)]
    if nominal is not None:
        tasks[:0] = ([("nominal", pair, nominal.at(torque_nm=[t]), options) for t in nominal.torques_nm] if parallel
                     else [("nominal", pair, nominal, options)])
    return tasks


def _stats(values) -> dict:
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    if v.size == 0:
        return {"p50": None, "p90": None, "max": None, "sets": 0}
    return {"p50": float(np.percentile(v, 50)), "p90": float(np.percentile(v, 90)), "max": float(v.max()),
            "sets": int(v.size)}


def _num(v):
    return float(v) if v is not None and math.isfinite(v) else None


def tolerance_json(box, t, samples, seed, tolerances) -> dict:
    """The "tolerance" block of torque index t of a :func:`tolerance_box` (issue 43's contract)."""
    from .. import assembly_errors

    rows = [sets[t] for sets in box]
    return {
        "samples": samples, "seed": seed,
        "tolerances": {k: float(v) for k, v in tolerances.items()},
        "te_peak_to_peak_urad": _stats(r["te_peak_to_peak_urad"] for r in rows),
        "max_pressure_mpa": _stats(r["max_pressure_mpa"] for r in rows),
        "root_stress_max_mpa": {m: _stats(r["root_stress_max_mpa"][m] for r in rows) for m in MEMBERS},
        "edge_contact_fraction": sum(r["edge_contact"] for r in rows) / len(rows),
        "sets": [{"errors": assembly_errors.from_layout(r["errors"]),
                  "te_peak_to_peak_urad": _num(r["te_peak_to_peak_urad"]),
                  "max_pressure_mpa": _num(r["max_pressure_mpa"]),
                  "root_stress_max_mpa": {m: _num(r["root_stress_max_mpa"][m]) for m in MEMBERS}} for r in rows],
        "note": "each set a full loaded analysis with that error set in [misalignment] (the draws of sweep and "
                "explore: uniform in the box about the file's misalignment); p50, p90 and max over the sets "
                "with a value (sets: how many)",
    }


def torque_map_json(results) -> dict:
    """The "torque_map" block of the results at each torque: per torque the TE peak-to-peak, the largest
    pair_max_pressure_mpa (edge peaks included), the members' largest root stress and the mean mesh
    stiffness (null where not known)."""
    from .results.batch import summary

    s = [summary(r) for r in results]
    return {"torque_nm": [float(r.torque_nm) for r in results],
            "te_peak_to_peak_urad": [_num(x["te_peak_to_peak_urad"]) for x in s],
            "max_pressure_mpa": [_num(x["max_pressure_mpa"]) for x in s],
            "root_stress_max_mpa": {m: [_num(x["root_stress_max_mpa"][m]) for x in s] for m in MEMBERS},
            "mesh_stiffness_mean_n_per_um": [_num(x["mesh_stiffness_mean_n_per_um"]) for x in s]}
