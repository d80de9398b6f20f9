"""Running an exploration: fixed chunks of designs, on any executor, kept on disk as they finish.

The designs are cut into chunks of ``chunk`` consecutive designs; a chunk's rows depend only on the
request and the chunk's index (never on the worker or the number of workers), so one worker, N
local workers and a Dask cluster write the same rows bit for bit.  Each finished chunk is written
at once to ``DIR/chunks/`` (numpy .npz, written to a temporary name and renamed); the request is in
``DIR/request.json``.  An interrupted run (Ctrl-C, a lost worker) keeps its finished chunks, and
``--resume DIR`` computes only the missing ones.
"""
from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import UserError
from .grid import Plan, Vary

#: designs per chunk: large enough for the batched kernels, small enough to lose little on a stop
CHUNK = 256
REQUEST = "request.json"
CHUNKS = "chunks"


@dataclass(frozen=True)
class Request:
    """Everything that defines the rows (stored in DIR/request.json)."""

    plan: Plan
    tolerances: dict
    mc: int = 0
    mc_positions: int = 20
    mc_flank: str = "right"
    chunk: int = CHUNK
    backend: str = "auto"
    source: str = ""
    extra: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        d = asdict(self)
        d["plan"]["varies"] = [asdict(v) for v in self.plan.varies]
        return d

    @classmethod
    def from_json(cls, d: dict) -> "Request":
        p = d["plan"]
        plan = Plan(p["base"], tuple(Vary(**v) for v in p["varies"]), p.get("samples"), p.get("seed", 0))
        return cls(plan, dict(d["tolerances"]), d["mc"], d["mc_positions"], d["mc_flank"], d["chunk"], d["backend"],
                   d.get("source", ""), d.get("extra", {}))

    @property
    def chunks(self) -> int:
        return -(-self.plan.count // self.chunk)


def compute_chunk(task: tuple) -> dict:
    """The rows of chunk ``index`` of a request (given as its JSON dict): what a worker runs."""
    from .. import parallel
    from . import rows

    request_json, index = task
    parallel.single_threaded()
    req = Request.from_json(request_json)
    start = index * req.chunk
    stop = min(req.plan.count, start + req.chunk)
    cols = rows.compute(req.plan, start, stop, req.tolerances, req.backend)
    if req.mc:
        rows.monte_carlo(cols, req.plan, start, stop, req.tolerances, req.mc, req.mc_positions, req.mc_flank,
                         req.plan.seed, req.backend)
    return {k: (np.asarray(v, dtype=str) if np.asarray(v).dtype == object else np.asarray(v)) for k, v in cols.items()}


def warm_up() -> None:
    """Run one design of the packaged case 1: loads (or compiles) every compiled function a chunk uses."""
    from ..spec import load_example, spec_to_dict
    from ..sweep import DEFAULT_RANGES

    plan = Plan(spec_to_dict(load_example("case1")), ())
    compute_chunk((Request(plan, dict(DEFAULT_RANGES)).to_json(), 0))


def _chunk_path(out_dir: str, index: int) -> str:
    return os.path.join(out_dir, CHUNKS, f"chunk_{index:07d}.npz")


def finished(out_dir: str, req: Request) -> list[int]:
    """Indices of the chunks already on disk."""
    return [i for i in range(req.chunks) if os.path.exists(_chunk_path(out_dir, i))]


def save_chunk(out_dir: str, index: int, cols: dict) -> None:
    path = _chunk_path(out_dir, index)
    tmp = path + ".tmp.npz"
    np.savez(tmp, **cols)
    os.replace(tmp, path)


def load_table(out_dir: str, req: Request) -> dict:
    """The finished chunks' rows, in design order (columns by name)."""
    parts = []
    for i in finished(out_dir, req):
        with np.load(_chunk_path(out_dir, i), allow_pickle=False) as z:
            parts.append({k: z[k] for k in z.files})
    if not parts:
        return {}
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def prepare(out_dir: str, req: Request, resume: bool) -> Request:
    """Create DIR (fresh) or read its request (resume); refuse to mix two runs in one DIR."""
    path = os.path.join(out_dir, REQUEST)
    if resume:
        if not os.path.exists(path):
            raise UserError(f"--resume {out_dir}: no {REQUEST} there; start a run with --out {out_dir}")
        with open(path) as f:
            return Request.from_json(json.load(f))
    if os.path.exists(path):
        with open(path) as f:
            if json.load(f) != json.loads(json.dumps(req.to_json())):
                raise UserError(f"--out {out_dir}: holds another exploration ({REQUEST}); continue it with --resume"
                                f" {out_dir} or choose another --out")
    os.makedirs(os.path.join(out_dir, CHUNKS), exist_ok=True)
    with open(path, "w") as f:
        json.dump(req.to_json(), f, indent=1)
    return req


class Progress:
    """designs done, rate and time left on a terminal (stderr), at most ~4 times a second."""

    def __init__(self, total: int, done: int, stream=None):
        self.stream = stream or sys.stderr
        self.total, self.done, self.start_done = total, done, done
        self.t0 = self.last = time.perf_counter()
        self.on = getattr(self.stream, "isatty", lambda: False)()

    def update(self, n: int) -> None:
        self.done += n
        now = time.perf_counter()
        if not self.on or (now - self.last < 0.25 and self.done < self.total):
            return
        self.last = now
        rate = (self.done - self.start_done) / max(now - self.t0, 1e-9)
        left = (self.total - self.done) / rate if rate > 0 else float("nan")
        self.stream.write(f"\r  explore: {self.done}/{self.total} designs ({100 * self.done / self.total:.1f} %),"
                          f" {rate:.0f} designs/s, {left:.0f} s left   ")
        if self.done >= self.total:
            self.stream.write("\n")
        self.stream.flush()


def execute(out_dir: str, req: Request, ex, progress: Progress | None = None) -> tuple[bool, str]:
    """Compute the missing chunks on the executor ``ex``; (complete, why not)."""
    from ..parallel import WorkLost

    todo = [i for i in range(req.chunks) if not os.path.exists(_chunk_path(out_dir, i))]
    payload = req.to_json()
    try:
        for k, cols in ex.map_unordered(compute_chunk, [(payload, i) for i in todo]):
            save_chunk(out_dir, todo[k], cols)
            if progress:
                progress.update(len(cols["design"]))
    except KeyboardInterrupt:
        return False, "interrupted (Ctrl-C)"
    except WorkLost as exc:
        return False, str(exc)
    return True, ""
