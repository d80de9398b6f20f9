"""``beveloid optimize FILE --vary KEY=LOW:HIGH [...] --torque-nm T1,T2,... [...]``: the flank modification
that is quiet and strong over a duty cycle and a tolerance box (docs/optimize.md).

``configure(parser)`` adds the arguments, ``run(args) -> int`` runs the search (the work is the package
beveloid/optimize/).  Exit status: 0 when the budget is evaluated, 1 when the run stopped early (Ctrl-C:
130) with the finished candidates written and ``--resume DIR`` to continue, 2 for bad input (one line).
"""
from __future__ import annotations

import argparse
import json
import sys
import time

from ..errors import OptionError, StopReason, UserError


def configure(p: argparse.ArgumentParser) -> None:
    from .common import add_ltca_flags
    from .explore import add_tolerances_flag

    p.add_argument("file", metavar="FILE", nargs="?", help="TOML design spec: the unmodified design (not with --resume)")
    p.add_argument("--vary", action="append", default=[], metavar="KEY=LOW:HIGH",
                   help="a numeric micro-geometry key of either member over a continuous range, e.g."
                        " pinion.lead_crowning_um=0:40 (crowning, tip and end relief, lead slope); repeat for more")
    p.add_argument("--torque-nm", metavar="T1,T2,...", help="the duty cycle's pinion torques (N m)")
    p.add_argument("--weights", metavar="W1,W2,...", help="the torques' weights (default equal)")
    p.add_argument("--samples", type=int, default=0, metavar="K",
                   help="error sets drawn in the tolerance box as `beveloid sweep` draws them, the same for every"
                        " candidate (default 0: the file's [misalignment] only)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the error sets and the search (default 0)")
    add_tolerances_flag(p, " about the file's [misalignment]")
    p.add_argument("--objectives", default="te,pressure", metavar="te,pressure,root,loss",
                   help="minimised: te = loaded TE peak-to-peak, pressure = largest peak pressure (edges included),"
                        " root = larger root stress (FE tooth) (default te,pressure)")
    p.add_argument("--budget", type=int, metavar="N", help="candidates evaluated (default 128)")
    p.add_argument("--population", type=int, metavar="N",
                   help="NSGA-II population (default 8 per varied key, 8 to 32)")
    p.add_argument("--constraints", choices=("rating", "none"), default="rating",
                   help="rating: `beveloid rating`'s verdict at the highest torque must pass (every safety"
                        " meets its minimum, no edge beyond the edge-contact rule) (default); none: not computed"
                        " (quicker looks)")
    add_ltca_flags(p)
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: the cores)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on an existing Dask distributed cluster")
    p.add_argument("--out", default="optimize_out", metavar="DIR", help="output folder (default optimize_out)")
    p.add_argument("--resume", metavar="DIR", help="continue the run in DIR (with --budget: a larger budget)")
    p.add_argument("--json", action="store_true", help="print the front as JSON on stdout")


def _request(args):
    from .. import ltca
    from ..ltca.options import default_tooth_model
    from ..optimize import request as rq
    from ..spec import load_spec
    from ..sweep import MAX_SEED
    from .common import ltca_options
    from .explore import _raw, parse_tolerances

    if not args.file:
        raise UserError("FILE is missing: give the design's TOML spec (or --resume DIR)")
    if not args.vary:
        raise UserError("--vary is missing: give at least one KEY=LOW:HIGH, e.g. pinion.lead_crowning_um=0:40")
    varies = tuple(rq.parse_vary(t) for t in args.vary)
    keys = [v.key for v in varies]
    if len(set(keys)) != len(keys):
        raise UserError(f"--vary {next(k for k in keys if keys.count(k) > 1)}: given twice; vary each key once")
    if args.torque_nm is None:
        raise UserError("--torque-nm is missing: give the duty cycle's pinion torques, e.g. 100,200,400")
    torques = rq.parse_numbers(args.torque_nm, "--torque-nm", "pinion torques in N m, e.g. 100,200,400")
    for t in torques:
        try:
            ltca.options.check_torque(t, key="--torque-nm")
        except OptionError as exc:
            raise UserError(exc.for_flag("--torque-nm", shown=args.torque_nm)) from None
    weights = (1.0,) * len(torques)
    if args.weights is not None:
        weights = rq.parse_numbers(args.weights, "--weights", "one weight > 0 per torque")
        if len(weights) != len(torques):
            raise UserError(f"--weights {args.weights}: {len(weights)} weights for {len(torques)} torques; give one"
                            " per torque")
    if not 0 <= args.samples <= rq.MAX_SAMPLES:
        raise UserError(f"--samples = {args.samples}: must be an integer from 0 (the file's errors) to {rq.MAX_SAMPLES}")
    if not 0 <= args.seed <= MAX_SEED:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to {MAX_SEED}")
    budget = rq.DEFAULT_BUDGET if args.budget is None else args.budget
    if not 1 <= budget <= rq.MAX_BUDGET:
        raise UserError(f"--budget = {budget}: must be an integer from 1 to {rq.MAX_BUDGET}")
    population = rq.default_population(len(varies)) if args.population is None else args.population
    if not 4 <= population <= 1000:
        raise UserError(f"--population = {population}: must be an integer from 4 to 1000")
    tooth = args.tooth_model or default_tooth_model()
    analysis = ltca_options(args, tooth_model=tooth)  # the loaded analysis' own range table, named by the flags
    if args.positions < 3:
        raise UserError(f"--positions = {args.positions}: must be at least 3 (a TE peak-to-peak needs a cycle)")
    objectives = rq.parse_objectives(args.objectives, tooth)
    spec = load_spec(args.file)
    rq.check_loss_objective(objectives, spec)
    tolerances = parse_tolerances(args.tolerances)
    if args.samples:
        from .. import assembly_errors

        for key, half in tolerances.items():
            centre = abs(float(getattr(spec.misalignment, key)))
            limit = assembly_errors.BY_KEY[key].limit
            if centre + half > limit:
                raise UserError(f"--tolerances {key}: {half:g} about misalignment.{key} = {centre:g} reaches"
                                f" {centre + half:g}; |nominal| + half-width must be <= {limit:g}")
    req = rq.Request(base=_raw(args.file, spec), varies=varies, torques_nm=torques, weights=weights,
                     objectives=objectives, samples=args.samples, seed=args.seed, tolerances=tolerances, budget=budget,
                     population=population, ltca=analysis, constraints=args.constraints, source=str(args.file))
    req.check()
    return req


def run(args: argparse.Namespace) -> int:
    """Optimise the flank modification over a duty cycle and a tolerance box (NSGA-II; Pareto front).

    Writes DIR/candidates.csv, pareto.csv, summary.json, pareto_<n>.toml (one spec per Pareto candidate)
    and the figures pareto.png, te_vs_torque.png, knee_pattern.png; progress on stderr.
    """
    from .. import parallel
    from ..optimize import report, search
    from .paths import check_output_dir

    out = args.resume or args.out
    if args.resume:
        if args.file or args.vary:
            raise UserError(f"--resume {args.resume}: the run's FILE and --vary are in {args.resume}/request.json;"
                            " give --resume DIR alone (with --budget, --workers or --scheduler)")
        if args.budget is not None and not 1 <= args.budget <= 100_000:
            raise UserError(f"--budget = {args.budget}: must be an integer from 1 to 100000")
        req = search.prepare(out, None, resume=True, budget=args.budget)
    else:
        req = _request(args)
        check_output_dir(out, "--out")
        req = search.prepare(out, req, resume=False)
    t0 = time.perf_counter()
    print(f"beveloid optimize: the unmodified design of {req.source}", file=sys.stderr)
    try:
        ex = parallel.executor(args.workers, args.scheduler)
        with ex:  # (local workers start meanwhile: issue 59)
            # the unmodified design: on local worker processes (two or more: one worker is this process) with the
            # first generation where no FE data is to be made, else here first (its FE data then on disk for them)
            alongside = ex.shares_files and getattr(ex, "workers", 1) > 1 and search.baseline_alongside(out, req)
            base = None if alongside else search.baseline(out, req)
            ran = search.run(out, req, ex, search.Progress(), base, baseline=alongside)
            base = base or search.load(out, search.BASELINE)
            where = ex.description
    except KeyboardInterrupt:
        if not args.resume:
            print(f"beveloid optimize: {_nothing_kept(out)}", file=sys.stderr, flush=True)
        raise
    stop, why, records = ran.stop, ran.why, ran.record_dicts()
    if stop is not None and not records and not args.resume:  # stopped before its first candidate
        print(f"beveloid optimize: stopped ({why}) before the first candidate; {_nothing_kept(out)}", file=sys.stderr)
        return 130 if stop is StopReason.INTERRUPTED else 1
    if base is None:  # stopped before the unmodified design (evaluated with the first generation) came back
        print(f"beveloid optimize: stopped ({why}) before the unmodified design's numbers; {len(records)} of"
              f" {req.budget} candidates kept in {out}; continue with `beveloid optimize --resume {out}`", file=sys.stderr)
        return 130 if stop is StopReason.INTERRUPTED else 1
    records = sorted(records, key=lambda r: r["candidate"])
    on = report.pareto_mask(req, records)
    order = report.front_order(req, records, on)
    specs = report.write_specs(out, req, records, order)
    summ = report.summary(req, records, base, report.RunInfo(stop is None, why, time.perf_counter() - t0, where),
                          report.Front(on, order, specs))
    report.write(out, req, records, summ, on)
    summ["figures"] = report.figures(out, req, records, base, on) if records else []
    if args.json:
        print(json.dumps(report.json_output(summ), allow_nan=False))
    else:
        _print(summ, out)
    if stop is not None:
        print(f"beveloid optimize: stopped ({why}); {len(records)} of {req.budget} candidates kept in {out}; continue"
              f" with `beveloid optimize --resume {out}`", file=sys.stderr)
        return 130 if stop is StopReason.INTERRUPTED else 1
    return 0


def _nothing_kept(out: str) -> str:
    """A fresh run stopped before its first candidate: its request.json and empty candidates/ are removed
    (the folder too when this run made it, on the CLI's way out); what it says of them."""
    import os

    from ..optimize import search
    from ..outputs import interrupted_note

    folder = os.path.join(out, search.CANDIDATES)
    if os.path.isdir(folder) and os.listdir(folder):  # the baseline was kept: --resume takes it
        return f"the unmodified design's numbers are kept in {out}; continue with `beveloid optimize --resume {out}`"
    for path, remove in ((folder, os.rmdir), (os.path.join(out, search.REQUEST), os.remove)):
        try:
            remove(path)
        except OSError:
            pass
    return interrupted_note(out, "--out")


def _print(summ, out):
    from .common import number

    q = summ["objectives"]
    lines = [f"Optimised {', '.join(v['key'] for v in summ['varied'])} of {summ['file']}: {summ['evaluated']}"
             f" candidates in {summ['seconds']:.1f} s ({summ['executor']}), objectives {', '.join(q)}"]
    b = summ["baseline"]
    lines.append("  unmodified: " + ", ".join(f"{k} {number(b['objectives'].get(k), '.4g')}" for k in q)
                 + ("" if b["dominated_by"] is None else
                    f"; beaten on every objective by {len(b['dominated_by'])} candidates"))
    if summ["pareto"]:
        lines.append(f"Pareto front: {len(summ['pareto'])} candidates")
    else:
        passes = "" if summ["constraints"] != "rating" else (
            f" and passes `beveloid rating`'s verdict at {max(summ['torques_nm']):g} N m")
        lines.append(f"Pareto front: empty: no candidate is ok{passes} (candidates.csv: status, feasible, reason)")
    for e in summ["pareto"][:12]:
        lines.append(f"  {e['spec_file']}: " + ", ".join(f"{k} = {v:.4g}" for k, v in e["values"].items()) + " -> "
                     + ", ".join(f"{k} {number(e['objectives'][k], '.4g')}" for k in q))
    picked = {k: v for k, v in summ["picks"].items() if v is not None}
    if picked:
        lines.append("picks (candidate): " + ", ".join(f"{k} {v}" for k, v in picked.items()))
    specs = [e["spec_file"] for e in summ["pareto"]]
    spec_files = [] if not specs else [specs[0] if len(specs) == 1 else f"pareto_1.toml .. pareto_{len(specs)}.toml"]
    lines.append(f"Files in {out}: " + ", ".join(["candidates.csv", "pareto.csv", "summary.json", *spec_files,
                                                   *summ.get("figures", [])]))
    print("\n".join(lines))
