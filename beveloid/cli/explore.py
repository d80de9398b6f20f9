"""``beveloid explore FILE --vary KEY=START:STOP:COUNT [...]``: map the design space.

``configure(parser)`` adds the arguments, ``run(args) -> int`` runs the exploration (the work is
the package beveloid/explore/; see its run.py for chunks and resume, report.py for the files).  Exit status: 0 when every
design is done, 1 when the run stopped early (Ctrl-C: 130) with the finished designs written and
``--resume DIR`` to continue, 2 for bad input (one line).
"""
from __future__ import annotations

import argparse
import json
import sys
import time

from ..errors import StopReason, UserError
from ..status import DesignStatus
from .common import solver_of

TOLERANCE_NAMES = {"dx": "dx_mm", "dy": "dy_mm", "dz": "dz_mm", "vertical": "vertical_deg",
                   "horizontal": "horizontal_deg"}


def configure(p: argparse.ArgumentParser) -> None:
    from ..solver.backends import BACKENDS

    p.add_argument("file", metavar="FILE", nargs="?", help="TOML design spec: the base design (not with --resume)")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=START:STOP:COUNT",
                   help="replace a numeric spec key (dotted, as in `beveloid example --schema`) by COUNT values from"
                        " START to STOP; repeat for a grid (the first key varies slowest)")
    p.add_argument("--samples", type=int, metavar="N",
                   help="N designs from a Latin hypercube sample over the --vary ranges instead of the grid")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the sample and the Monte Carlo (default 0)")
    add_tolerances_flag(p)
    p.add_argument("--mc", type=int, default=0, metavar="K",
                   help="also a Monte Carlo sweep of K error sets in the box per design (edge-contact fraction, TE)")
    p.add_argument("--mc-positions", type=int, default=20, metavar="N", help="contact positions per MC set (default 20)")
    p.add_argument("--mc-flank", choices=("left", "right"), default="right", help="flank of the MC sweep (default right)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: the cores)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing Dask distributed cluster (e.g. tcp://10.0.0.1:8786)")
    p.add_argument("--out", default="explore_out", metavar="DIR", help="output folder (default explore_out)")
    p.add_argument("--resume", metavar="DIR", help="continue the run in DIR without redoing finished designs")
    p.add_argument("--chunk", type=int, default=256, metavar="N",
                   help="designs per chunk of work (default 256): the unit of resume; the rows do not depend on it")
    p.add_argument("--backend", choices=BACKENDS, default="auto", help="solver backend (default auto)")
    p.add_argument("--json", action="store_true", help="print the summary and every row as JSON on stdout")


def add_tolerances_flag(p: argparse.ArgumentParser, about: str = "") -> None:
    """``--tolerances``, the half-widths of the assembly-error box that explore, ltca and optimize draw
    in (read by :func:`parse_tolerances`); ``about``: what the box is centred on, for the help."""
    from ..assembly_errors import DEFAULT_RANGES

    default = ",".join(f"{k}={DEFAULT_RANGES[v]:g}" for k, v in TOLERANCE_NAMES.items())
    p.add_argument("--tolerances", default=default, metavar="dx=MM,dy=MM,dz=MM,vertical=DEG,horizontal=DEG",
                   help=f"half-widths of the assembly-error box{about} (default {default})")


def parse_tolerances(text: str) -> dict:
    """``dx=0.5,vertical=0.2`` -> {dx_mm: 0.5, ..., vertical_deg: 0.2} (unnamed ones: the sweep's defaults)."""
    from .. import assembly_errors
    from ..assembly_errors import DEFAULT_RANGES

    out = dict(DEFAULT_RANGES)
    for part in filter(None, (s.strip() for s in text.split(","))):
        name, _, value = part.partition("=")
        if name not in TOLERANCE_NAMES:
            raise UserError(f"--tolerances {part}: unknown error {name!r}; valid: {', '.join(TOLERANCE_NAMES)}")
        key = TOLERANCE_NAMES[name]
        limit = assembly_errors.BY_KEY[key].limit
        try:
            x = float(value)
        except ValueError:
            x = float("nan")
        if not 0 <= x <= limit:
            unit = assembly_errors.BY_KEY[key].unit
            raise UserError(f"--tolerances {name}={value}: must be a number from 0 to {limit:g} ({unit})")
        out[key] = x
    return out


def _raw(path, spec) -> dict:
    """The file's tables as it gives them (so that a key it leaves out, e.g. tooth_surface, is chosen
    per design by the spec's own rule); the validated spec's keys if the file cannot be read again."""
    import tomllib

    from ..spec import spec_to_dict

    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except (OSError, ValueError):
        return spec_to_dict(spec)


def _request(args):
    from ..spec import load_spec
    from ..explore.grid import Plan, parse_vary
    from ..explore.run import Request

    if not args.file:
        raise UserError("FILE is missing: give the base design's TOML spec (or --resume DIR)")
    if not args.vary:
        raise UserError("--vary is missing: give at least one KEY=START:STOP:COUNT (see `beveloid example --schema`)")
    varies = tuple(parse_vary(t) for t in args.vary)
    keys = [v.key for v in varies]
    if len(set(keys)) != len(keys):
        raise UserError(f"--vary {next(k for k in keys if keys.count(k) > 1)}: given twice; vary each key once")
    if args.samples is not None and not 1 <= args.samples <= 10_000_000:
        raise UserError(f"--samples = {args.samples}: must be an integer from 1 to 10000000")
    if not 0 <= args.seed < 2 ** 63:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to 2**63 - 1")
    if not 0 <= args.mc <= 100_000:
        raise UserError(f"--mc = {args.mc}: must be an integer from 0 (no Monte Carlo) to 100000")
    if not 2 <= args.mc_positions <= 1000:
        raise UserError(f"--mc-positions = {args.mc_positions}: must be an integer from 2 to 1000")
    if not 1 <= args.chunk <= 100_000:
        raise UserError(f"--chunk = {args.chunk}: must be an integer from 1 to 100000")
    spec = load_spec(args.file)
    plan = Plan(_raw(args.file, spec), varies, args.samples, args.seed)
    plan.check()
    tolerances = parse_tolerances(args.tolerances)
    for key, half in tolerances.items():  # the MC draws about the file's misalignment
        from .. import assembly_errors

        centre = abs(float(getattr(spec.misalignment, key)))
        if args.mc and centre + half > assembly_errors.BY_KEY[key].limit:
            raise UserError(f"--tolerances {key}: {half:g} about misalignment.{key} = {centre:g} reaches"
                            f" {centre + half:g}; |nominal| + half-width must be <= {assembly_errors.BY_KEY[key].limit:g}")
    solver_of(args.backend)  # a backend that is not installed: one line here, not in every worker
    return Request(plan, tolerances, args.mc, args.mc_positions, args.mc_flank, chunk=args.chunk, backend=args.backend,
                   source=str(args.file))


def run(args: argparse.Namespace) -> int:
    """Map a design space: status, working data, FPD angles and sensitivities per design; Pareto front.

    Writes DIR/explore.csv, pareto.csv, summary.json and figures (heat maps, Pareto scatter and table).
    """
    from .. import interrupts, parallel
    from .paths import check_output_dir, created_here
    from ..explore import run as runner

    out = args.resume or args.out
    if args.resume:
        if args.file or args.vary:
            raise UserError(f"--resume {args.resume}: the run's FILE and --vary are in {args.resume}/request.json;"
                            f" give --resume DIR alone (with --workers or --scheduler)")
        req = runner.prepare(out, None, resume=True)
    else:
        req = _request(args)
        check_output_dir(out, "--out")
        req = runner.prepare(out, req, resume=False, log=_say)
    chunks = runner.Chunks(out, req, log=_say)  # the chunks a run before finished, read once
    t0 = time.perf_counter()
    ex = parallel.executor(args.workers, args.scheduler, initializer=runner.warm_up)
    # after the last chunk a first Ctrl-C lets the outputs be written (a second stops at once)
    late = interrupts.Deferred(on_first=lambda: _say("beveloid explore: Ctrl-C: writing the outputs of the finished"
                                                     " designs first (Ctrl-C again to stop at once)"))
    try:
        with ex:
            ran = runner.execute(out, req, ex, runner.Progress(chunks.designs), chunks)
            late.start()
            # the figures are drawn by the workers of a run that ended well (else here)
            return _finish(args, out, req, chunks, (ran.stop, ran.why, ex.description, time.perf_counter() - t0),
                           late, created_here, ex if ran.stop is None else None)
    except KeyboardInterrupt:  # a second Ctrl-C while the outputs were written (whole files or none)
        interrupts.reported()
        if not chunks.parts and created_here(out):
            _discard(out, runner)
            _say("beveloid explore: interrupted before any design finished; nothing written")
        else:
            more = (f"continue with `beveloid explore --resume {out}`" if chunks.missing()
                    else f"`beveloid explore --resume {out}` writes the outputs")
            _say(f"beveloid explore: interrupted; {chunks.designs} of {_designs(req.plan.count)} kept in {out}; {more}")
        return 130
    finally:
        late.stop()


def _say(line: str) -> None:
    print(line, file=sys.stderr)


def _designs(n: int) -> str:
    return f"{n} design{'' if n == 1 else 's'}"


def _finish(args, out, req, chunks, ended, late, created_here, ex=None) -> int:
    """The outputs of what finished: the base design's row, the Pareto front, the files (the figures drawn on
    the executor ``ex`` while the data files are written, or here when None); the lines that say how the run
    ended (``ended``: why it stopped, in words, where it ran, seconds)."""
    from .. import interrupts
    from ..explore import report, rows
    from ..explore import run as runner
    from ..explore.grid import Plan

    stop, why, where, seconds = ended
    table = chunks.table()
    if not table and created_here(out):
        # stopped before any design finished, in a folder this run made: leave nothing behind (the
        # CLI removes the folder once empty)
        _discard(out, runner)
        _say(f"beveloid explore: {why}: stopped before any design finished; nothing written")
        interrupts.reported()
        return 130 if stop is StopReason.INTERRUPTED else 1
    complete = not chunks.missing()
    base_cols = chunks.base
    if base_cols is None:  # the run stopped before the base design's task ran: here
        base_plan = Plan(req.plan.base, (), seed=req.plan.seed)
        base_cols = rows.compute(base_plan, 0, 1, req.tolerances, solver=req.solver)
        if req.mc:
            rows.monte_carlo(base_cols, base_plan, slice(0, 1), req.tolerances, rows.monte_carlo_request(req),
                             solver=req.solver)
    base_row = report.records(base_cols)[0]
    values = Plan(req.plan.base, ()).base_values()
    base_row.update({k: values[k] for k in req.plan.keys})
    if table:
        report.mark_pareto(table, bool(req.mc))
    summ = report.summary(req, table, base_row, complete, why, seconds, where)
    figures = []
    if table:
        drawn = report.drawn_figures(req, table, base_row, ex)
        report.write_data(out, table, chunks.csv_rows(), summ)
        figures = report.write_figures(out, drawn, go_on=lambda: not late.pressed)
    if args.json:
        print(json.dumps(dict(summ, rows=report.records(table)), allow_nan=False))
    else:
        _print(summ, out)
    interrupted = stop is StopReason.INTERRUPTED or late.pressed
    if complete and not interrupted:  # (a worker lost after the last chunk: nothing is missing)
        return 0
    if not complete:
        _say(f"beveloid explore: {why}; {summ['designs_done']} of {_designs(summ['designs'])} kept in {out};"
             f" continue with `beveloid explore --resume {out}`")
    elif len(figures) < len(report.FIGURES):
        _say(f"beveloid explore: interrupted after every design finished; {', '.join(report.DATA_FILES)} written in"
             f" {out}, not every figure: `beveloid explore --resume {out}` draws them")
    else:
        _say(f"beveloid explore: interrupted after every design finished; every output is written in {out}")
    interrupts.reported()
    return 130 if interrupted else 1


def _discard(out, runner) -> None:
    """Remove the request, the chunk folder and the chunk files a run wrote into ``out``."""
    import os

    folder = os.path.join(out, runner.CHUNKS)  # (chunk files a worker wrote before its result came back)
    for name in os.listdir(folder) if os.path.isdir(folder) else ():
        if name.startswith("chunk_"):
            os.remove(os.path.join(folder, name))
    for remove, name in ((os.remove, runner.REQUEST), (os.rmdir, runner.CHUNKS)):
        try:
            remove(os.path.join(out, name))
        except OSError:
            pass


def _print(summ, out):
    counts = ", ".join(f"{v} {k}" for k, v in sorted(summ["status_counts"].items(), key=lambda kv: -kv[1]))
    lines = [f"Explored {summ['designs_done']} of {_designs(summ['designs'])} of {summ['file']} in"
             f" {summ['seconds']:.1f} s ({summ['executor']}): {counts}",
             f"Pareto front on ({', '.join(summ['objectives'])}): {_designs(len(summ['pareto_designs']))}"]
    keys = [v["key"] for v in summ["varied"]]
    for row in summ["pareto_designs"][:10]:
        lines.append("  " + ", ".join(f"{k} {row[k]:.4g}" for k in keys)
                     + f": max FPD {row['max_fpd_angle_deg']:.3f} deg, worst path shift {row['worst_path_shift_mm']:.3f} mm")
    b = summ["base_design"]
    if b.get("status") == DesignStatus.OK:
        lines.append(f"Base design: max FPD {b['max_fpd_angle_deg']:.3f} deg, worst path shift"
                     f" {b['worst_path_shift_mm']:.3f} mm")
    from pathlib import Path

    from ..explore.report import DATA_FILES, FIGURES

    written = [n for n in DATA_FILES + FIGURES if (Path(out) / n).is_file()]  # an interrupted run may have written none
    lines.append(f"Files in {out}: {', '.join(written)}" if written else f"No result files written in {out}")
    print("\n".join(lines))
