"""The search: pymoo's NSGA-II (ask and tell) over the varied keys, the candidates evaluated on any
executor (beveloid.parallel) and each kept on disk as it finishes.

The first population is a Latin hypercube sample (scipy.stats.qmc.LatinHypercube, seeded by
``--seed``) over the ranges; NSGA-II (simulated binary crossover, polynomial mutation, its
constrained non-dominated sorting and crowding) makes the next from the evaluated ones, seeded too.
Candidate i is the i-th the algorithm asks for; ``--budget`` stops it after that many (the last
generation cut short).  A candidate's numbers depend only on the request and its values, never on
where it ran, so the run is the same on one worker, N workers and a cluster, and a resumed run
(``--resume DIR``) replays the seeded search, takes every candidate already on disk
(``DIR/candidates/``) and evaluates only the others.

What the algorithm is told: the objectives of a candidate that is ``ok``, else a large number; the
constraint g, <= 0 exactly when ``beveloid rating``'s verdict passes (evaluate.shortfall: the worst
relative shortfall over the verdict's governing criteria), and 1e3 for a candidate without numbers.
"""
from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from ..errors import StopReason
from ..result import thaw
from ..runstore import REQUEST, RunResult, RunStore  # noqa: F401  (REQUEST: the CLI reads it here)
from ..status import EvaluationStatus
from .evaluate import evaluate, evaluate_task
from .request import Request

CANDIDATES = "candidates"
BASELINE = "baseline"
#: what the algorithm is told for a candidate without numbers
FAILED_OBJECTIVE = 1e30
FAILED_CONSTRAINT = 1e3


def _path(out_dir: str, name) -> str:
    stem = name if isinstance(name, str) else f"{int(name):06d}"
    return os.path.join(out_dir, CANDIDATES, f"{stem}.json")


def save(out_dir: str, name, rec: dict) -> None:
    path = _path(out_dir, name)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(rec, f, allow_nan=False)
    os.replace(tmp, path)


def load(out_dir: str, name) -> dict | None:
    try:
        with open(_path(out_dir, name)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def prepare(out_dir: str, req: Request | None, resume: bool, budget: int | None = None) -> Request:
    """Create DIR (fresh) or read its request (resume; ``budget`` extends it); refuse to mix two runs
    (:class:`beveloid.runstore.RunStore`)."""
    from ..explore.run import code_version

    store = RunStore(out_dir, CANDIDATES, "candidates", "optimisation")
    if resume:
        held = store.resumed(code_version())
        req = Request.from_json(held if budget is None else dict(held, budget=budget))
    else:
        req = Request.from_json(dict(req.to_json(), code=code_version()))
        store.check_fresh(req.to_json(), ignore=("budget",))
    store.write(req.to_json())
    return req


def told(req: Request, rec: dict) -> tuple:
    """(F, G) of a record for the algorithm (module docstring)."""
    if rec["status"] != EvaluationStatus.OK:
        return np.full(len(req.objectives), FAILED_OBJECTIVE), np.array([FAILED_CONSTRAINT])
    F = np.array([rec["objectives"][q] for q in req.quantities], dtype=float)
    s = rec.get("safety")
    if s is None:
        return F, np.array([0.0])
    return F, np.array([FAILED_CONSTRAINT if s["shortfall"] is None else s["shortfall"]])


def initial(req: Request, baseline: dict | None = None) -> np.ndarray:
    """The first population: a Latin hypercube sample over the ranges (seeded), its first row the
    unmodified design's values (``baseline``) when they lie inside the ranges: the search then starts
    from the design it is to improve, and its front is never worse than that design (if feasible)."""
    from scipy.stats import qmc

    lo = np.array([v.start for v in req.varies])
    hi = np.array([v.stop for v in req.varies])
    u = qmc.LatinHypercube(d=len(req.varies), seed=np.random.default_rng(req.seed)).random(req.population)
    X = lo + u * (hi - lo)
    if baseline is not None:
        x0 = np.array([baseline[k] for k in req.keys], dtype=float)
        if np.all((x0 >= lo) & (x0 <= hi)):
            X[0] = x0
    return X


def algorithm(req: Request, baseline: dict | None = None):
    """NSGA-II set up on the request's problem, seeded (``baseline``: see :func:`initial`)."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.termination.max_eval import MaximumFunctionCallTermination

    problem = Problem(n_var=len(req.varies), n_obj=len(req.objectives), n_ieq_constr=1,
                      xl=np.array([v.start for v in req.varies]), xu=np.array([v.stop for v in req.varies]))
    alg = NSGA2(pop_size=req.population, sampling=initial(req, baseline), eliminate_duplicates=True)
    alg.setup(problem, termination=MaximumFunctionCallTermination(10 ** 9), seed=req.seed, verbose=False)
    return alg


class Progress:
    """A :class:`beveloid.progress.Progress`: candidates done, the time per candidate and the time left, on
    stderr (a line per batch); ``what`` says how many of the batch came from disk."""

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr
        self.t0 = time.perf_counter()

    def __call__(self, done: int, total: int | None, what: str) -> None:
        rate = ""
        if done and total:
            each = (time.perf_counter() - self.t0) / done
            rate = f", {each:.1f} s a candidate, about {each * (total - done):.0f} s left"
        self.stream.write(f"beveloid optimize: {done}/{total} {what}{rate}\n")
        self.stream.flush()


def baseline(out_dir: str, req: Request) -> dict:
    """The file's own design, evaluated in this process (before the workers: its FE tooth data is then on
    disk for them) and kept as DIR/candidates/baseline.json."""
    rec = load(out_dir, BASELINE)
    if rec is None:
        rec = evaluate(req, req.baseline_values())
        rec["candidate"] = BASELINE
        save(out_dir, BASELINE, rec)
    return rec


def baseline_alongside(out_dir: str, req: Request) -> bool:
    """Whether :func:`run` may evaluate the file's own design on the workers with the first generation
    (``baseline=True``) instead of :func:`baseline` in this process before them: where it is not on disk yet
    and every FE tooth a candidate reads (its loaded analyses' and its rating's, both members' bodies) is: no two
    processes then make the same FE data at once, and the workers do not wait idle while this process
    evaluates it (issue 59: one candidate and this process's loads on a quiet 2-core machine)."""
    from ..ltca.model.teeth import fe_data_on_disk
    from ..ltca.options import Material
    from ..pair import Pair

    if load(out_dir, BASELINE) is not None:
        return False
    pair = Pair.from_spec(req.spec(req.baseline_values()))
    options = [req.ltca] + ([req.rating_options().ltca] if req.constraints == "rating" else [])
    return all(fe_data_on_disk(pair, o, o.material or Material.from_spec(pair.spec)) for o in options)


@dataclass(frozen=True, eq=False)
class OptimizeRun(RunResult):
    """How a run of :func:`run` ended (:class:`beveloid.runstore.RunResult`), and its ``records``: the
    candidates' records in the order the algorithm asked for them (each as kept in ``out_dir``/candidates/,
    frozen); ``options``: the run's :class:`Request`."""

    records: tuple = ()

    def record_dicts(self) -> list:
        """The records as the JSON files hold them (dicts and lists), for the report."""
        return thaw(self.records)

    def to_json(self) -> dict:
        return dict(super().to_json(), records=self.record_dicts())


def run(out_dir: str, req: Request, ex, progress=None, base: dict | None = None, baseline: bool = False) -> OptimizeRun:
    """Ask, evaluate (on ``ex``) and tell until the budget: an :class:`OptimizeRun` (the records in candidate
    order, None or a StopReason, a line saying why it stopped).  ``base``: the unmodified design's record (:func:`baseline`), the first
    candidate when its values lie inside the ranges (its numbers are taken, not computed again).  ``baseline``
    (``base`` None): that record evaluated on ``ex`` as one more task of the first generation and kept as
    :func:`baseline` keeps it (:func:`baseline_alongside`); the candidate of its values takes its numbers when
    it comes back."""
    from ..parallel import WorkLost

    base_values = base["values"] if base is not None else req.baseline_values() if baseline else None
    alg = algorithm(req, base_values)
    payload = req.to_json()
    records: list = []
    while len(records) < req.budget:
        pop = alg.ask()
        X = pop.get("X")[: req.budget - len(records)]
        pop = pop[: len(X)]
        start = len(records)
        batch: list = [None] * len(X)
        todo, waiting = [], []  # waiting: the candidates of the baseline's values, while it is evaluated
        pending = base is None and baseline
        for j, x in enumerate(X):
            rec = load(out_dir, start + j)
            values = dict(zip(req.keys, (float(v) for v in x)))
            if rec is None and pending and base_values == values:
                waiting.append(j)
                continue
            if rec is None and base is not None and base["values"] == values:
                rec = dict(base, candidate=start + j)
                save(out_dir, start + j, rec)
            if rec is not None and rec["values"] == values:
                batch[j] = rec
            else:
                todo.append(j)
        tasks = [(payload, start + j, dict(zip(req.keys, (float(v) for v in X[j])))) for j in todo]
        if pending:  # first: it starts as soon as a worker is free
            tasks.insert(0, (payload, BASELINE, dict(base_values)))
        try:
            for k, rec in ex.map_unordered(evaluate_task, tasks):
                if pending and k == 0:
                    save(out_dir, BASELINE, rec)
                    base = rec
                    for j in waiting:
                        batch[j] = dict(base, candidate=start + j)
                        save(out_dir, start + j, batch[j])
                    continue
                j = todo[k - 1] if pending else todo[k]
                save(out_dir, start + j, rec)
                batch[j] = rec
        except KeyboardInterrupt:
            return OptimizeRun(out_dir, StopReason.INTERRUPTED, str(StopReason.INTERRUPTED),
                               records + [r for r in batch if r is not None], options=req)
        except WorkLost as exc:
            return OptimizeRun(out_dir, StopReason.WORK_LOST, str(exc), records + [r for r in batch if r is not None],
                               options=req)
        if progress:
            progress(len(records) + len(X), req.budget, f"candidates ({len(X) - len(todo)} from disk)")
        FG = [told(req, r) for r in batch]
        pop.set("F", np.array([f for f, _ in FG]), "G", np.array([g for _, g in FG]))
        alg.tell(infills=pop)
        records += batch
    return OptimizeRun(out_dir, None, "", records, options=req)
