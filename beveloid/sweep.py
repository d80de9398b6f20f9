"""Monte Carlo tolerance sweep: K random assembly-error sets x N contact positions.

Positions are spread over the aligned engagement of one tooth pair on the chosen flank (the
pinion angles at which the aligned contact lies on both flanks), so that a point that is not
'ok' under an error set means the contact has left the flank there.  Two backends solve the
same generated equations: "compiled" (numba, the default when installed) and "numpy".
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from . import assembly_errors, mesh, tca
from .errors import OptionError
from .result import Result, freeze, thaw
from .solver import threads
from .status import Status, carries_numbers

#: Default half-widths of the uniform error ranges (defined with the errors, where a command reads them
#: without importing the sweep)
DEFAULT_RANGES = assembly_errors.DEFAULT_RANGES
#: samples x positions above this is refused: the sweep holds ~220 bytes per contact point (~1.1 GB here).
MAX_CONTACT_POINTS = 5_000_000
#: (smallest, largest) samples and positions of a sweep: the one range table the CLI reads
SIZES = {"samples": (1, 10_000_000), "positions": (2, 10_000)}


class SweepSizeError(OptionError):
    """A sweep size out of range: an :class:`beveloid.errors.OptionError` (key, value, what is valid)."""


def check_sweep_size(samples, positions):
    """The sizes of SIZES, and samples * positions <= MAX_CONTACT_POINTS, else a one-line
    SweepSizeError naming the option (``samples``, ``positions``; the command line names its flags)."""
    for key, v in (("samples", samples), ("positions", positions)):
        lo, hi = SIZES[key]
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
            raise SweepSizeError(key, v, f"must be an integer from {lo} to {hi}")
    if samples * positions > MAX_CONTACT_POINTS:
        raise SweepSizeError("samples", samples,
                             f"times positions = {positions} makes {samples * positions} contact points: at most"
                             f" {MAX_CONTACT_POINTS} per sweep (memory, ~220 bytes a point); use fewer samples or"
                             f" positions, or run several sweeps with different seeds")


def draw_errors(samples, ranges=None, seed=0, nominal=None, start=0):
    """Uniform error sets (K, 5) in (mm, mm, mm, rad, rad) about ``nominal``: sets start .. start +
    samples - 1 of the seed's stream.

    ``ranges`` are half-widths and ``nominal`` the centre (dicts keyed like DEFAULT_RANGES: mm / deg;
    missing range keys take DEFAULT_RANGES, missing nominal keys are 0).  The generator is the seed's
    PCG64 stream advanced past the 5 * start draws before the first set, so a chunk of sets drawn on its
    own (on any worker) is the same as that part of the whole draw: the one draw of the package.
    """
    half = assembly_errors.to_layout(dict(DEFAULT_RANGES, **(ranges or {})))
    centre = assembly_errors.to_layout(dict(nominal or {}))
    bits = np.random.PCG64(seed)
    bits.advance(len(half) * start)
    return centre + np.random.Generator(bits).uniform(-1.0, 1.0, (samples, len(half))) * half


class Aligned(NamedTuple):
    """What a chunk needs of the aligned pair to reduce its error sets to the sweep's numbers."""

    pinion_z_mm: np.ndarray  # (N,) axial position of the aligned pinion contact at each grid angle (S_1)
    gear_z_mm: np.ndarray  # (N,) the gear's (S_2)
    ref_pinion_angle: float  # rad, the aligned contact at the pitch point (the TE reference)
    ref_gear_angle: float  # rad
    ratio: float  # N1 / N2
    per_pitch: int  # grid steps per pinion pitch (position_lattice)
    first: int  # lattice index of the first grid angle
    sign: float  # the flank's first-touch sign (mesh.envelope)


class ChunkTask(NamedTuple):
    """One chunk of a sweep, as a worker receives it: error sets start .. stop - 1 on the angle grid."""

    geometry: object
    flank: str
    start: int
    stop: int
    ranges: dict
    seed: int
    nominal: dict
    grid: np.ndarray
    solver: object
    aligned: Aligned


class ChunkSolution(NamedTuple):
    """What a worker returns for a chunk: its error sets, per set and angle the status codes, the Newton
    iterations summed over its points, and per set the mean path shifts (mm) and the mesh TE
    peak-to-peak (rad), nan for a set without contact."""

    errors: np.ndarray
    status: np.ndarray
    iterations: int
    pinion_shift_mm: np.ndarray
    gear_shift_mm: np.ndarray
    te_peak_to_peak: np.ndarray


def solve_chunk(task: ChunkTask) -> ChunkSolution:
    """The error sets of one chunk, drawn on their own, solved (what a worker runs; module level: pickled)."""
    from .parallel import single_threaded

    single_threaded()
    return _solve_sets(task)


def _solve_sets(task: ChunkTask) -> ChunkSolution:
    """The chunk's sets drawn, solved and reduced to its per-set numbers: on any worker or thread, the
    numbers of each set are those of the whole sweep in one piece (every reduction is per set)."""
    errors = draw_errors(task.stop - task.start, task.ranges, task.seed, task.nominal, start=task.start)
    geom, flank, grid, al = task.geometry, task.flank, task.grid, task.aligned
    sol = tca.solve_grid(geom, flank, errors, grid, solver=task.solver)
    ok = carries_numbers(sol.status)
    P1, P2 = tca.solved_contact_points(geom, flank, sol.x, sol.status, solver=task.solver)
    n_ok = ok.sum(axis=1)
    has = n_ok > 0
    shifts = []
    for P, z in ((P1, al.pinion_z_mm), (P2, al.gear_z_mm)):
        shift = np.full(errors.shape[0], np.nan)
        shift[has] = np.where(ok, P[..., 2] - z[None, :], 0.0).sum(axis=1)[has] / n_ok[has]
        shifts.append(shift)
    te = mesh.transmission_error(tca.unknowns(sol.x).gear_angle_rad, grid[None, :], al.ref_gear_angle,
                                 al.ref_pinion_angle, al.ratio)
    ptp = mesh_te_peak_to_peak(np.where(ok, te, np.nan), al.per_pitch, al.first, al.sign)
    return ChunkSolution(errors, sol.status, int(sol.iterations.sum()), *shifts, ptp)


def engagement_window(geom, flank, ref=None, resolution=400, *, solver: "tca.Solver | None" = None):
    """Pinion-angle interval over which the aligned pair-0 contact is 'ok' (rad), solved by ``solver``
    (a :class:`beveloid.solver.Solver`; None: the default)."""
    ref = ref or tca.reference_contact(geom, flank, tca.Solver.of(solver).options)
    p1, _ = geom.pitch_angles
    grid = ref.pinion_angle + np.linspace(-2.5 * p1, 2.5 * p1, resolution)
    sol = tca.solve_grid(geom, flank, np.zeros((1, len(tca.ERROR_NAMES))), grid, solver=solver)
    ok = np.nonzero(sol.status[0] == Status.OK)[0]
    if ok.size == 0:
        raise tca.NoContactError(f"the aligned {flank} flank has no contact on the flanks")
    lo, hi = grid[ok[0]], grid[ok[-1]]
    return lo, hi


def _stats(v):
    v = np.asarray(v, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return {"count": 0}
    return {"count": int(v.size), "mean": float(v.mean()), "std": float(v.std()), "min": float(v.min()),
            "p05": float(np.percentile(v, 5)), "p50": float(np.percentile(v, 50)),
            "p95": float(np.percentile(v, 95)), "max": float(v.max())}


@dataclass(frozen=True)
class SweepResult(Result):
    """The sweep of ``pair`` under ``options`` (a :class:`sweep.Options`): per error set its numbers;
    deep-frozen, its JSON by :meth:`to_json`."""

    flank: str
    samples: int
    positions: int
    errors: np.ndarray
    pinion_angles: np.ndarray
    status_codes: np.ndarray
    pinion_shift_mm: np.ndarray  # (K,) mean axial shift of the pinion contact vs aligned
    gear_shift_mm: np.ndarray
    te_peak_to_peak: np.ndarray  # (K,) rad
    sensitivity: dict
    backend: str
    seconds: float  # the K x N points solved and reduced to their per-set numbers (on threads: the parallel part)
    newton_iterations_mean: float
    ranges: dict = field(default_factory=dict)
    #: centre of the error distribution (mm / deg keys like DEFAULT_RANGES); the file's [misalignment] in the CLI
    nominal_errors: dict = field(default_factory=lambda: {k: 0.0 for k in DEFAULT_RANGES})
    seconds_total: float = float("nan")  # the whole sweep: window, aligned path, solve, statistics

    @property
    def contact_points_solved(self):
        return int(self.status_codes.size)

    def to_json(self) -> dict:
        """The JSON of ``beveloid sweep --json`` (strict: no NaN)."""
        codes = self.status_codes
        any_edge = (codes == Status.EDGE).any(axis=1)
        any_off = (codes >= Status.OUTSIDE).any(axis=1)
        all_off = (codes >= Status.OUTSIDE).all(axis=1)
        return {
            "flank": self.flank,
            "samples": self.samples,
            "positions": self.positions,
            "contact_points_solved": self.contact_points_solved,
            "backend": self.backend,
            "seconds": self.seconds,
            "seconds_total": self.seconds_total,
            "us_per_point": self.seconds / max(1, self.contact_points_solved) * 1e6,
            "us_per_point_total": self.seconds_total / max(1, self.contact_points_solved) * 1e6,
            "newton_iterations_mean": self.newton_iterations_mean,
            "ranges": thaw(self.ranges),
            "nominal_errors": thaw(self.nominal_errors),
            "pinion_angle_window_rad": [float(self.pinion_angles[0]), float(self.pinion_angles[-1])],
            "status_counts": {s.label: int((codes == s).sum()) for s in Status},
            "fraction_sets_with_edge_contact": float(any_edge.mean()),
            "fraction_sets_with_contact_off_flank": float(any_off.mean()),
            "fraction_sets_entirely_off_flank": float(all_off.mean()),
            "sets_with_failed_points": int((codes == Status.FAILED).any(axis=1).sum()),
            "sets_with_contact": int((codes <= 1).any(axis=1).sum()),
            "pinion_path_shift_mm": _stats(self.pinion_shift_mm),
            "gear_path_shift_mm": _stats(self.gear_shift_mm),
            "te_peak_to_peak_urad": _stats(self.te_peak_to_peak * 1e6),
            "sensitivity": thaw(self.sensitivity),
        }


def position_lattice(ref_angle, lo, hi, positions, pinion_pitch):
    """(pinion angles (positions,), steps per pinion pitch m, lattice index of the first angle):
    ``positions`` angles ref + j p1/m inside [lo, hi] less 1 % at each end (the aligned
    engagement), m the fewest steps per pitch that fit them, centred; on this lattice a mesh cycle
    folds exactly onto neighbouring pairs (see mesh_te_peak_to_peak)."""
    pad = 0.01 * (hi - lo)
    a, b = lo + pad - ref_angle, hi - pad - ref_angle
    m = max(1, math.ceil(pinion_pitch * positions / (b - a)))
    h = pinion_pitch / m
    first_slot, last_slot = math.ceil(a / h), math.floor(b / h)
    first = first_slot + max(0, (last_slot - first_slot - (positions - 1)) // 2)
    return ref_angle + h * (first + np.arange(positions)), m, first


def mesh_te_peak_to_peak(te, m, first, sign):
    """Peak-to-peak (K,) of the mesh TE envelope from pair 0's TE (K, N) on the lattice of
    :func:`position_lattice` (nan where no contact): pair k at angle phi is pair 0 at phi - k p1,
    so angles one pinion pitch (m steps) apart are the same cycle angle of neighbouring pairs;
    the envelope over them (mesh.envelope, the flank's first-touch sign) is the TE of the mesh,
    as tca reports it.  nan for a set without contact."""
    K, N = te.shape
    idx = first + np.arange(N)
    cycle, turn = idx % m, idx // m
    turn = turn - turn.min()
    folded = np.full((int(turn.max()) + 1, K, m), np.nan)
    folded[turn, :, cycle] = te.T
    env, _ = mesh.envelope(folded, sign)
    return mesh.peak_to_peak(env)


def aligned_path(geom, flank, positions, *, solver: "tca.Solver | None" = None) -> tuple[np.ndarray, Aligned]:
    """(the sweep's pinion angles (positions,), :class:`Aligned`): the lattice over the aligned engagement
    (:func:`position_lattice`) and the aligned pair's path on it, what every chunk reduces against."""
    ref = tca.reference_contact(geom, flank, tca.Solver.of(solver).options)
    lo, hi = engagement_window(geom, flank, ref, solver=solver)
    grid, per_pitch, first = position_lattice(ref.pinion_angle, lo, hi, positions, geom.pitch_angles[0])
    xa = tca.solve_grid(geom, flank, np.zeros((1, len(tca.ERROR_NAMES))), grid, solver=solver).x
    p_al, g_al = tca.contact_points(geom, flank, xa[0])
    return grid, Aligned(pinion_z_mm=np.ascontiguousarray(p_al[:, 2]), gear_z_mm=np.ascontiguousarray(g_al[:, 2]),
                         ref_pinion_angle=float(ref.pinion_angle),
                         ref_gear_angle=float(tca.unknowns(ref.x).gear_angle_rad),
                         ratio=geom.pinion.teeth / geom.gear.teeth, per_pitch=per_pitch, first=first,
                         sign=float(tca.first_touch_sign(geom, flank)))


def _run(pair, options: "Options", solver, executor, progress):
    """The sweep itself (:func:`analyze`)."""
    flank, samples, positions, seed = options.flank, options.samples, options.positions, options.seed
    ranges, nominal, chunk = options.ranges, options.nominal, options.chunk
    t_start = time.perf_counter()
    geom = tca.geometry_of(pair)
    grid, aligned = aligned_path(geom, flank, positions, solver=solver)
    t0 = time.perf_counter()
    errors = np.empty((samples, len(tca.ERROR_NAMES)))
    C = np.empty((samples, positions), dtype=np.int64)
    ptp, pinion_shift, gear_shift = np.empty(samples), np.empty(samples), np.empty(samples)
    # in this process on threads (the compiled core releases the GIL, numpy too): whole chunks, each
    # solved and reduced on its thread; many more chunks than threads, so that none finishes last alone
    on_threads = executor is None and solver.compiled and samples > tca.SERIAL_MAX_SETS and threads.count() > 1
    bounds = (threads.pieces(samples, threads.count(), chunk) if on_threads else
              [(s, min(samples, s + chunk)) for s in range(0, samples, chunk)])
    tasks = [ChunkTask(geom, flank, a, b, dict(DEFAULT_RANGES, **(ranges or {})), seed, dict(nominal or {}), grid,
                       solver, aligned) for a, b in bounds]
    if on_threads:
        solved = threads.map_unordered(_solve_sets, tasks, threads.count())
    elif executor is None:  # in this process, in order
        solved = ((k, _solve_sets(t)) for k, t in enumerate(tasks))
    else:
        solved = executor.map_unordered(solve_chunk, tasks)
    done = iterations = 0
    for k, part in solved:
        sl = slice(tasks[k].start, tasks[k].stop)
        errors[sl], C[sl], pinion_shift[sl], gear_shift[sl], ptp[sl] = (
            part.errors, part.status, part.pinion_shift_mm, part.gear_shift_mm, part.te_peak_to_peak)
        iterations += part.iterations
        done += sl.stop - sl.start
        if progress:
            progress(done, samples, "error sets")
    seconds = time.perf_counter() - t0
    s = tca.sensitivity(geom, flank, solver=solver)
    names = assembly_errors.KEYS
    per = [e.to_layout for e in assembly_errors.ERRORS]
    sens = {
        "pinion_axial_shift_mm_per_unit": {n: float(s["pinion_contact_D_errors"][2, i] * per[i]) for i, n in enumerate(names)},
        "gear_axial_shift_mm_per_unit": {n: float(s["gear_contact_D_errors"][2, i] * per[i]) for i, n in enumerate(names)},
        "gear_angle_urad_per_unit": {n: float(s["gear_angle_D_errors"][i] * per[i] * 1e6) for i, n in enumerate(names)},
        "units": "per mm for dx, dy, dz; per degree for vertical, horizontal; at the aligned pitch point",
    }
    r = dict(DEFAULT_RANGES, **(ranges or {}))
    return SweepResult(flank=flank, samples=samples, positions=positions, errors=errors, pinion_angles=grid,
                       status_codes=C, pinion_shift_mm=pinion_shift, gear_shift_mm=gear_shift, te_peak_to_peak=ptp,
                       sensitivity=sens, backend=solver.backend, seconds=seconds,
                       newton_iterations_mean=iterations / C.size,
                       ranges=r, nominal_errors={k: 0.0 for k in DEFAULT_RANGES} | dict(nominal or {}),
                       seconds_total=time.perf_counter() - t_start, pair=pair, options=options)


#: largest seed (the CLI's --seed)
MAX_SEED = 2 ** 63 - 1


@dataclass(frozen=True)
class Options:
    """A Monte Carlo sweep: ``samples`` error sets x ``positions`` contact positions on ``flank``; the sets
    uniform within the half-widths ``ranges`` about ``nominal`` (dicts keyed like DEFAULT_RANGES, mm / deg;
    missing range keys take DEFAULT_RANGES, missing nominal keys are 0), drawn from ``seed``; solved in
    chunks of at most ``chunk`` sets (in this process on several threads, enough smaller pieces that each
    thread takes several; the numbers do not depend on the chunks).  Validates itself: a bad value raises a one-line OptionError (key, value,
    what is valid; SweepSizeError for the sizes)."""

    flank: str = "right"
    samples: int = 1000
    positions: int = 50
    seed: int = 0
    ranges: dict = field(default_factory=lambda: dict(DEFAULT_RANGES))
    nominal: dict = field(default_factory=lambda: {k: 0.0 for k in DEFAULT_RANGES})
    chunk: int = 2000

    def __post_init__(self):
        if self.flank not in tca.FLANKS:
            raise OptionError("flank", self.flank, f"must be one of {', '.join(tca.FLANKS)}")
        check_sweep_size(self.samples, self.positions)
        for key, value, lo, hi in (("seed", self.seed, 0, MAX_SEED), ("chunk", self.chunk, 1, 10_000_000)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
                raise OptionError(key, value, f"must be an integer from {lo} to {hi}")
        for name, given in (("ranges", self.ranges), ("nominal", self.nominal)):
            unknown = set(given) - set(DEFAULT_RANGES)
            if unknown:
                raise OptionError(f"{name}.{sorted(unknown)[0]}", given[sorted(unknown)[0]],
                                  f"not an error; valid: {', '.join(DEFAULT_RANGES)}")
        ranges = dict(DEFAULT_RANGES, **self.ranges)
        nominal = {k: 0.0 for k in DEFAULT_RANGES} | dict(self.nominal)
        for key, half in ranges.items():
            limit, unit = assembly_errors.BY_KEY[key].limit, assembly_errors.BY_KEY[key].unit
            if not (isinstance(half, (int, float, np.floating)) and 0 <= half < limit):
                raise OptionError(f"ranges.{key}", half, f"must be >= 0 and < {limit:g} ({unit})")
            if not abs(nominal[key]) + half <= limit:
                raise OptionError(f"ranges.{key}", half, f"about nominal {nominal[key]:g} reaches"
                                  f" {abs(nominal[key]) + half:g}; |nominal| + half-width must be <= {limit:g} ({unit})")
        object.__setattr__(self, "ranges", freeze(ranges))
        object.__setattr__(self, "nominal", freeze(nominal))


def analyze(pair, options: Options | None = None, *, solver: "tca.Solver | None" = None, executor=None,
            progress=None) -> SweepResult:
    """The sweep of ``options`` (None: the default :class:`Options`) on a :class:`beveloid.pair.Pair` (or its
    PairGeometry): a deep-frozen :class:`SweepResult` (its JSON: ``to_json()``).  ``solver``: a :class:`beveloid.solver.Solver`
    (None: the default); ``executor``: beveloid.parallel.executor(...) for the chunks (the same numbers on
    one worker, N workers and a cluster); ``progress``: a :class:`beveloid.progress.Progress` (the error sets
done) or None."""
    if options is None:
        options = Options()
    if not isinstance(options, Options):
        raise TypeError(f"sweep.analyze needs a sweep.Options, not {type(options).__name__}")
    return _run(pair, options, tca.Solver.of(solver), executor, progress)
