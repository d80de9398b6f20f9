"""``beveloid rating FILE --torque-nm T [--flank left|right] [--positions N] [--pairs K] [--grid ACROSSxALONG]
[--tooth-model fe|plate] [--fe-refinement N] [--fe-coarsen F] [--samples K] [--seed S] [--tolerances ...]
[--json] [--plot OUT.png]``.

Strength rating (docs/rating.md): ISO 6336-2/-3:2019 (method B) on the virtual cylindrical gear of the
toe, middle and heel sections of each member, and the local stresses of the loaded contact (LTCA
surface peak pressure; the FE root stress where available) at K_A K_v T, with permissible stresses,
safety factors S_F and S_H from both, and a verdict (with the edge-contact rule: a flank edge loaded
above its limit makes it conditional).  The torque is the pinion torque; K_A, K_v (else ISO 6336-1
method B from the speed and the LTCA's mesh stiffness), speed, life, accuracy grade and the minimum
safeties come from the spec's [rating], the material types, qualities and limits from [material].
The JSON: "torque_nm", "flank", "K_A", "K_v", "K_v_source", "dynamic_factor", per member "sections"
{"toe", "middle", "heel"} (virtual_teeth, normal_profile_shift, helix_angle_deg, s_Fn_mm, rho_F_mm,
h_Fe_mm, alpha_Fen_deg, Y_F, Y_S, Y_beta, f_eps, sigma_F0_mpa, Z_H, Z_E, Z_eps, Z_beta, sigma_H0_mpa),
"root_stress_max_mpa", "contact_pressure_max_mpa", "safety_bending", "safety_pitting",
"safety_bending_iso", "safety_pitting_iso" (null where not computed), "K_H_beta", "K_F_beta",
"face_load", "material", "strength_factors" (Z_L, Z_v, Z_R, Y_X, Y_RrelT with their inputs), "verdict"
and "notes"; "tolerance_box" with --samples (docs/rating.md 7).

Exit status (docs/rating.md 6): 0 the pair passes, 3 it fails, 4 it is conditional (passes only if an
edge is relieved), 5 no safety could be computed; 2 bad input, 1 an output that could not be written.
"""
from __future__ import annotations

import argparse
import json

from ..errors import UserError
from .paths import check_output_file


def configure(p: argparse.ArgumentParser) -> None:
    from .. import rating
    from .common import add_ltca_flags

    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    p.add_argument("--torque-nm", type=float, required=True, metavar="T", help="nominal pinion torque (N m), > 0")
    add_ltca_flags(p, positions=rating.POSITIONS)  # the LTCA's flags, as `beveloid ltca` takes them
    p.add_argument("--samples", type=int, default=None, metavar="K",
                   help="K_H_beta from the tolerance box under load: K error sets drawn about the file's "
                        "[misalignment] (the draws of ltca --samples), each a full LTCA; the ISO sections take "
                        "K_H_beta's 90th percentile (default [rating] tolerance_samples, 0: the file's errors alone)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the error sets (default 0)")
    from .explore import add_tolerances_flag

    add_tolerances_flag(p, " of --samples")
    p.add_argument("--plot", metavar="OUT.png", help="write S_F and S_H along the face of both members here")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    """Strength rating: ISO 6336 per section and the loaded contact's local stresses, safety factors."""
    import sys

    from .. import rating
    from ..pair import Pair
    from ..rating.report import table
    from ..spec import load_spec

    from .common import load_case, ltca_options

    load = load_case(args.torque_nm)
    if args.samples is not None and not 0 <= args.samples <= rating.MAX_TOLERANCE_SAMPLES:
        raise UserError(f"--samples = {args.samples}: must be an integer from 0 (the file's errors alone) to "
                        f"{rating.MAX_TOLERANCE_SAMPLES}")
    if not 0 <= args.seed < 2 ** 63:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to 2**63 - 1")
    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")
    spec = load_spec(args.file)
    samples = spec.rating.tolerance_samples if args.samples is None else args.samples
    from .ltca import _tolerances

    options = rating.Options(ltca=ltca_options(args), tolerance_samples=samples, tolerance_seed=args.seed,
                             tolerances=_tolerances(args, spec) if samples else None)
    pair = Pair.from_spec(spec)
    from ..progress import for_terminal

    result = rating.analyze(pair, load, options, face_points=21 if args.plot else 0,
                            progress=for_terminal() if samples else None)
    if args.plot is not None:
        from ..rating.plots import safety_along_face

        try:
            safety_along_face(result, pair.geometry, args.plot, title=f"{pair.spec.source}: pinion torque "
                                                                      f"{args.torque_nm:g} N m")
        except OSError as exc:
            raise UserError(f"--plot = {args.plot}: cannot write there ({exc.strerror or exc})") from None
    if args.json:
        print(json.dumps(result.to_json(), allow_nan=False))
    else:
        print(table(result))
    v = rating.verdict(result)
    if args.json:
        print(f"beveloid: verdict: {v['line']}", file=sys.stderr)
    return v["exit_status"]
