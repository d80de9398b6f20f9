"""``beveloid export FILE [--format FORMAT] [--member pinion|gear|both] [--assembled] [--out DIR]``.

Writes solid models of the designed pair (:mod:`beveloid.export`): one file per member in its own
frame (``<stem>_pinion.step``, ``<stem>_gear.step``; the stem is the spec file's name), or with
``--assembled`` one file ``<stem>_pair.<ext>`` with the members placed as designed.  Prints one line
per file written.  The formats are the writers of :data:`beveloid.export.formats.WRITERS`; without a
writer's extra it says in one line what to install (exit 2).
"""
from __future__ import annotations

import argparse
from pathlib import Path


def configure(parser: argparse.ArgumentParser) -> None:
    from ..export.formats import WRITERS  # numpy-free: no OpenCASCADE or trimesh imported here

    parser.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    parser.add_argument("--format", choices=tuple(WRITERS), default=next(iter(WRITERS)),
                        help="; ".join(f"{w.name}: {w.help}" for w in WRITERS.values())
                        + f"; default {next(iter(WRITERS))}")
    parser.add_argument("--member", choices=("pinion", "gear", "both"), default="both",
                        help="which member to export (default both)")
    parser.add_argument("--assembled", action="store_true",
                        help="one file with the members placed as designed (fixed frame S_f, Eqs 30-35, with the"
                             " file's [misalignment]) instead of one file per member in its own frame")
    parser.add_argument("--out", default=".", metavar="DIR", help="output folder (default: the current folder)")


def run(args: argparse.Namespace) -> int:
    """Write solid models of the designed pair (STEP, STL: the writers of beveloid.export.formats).

    Each member is a whole gear: every tooth with its flanks, root fillets, tip and root cones, the
    toe and heel faces, and a bore (bore_diameter_mm, 0: none).
    """
    from ..errors import UserError
    from ..export import WRITERS, CadMissing, ExportOptions, export, require_cad
    from ..pair import Pair
    from .paths import check_output_dir

    try:
        require_cad(args.format)
    except CadMissing as exc:
        raise UserError(str(exc)) from None
    check_output_dir(args.out, "--out")
    pair = Pair.from_spec(args.file)
    members = ("pinion", "gear") if args.member == "both" else (args.member,)
    options = ExportOptions(format=args.format, members=members, assembled=args.assembled, out_dir=args.out,
                            stem=Path(args.file).stem or "beveloid")
    try:
        result = export(pair, options)
    except OSError as exc:
        if exc.filename is None:  # not a file of DIR (e.g. a closed stdout): the CLI reports it
            raise
        raise UserError(f"--out = {args.out}: cannot write there ({exc.strerror or exc})") from None
    kind = WRITERS[args.format].accuracy
    for f in result.files:
        extra = f", {f.triangles} triangles" if f.triangles is not None else ""
        print(f"{f.path}: {' + '.join(f'{m} ({t} teeth)' for m, t in zip(f.members, f.teeth))},"
              f" volume {f.volume_mm3:.1f} mm3, {kind} within {f.max_error_um:.3f} um of the generated"
              f" surfaces at off-sample points{extra}")
    return 0
