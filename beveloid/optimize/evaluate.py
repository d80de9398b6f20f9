"""One candidate: its loaded quantities over the duty cycle and the error sets, its objectives and the
rating's local safeties at the highest torque.

The quantities of one loaded analysis (``beveloid ltca`` reports each of them):

* ``te_peak_to_peak_urad``: the loaded TE peak-to-peak (its JSON
  ``loaded_transmission_error_peak_to_peak_urad``);
* ``max_pressure_mpa``: the largest pair peak pressure over the cycle, edge peaks included (the
  largest of ``pair_max_pressure_mpa``);
* ``root_stress_max_mpa``: the larger member's root stress maximum (the larger of
  ``root_stress_max_mpa``; FE tooth only);
* ``mesh_power_loss_w``: the mesh power loss, mean over the cycle, at ``[rating] pinion_speed_rpm`` with the
  file's ``[lubricant]`` (``beveloid ltca --speed-rpm``'s ``mesh_power_loss_w``; only for the objective
  ``loss``: docs/tribology.md).

Each torque's quantity is the value at the file's errors (``--samples 0``) or the 90th percentile
(``numpy.percentile``, its default method) over the K error sets; an objective is the weighted mean
over the torques, sum w_i q_i / sum w_i.  A candidate missing any of its quantities (an analysis with
fewer than 3 converged positions, no root stress) has the status ``incomplete``, null objectives, and
takes no part in the front.
"""
from __future__ import annotations

import functools
import json
import math
import time
from typing import NamedTuple

import numpy as np

from ..status import EvaluationStatus
from .request import OBJECTIVES, PERCENTILE, Request

QUANTITIES = tuple(OBJECTIVES.values())


class LoadedQuantities(NamedTuple):
    """(T, K) arrays over the torques and the error sets; nan where the analysis gives none."""

    te_peak_to_peak_urad: np.ndarray
    max_pressure_mpa: np.ndarray
    root_stress_max_mpa: np.ndarray
    converged_positions: np.ndarray  # (T, K) int
    mesh_power_loss_w: np.ndarray = None  # (T, K); nan without a speed
    extra: tuple = ()  # the LTCAResult of each ``extra`` case of loaded_quantities


def loaded_quantities(pair, load, options, *, solver=None, speed_rpm=None, extra=()) -> LoadedQuantities:
    """The quantities of the loaded analysis of ``pair`` at every torque (N m, pinion) and error set of
    ``load`` (an ltca.LoadCase), with ``options`` (an ltca.Options): the tolerance box under load of
    ``beveloid ltca --samples`` (:func:`beveloid.ltca.studies.box_results`, the same calls of the batched
    engine), so that it reproduces them exactly.  ``solver``: the Solver of every call (None: the default one);
    ``speed_rpm``: the pinion speed of the mesh power loss (the pair's [lubricant]; None: not computed);
    ``extra``: more (error set, torque) cases analysed in the same first call (the rating's LTCA:
    ``rating.ltca_case``), their results in ``extra``."""
    from ..ltca.studies import box_results

    sets = load.error_sets(pair)
    shape = (len(load.torques_nm), len(sets))
    te, p, root, loss = (np.full(shape, np.nan) for _ in range(4))
    conv = np.zeros(shape, dtype=int)
    results = box_results(pair, load, options, solver=solver, extra=extra)
    results, more = results[:len(sets)], results[len(sets):]
    for k, row in enumerate(results):
        for i, r in enumerate(row):
            ok = r.converged
            conv[i, k] = int(ok.sum())
            te[i, k] = r.loaded_te_peak_to_peak * 1e6
            peaks = r.pair_max_pressure_mpa[ok]
            if np.isfinite(peaks).any():
                p[i, k] = float(np.nanmax(peaks))
            tops = [v for v in r.root_stress_max_mpa().values() if v is not None]
            if tops:
                root[i, k] = max(tops)
            if speed_rpm is not None:
                from .. import tribology

                loss[i, k] = tribology.evaluate(r, pair, speed_rpm, errors=sets[k]).mesh_power_loss_w
    return LoadedQuantities(te, p, root, conv, loss, tuple(r[0] for r in more))


def per_torque(q: np.ndarray, samples: int) -> np.ndarray:
    """(T,) each torque's quantity: the value at the file's errors, or the 90th percentile over the sets
    (nan when a set has none)."""
    q = np.asarray(q, dtype=float)
    if samples == 0:
        return q[:, 0]
    return np.array([np.percentile(row, PERCENTILE) if np.isfinite(row).all() else math.nan for row in q])


def objective(q_torque: np.ndarray, weights) -> float:
    """sum w_i q_i / sum w_i (nan when a torque's quantity is missing)."""
    w = np.asarray(weights, dtype=float)
    return float(np.dot(w, q_torque) / w.sum())


def _num(v):
    v = float(v)
    return v if math.isfinite(v) else None


def safeties(req: Request, pair, *, solver=None, ltca_result=None) -> dict:
    """The rating at the highest torque (``beveloid rating`` at its defaults with the run's flank and tooth
    model: ``Request.rating_options``) and its verdict, the one
    the command prints: ``feasible`` is the verdict's ``passes`` (every deciding safety meets its minimum and no
    edge contact exceeds the edge-contact rule; a CONDITIONAL verdict is not feasible), ``shortfall`` the
    constraint the search is told (:func:`shortfall`).  The lowest local S_F and S_H are kept for the tables.
    ``solver``: that of the loaded analyses (None: the default one); ``ltca_result``: the rating's LTCA already
    run (``rating.ltca_case``'s case: :func:`evaluate` runs it in the candidate's box call), else run here."""
    from .. import rating

    from ..ltca import LoadCase

    r = rating.analyze(pair, LoadCase(max(req.torques_nm)), req.rating_options(), solver=solver, ltca_result=ltca_result)
    v = rating.verdict(r)
    sf = [m.safety_bending for m in r.members.values() if m.safety_bending is not None]
    sh = [m.safety_pitting for m in r.members.values() if m.safety_pitting is not None]
    f = r.factors
    return {"safety_bending_local": min(sf) if sf else None, "safety_pitting_local": min(sh) if sh else None,
            "S_Fmin": f.S_Fmin, "S_Hmin": f.S_Hmin, "torque_nm": max(req.torques_nm),
            "feasible": bool(v["passes"]), "shortfall": shortfall(v), "verdict_status": v["status"],
            "verdict_condition": v.get("condition"), "verdict": v["line"]}


def shortfall(verdict: dict) -> float | None:
    """The constraint g of a rating's verdict (``rating.verdict``), <= 0 exactly when it passes: the worst
    relative shortfall over its governing criteria, 1 - value / required of a minimum (a safety) and
    1 - required / value of a maximum (the edge rule's load share), at least 1e-6 for a verdict that does
    not pass (None: no criterion has a value)."""
    terms = []
    for c in verdict.get("criteria", ()):
        if not c["governs"] or c["value"] is None:
            continue
        if c.get("limit") == "maximum":
            terms.append(1.0 - c["required"] / c["value"] if c["value"] > 0 else -1.0)
        else:
            terms.append(1.0 - c["value"] / c["required"])
    if not terms:
        return None
    g = max(terms)
    return float(min(g, 0.0) if verdict["passes"] else max(g, 1e-6))


def evaluate(req: Request, values: dict, error_sets: np.ndarray | None = None) -> dict:
    """The record of one candidate (JSON-ready): values, status, each quantity per torque and set, the
    objectives, the safeties."""
    from ..errors import UserError
    from ..pair import Pair
    from ..spec import SpecError

    t0 = time.perf_counter()
    rec = {"values": {k: float(v) for k, v in values.items()}, "status": EvaluationStatus.OK, "reason": ""}
    try:
        pair = Pair.from_spec(req.spec(values))
    except (SpecError, UserError) as exc:  # the spec's rules or the design refuse these values
        return _failed(rec, req, EvaluationStatus.REFUSED, exc, t0)
    sets = req.error_sets() if error_sets is None else error_sets
    solver = req.solver  # the run's: the candidate's loaded analyses and its rating
    try:
        speed = pair.spec.rating.pinion_speed_rpm if "loss" in req.objectives else None
        # the rating's LTCA one more case of the box's call where it is one (its set-up and waves shared)
        case = _rating_case(req, pair) if req.constraints == "rating" else None
        lq = loaded_quantities(pair, req.load_case(sets), req.ltca, solver=solver, speed_rpm=speed,
                               extra=() if case is None else (case,))
        rec["safety"] = (safeties(req, pair, solver=solver, ltca_result=lq.extra[0] if lq.extra else None)
                         if req.constraints == "rating" else None)
    except UserError as exc:  # no contact at all (the flank is turned off its mate)
        return _failed(rec, req, EvaluationStatus.FAILED, exc, t0)
    rec["quantities"] = {q: [[_num(v) for v in row] for row in getattr(lq, q)] for q in QUANTITIES}
    rec["converged_positions"] = lq.converged_positions.tolist()
    tq = {q: per_torque(getattr(lq, q), req.samples) for q in QUANTITIES}
    rec["per_torque"] = {q: [_num(v) for v in tq[q]] for q in QUANTITIES}
    rec["objectives"] = {q: _num(objective(tq[q], req.weights)) for q in req.quantities}
    missing = [q for q in req.quantities if rec["objectives"][q] is None]
    if missing:
        least = int(lq.converged_positions.min())
        rec["status"] = EvaluationStatus.INCOMPLETE
        rec["reason"] = (f"no {', '.join(missing)} at some torque or error set (fewest converged positions:"
                         f" {least} of {req.ltca.positions})")
    rec["seconds"] = time.perf_counter() - t0
    return rec


def _rating_case(req: Request, pair):
    """The (error set, torque) of the candidate's rating's LTCA (``rating.ltca_case``), or None: also where the
    rating's LTCA options are not the run's (its own positions or grid: ``Request.rating_options``), which one
    call of the box cannot run beside the box's."""
    from .. import rating
    from ..ltca import LoadCase

    options = req.rating_options()
    if options.ltca != req.ltca:
        return None
    return rating.ltca_case(pair, LoadCase(max(req.torques_nm)), options)


def _failed(rec: dict, req: Request, status: str, exc: Exception, t0: float) -> dict:
    rec.update(status=status, reason=f"{type(exc).__name__}: {' '.join(str(exc).split())}", quantities=None,
               per_torque=None, objectives={q: None for q in req.quantities}, safety=None,
               seconds=time.perf_counter() - t0)
    return rec


@functools.lru_cache(maxsize=1)
def _request(text: str) -> Request:
    """The run's Request in this worker, read once per run (and with it its one Solver)."""
    return Request.from_json(json.loads(text))


def evaluate_task(task) -> dict:
    """What a worker runs: (request JSON, candidate index, values) -> the record (module level: pickled)."""
    from .. import parallel

    parallel.single_threaded()
    request, index, values = task
    rec = evaluate(_request(json.dumps(request, sort_keys=True)), values)
    rec["candidate"] = index
    return rec
