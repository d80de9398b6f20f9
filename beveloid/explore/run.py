"""Running an exploration: fixed chunks of designs, on any executor, kept on disk as they finish.

The designs are cut into chunks of ``chunk`` consecutive designs; a chunk's rows depend only on the
request and the chunk's index (never on the worker or the number of workers), so one worker, N
local workers and a Dask cluster write the same rows bit for bit.  A worker computes a chunk's rows
and their CSV text (report.csv_rows: the per-cell work of the CSV files is done there, in parallel);
each finished chunk is written at once to ``DIR/chunks/`` (numpy .npz, written to a temporary name
and renamed: by the worker itself where it shares this file system, this process and local
processes, else here as it arrives) and kept in memory (:class:`Chunks`: a run reads the chunks of an earlier one once, and
computes again one that is damaged).  The base design's row is a task of its own (:data:`BASE`).
The request is in ``DIR/request.json``.  An interrupted run (Ctrl-C, a lost worker) keeps its
finished chunks, and ``--resume DIR`` computes only the missing ones.
"""
from __future__ import annotations

import functools
import hashlib
import os
import sys
import time
import zipfile
from collections import Counter
from dataclasses import asdict, dataclass, field
from typing import NamedTuple

import numpy as np

from ..errors import StopReason
from ..runstore import REQUEST, RunResult, RunStore, version_text  # noqa: F401  (REQUEST: the CLI reads it here)
from .grid import Plan, Vary

#: designs per chunk: large enough for the batched kernels, small enough to lose little on a stop
CHUNK = 256
CHUNKS = "chunks"
#: the index of the task that computes the base design's row (not a chunk)
BASE = -1
#: in a chunk beside its columns: the CSV text of its rows (UTF-8, uint8) and where each row ends in it
TEXT, ROW_ENDS = "_csv_text", "_csv_row_ends"
#: in a chunk file: the names of the columns in order, and the float columns as one array (n, k)
ORDER, FLOATS = "_columns", "_float_columns"


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

    @functools.cached_property
    def solver(self):
        """The :class:`beveloid.solver.Solver` of the request's ``backend`` (the name it is stored by), made
        once per request: every chunk of the run solves with the same Solver."""
        from ..solver import Solver

        return Solver(self.backend)


class ChunkTask(NamedTuple):
    """What a worker gets: the request (its JSON dict), the index of the chunk (:data:`BASE`: the base
    design) and the run's folder where the worker writes the chunk file itself (None: the caller does)."""

    request: dict
    index: int
    out_dir: str | None = None


def compute_chunk(task: ChunkTask) -> dict:
    """The rows of chunk ``task.index`` of a request, and their CSV text (report.csv_rows, under
    :data:`TEXT` and :data:`ROW_ENDS`): what a worker runs; written to ``task.out_dir`` too when given
    (:func:`save_chunk`).  ``task.index == BASE``: the row of the request's base design (no text, no file)."""
    from .. import parallel
    from . import report, rows

    parallel.single_threaded()
    req = Request.from_json(task.request)
    if task.index == BASE:
        plan, start, stop = Plan(req.plan.base, (), seed=req.plan.seed), 0, 1
    else:
        plan, start = req.plan, task.index * req.chunk
        stop = min(req.plan.count, start + req.chunk)
    solver = req.solver
    cols = rows.compute(plan, start, stop, req.tolerances, solver=solver)
    if req.mc:
        rows.monte_carlo(cols, plan, slice(start, stop), req.tolerances, rows.monte_carlo_request(req), solver=solver)
    cols = {k: (np.asarray(v, dtype=str) if np.asarray(v).dtype == object else np.asarray(v)) for k, v in cols.items()}
    if task.index != BASE:
        cols[TEXT], cols[ROW_ENDS] = report.csv_rows(cols)
        if task.out_dir is not None:
            save_chunk(task.out_dir, task.index, cols)
    return cols


def warm_up() -> None:
    """Run one design of the packaged case 1: loads (or compiles) every compiled function a chunk uses."""
    from ..spec import load_example, spec_to_dict
    from ..assembly_errors import DEFAULT_RANGES

    plan = Plan(spec_to_dict(load_example("case1")), ())
    compute_chunk(ChunkTask(Request(plan, dict(DEFAULT_RANGES)).to_json(), 0))


def _chunk_path(out_dir: str, index: int) -> str:
    return os.path.join(out_dir, CHUNKS, f"chunk_{index:07d}.npz")


def finished(out_dir: str, req: Request) -> list[int]:
    """Indices of the chunks on disk."""
    return [i for i in range(req.chunks) if os.path.exists(_chunk_path(out_dir, i))]


def save_chunk(out_dir: str, index: int, cols: dict) -> None:
    """A chunk's columns (and text) in ``DIR/chunks/`` (written under a temporary name, then renamed): the
    float columns as one 2-D array (:data:`FLOATS`), the others one array each, the names in order
    (:data:`ORDER`)."""
    path = _chunk_path(out_dir, index)
    tmp = path + ".tmp.npz"
    names = [k for k in cols if k not in (TEXT, ROW_ENDS)]
    floats = [k for k in names if cols[k].dtype == np.float64]
    packed = {k: v for k, v in cols.items() if k not in floats}
    packed[ORDER] = np.array(names)
    packed[FLOATS] = np.stack([cols[k] for k in floats], axis=1) if floats else np.zeros((len(cols["design"]), 0))
    np.savez(tmp, **packed)
    os.replace(tmp, path)


def _unpack(raw: dict) -> dict:
    """The columns of a chunk file in their order (a file of one array per column, as an older version
    wrote them, as it is)."""
    if ORDER not in raw:
        return raw
    names, floats = raw.pop(ORDER).tolist(), raw.pop(FLOATS)
    apart = [k for k in names if k not in raw]
    if floats.ndim != 2 or floats.shape[1] != len(apart):
        raise ValueError("the float columns do not match their names")
    cols = dict(zip(apart, floats.T))
    cols = {k: raw[k] if k in raw else cols[k] for k in names}
    cols.update({k: raw[k] for k in (TEXT, ROW_ENDS) if k in raw})
    return cols


def _read_chunk(out_dir: str, req: Request, index: int) -> dict | None:
    """The columns of a chunk file, None when it is not a chunk of these designs (damaged, cut short,
    overwritten): whatever np.load raises on such bytes, or rows that are not the chunk's designs."""
    try:
        with np.load(_chunk_path(out_dir, index), allow_pickle=False) as z:
            cols = _unpack({k: z[k] for k in z.files})
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
        return None
    start = index * req.chunk
    designs = np.arange(start, min(req.plan.count, start + req.chunk))
    columns = [v for k, v in cols.items() if k not in (TEXT, ROW_ENDS)]
    if "design" not in cols or not np.array_equal(cols["design"], designs) or any(
            v.shape != designs.shape for v in columns):
        return None
    if (TEXT in cols) != (ROW_ENDS in cols) or (ROW_ENDS in cols and (
            cols[ROW_ENDS].shape != designs.shape or cols[ROW_ENDS][-1] != cols[TEXT].size)):
        return None
    return cols


class Chunks:
    """The finished chunks of a run: read from DIR once (those a run before finished), and kept as they
    finish.  A chunk file that is not a chunk of this run (damaged, overwritten, cut short) is removed,
    with one line to ``log`` naming it, and is computed again as a missing one."""

    def __init__(self, out_dir: str, req: Request, log=None):
        self.out_dir, self.req = out_dir, req
        self.parts: dict[int, dict] = {}
        #: the base design's row (compute_chunk of BASE), once computed
        self.base: dict | None = None
        damaged = []
        for i in finished(out_dir, req):
            cols = _read_chunk(out_dir, req, i)
            if cols is None:
                damaged.append(i)
            else:
                self.parts[i] = cols
        names = {i: tuple(k for k in cols if k not in (TEXT, ROW_ENDS)) for i, cols in self.parts.items()}
        usual = Counter(names.values()).most_common(1)[0][0] if names else ()
        damaged += [i for i, n in names.items() if n != usual]  # the columns of another run's chunk
        for i in sorted(damaged):
            self.parts.pop(i, None)
            os.remove(_chunk_path(out_dir, i))
        if damaged and log:
            which = ", ".join(f"{i} ({os.path.basename(_chunk_path(out_dir, i))})" for i in sorted(damaged))
            log(f"beveloid explore: {out_dir}: chunk{'s' if len(damaged) > 1 else ''} {which} of {CHUNKS}/"
                f" {'are' if len(damaged) > 1 else 'is'} damaged (not a chunk of this run): computing"
                f" {'them' if len(damaged) > 1 else 'it'} again")

    def missing(self) -> list[int]:
        return [i for i in range(self.req.chunks) if i not in self.parts]

    @property
    def designs(self) -> int:
        """Designs in the finished chunks."""
        return sum(len(cols["design"]) for cols in self.parts.values())

    def add(self, index: int, cols: dict, saved: bool = False) -> None:
        """A chunk that finished: written to DIR (unless its worker ``saved`` it there) and kept."""
        if not saved:
            save_chunk(self.out_dir, index, cols)
        self.parts[index] = cols

    def table(self) -> dict:
        """The finished rows in design order (columns by name; {} when none)."""
        parts = [self.parts[i] for i in sorted(self.parts)]
        if not parts:
            return {}
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0] if k not in (TEXT, ROW_ENDS)}

    def csv_rows(self) -> list:
        """The CSV text of the finished rows, a report.CsvRows per chunk in design order: as the workers
        made it (for a chunk written by an older version, without it: made here)."""
        from . import report

        return [report.CsvRows(p[TEXT], p[ROW_ENDS]) if TEXT in p
                else report.csv_rows({k: v for k, v in p.items() if k not in (TEXT, ROW_ENDS)})
                for p in (self.parts[i] for i in sorted(self.parts))]


def load_table(out_dir: str, req: Request) -> dict:
    """The finished chunks' rows on disk, in design order (columns by name)."""
    return Chunks(out_dir, req).table()


def prepare(out_dir: str, req: Request | None, resume: bool, log=None) -> Request:
    """Create DIR (fresh) or read its request (resume); refuse to mix two runs in one DIR
    (:class:`beveloid.runstore.RunStore`).

    Chunks are reused only when computed by the same code (:func:`code_version`): a fresh run of the
    same request into a DIR made by another version removes the old chunks (``log`` says so, one line)
    and computes them again; ``--resume`` of such a DIR is refused with a line saying how to go on.
    """
    store = RunStore(out_dir, CHUNKS, "chunks", "exploration")
    now = code_version()
    if resume:
        return Request.from_json(store.resumed(now))
    held = store.check_fresh(req.to_json(), ignore=("code",))
    if held is not None and held.get("code") != now:
        stale = finished(out_dir, req)
        for i in stale:
            os.remove(_chunk_path(out_dir, i))
        if log and stale:
            log(f"beveloid explore: {out_dir} holds {len(stale)} chunks of this request computed by"
                f" {version_text(held.get('code', {}))}; this is {version_text(now)}: computing them again")
    store.write(req.to_json())
    return req


class Progress:
    """A :class:`beveloid.progress.Progress`: designs done, rate and time left on a terminal (stderr), at most
    ~4 times a second; ``done``: the designs already done when the run starts (not counted in the rate)."""

    def __init__(self, done: int = 0, stream=None):
        self.stream = stream or sys.stderr
        self.start_done = done
        self.t0 = self.last = time.perf_counter()
        self.on = getattr(self.stream, "isatty", lambda: False)()

    def __call__(self, done: int, total: int | None, what: str) -> None:
        now = time.perf_counter()
        if not self.on or not total or (now - self.last < 0.25 and done < total):
            return
        self.last = now
        rate = (done - self.start_done) / max(now - self.t0, 1e-9)
        left = (total - done) / rate if rate > 0 else float("nan")
        self.stream.write(f"\r  explore: {done}/{total} {what} ({100 * done / total:.1f} %),"
                          f" {rate:.0f} {what}/s, {left:.0f} s left   ")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


@dataclass(frozen=True, eq=False)
class ExploreRun(RunResult):
    """How a run of :func:`execute` ended (:class:`beveloid.runstore.RunResult`; its rows are in
    ``out_dir``); ``options``: the run's :class:`Request`."""


def execute(out_dir: str, req: Request, ex, progress=None,
            chunks: Chunks | None = None) -> ExploreRun:
    """Compute the missing chunks and the base design's row on the executor ``ex``, keeping them in
    ``chunks`` (read from ``out_dir`` if not given): an :class:`ExploreRun`, its ``stop`` None when
    complete, else why it stopped and a line saying so."""
    from ..parallel import WorkLost

    chunks = Chunks(out_dir, req) if chunks is None else chunks
    payload = req.to_json()
    # workers that share this file system write their chunk files themselves (in parallel)
    where = out_dir if getattr(ex, "shares_files", False) else None
    # the base design first: a run stopped early has it too (else the caller computes it, here)
    tasks = [ChunkTask(payload, BASE)] + [ChunkTask(payload, i, where) for i in chunks.missing()]
    try:
        for k, cols in ex.map_unordered(compute_chunk, tasks):
            if tasks[k].index == BASE:
                chunks.base = cols
                continue
            chunks.add(tasks[k].index, cols, saved=where is not None)
            if progress:
                progress(chunks.designs, req.plan.count, "designs")
    except KeyboardInterrupt:
        return ExploreRun(out_dir, StopReason.INTERRUPTED, str(StopReason.INTERRUPTED), options=req)
    except WorkLost as exc:
        return ExploreRun(out_dir, StopReason.WORK_LOST, str(exc), options=req)
    return ExploreRun(out_dir, None, "", options=req)
