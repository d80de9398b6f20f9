"""What an optimisation writes: candidates.csv, pareto.csv, summary.json, a spec pareto_<n>.toml per
Pareto candidate, the figures, and the ``--json`` dict.

The front: the candidates that are ``ok``, meet the safeties (or were run with ``--constraints none``)
and that no other such candidate beats on every objective (beveloid.explore.pareto.front).  The picks:
the lowest TE, the lowest pressure (on the front when those are objectives) and the knee, the front
candidate nearest to the front's ideal point with each objective scaled to 0..1 over the front.
Floats are written with repr: the same records give the same files.
"""
from __future__ import annotations

import json
import math
import os
from typing import NamedTuple

import numpy as np

from ..explore.pareto import front
from ..spec import spec_to_dict
from ..status import EvaluationStatus
from .evaluate import QUANTITIES
from .request import OBJECTIVES

FIGURES = ("pareto.png", "te_vs_torque.png", "knee_pattern.png")
SAFETY_KEYS = ("safety_bending_local", "safety_pitting_local", "S_Fmin", "S_Hmin")


def eligible(rec: dict) -> bool:
    s = rec.get("safety")
    return rec["status"] == EvaluationStatus.OK and (s is None or s["feasible"])


def pareto_mask(req, records: list) -> np.ndarray:
    P = np.array([[rec["objectives"][q] if eligible(rec) else np.nan for q in req.quantities] for rec in records],
                 dtype=float).reshape(len(records), len(req.quantities))
    return front(P)


def knee(req, records: list, on: np.ndarray):
    """Index of the front candidate nearest to the ideal point (objectives scaled to 0..1 over the front)."""
    idx = np.flatnonzero(on)
    if idx.size == 0:
        return None
    P = np.array([[records[i]["objectives"][q] for q in req.quantities] for i in idx], dtype=float)
    span = P.max(axis=0) - P.min(axis=0)
    Z = (P - P.min(axis=0)) / np.where(span > 0, span, 1.0)
    return int(idx[int(np.argmin(np.linalg.norm(Z, axis=1)))])


def picks(req, records: list, on: np.ndarray) -> dict:
    """{"lowest_te", "lowest_pressure", "knee"}: candidate indices (lowest among the eligible)."""
    out = {}
    for name, q in (("lowest_te", OBJECTIVES["te"]), ("lowest_pressure", OBJECTIVES["pressure"])):
        vals = [(rec["objectives"].get(q) if q in rec["objectives"] else _torque_mean(req, rec, q), i)
                for i, rec in enumerate(records) if eligible(rec)]
        vals = [(v, i) for v, i in vals if v is not None]
        out[name] = min(vals)[1] if vals else None
    out["knee"] = knee(req, records, on)
    return out


def _torque_mean(req, rec, q):
    """The weighted objective of a quantity that is not an objective of the run (for the picks)."""
    from .evaluate import objective

    vals = (rec.get("per_torque") or {}).get(q)
    if vals is None or any(v is None for v in vals):
        return None
    return objective(np.array(vals, dtype=float), req.weights)


def row(req, rec: dict, on_front: bool) -> dict:
    """One CSV row: the values, the status, each objective, each torque's quantities, the safeties."""
    out = {"candidate": rec["candidate"]}
    out.update({k: rec["values"][k] for k in req.keys})
    out["status"] = rec["status"]
    s = rec.get("safety")
    out["feasible"] = "" if s is None else s["feasible"]
    out["pareto"] = bool(on_front)
    for q in req.quantities:
        out[q] = rec["objectives"][q]
    tq = rec.get("per_torque") or {}
    for q in QUANTITIES:
        for t, v in zip(req.torques_nm, tq.get(q) or [None] * len(req.torques_nm)):
            out[f"{q}_at_{t:g}_nm"] = v
    for k in SAFETY_KEYS:
        out[k] = None if s is None else s[k]
    out["reason"] = rec.get("reason", "") or infeasible_reason(s)
    return out


def infeasible_reason(safety: dict | None) -> str:
    """Why a candidate the loaded analyses accepted is not feasible: the rating's verdict status at the
    rated torque and, for a conditional one, its condition ("" for a feasible or unrated candidate)."""
    if not safety or safety["feasible"]:
        return ""
    status = getattr(safety["verdict_status"], "value", safety["verdict_status"])
    condition = safety.get("verdict_condition")
    return (f"rating at {safety['torque_nm']:g} N m: {str(status).upper()}"
            + (f", {condition}" if isinstance(condition, str) and condition else ""))


def _cell(v) -> str:
    """A CSV cell: "" for a missing or non-finite number, true/false, integers as such, floats by repr."""
    if v is None or isinstance(v, str):
        return v or ""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v)) if math.isfinite(v) else ""


def write_csv(path: str, rows: list) -> None:
    import csv

    keys = list(rows[0]) if rows else ["candidate"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for r in rows:
            w.writerow([_cell(r[k]) for k in keys])


def toml_text(data: dict, header: str = "") -> str:
    """A spec's tables as TOML (flat sections of numbers, strings and booleans; floats by repr)."""
    lines = [f"# {h}" for h in header.splitlines()]
    for section, table in data.items():
        lines += ["", f"[{section}]"]
        for key, v in table.items():
            if isinstance(v, bool):
                text = "true" if v else "false"
            elif isinstance(v, (int, np.integer)):
                text = str(int(v))
            elif isinstance(v, (float, np.floating)):
                text = repr(float(v))
            else:
                text = json.dumps(str(v))
            lines.append(f"{key} = {text}")
    return "\n".join(lines) + "\n"


def reproduce_commands(req, spec_file: str) -> list:
    """The commands that reproduce a candidate's numbers: ``beveloid ltca`` over the duty cycle (with
    ``--samples``, the same error sets: the "tolerance" blocks' p90) and ``beveloid rating``."""
    lt = req.ltca
    grid = "" if lt.grid is None else f" --grid {lt.grid[0]}x{lt.grid[1]}"
    tooth = f" --tooth-model {lt.tooth_model}"
    if lt.tooth_model == "fe":
        tooth += f" --fe-refinement {lt.fe_refinement} --fe-coarsen {lt.fe_coarsen:g}"
    common = f" --flank {lt.flank} --positions {lt.positions}{tooth} --pairs {lt.pairs}{grid}"
    box = ""
    if req.samples:
        tol = ",".join(f"{k.rsplit('_', 1)[0]}={v!r}" for k, v in req.tolerances.items())  # dx_mm -> dx
        box = f" --samples {req.samples} --seed {req.seed} --tolerances {tol}"
    torques = ",".join(f"{t:g}" for t in req.torques_nm)
    out = [f"beveloid ltca {spec_file} --torque-nm {torques}{common}{box} --json"]
    if req.constraints == "rating":  # the rating at its own numerical settings (Request.rating_options)
        out.append(f"beveloid rating {spec_file} --torque-nm {max(req.torques_nm):g} --flank {lt.flank} "
                   f"--tooth-model {lt.tooth_model} --json")
    return out


def dominating(req, records: list, base: dict) -> list:
    """The candidates (numbers) that beat the unmodified design on every objective, or None when it has none."""
    if base["status"] != EvaluationStatus.OK:
        return None
    b = np.array([base["objectives"][q] for q in req.quantities])
    out = []
    for rec in records:
        if eligible(rec):
            f = np.array([rec["objectives"][q] for q in req.quantities])
            if (f <= b).all() and (f < b).any():
                out.append(rec["candidate"])
    return out


def front_order(req, records: list, on: np.ndarray) -> list:
    """The front candidates' indices sorted by the objectives (the first, then the next)."""
    return sorted((int(i) for i in np.flatnonzero(on)), key=lambda i: [records[i]["objectives"][q]
                                                                       for q in req.quantities])


def write_specs(out_dir: str, req, records: list, front_idx: list) -> dict:
    """pareto_<n>.toml for each front candidate (n = 1.. in front order): {candidate index: file name}."""
    names = {}
    for n, i in enumerate(front_idx, start=1):
        rec = records[i]
        name = f"pareto_{n}.toml"
        header = (f"beveloid optimize: Pareto candidate {rec['candidate']} of {req.source}\n"
                  + ", ".join(f"{k} = {v!r}" for k, v in rec["values"].items())
                  + "\nits numbers at the file's errors: " + "; ".join(reproduce_commands(req, name)))
        with open(os.path.join(out_dir, name), "w") as f:
            f.write(toml_text(spec_to_dict(req.spec(rec["values"])), header))
        names[i] = name
    return names


def _entry(req, rec: dict, spec_file=None) -> dict:
    out = {"candidate": rec.get("candidate"), "values": dict(rec["values"]), "status": rec["status"],
           "objectives": {q: rec["objectives"].get(q) for q in req.quantities},
           "per_torque": rec.get("per_torque"), "safety": rec.get("safety")}
    if spec_file is not None:
        out["spec_file"] = spec_file
    return out


class RunInfo(NamedTuple):
    """How a run went: complete or why it stopped, its seconds and where it ran."""

    complete: bool
    why: str
    seconds: float
    where: str


class Front(NamedTuple):
    """The front: its mask over the records, its order (:func:`front_order`) and each one's spec file."""

    on: np.ndarray
    order: list
    specs: dict


def summary(req, records: list, base: dict, info: RunInfo, fr: Front) -> dict:
    """summary.json: the request, the baseline, the front (in its order) with its spec files, the picks."""
    on, order, specs = fr
    from .. import assembly_errors

    statuses = {}
    for rec in records:
        statuses[rec["status"]] = statuses.get(rec["status"], 0) + 1
    pk = picks(req, records, on)
    sets = req.error_sets()
    return {
        "file": req.source,
        "objectives": list(req.quantities),
        "varied": [{"key": v.key, "low": v.start, "high": v.stop} for v in req.varies],
        "torques_nm": list(req.torques_nm), "weights": list(req.weights),
        "samples": req.samples, "seed": req.seed, "tolerances": req.tolerances,
        "error_sets": [assembly_errors.from_layout(e) for e in sets],
        "aggregation": ("each torque's quantity at the file's errors" if req.samples == 0 else
                        "each torque's quantity: the 90th percentile over the error sets (numpy.percentile)")
                       + "; an objective: sum w_i q_i / sum w_i",
        "ltca": {k: req.to_json()["ltca"][k] for k in ("flank", "positions", "pairs", "grid", "tooth_model",
                                                       "fe_refinement", "fe_coarsen")},
        "constraints": req.constraints, "search": {"algorithm": "NSGA-II (pymoo)", "population": req.population,
                                                   "budget": req.budget, "initial": "Latin hypercube (scipy.stats.qmc)"},
        "evaluated": len(records), "complete": info.complete, "stopped": info.why or None,
        "status_counts": statuses, "seconds": info.seconds, "executor": info.where,
        "baseline": dict(_entry(req, base), dominated_by=dominating(req, records, base)),
        "pareto": [_entry(req, records[i], specs.get(i)) for i in order],
        "picks": {k: (None if i is None else records[i]["candidate"]) for k, i in pk.items()},
        "reproduce": reproduce_commands(req, "pareto_<n>.toml"),
    }


def json_output(summ: dict) -> dict:
    """The --json dict: the issue's shape (objectives, baseline, pareto, evaluated) and the picks."""
    strip = lambda e: {k: e[k] for k in ("values", "objectives", "safety", "spec_file") if k in e}  # noqa: E731
    base = dict(strip(summ["baseline"]), dominated_by=summ["baseline"]["dominated_by"])
    return {"objectives": summ["objectives"], "baseline": base,
            "pareto": [strip(e) for e in summ["pareto"]], "evaluated": summ["evaluated"], "picks": summ["picks"],
            "complete": summ["complete"]}


def write(out_dir: str, req, records: list, summ: dict, on: np.ndarray) -> None:
    rows = [row(req, rec, o) for rec, o in zip(records, on)]
    write_csv(os.path.join(out_dir, "candidates.csv"), rows)
    write_csv(os.path.join(out_dir, "pareto.csv"), [r for r, o in zip(rows, on) if o])
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summ, f, indent=1, allow_nan=False)


def figures(out_dir: str, req, records: list, base: dict, on: np.ndarray) -> list:
    """pareto.png, te_vs_torque.png and knee_pattern.png (the knee's contact pattern at the highest torque, at
    the file's errors): the files written."""
    from ..plots import _plt

    plt = _plt()
    written = []
    q = req.quantities
    ok = [i for i, r in enumerate(records) if r["status"] == EvaluationStatus.OK]
    fig, ax = plt.subplots(figsize=(6.5, 5))
    xq = q[0]
    yq = q[1] if len(q) > 1 else None
    xs = lambda idx, key: [records[i]["objectives"][key] for i in idx]  # noqa: E731
    bad = [i for i in ok if not eligible(records[i])]
    good = [i for i in ok if eligible(records[i]) and not on[i]]
    fr = sorted(np.flatnonzero(on), key=lambda i: records[i]["objectives"][xq])
    if yq is None:  # one objective: against the first varied key
        key = req.keys[0]
        vx = lambda idx: [records[i]["values"][key] for i in idx]  # noqa: E731
        ax.plot(vx(good), xs(good, xq), "o", color="0.6", ms=4, label="candidates")
        ax.plot(vx(bad), xs(bad, xq), "x", color="tab:orange", ms=5, label="violates S_Fmin / S_Hmin")
        ax.plot(vx(fr), xs(fr, xq), "o", color="tab:red", ms=7, label="best")
        if base["status"] == EvaluationStatus.OK:
            ax.plot([base["values"][key]], [base["objectives"][xq]], "*", color="k", ms=12, label="unmodified (file)")
        ax.set_xlabel(key)
        ax.set_ylabel(xq)
    else:
        ax.plot(xs(good, xq), xs(good, yq), "o", color="0.6", ms=4, label="candidates")
        ax.plot(xs(bad, xq), xs(bad, yq), "x", color="tab:orange", ms=5, label="violates S_Fmin / S_Hmin")
        ax.plot(xs(fr, xq), xs(fr, yq), "o-", color="tab:red", ms=6, label="Pareto front")
        if base["status"] == EvaluationStatus.OK:
            ax.plot([base["objectives"][xq]], [base["objectives"][yq]], "*", color="k", ms=12,
                    label="unmodified (file)")
        ax.set_xlabel(xq)
        ax.set_ylabel(yq)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{os.path.basename(req.source)}: {len(records)} candidates", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "pareto.png"), dpi=110)
    plt.close(fig)
    written.append("pareto.png")
    pk = picks(req, records, on)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    te = OBJECTIVES["te"]
    lines = [("unmodified (file)", base)] + [(f"{name.replace('_', ' ')} (candidate {records[i]['candidate']})",
                                             records[i]) for name, i in pk.items() if i is not None]
    for label, rec in lines:
        vals = (rec.get("per_torque") or {}).get(te)
        if vals is None:
            continue
        ax.plot(req.torques_nm, [np.nan if v is None else v for v in vals], "o-", label=label)
    what = "at the file's errors" if req.samples == 0 else f"the 90th percentile over {req.samples} error sets"
    ax.set_xlabel("pinion torque (N m)")
    ax.set_ylabel("loaded TE peak-to-peak (urad)")
    ax.set_title(f"loaded TE peak-to-peak, {what}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "te_vs_torque.png"), dpi=110)
    plt.close(fig)
    written.append("te_vs_torque.png")
    if pk["knee"] is not None:
        written += knee_pattern(out_dir, req, records[pk["knee"]], solver=req.solver)
    return written


def knee_pattern(out_dir: str, req, rec: dict, *, solver=None) -> list:
    """The knee's contact pattern on both flanks at the highest torque, at the file's errors."""
    from .. import ltca
    from ..ltca.results.plots import PRESSURE_LABEL, _colorbar, ltca_pattern, surface_scale_mpa
    from ..pair import Pair
    from ..plots import _plt

    plt = _plt()

    pair = Pair.from_spec(req.spec(rec["values"]))
    result = ltca.analyze(pair, ltca.LoadCase(max(req.torques_nm)), req.ltca, solver=solver)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    vmax = surface_scale_mpa(result)
    for ax, member in zip(axes, ("pinion", "gear")):
        sc, clipped = ltca_pattern(ax, result, pair.geometry, member, vmax=vmax)
        if sc is not None:
            _colorbar(fig, sc, ax, PRESSURE_LABEL, clipped)
    vals = ", ".join(f"{k} = {v:.4g}" for k, v in rec["values"].items())
    fig.suptitle(f"knee (candidate {rec['candidate']}: {vals}) at {max(req.torques_nm):g} N m", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "knee_pattern.png"), dpi=110)
    plt.close(fig)
    return ["knee_pattern.png"]


def finite(v) -> bool:
    return v is not None and math.isfinite(v)
