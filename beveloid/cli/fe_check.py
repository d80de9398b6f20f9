"""``beveloid fe-check FILE --torque-nm T [--position K] [--flank left|right] [--positions N] [--tooth-model fe|plate]
[...the other flags of ``beveloid ltca``'s loaded analysis] [--refinement N]
[--no-local-refinement] [--fine-fillets] [--contact-size-um UM] [--max-strip-elements N] [--coarsen F] [--out DIR] [--json]``.

An independent check of the loaded contact: both members' sectors meshed as second-order
tetrahedra, frictionless contact found by CalculiX (``ccx``, Debian's package ``calculix-ccx``),
beside the LTCA at the same position and torque.  The JSON: {"calculix_version", "position",
"pinion_angle_rad", "calculix": BLOCK, "ltca": BLOCK, "files", "notes", ...} with BLOCK =
{"pair_normal_load_n" [P], "pair_max_pressure_mpa" [P], "contact_area_mm2" [P],
"loaded_transmission_error_urad", "root_stress_max_mpa" {"pinion", "gear"},
"moment_about_pinion_axis_nm"}, the tooth pairs in the same order in both blocks; a number that
could not be computed is null.  --out DIR keeps the deck, CalculiX's output and a VTU (ParaView)
of displacement, stress and contact pressure.  See docs/fe_check.md.
"""
from __future__ import annotations

import argparse
import json
import math
import sys

from ..fe.sizes import MAX_STRIP_ELEMENTS
from .common import add_error_flags, add_ltca_flags, apply_error_flags

__all__ = ["configure", "run", "format_summary"]

#: the name of the check's files in --out (the deck fe_check.inp, CalculiX's fe_check.frd, .dat, ...)
JOB = "fe_check"
#: the flag of each fecheck.Options key whose flag is not its key's (--key-with-dashes)
FLAGS = {"out_dir": "--out", "local_refinement": "--no-local-refinement"}


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    p.add_argument("--torque-nm", type=float, required=True, metavar="T", help="pinion torque (N m), > 0")
    p.add_argument("--position", type=int, default=None, metavar="K",
                   help="the LTCA's position (0 to --positions - 1) to check (default: the one with the most tooth pairs in "
                        "contact)")
    add_ltca_flags(p)  # the LTCA beside the check, as `beveloid ltca` takes it
    p.add_argument("--refinement", type=int, default=1, metavar="N",
                   help="mesh refinement 1-4 (default 1, the coarse check: loads, TE, root stress; N divides every "
                        "size, 3 is the FE tooth's own sizes, for the peak pressure where that reaches the contact's "
                        "half-width: several GB of memory)")
    p.add_argument("--no-local-refinement", action="store_true",
                   help="mesh with the face-wide sizes only (default: refined over the LTCA's loaded patches)")
    p.add_argument("--fine-fillets", action="store_true",
                   help="mesh the fillets of the loaded teeth at the FE tooth's sizes at this refinement (default: "
                        "three times them, as the rest of the sectors at refinement 1; about 5 times the elements)")
    p.add_argument("--contact-size-um", type=float, default=None, metavar="UM",
                   help="element size over the loaded patches, 10-2000 um (default: b / 3 of each patch)")
    p.add_argument("--max-strip-elements", type=int, default=MAX_STRIP_ELEMENTS, metavar="N",
                   help=f"cap on the estimated elements of one sector's refined patches at refinement 3 (default "
                        f"{MAX_STRIP_ELEMENTS}; refinement N multiplies their sizes by 3 / N)")
    p.add_argument("--coarsen", type=float, default=1.0, metavar="F",
                   help="multiply every element size by F, 0.125-2.5 (default 1; > 1 for a quick look)")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="keep the deck, CalculiX's output and the VTU in this folder (a Ctrl-C removes what the run"
                        " wrote there)")
    add_error_flags(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    """Check the loaded contact by full-contact finite elements (CalculiX) beside the LTCA.

    Needs CalculiX's ccx (Debian: apt-get install calculix-ccx).  Progress goes to stderr.
    """
    from .. import fecheck
    from ..errors import UserError
    from ..fecheck.run import CCX_MISSING, ccx_path
    from ..pair import Pair
    from ..spec import load_spec
    from .common import load_case, ltca_options, named_by_flag
    from .paths import check_output_dir

    load = load_case(args.torque_nm)
    with named_by_flag(FLAGS):
        options = fecheck.Options(ltca=ltca_options(args), position=args.position, refinement=args.refinement,
                                  out_dir=args.out, coarsen=args.coarsen, local_refinement=not args.no_local_refinement,
                                  fine_fillets=args.fine_fillets,
                                  contact_size_um=args.contact_size_um, max_strip_elements=args.max_strip_elements)
    if args.out is not None:
        check_output_dir(args.out, "--out")
    if ccx_path() is None:
        raise UserError(CCX_MISSING)
    spec = apply_error_flags(load_spec(args.file), args)
    pair = Pair.from_spec(spec)
    from ..progress import Lines

    progress = Lines(sys.stderr)
    if args.out is None:
        out = fecheck.analyze(pair, load, options, progress=progress).to_json()
    else:
        out = _into_folder(pair, load, options, progress, args.out).to_json()
    if args.json:
        print(json.dumps(out, allow_nan=False))
    else:
        print(format_summary(out))
    return 0


def _into_folder(pair, load, options, progress, folder):
    """The check with its files (deck, CalculiX's output, VTU) kept in ``folder``; a Ctrl-C removes the
    files this run had written there (a deck without results, CalculiX's partial output, its spooles.out:
    every file new since the start and the job's files rewritten) and says so."""
    import time
    from pathlib import Path

    from .. import fecheck
    from ..outputs import interrupted_files_note

    t0 = time.time()
    before = {p.name for p in Path(folder).iterdir()} if Path(folder).is_dir() else set()
    try:
        return fecheck.analyze(pair, load, options, progress=progress)
    except KeyboardInterrupt:  # the job's files of this run, and whatever else CalculiX made (spooles.out)
        mine = [p for p in sorted(Path(folder).iterdir()) if p.is_file() and (
            p.name not in before or (p.name.startswith(f"{JOB}.") and p.stat().st_mtime >= t0 - 1.0))]
        for p in mine:
            p.unlink(missing_ok=True)
        print(f"beveloid fe-check: {interrupted_files_note(folder, '--out', [p.name for p in mine])}",
              file=sys.stderr, flush=True)
        raise


def format_summary(out: dict) -> str:
    from ..plots import pinion_angle_text

    fmt = lambda v, f: "-" if v is None or not math.isfinite(v) else format(v, f)  # noqa: E731
    c, lt = out["calculix"], out["ltca"]
    lines = [f"fe-check at position {out['position']} ({pinion_angle_text(out['pinion_angle_rad'], 4)}), "
             f"{out['flank']} flank, pinion torque {out['torque_nm']:g} N m; CalculiX {out['calculix_version']}",
             "", f"{'quantity':36s}{'CalculiX':>14s}{'LTCA':>14s}"]
    for i, k in enumerate(out["tooth_pairs"]):
        for key, label, f in (("pair_normal_load_n", "normal load (N)", ".1f"),
                              ("pair_max_pressure_mpa", "peak pressure (MPa)", ".0f"),
                              ("contact_area_mm2", "contact area (mm2)", ".2f")):
            lines.append(f"{'pair ' + str(k) + ' ' + label:36s}{fmt(c[key][i], f):>14s}{fmt(lt[key][i], f):>14s}")
    lines.append(f"{'loaded TE (urad)':36s}{fmt(c['loaded_transmission_error_urad'], '.1f'):>14s}"
                 f"{fmt(lt['loaded_transmission_error_urad'], '.1f'):>14s}")
    for m in ("pinion", "gear"):
        lines.append(f"{m + ' root stress max (MPa)':36s}{fmt(c['root_stress_max_mpa'][m], '.0f'):>14s}"
                     f"{fmt(lt['root_stress_max_mpa'][m], '.0f'):>14s}")
    lines.append(f"{'moment about pinion axis (N m)':36s}{fmt(c['moment_about_pinion_axis_nm'], '.2f'):>14s}"
                 f"{fmt(lt['moment_about_pinion_axis_nm'], '.2f'):>14s}")
    lines += [""] + [f"note: {n}" for n in out["notes"]]
    if out["files"]:
        lines.append("files: " + ", ".join(f"{k} {v}" for k, v in out["files"].items()))
    return "\n".join(lines)
