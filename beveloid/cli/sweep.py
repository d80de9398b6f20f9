"""``beveloid sweep FILE --samples K --positions N [--seed S] [--flank left|right] [--backend B] [--json]``.

The random error sets are drawn uniformly about the file's ``[misalignment]`` (the nominal errors,
0 when the table is absent), within the half-widths ``--dx-max`` ... ``--horizontal-max``; the
nominal plus the half-width must stay within the spec's limits (10 mm, 5 deg).
"""
from __future__ import annotations

import argparse
import json
import sys

from .. import assembly_errors
from ..errors import UserError
from .common import number, solver_of
from ..solver.backends import BACKENDS
from ..status import PointStatus
from ..sweep import DEFAULT_RANGES, MAX_CONTACT_POINTS

LIMITS = {e.key: e.limit for e in assembly_errors.ERRORS}


def _flag(key):
    return "--" + key.replace("_mm", "").replace("_deg", "") + "-max"


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one); its"
                   " [misalignment] is the nominal error set the random sets are drawn around")
    p.add_argument("--samples", type=int, default=1000, metavar="K", help="random error sets (default 1000)")
    p.add_argument("--positions", type=int, default=50, metavar="N",
                   help="contact positions per set over the aligned engagement (default 50); samples x positions"
                        f" must not exceed {MAX_CONTACT_POINTS}")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("--flank", choices=("left", "right"), default="right", help="flank pair (default right)")
    for key, val in DEFAULT_RANGES.items():
        unit = "MM" if key.endswith("_mm") else "DEG"
        p.add_argument(_flag(key), dest=key, type=float, default=val, metavar=unit,
                       help=f"half-width of the uniform {key} range about the file's misalignment.{key}"
                            f" (default {val})")
    p.add_argument("--backend", choices=BACKENDS, default="auto",
                   help="solver backend: compiled (numba) when installed, else numpy (default auto)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    where = p.add_mutually_exclusive_group()  # beveloid.parallel: the same numbers on any of them
    where.add_argument("--workers", type=int, metavar="N", help="solve chunks of error sets on N local processes")
    where.add_argument("--scheduler", metavar="ADDRESS", help="solve them on an existing Dask distributed cluster")


def run(args: argparse.Namespace) -> int:
    """Monte Carlo tolerance sweep over random assembly errors.

    The error sets are drawn uniformly about the file's [misalignment] (the nominal errors) within
    the --*-max half-widths.  Reports the point counts per status, the contact-path shift
    distribution, the fraction of error sets with edge contact or contact off the flank, TE
    peak-to-peak statistics (each with the number of sets behind it) and first-order sensitivities.
    """
    from .. import tca
    from ..pair import Pair
    from ..progress import for_terminal
    from ..spec import load_spec
    from .. import sweep
    from ..sweep import SweepSizeError, check_sweep_size

    try:
        check_sweep_size(args.samples, args.positions)
    except SweepSizeError as exc:  # named by its fields: the flag of the key
        raise UserError(exc.for_flag("--" + exc.key)) from None
    if not 0 <= args.seed < 2 ** 63:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to 2**63 - 1")
    solver = solver_of(args.backend)
    ranges = {}
    for key in DEFAULT_RANGES:
        v = getattr(args, key)
        unit = "mm" if key.endswith("_mm") else "deg"
        if not (v >= 0 and v < LIMITS[key]):
            raise UserError(f"{_flag(key)} = {v}: must be >= 0 and < {LIMITS[key]:g} ({unit})")
        ranges[key] = v
    spec = load_spec(args.file)
    nominal = {key: float(getattr(spec.misalignment, key)) for key in DEFAULT_RANGES}
    for key, centre in nominal.items():
        unit = "mm" if key.endswith("_mm") else "deg"
        if abs(centre) + ranges[key] > LIMITS[key]:
            raise UserError(
                f"{_flag(key)} = {ranges[key]:g} with misalignment.{key} = {centre:g} in the file: the errors"
                f" would reach {abs(centre) + ranges[key]:g} {unit}; |nominal| + half-width must be <="
                f" {LIMITS[key]:g} {unit}")
    pair = Pair.from_spec(spec)
    progress = for_terminal(sys.stderr)
    from contextlib import nullcontext

    from ..parallel import executor

    parallel = args.workers is not None or args.scheduler is not None
    startup_s = None
    try:
        if solver.backend == "compiled" and not parallel:
            startup_s = _warm_up(pair, args.flank, solver)
        with (executor(args.workers, args.scheduler) if parallel else nullcontext()) as ex:
            options = sweep.Options(flank=args.flank, samples=args.samples, positions=args.positions, seed=args.seed,
                                    ranges=ranges, nominal=nominal)  # the flags are checked above, one line each
            res = sweep.analyze(pair, options, solver=solver, executor=ex, progress=progress)
    except tca.NoContactError as exc:
        # the aligned pair has no contact on this flank: the sweep has no engagement to sample
        raise UserError(f"{args.file}: cannot sweep the {args.flank} flank: {exc} (the aligned pair does not"
                        f" touch within the flank boundaries, so there is no engagement to sample); check the"
                        f" design with `beveloid tca {args.file} --flank {args.flank}`") from None
    out = res.to_json()
    if args.json:
        print(json.dumps(out, allow_nan=False))
        return 0
    print(format_sweep(dict(out, solver_startup_s=startup_s), args.file))
    return 0


def _warm_up(pair, flank, solver) -> float:
    """Seconds to make the compiled solver ready (numba compiles it on the first run after an
    installation, later runs load it from the cache): a small sweep that calls what the real one
    calls, the serial and the parallel paths, so the sweep's own time is the solve alone."""
    import time

    from .. import sweep, tca

    t0 = time.perf_counter()
    try:
        sweep.analyze(pair, sweep.Options(flank=flank, samples=tca.SERIAL_MAX_SETS + 1, positions=2), solver=solver)
    except tca.NoContactError:
        pass  # the real sweep reports it
    return time.perf_counter() - t0


def _row(name, st, unit, samples, scale=1.0, fmt="+.3f"):
    n = st.get("count", 0)
    if not n:
        return f"  {name:<28} {'(no set with contact on the flank)':<64}  {unit:<5} 0 of {samples} sets"
    vals = [number(st[k] * scale, fmt) for k in ("mean", "std", "p05", "p50", "p95")]
    return f"  {name:<28} " + "  ".join(f"{v:>10}" for v in vals) + f"  {unit:<5} {n} of {samples} sets"


def format_sweep(o, file):
    k = o["samples"]
    counts = o["status_counts"]
    total = max(1, o["contact_points_solved"])
    nominal = o["nominal_errors"]
    L = [f"Tolerance sweep of {file}, {o['flank']} flank: {k} error sets x {o['positions']} positions "
         f"= {o['contact_points_solved']} contact points ({o['backend']}, {o['seconds']:.2f} s, "
         f"{o['us_per_point']:.2f} us/point, {o['newton_iterations_mean']:.2f} Newton iterations per point)",
         *([f"  compiled solver ready in {o['solver_startup_s']:.2f} s before the sweep (not in the time above):"
            " numba compiles it once, on the first run after installation, and later runs load it from the cache"]
           if o.get("solver_startup_s") is not None else []),
         "  nominal errors (the file's [misalignment]): " + ", ".join(f"{n} {v:g}" for n, v in nominal.items()),
         "  error ranges (uniform about the nominal, +-): " + ", ".join(f"{n} {v:g}" for n, v in o["ranges"].items()),
         "  contact points: " + ", ".join(f"{counts[s]} {s} ({100 * counts[s] / total:.1f} %)"
                                          for s in PointStatus),
         f"  error sets with contact on the flank: {o['sets_with_contact']} of {k}; with failed points:"
         f" {o['sets_with_failed_points']} of {k}", "",
         f"  {'':<28} " + "  ".join(f"{h:>10}" for h in ("mean", "std", "p5", "p50", "p95")) + "  unit  from",
         _row("pinion path shift", o["pinion_path_shift_mm"], "mm", k),
         _row("gear path shift", o["gear_path_shift_mm"], "mm", k),
         _row("TE peak-to-peak", o["te_peak_to_peak_urad"], "urad", k, fmt=".2e"), "",
         f"  sets with edge contact:           {100 * o['fraction_sets_with_edge_contact']:.1f} % of {k}",
         f"  sets with contact off the flank:  {100 * o['fraction_sets_with_contact_off_flank']:.1f} % of {k}",
         f"  sets entirely off the flank:      {100 * o['fraction_sets_entirely_off_flank']:.1f} % of {k}", "",
         "  first-order sensitivity of the path (pinion axial shift, at the aligned pitch point):"]
    for name, v in o["sensitivity"]["pinion_axial_shift_mm_per_unit"].items():
        unit = "mm/mm" if name.endswith("_mm") else "mm/deg"
        L.append(f"    {name:<16} {number(v, '+10.3f')} {unit}")
    return "\n".join(L)
