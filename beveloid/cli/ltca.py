"""``beveloid ltca FILE --torque-nm T[,T...] [--positions N] [--pairs K] [--flank left|right] [--dx MM] [--dy MM]
[--dz MM] [--vertical DEG] [--horizontal DEG] [--grid ACROSSxALONG] [--samples K] [--seed S] [--tolerances ...]
[--workers N | --scheduler ADDRESS] [--csv DIR] [--plot OUT.png] [--json]``.

A torque list is the torque map (JSON ``map`` + ``torque_map``), ``--samples`` the tolerance box under
load (JSON ``tolerance``); every run reports ``te_harmonics_urad`` / ``te_harmonics_um`` and the mesh
stiffness's mean and peak-to-peak (docs/commands.md, docs/loaded_contact.md 8.6).

Loaded tooth contact analysis (approximate: half-space + thin-slice teeth, frictionless; see
docs/loaded_contact.md).  The torque is the pinion torque.  The JSON holds "torque_nm",
"pinion_angle_rad" [N], "loaded_transmission_error_urad" [N], "tooth_pairs" [P],
"pair_normal_load_n" [N][P], "pair_max_pressure_mpa" [N][P], "pair_patch_semi_axes_mm" [N][P][2]
(across, along: sqrt(5 <x^2>) of the pressure), "contact_area_mm2" [N],
"pattern_area_fraction" {"pinion", "gear"}, "status" [N] and "solver" (iterations and residuals);
a position that did not converge has null numbers.  Since issue 23 also: "pair_surface_max_pressure_mpa"
and "pair_edge_max_pressure_mpa" [N][P] (the peak away from / at a flank edge; the edge one is
grid-dependent), "grid_convergence" (per position the change of the surface peak and of the pair
loads against the once-coarsened grid, with tolerances), "validity" (None per position inside the
model: linear elastic, small strain), "loaded_transmission_error_peak_to_peak_urad" (null with fewer
than 3 converged positions), "warnings" (also printed on stderr), per-pair grid extents,
"pair_hertz_max_pressure_mpa" [N][P] with its note, and "tooth_height_mm" {"pinion", "gear"}
(the Hertz note's yardstick: the LTCA holds Hertz within 5 % where the patch's semi-axis along
the contact is under half of it).
"""
from __future__ import annotations

import argparse
import json
import math
import os

from .paths import check_output_dir, check_output_file
from .common import add_error_flags, add_ltca_flags, apply_error_flags, errors_label, ltca_options, number, parse_torques
from ..errors import UserError


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    p.add_argument("--torque-nm", required=True, metavar="T[,T...]",
                   help="pinion torque (N m), > 0; a comma list (50,100,200,400) gives the torque map: the whole "
                        "analysis at each torque")
    add_ltca_flags(p)
    add_error_flags(p)
    p.add_argument("--plot", metavar="OUT.png", help="write the contact patterns, loaded TE and load sharing here "
                                                     "(and the per-position pressure maps beside it; with"
                                                     " --samples the error sets at OUT_tolerance.png)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("--csv", metavar="DIR", help="write DIR/ltca.csv: one row per position and torque (pinion angle, "
                                                "loaded TE, mesh stiffness, pair loads), for a dynamics model")
    p.add_argument("--speed-rpm", metavar="N[,N...]",
                   help="pinion speed (rpm) for the tribology (film, friction, power loss, efficiency, scuffing: "
                        "docs/tribology.md); needs a [lubricant] section; default [rating] pinion_speed_rpm when the "
                        "file has a lubricant; a comma list with several torques gives the efficiency map")
    p.add_argument("--samples", type=int, default=0, metavar="K",
                   help="the tolerance box under load: K error sets drawn about the file's [misalignment] (the "
                        "draws of sweep and explore), each a full loaded analysis at every torque")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the error sets (default 0)")
    from .explore import add_tolerances_flag

    add_tolerances_flag(p)
    where = p.add_mutually_exclusive_group()  # beveloid.parallel: the same numbers on any of them
    where.add_argument("--workers", type=int, metavar="N", help="analyse chunks of error sets on N local processes")
    where.add_argument("--scheduler", metavar="ADDRESS", help="analyse them on an existing Dask distributed cluster")


def run(args: argparse.Namespace) -> int:
    """Loaded tooth contact analysis under a pinion torque (approximate: Boussinesq half-space + the FE tooth, or the plate tooth's beams with --tooth-model plate).

    Prints per position the loaded TE, the load of each tooth pair, its peak pressure and the
    contact area; --json prints the full arrays.  Warnings (grid not converged, outside the
    model's validity, edge peaks) go to stderr, one line each.
    """
    import sys

    from .. import ltca
    from ..pair import Pair
    from ..solver import Solver

    torques = parse_torques(args.torque_nm)
    options = ltca_options(args)
    if not 0 <= args.samples <= 100_000:
        raise UserError(f"--samples = {args.samples}: must be an integer from 0 (no tolerance box) to 100000")
    if not 0 <= args.seed < 2 ** 63:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to 2**63 - 1")
    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")
    if args.csv is not None:
        check_output_dir(args.csv, "--csv")  # the one output rule (beveloid.outputs)
    from ..spec import load_spec

    spec = apply_error_flags(load_spec(args.file), args)
    speeds = parse_speeds(args.speed_rpm, spec)
    tolerances = _tolerances(args, spec) if args.samples else None
    pair = Pair.from_spec(spec)
    from ..parallel import executor

    if args.workers is not None or args.scheduler is not None:
        executor(args.workers, args.scheduler)  # checks the flags (one line) before any work
    load = ltca.LoadCase(torques)
    box = None
    if tolerances is None:
        # the contact patterns once per run: the JSON, the table and the figures read them
        results = [r.with_patterns() for r in ltca.analyze_many(pair, load, options, solver=Solver()).results[0]]
    else:
        from .. import sweep
        from ..progress import for_terminal

        nominal = {key: float(getattr(spec.misalignment, key)) for key in tolerances}
        draws = sweep.draw_errors(args.samples, ranges=tolerances, seed=args.seed, nominal=nominal)
        # the file's errors (with their patterns) one more task of the box's workers: no analysis here
        results, box = ltca.studies.tolerance_box(pair, load.at(errors=draws), options, workers=args.workers,
                                                  scheduler=args.scheduler, progress=for_terminal(), nominal=load)
    geom = pair.geometry
    label = f"{spec.source}: {errors_label(spec)}"
    if args.plot is not None:
        if box is not None:  # the figures of the file's errors say so, and the box has its own
            label = f"{spec.source}, the file's errors ({errors_label(spec)}); {args.samples} error sets: " \
                    f"{os.path.basename(_stem(args.plot))}_tolerance.png"
            _tolerance_plot(results, box, _stem(args.plot) + "_tolerance.png",
                            f"{spec.source}: {args.samples} error sets in the tolerance box (seed {args.seed})")
        _plot(results, geom, args.plot, label)
    trib = _tribology(results, pair, speeds) if speeds else None
    if args.csv is not None:
        write_csv(results, geom, args.csv)
        if trib is not None:
            from ..tribology.report import write_csv as tribology_csv

            tribology_csv(trib, args.csv)
    if args.plot is not None and trib is not None:
        _plot_tribology(trib, results, geom, args.plot, label)
    for r in results:
        for w in r.warnings():
            print(f"beveloid: warning: {w if len(results) == 1 else f'{r.torque_nm:g} N m: {w}'}", file=sys.stderr)
    entries = []
    for t, r in enumerate(results):
        d = r.to_json()
        if box is not None:
            d["tolerance"] = ltca.studies.tolerance_json(box, t, args.samples, args.seed, tolerances)
        if trib is not None:
            if len(speeds) == 1:
                d.update(trib[t][0].to_json())
            else:
                d["speeds"] = [x.to_json() for x in trib[t]]
        entries.append(d)
    out = entries[0] if len(results) == 1 else {"map": entries, "torque_map": ltca.studies.torque_map_json(results)}
    if trib is not None and len(speeds) > 1:
        from ..tribology.report import map_json

        out = dict(out) if len(results) > 1 else {"map": entries}
        out["efficiency_map"] = map_json(trib)
    if args.json:
        print(json.dumps(out, allow_nan=False))
    else:
        for r, d in zip(results, entries):
            print(format_summary(r, geom, spec))
            if "tolerance" in d:
                print(format_tolerance(d["tolerance"]))
            print()
        if len(results) > 1:
            print(format_torque_map(out["torque_map"]))
        if trib is not None:
            from ..tribology.report import format_lines

            for row in trib:
                for x in row:
                    print(f"{x.torque_nm:g} N m: " + "\n".join(format_lines(x)))
    return 0


def parse_speeds(text, spec) -> list:
    """The pinion speeds (rpm) of the tribology: --speed-rpm (one or a comma list), else [rating]
    pinion_speed_rpm when the file names a lubricant; [] for none.  A speed without a lubricant is
    refused (one line)."""
    if text is None:
        given = spec.rating.pinion_speed_rpm
        return [given] if given is not None and spec.lubricant.given else []
    out = []
    for part in str(text).split(","):
        try:
            v = float(part)
        except ValueError:
            v = math.nan
        if not (math.isfinite(v) and 0 < v <= 1e6):
            raise UserError(f"--speed-rpm = {text}: each speed must be a number > 0 and <= 1e6 (rpm), comma-separated")
        out.append(v)
    if not spec.lubricant.given:
        raise UserError(f"--speed-rpm = {text}: needs a [lubricant] section in {spec.source} (an oil: iso_vg or the "
                        "kinematic viscosities, and temperature_c; docs/tribology.md)")
    return out


def _tribology(results, pair, speeds):
    """[[TribologyResult per speed] per torque]: each torque's contact once, every speed from it."""
    from .. import tribology

    try:
        return tribology.efficiency_map(results, pair, speeds)
    except tribology.LubricantError as exc:
        raise UserError(str(exc)) from None


def _plot_tribology(trib, results, geom, path, label):
    from ..tribology.plots import efficiency_map, flank_fields

    stem = path[:-4] if path.endswith(".png") else path
    try:
        x = trib[0][0]
        flank_fields(x, results[0], geom, stem + "_tribology.png",
                     title=f"{label}, {x.torque_nm:g} N m at {x.speed_rpm:g} rpm")
        if len(trib) > 1 or len(trib[0]) > 1:
            efficiency_map(trib, stem + "_efficiency.png", title=label)
    except OSError as exc:
        raise UserError(f"--plot = {path}: cannot write there ({exc.strerror or exc})") from None


def _tolerances(args, spec) -> dict:
    """The half-widths of --tolerances (explore's parser), each with the file's misalignment inside the
    errors' limits."""
    from .. import assembly_errors
    from .explore import parse_tolerances

    tol = parse_tolerances(args.tolerances)
    for key, half in tol.items():
        centre = abs(float(getattr(spec.misalignment, key)))
        if centre + half > assembly_errors.BY_KEY[key].limit:
            raise UserError(f"--tolerances {key}: {half:g} about misalignment.{key} = {centre:g} reaches"
                            f" {centre + half:g}; |nominal| + half-width must be <= "
                            f"{assembly_errors.BY_KEY[key].limit:g}")
    return tol


def write_csv(results, geom, folder):
    """DIR/ltca.csv: one row per position and torque, units in every column name; empty cells where a
    position did not converge."""
    import csv

    from ..ltca.results.batch import gear_base_radius_mm

    os.makedirs(folder, exist_ok=True)
    rb = gear_base_radius_mm(geom)
    pairs = results[0].tooth_pairs
    head = (["torque_nm", "position", "pinion_angle_rad", "status", "loaded_te_urad", "loaded_te_line_of_action_um",
             "unloaded_te_urad", "mesh_stiffness_n_per_um"] + [f"pair_{k}_load_n" for k in pairs])
    cell = lambda v: "" if v is None or not math.isfinite(v) else repr(float(v))  # noqa: E731
    path = os.path.join(folder, "ltca.csv")
    tmp = path + ".tmp"
    try:
        with open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(head)
            for r in results:
                k = r.mesh_stiffness_n_per_um
                for j, phi in enumerate(r.pinion_angle):
                    w.writerow([repr(float(r.torque_nm)), j, repr(float(phi)), r.status[j], cell(r.loaded_te[j] * 1e6),
                                cell(r.loaded_te[j] * rb * 1e3), cell(r.unloaded_te[j] * 1e6),
                                cell(None if k is None else k[j])] + [cell(v) for v in r.pair_load_n[j]])
        os.replace(tmp, path)
    except OSError as exc:
        raise UserError(f"--csv = {folder}: cannot write there ({exc.strerror or exc})") from None
    return path


def _stem(path: str) -> str:
    return path[:-4] if path.endswith(".png") else path


def _tolerance_plot(results, box, path, title):
    from ..ltca.results.plots import tolerance_box

    try:
        tolerance_box(results, box, path, title)
    except OSError as exc:
        raise UserError(f"--plot = {path}: cannot write there ({exc.strerror or exc})") from None


def _plot(results, geom, path, label):
    from ..ltca.results.plots import ltca_summary, ltca_torques, te_map

    stem = _stem(path)
    try:
        if len(results) == 1:
            r = results[0]
            ltca_summary(r, geom, path, title=f"{label}, pinion torque {r.torque_nm:g} N m")
            te_map(results, stem + "_spectrum.png", title=label)
        else:
            te_map(results, path, title=label)
            ltca_torques(results, geom, stem + "_torques.png", title=label)
    except OSError as exc:
        raise UserError(f"--plot = {path}: cannot write there ({exc.strerror or exc})") from None


def format_tolerance(t) -> str:
    fmt = number
    lines = [f"tolerance box: {t['samples']} error sets (seed {t['seed']}), edge contact in "
             f"{t['edge_contact_fraction'] * 100:.0f} % of them", "                            p50        p90        max"]
    rows = [("TE peak-to-peak (urad)", t["te_peak_to_peak_urad"]), ("max pressure (MPa)", t["max_pressure_mpa"])]
    rows += [(f"{m} root stress (MPa)", s) for m, s in t["root_stress_max_mpa"].items()]
    for name, s in rows:
        lines.append(f"  {name:<24}" + "".join(f"{fmt(s[q], '.2f'):>11}" for q in ("p50", "p90", "max")))
    return "\n".join(lines)


def format_torque_map(m) -> str:
    fmt = number
    lines = ["torque map:", "  torque (N m)  TE p-p (urad)  max pressure (MPa)  root pinion (MPa)  root gear (MPa)"
             "  mesh stiffness mean (N/um)"]
    for i, t in enumerate(m["torque_nm"]):
        lines.append(f"  {t:>12g}  {fmt(m['te_peak_to_peak_urad'][i], '.3f'):>13}  {fmt(m['max_pressure_mpa'][i], '.0f'):>18}"
                     f"  {fmt(m['root_stress_max_mpa']['pinion'][i], '.1f'):>17}"
                     f"  {fmt(m['root_stress_max_mpa']['gear'][i], '.1f'):>15}"
                     f"  {fmt(m['mesh_stiffness_mean_n_per_um'][i], '.1f'):>26}")
    return "\n".join(lines)


def _root_stress_lines(result) -> list:
    if result.tooth_model != "fe":
        return ["root stress: not computed with the plate tooth (--tooth-model fe)"]
    top, where = result.root_stress_max_mpa(), result.root_stress_location()
    out = []
    for m in ("pinion", "gear"):
        if top.get(m) is None:
            out.append(f"{m} root stress: not available (no converged position)")
            continue
        w = where[m]
        out.append(f"{m} root stress (max principal, loaded fillet): {top[m]:.1f} MPa at position {w['position']}, "
                   f"pair {w['pair']}, z = {w['z_mm']:.2f} mm, {w['height_mm']:.2f} mm above the root")
    return out


def format_summary(result, geom, spec) -> str:
    from ..plots import PINION_ANGLE_LABEL, pinion_angle_deg

    fmt = number
    lines = [f"Loaded TCA of {spec.source}, {result.flank} flank, pinion torque {result.torque_nm:g} N m,"
             f" {errors_label(spec)}", ""]
    head = [PINION_ANGLE_LABEL, "status", "TE loaded (urad)", "TE unloaded (urad)", "area (mm2)"]
    head += [f"F pair {k} (N)" for k in result.tooth_pairs] + [f"p_max pair {k} (MPa)" for k in result.tooth_pairs]
    rows = [head]
    for j, phi in enumerate(result.pinion_angle):
        rows.append([f"{pinion_angle_deg(phi):.3f}", result.status[j], fmt(result.loaded_te[j] * 1e6, ".3f"),
                     fmt(result.unloaded_te[j] * 1e6, ".3f"), fmt(result.contact_area_mm2[j], ".2f")]
                    + [fmt(v, ".1f") for v in result.pair_load_n[j]]
                    + [fmt(v, ".0f") + ("*" if math.isfinite(e) and e >= v else "")
                       for v, e in zip(result.pair_max_pressure_mpa[j], result.pair_edge_max_pressure_mpa[j])])
    w = [max(len(r[i]) for r in rows) for i in range(len(head))]
    lines += ["  ".join(c.rjust(wi) for c, wi in zip(r, w)) for r in rows]
    frac = {m: result.pattern(m).area_fraction for m in ("pinion", "gear")}
    lines += ["", "share of each flank that carries pressure somewhere in the cycle: "
              + ", ".join(f"{m} {fmt(f * 100 if f is not None else None, '.1f')}%" for m, f in frac.items()),
              f"grid per pair: {result.grid.across_cells} x {result.grid.along_cells} cells, sized from each pair's Hertz "
              f"semi-axes (up to +-{result.across_half_mm:.3f} mm across and +-{result.along_half_mm:.2f} mm along the"
              " contact line)"]
    if any("*" in c for r in rows[1:] for c in r):
        lines += ["* the peak is at a flank edge: grid-dependent (see pair_edge_max_pressure_mpa and "
                  "pair_surface_max_pressure_mpa in --json)"]
    ptp = result.loaded_te_peak_to_peak
    lines += [f"loaded TE peak-to-peak: {fmt(ptp * 1e6, '.3f')} urad" if math.isfinite(ptp) else
              "loaded TE peak-to-peak: not available (needs 3 or more converged positions)"]
    from ..ltca.results.batch import loaded_contact_ratio

    eps = loaded_contact_ratio(result)
    lines += [f"loaded contact ratio: {fmt(eps, '.3f')} (mean number of tooth pairs carrying load over the cycle;"
              " the unmodified flanks' unloaded one: `beveloid design`)"]
    lines += _root_stress_lines(result)
    lines += [f"note: {n}" for n in result.notes]
    teeth = (f"FE tooth (refinement {result.fe_refinement})" if result.tooth_model == "fe"
             else "thin-slice plate tooth beams")
    lines += [f"approximate: Boussinesq half-space + {teeth}, frictionless (docs/loaded_contact.md)"]
    return "\n".join(lines)
