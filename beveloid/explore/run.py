"""Running an exploration: fixed chunks of designs, on any executor, kept on disk as they finish.

The designs are cut into chunks of ``chunk`` consecutive designs; a chunk's rows depend only on the
request and the chunk's index (never on the worker or the number of workers), so one worker, N
local workers and a Dask cluster write the same rows bit for bit.  Each finished chunk is written
at once to ``DIR/chunks/`` (numpy .npz, written to a temporary name and renamed); the request is in
``DIR/request.json``.  An interrupted run (Ctrl-C, a lost worker) keeps its finished chunks, and
``--resume DIR`` computes only the missing ones.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import time
from dataclasses import asdict, dataclass, field
from typing import NamedTuple

import numpy as np

from ..errors import ErrorCode, StopReason, UserError
from .grid import Plan, Vary

#: designs per chunk: large enough for the batched kernels, small enough to lose little on a stop
CHUNK = 256
REQUEST = "request.json"
CHUNKS = "chunks"


def code_version() -> dict:
    """What computed the rows: the package version and a digest of the generated kernels (every module
    of ``beveloid.generated``, the code ``beveloid derive`` writes)."""
    from .. import __version__, generated

    digest = hashlib.sha1()
    folder = generated.__path__[0]
    for name in sorted(os.listdir(folder)):
        if name.endswith(".py"):
            with open(os.path.join(folder, name), "rb") as f:
                digest.update(name.encode() + b"\0" + f.read())
    return {"package_version": __version__, "generated_kernels_sha1": digest.hexdigest()[:16]}


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
    #: the code that computes the rows (:func:`code_version`); chunks of another version are not reused
    code: dict = field(default_factory=code_version)

    def to_json(self) -> dict:
        d = asdict(self)
        d["plan"]["varies"] = [asdict(v) for v in self.plan.varies]
        return d

    @classmethod
    def from_json(cls, d: dict) -> "Request":
        p = d["plan"]
        plan = Plan(p["base"], tuple(Vary(**v) for v in p["varies"]), p.get("samples"), p.get("seed", 0))
        return cls(plan, dict(d["tolerances"]), d["mc"], d["mc_positions"], d["mc_flank"], d["chunk"], d["backend"],
                   d.get("source", ""), d.get("extra", {}), dict(d.get("code", {})))

    @property
    def chunks(self) -> int:
        return -(-self.plan.count // self.chunk)


class ChunkTask(NamedTuple):
    """What a worker gets: the request (its JSON dict) and the index of the chunk."""

    request: dict
    index: int


def compute_chunk(task: ChunkTask) -> dict:
    """The rows of chunk ``task.index`` of a request: what a worker runs."""
    from .. import parallel
    from . import rows

    parallel.single_threaded()
    req = Request.from_json(task.request)
    start = task.index * req.chunk
    stop = min(req.plan.count, start + req.chunk)
    cols = rows.compute(req.plan, start, stop, req.tolerances, req.backend)
    if req.mc:
        rows.monte_carlo(cols, req.plan, slice(start, stop), req.tolerances, rows.monte_carlo_request(req),
                         req.backend)
    return {k: (np.asarray(v, dtype=str) if np.asarray(v).dtype == object else np.asarray(v)) for k, v in cols.items()}


def warm_up() -> None:
    """Run one design of the packaged case 1: loads (or compiles) every compiled function a chunk uses."""
    from ..spec import load_example, spec_to_dict
    from ..sweep import DEFAULT_RANGES

    plan = Plan(spec_to_dict(load_example("case1")), ())
    compute_chunk(ChunkTask(Request(plan, dict(DEFAULT_RANGES)).to_json(), 0))


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


def _version_text(code: dict) -> str:
    return (f"beveloid {code.get('package_version', '(unknown)')}, generated kernels"
            f" {code.get('generated_kernels_sha1', '(unknown)')}")


def prepare(out_dir: str, req: Request | None, resume: bool, log=None) -> Request:
    """Create DIR (fresh) or read its request (resume); refuse to mix two runs in one DIR.

    Chunks are reused only when computed by the same code (:func:`code_version`): a fresh run of the
    same request into a DIR made by another version removes the old chunks (``log`` says so, one line)
    and computes them again; ``--resume`` of such a DIR is refused with a line saying how to go on.
    """
    path = os.path.join(out_dir, REQUEST)
    now = code_version()
    if resume:
        if not os.path.exists(path):
            raise UserError(f"--resume {out_dir}: no {REQUEST} there; start a run with --out {out_dir}")
        with open(path) as f:
            old = Request.from_json(json.load(f))
        if old.code != now:
            raise UserError(f"--resume {out_dir}: its chunks were computed by {_version_text(old.code)}, this is"
                            f" {_version_text(now)}; rows of two versions would mix: run the same request again"
                            f" with --out {out_dir} (it recomputes every chunk) or with the version that started it",
                            code=ErrorCode.STALE_RESULTS)
        return old
    if os.path.exists(path):
        with open(path) as f:
            held = json.load(f)
        mine = json.loads(json.dumps(req.to_json()))
        if {k: v for k, v in held.items() if k != "code"} != {k: v for k, v in mine.items() if k != "code"}:
            raise UserError(f"--out {out_dir}: holds another exploration ({REQUEST}); continue it with --resume"
                            f" {out_dir} or choose another --out")
        if held.get("code") != mine["code"]:
            stale = finished(out_dir, req)
            for i in stale:
                os.remove(_chunk_path(out_dir, i))
            if log and stale:
                log(f"beveloid explore: {out_dir} holds {len(stale)} chunks of this request computed by"
                    f" {_version_text(held.get('code', {}))}; this is {_version_text(now)}: computing them again")
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


def execute(out_dir: str, req: Request, ex, progress: Progress | None = None) -> tuple[StopReason | None, str]:
    """Compute the missing chunks on the executor ``ex``: (None, "") when complete, else (why it stopped,
    a line saying so)."""
    from ..parallel import WorkLost

    todo = [i for i in range(req.chunks) if not os.path.exists(_chunk_path(out_dir, i))]
    payload = req.to_json()
    try:
        for k, cols in ex.map_unordered(compute_chunk, [ChunkTask(payload, i) for i in todo]):
            save_chunk(out_dir, todo[k], cols)
            if progress:
                progress.update(len(cols["design"]))
    except KeyboardInterrupt:
        return StopReason.INTERRUPTED, str(StopReason.INTERRUPTED)
    except WorkLost as exc:
        return StopReason.WORK_LOST, str(exc)
    return None, ""
