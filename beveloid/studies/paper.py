"""``beveloid paper --out DIR``: Table 1, the unloaded studies of Figs 10-22, the loaded contact of
Figs 24-25, the crowning and micro-geometry studies (beveloid/studies/crowning.py, loaded.py,
micro_geometry.py), with a report.

Everything is computed from examples/case1.toml and examples/case2.toml (shipped in the
package as beveloid/data/) by the design and TCA of this package; the paper's printed values
(beveloid/data/table1.toml) appear only in comparison columns.  The paper does not say which
flank pair its figures show; the study uses the right flank (the equations.md reading), and
the report gives the left flank's key numbers too.
"""
from __future__ import annotations

import csv
import math
import time
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from .. import interrupts
from ..status import PointStatus
from . import PAPER_CONTENTS as CONTENTS
from .crowning import PAPER_ALIGNED_TE_URAD
from .tasks import say as _progress

DEG = math.pi / 180


@dataclass(frozen=True)
class Study:
    figure: str  # e.g. "10"
    te_figure: str  # the paper's TE figure of the same errors
    case: str
    title: str
    errors: tuple  # ((label, (dx, dy, dz, vertical_deg, horizontal_deg)), ...)


def _q(v):
    return (v, v, v, 0.0, 0.0)


STUDIES = (
    Study("10", "13", "case1", "Case 1: gear offset errors dq = dx = dy = dz",
          (("aligned", _q(0.0)), ("dq = +0.5 mm", _q(0.5)), ("dq = -0.5 mm", _q(-0.5)), ("dq = +1.0 mm", _q(1.0)))),
    Study("11", "14", "case1", "Case 1: horizontal angular error",
          (("aligned", _q(0.0)), ("dgh = +0.03 deg", (0, 0, 0, 0, 0.03)), ("dgh = -0.03 deg", (0, 0, 0, 0, -0.03)))),
    Study("12", "15", "case1", "Case 1: vertical angular error",
          (("aligned", _q(0.0)), ("dgv = +0.2 deg", (0, 0, 0, 0.2, 0)), ("dgv = -0.2 deg", (0, 0, 0, -0.2, 0)))),
    Study("16", "19", "case2", "Case 2: gear offset errors dq = dx = dy = dz",
          (("aligned", _q(0.0)), ("dq = +0.5 mm", _q(0.5)), ("dq = -0.5 mm", _q(-0.5)), ("dq = +1.0 mm", _q(1.0)),
           ("dq = -1.0 mm", _q(-1.0)))),
    Study("17", "20", "case2", "Case 2: horizontal angular error",
          (("aligned", _q(0.0)), ("dgh = +0.04 deg", (0, 0, 0, 0, 0.04)), ("dgh = -0.04 deg", (0, 0, 0, 0, -0.04)))),
    Study("18", "21", "case2", "Case 2: vertical angular error",
          (("aligned", _q(0.0)), ("dgv = +0.25 deg", (0, 0, 0, 0.25, 0)), ("dgv = -0.25 deg", (0, 0, 0, -0.25, 0)))),
)

FLANK = "right"
CASES = ("case1", "case2")
#: the paper's edge-contact onset under dq = dx = dy = dz (mm): printed for case 1 only
PAPER_EDGE_ONSET_MM = {"case1": 1.0}


def _data_path(name):
    return resources.files("beveloid") / "data" / name


def load_table1():
    with _data_path("table1.toml").open("rb") as f:
        return tomllib.load(f)


def _err_vec(e):
    return np.array([e[0], e[1], e[2], e[3] * DEG, e[4] * DEG])


def _within_last_digit(printed: str, value: float) -> bool:
    """Signed comparison within one unit of the last printed digit (a flipped hand fails)."""
    s = printed.strip().lstrip("+-")
    dec = len(s.split(".")[1]) if "." in s else 0
    return abs(value - float(printed)) <= 10.0 ** (-dec) * (1 + 1e-9)


def table1_comparison(results):
    """Rows (symbol, quantity, member, printed, computed, match) for both cases."""
    t1 = load_table1()
    rows = []
    for case, res in results.items():
        tab = t1[case]
        pair = tab["pair"]
        rows.append((case, "xi_L (deg)", "pair", pair["xi_L_deg"], math.degrees(res.fpd_angle_left)))
        rows.append((case, "xi_R (deg)", "pair", pair["xi_R_deg"], math.degrees(res.fpd_angle_right)))
        for member in ("pinion", "gear"):
            m = res.member(member)
            p = tab[member]
            rows += [
                (case, "beta (deg)", member, p["beta_deg"], math.degrees(m.helix_angle)),
                (case, "x_t", member, p["x_t"], m.profile_shift),
                (case, "xi_t", member, p["xi_t"], m.transverse_angular_factor),
                (case, "d (mm)", member, p["d_mm"], m.mounting_distance_mm),
                (case, "gamma_w (deg)", member, p["gamma_w_deg"], math.degrees(m.working_cone_angle)),
                (case, "beta_w (deg)", member, p["beta_w_deg"], math.degrees(m.working_helix_angle)),
            ]
    return [(c, q, m, p, v, _within_last_digit(p, v)) for c, q, m, p, v in rows]


def _write_csv(path, study, geom_results):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["label", "dx_mm", "dy_mm", "dz_mm", "vertical_deg", "horizontal_deg", "flank", "tooth_pair",
                    "pinion_angle_rad", "gear_angle_rad", "transmission_error_urad", "pinion_x_mm", "pinion_y_mm",
                    "pinion_z_mm", "gear_x_mm", "gear_y_mm", "gear_z_mm", "status", "active"])
        for (label, e), res in zip(study.errors, geom_results):
            fr = res.flanks[FLANK]
            for i in range(len(fr.status)):
                vals = [fr.gear_angle[i], fr.transmission_error[i] * 1e6, *fr.pinion_contact[i], *fr.gear_contact[i]]
                w.writerow([label, *e, FLANK, int(fr.tooth_pair[i]), repr(float(fr.pinion_angle[i]))]
                           + ["" if not np.isfinite(v) else repr(float(v)) for v in vals]
                           + [fr.status[i], int(fr.active[i])])


def mean_contact_z(fr):
    """Mean axial position (mm) of pair 0's contact points on the pinion and the gear (nan if none):
    where the path lies on each flank (not its shift from the aligned path, `beveloid sweep`'s
    "path shift")."""
    ok = (fr.tooth_pair == 0) & np.isfinite(fr.pinion_contact[:, 2])
    if not ok.any():
        return float("nan"), float("nan")
    return float(fr.pinion_contact[ok, 2].mean()), float(fr.gear_contact[ok, 2].mean())


def edge_face_margin(geom, flank, dq):
    """Smallest distance (mm) from a toe or heel of the contacts over the engagement window under
    dx = dy = dz = dq, among the contacts not carried by a tip or form limit (those start and end
    the engagement of every pair, aligned or not); ``inf`` when there is none."""
    from .. import tca

    names = list(tca.tca_kernels.CONTACT_BOUNDARIES)
    profile = [names.index(f"{w} {b}") for w in ("pinion", "gear") for b in ("form limit", "tip")]
    face = [names.index(f"{w} {b}") for w in ("pinion", "gear") for b in ("toe", "heel")]
    fr = tca.mesh_flank(geom, flank, _err_vec(_q(dq)), positions=60, pairs=1, window_pitches=3)
    M = tca.contact_margins(geom, flank, fr.unknowns)
    on_profile = (M[:, profile] >= -1e-9).all(axis=1) & np.array(
        [b is None or not any(w in b for w in ("tip", "form limit")) for b in fr.contact_boundary])
    return float(np.min(np.where(on_profile, M[:, face].min(axis=1), np.inf)))


def edge_onset_offset(geom, flank, direction=+1.0, hi=3.0, tol=1e-4):
    """Smallest dq (dx = dy = dz = dq, sign = direction) at which a toe or heel starts to bear
    (edge contact at a face end), to ``tol`` mm; ``inf`` when none bears up to ``hi`` mm.

    A contact on the toe or heel itself has a face margin of 0 to round-off (either sign): a
    bearing is a margin within the solver's patch tolerance, so the search does not follow the
    sign of round-off.  The onset is the root of (face margin - that tolerance), found by
    scipy.optimize.brentq (the margin is the minimum over the window: continuous, with kinks).
    """
    from scipy.optimize import brentq

    from .. import tca

    clear = tca.DEFAULT_OPTIONS.patch_tol_mm

    def clearance(q):  # > 0: no toe or heel bears; finite for brentq (no contact counts as 1 m clear)
        return min(edge_face_margin(geom, flank, direction * q), 1e3) - clear

    if clearance(0.0) <= 0.0:
        return 0.0
    if clearance(hi) > 0.0:
        return float("inf")
    return float(brentq(clearance, 0.0, hi, xtol=0.5 * tol, rtol=1e-12))


def bearing_pattern_figure(geom, results, labels, out_png, title):
    """The hook for the bearing patterns: the results' contact ellipses (tca.Options.approach_mm), drawn
    (beveloid/contact_ellipse.py, plots.bearing_patterns)."""
    from .. import plots

    plots.bearing_patterns(results, labels, geom, FLANK, out_png, title)


def run(out_dir, positions=200, progress=_progress, tooth_model=None, workers=None):
    """Write figures, CSV and report.md into out_dir; returns the report path.

    The files are written into a folder of their own and moved into out_dir at the end
    (:func:`beveloid.studies.output.staged_folder`): two runs into one folder leave one run's files.
    ``workers``: processes for the studies' pieces (None: the cores this process may use, at most
    :data:`MAX_WORKERS`; 1: all in this process); the files are the same either way.
    """
    from .output import staged_folder

    t0 = time.perf_counter()
    with staged_folder(out_dir) as stage:
        write_study(stage, positions, progress, tooth_model, workers=workers)
    report = Path(out_dir) / "report.md"
    progress(f"done in {time.perf_counter() - t0:.1f} s: {report}")
    return report


#: the most worker processes a run starts (its independent pieces: per case, 4 FE members, 3 error
#: studies, onset, crowning, loaded contact, micro-geometry)
MAX_WORKERS = 4


def _study_task(figure, positions, out):
    """One error study (Figs 10-12, 16-18 with their TE figures): its figures and CSV into ``out``;
    returns its rows of the report's summary table."""
    from .. import plots, tca
    from ..pair import Pair

    st = next(s for s in STUDIES if s.figure == figure)
    out = Path(out)
    g = Pair.example(st.case).geometry
    res = [tca.analyze(g, tca.Options(positions=positions, errors=_err_vec(e))) for _, e in st.errors]  # with ellipses
    labels = [lab for lab, _ in st.errors]
    plots.contact_paths(res, labels, g, FLANK, out / f"fig{st.figure}_contact_path.png",
                        f"Fig {st.figure} - {st.title} ({FLANK} flank)")
    plots.transmission_error(res, labels, FLANK, out / f"fig{st.te_figure}_transmission_error.png",
                             f"Fig {st.te_figure} - {st.title} ({FLANK} flank)")
    _write_csv(out / f"fig{st.figure}_fig{st.te_figure}.csv", st, res)
    bearing_pattern_figure(g, res, labels, out / f"fig{st.figure}_bearing_pattern.png",
                           f"Fig {st.figure} errors - bearing pattern ({FLANK} flank, like Figs 24a/25a)")
    rows = []
    for (lab, e), r in zip(st.errors, res):
        fr = r.flanks[FLANK]
        pc, gc = mean_contact_z(fr)
        n_surface, n_edge = (sum(s == status for s in fr.status) for status in (PointStatus.OK, PointStatus.EDGE))
        rows.append((st.figure, st.case, lab, pc, gc, n_surface, n_edge, len(fr.status),
                     fr.te_peak_to_peak * 1e6, r.backlash_um, r.flanks["left"].te_peak_to_peak * 1e6))
    return rows


def _onset_task(case):
    from ..pair import Pair

    g = Pair.example(case).geometry
    return edge_onset_offset(g, FLANK, +1), edge_onset_offset(g, FLANK, -1)


def _crowning_task(case, positions, out):
    from . import crowning

    return crowning.case_rows(Path(out), case, STUDIES, _err_vec, _write_csv, positions=positions, flank=FLANK,
                              progress=_progress)


def compile_first(geom) -> float:
    """Seconds to make ready the solver core's paths, which every TCA piece runs (numba compiles them on
    the first run after an installation and caches them; later runs load them): a small TCA of each
    kind the studies run (paths, statuses, backlash, contact margins), so that the worker processes
    load numba's cache instead of each compiling the same functions.  This compile is the one that
    the rest waits for: the other compiled functions are made ready on the workers, the loaded
    contact's kernels beside it (:func:`_ltca_kernels_task`), the contact ellipses and the LTCA's
    normal gaps after it (:func:`_chords_task`, :func:`_ltca_gaps_task`)."""
    from .. import tca

    t0 = time.perf_counter()  # the first solve says when numba compiles (beveloid/solver/backends.py)
    tca.analyze(geom, tca.Options(positions=12, approach_mm=None, errors=np.zeros(5)))  # paths, statuses, backlash
    tca.contact_margins(geom, FLANK, tca.mesh_flank(geom, FLANK, positions=4, pairs=1, window_pitches=3).unknowns)
    return time.perf_counter() - t0


def _chords_task():
    """A piece once the core's paths are compiled (and in numba's cache): the contact ellipses of the
    bearing patterns compiled on a worker, by those of a small TCA; returns its seconds."""
    from .. import tca
    from ..pair import Pair

    t0 = time.perf_counter()
    tca.analyze(Pair.example("case1").geometry, tca.Options(positions=12, errors=np.zeros(5)))  # with ellipses
    return time.perf_counter() - t0


def _small_ltca(solver=None):
    """A small loaded contact of case 1 (the plate tooth, 2 positions): what compiles the LTCA's functions."""
    from .. import ltca
    from ..pair import Pair

    ltca.analyze(Pair.example("case1").geometry, ltca.LoadCase(100.0), ltca.Options(flank=FLANK, positions=2, tooth_model="plate"), solver=solver)


def _ltca_kernels_task():
    """A piece, the first on a worker: the loaded contact's own compiled kernels (beveloid/ltca/mechanics/kernel.py:
    compiled whatever the solver's backend) made ready while the main process compiles the solver core,
    by a small LTCA whose TCA runs on the numpy backend (that compiles none of the core), and the FE
    tooth's root-stress functions (beveloid/fe/principal.py), which both loaded pieces would otherwise
    compile at once; returns its seconds."""
    from ..fe import principal
    from ..solver import Solver

    t0 = time.perf_counter()
    _small_ltca(Solver("numpy"))
    principal.compile_now()
    return time.perf_counter() - t0


def _ltca_gaps_task():
    """A piece, once the core's paths are compiled and the LTCA's kernels ready: the same small LTCA on
    the compiled core, which compiles the core's normal gaps (the loaded contact's) and loads the rest
    from numba's cache; returns its seconds."""
    t0 = time.perf_counter()
    _small_ltca()
    return time.perf_counter() - t0


def write_study(out: Path, positions=200, progress=_progress, tooth_model=None, workers=None) -> None:
    """Compute every study and write its figures, CSV and report.md into the folder ``out``
    (``tooth_model``: the loaded contact's, None = the LTCA's default; ``workers``: see :func:`run`)."""
    from .. import ltca, plots, tca
    from ..design import format_table1
    from ..pair import Pair
    from ..parallel import default_workers
    from . import crowning, loaded as loaded_study, micro_geometry
    from .tasks import Tasks

    t0 = time.perf_counter()
    workers = min(MAX_WORKERS, default_workers()) if workers is None else workers
    model = ltca.Options(tooth_model=tooth_model).tooth_model
    steps = 6  # Table 1, the FE teeth, compile and the TCA studies, Fig 22 and sensitivity, the LTCA studies, report
    k = 0

    def step(msg):
        nonlocal k
        interrupts.check()  # a Ctrl-C swallowed by a compile callback in the last step stops here
        k += 1
        progress(f"[{k}/{steps}] {msg}")

    step("Table 1: direct design of both cases")
    pairs = {c: Pair.example(c) for c in CASES}
    designs = {c: p.design for c, p in pairs.items()}
    geoms = {c: p.geometry for c, p in pairs.items()}
    comparison = table1_comparison(designs)
    with open(out / "table1.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "quantity", "member", "printed", "computed", "within_last_printed_digit"])
        for row in comparison:
            w.writerow([row[0], row[1], row[2], row[3], repr(float(row[4])), row[5]])

    with Tasks(workers) as tasks:
        step(f"the loaded contact's FE teeth, on {tasks.workers} process{'es' if tasks.workers > 1 else ''}"
             if model == "fe" else f"the loaded contact's tooth: {model} (no FE data); {tasks.workers} "
             f"process{'es' if tasks.workers > 1 else ''}")
        kernels = tasks.submit(_ltca_kernels_task)  # first: it needs nothing of the core's compile
        fe = loaded_study.submit_fe_teeth(tasks, CASES, model)  # the longest pieces next: numba not needed
        step("the compiled solver, then Figs 10-21 (error studies), edge-contact onset, crowning study: TCA")
        seconds = compile_first(geoms["case1"])
        progress(f"   compiled solver ready in {seconds:.1f} s")
        # what needs the core's paths: the other compiles first; the bearing patterns wait for theirs
        kernels.get()  # (ready long before: the gaps' piece then loads them, never compiles them again)
        o, gaps, chords = str(out), tasks.submit(_ltca_gaps_task), tasks.submit(_chords_task)
        crowned = {c: tasks.submit(_crowning_task, c, positions, o) for c in CASES}
        onsets = {c: tasks.submit(_onset_task, c) for c in CASES}

        step("Fig 22 (aligned TE of both cases) and the sensitivity of the path")
        aligned = [tca.analyze(geoms[c], tca.Options(positions=positions, approach_mm=None, errors=np.zeros(5)))
                   for c in CASES]
        plots.transmission_error(aligned, [f"{c.replace('case', 'case ')} (xi_R = "
                                           f"{math.degrees(designs[c].fpd_angle_right):.4f} deg)" for c in CASES],
                                 FLANK, out / "fig22_transmission_error.png", "Fig 22 - aligned TE of both cases")
        sens = {c: tca.sensitivity(geoms[c], FLANK) for c in CASES}
        chords.get()
        studies = {st.figure: tasks.submit(_study_task, st.figure, positions, o) for st in STUDIES}

        step("Figs 24-25 (loaded contact) and the micro-geometry study: LTCA, once the FE teeth are ready")
        for handle in [*fe, gaps]:
            handle.get()
        loaded_parts = {c: tasks.submit(loaded_study.case_task, c, o, model) for c in CASES}
        micro_parts = {c: tasks.submit(micro_geometry.case_task, c) for c in CASES}

        summary = [row for st in STUDIES for row in _done(studies[st.figure], f"Fig {st.figure} / Fig {st.te_figure}",
                                                          progress)]
        onset = {c: _done(onsets[c], f"edge-contact onset, {c}", progress) for c in CASES}
        crowned_rows = [_done(crowned[c], f"crowning study, {c}", progress) for c in CASES]
        loaded = loaded_study.finish(out, {c: _done(loaded_parts[c], f"loaded contact, {c}", progress) for c in CASES},
                                     model)
        loaded += micro_geometry.finish(out, {c: _done(micro_parts[c], f"micro-geometry, {c}", progress)
                                              for c in CASES})

    step("report.md")
    report = _report(designs, comparison, summary, sens, onset, aligned, positions)
    report += "\n".join([*crowning.finish(out, crowned_rows, FLANK, positions), "", *loaded])
    report += "\n".join(["", "## This run", "", f"Every section above, the figures and data files included, computed in "
                          f"{time.perf_counter() - t0:.1f} s on {workers} process{'es' if workers > 1 else ''}.", ""])
    (out / "report.md").write_text(report)
    (out / "table1_case1.txt").write_text(format_table1(designs["case1"]) + "\n")
    (out / "table1_case2.txt").write_text(format_table1(designs["case2"]) + "\n")


def _done(handle, what, progress):
    """The piece's result, saying so when it has it."""
    value = handle.get()
    progress(f"   done: {what}")
    return value


def _fmt(v, f="{:.3f}"):
    return "-" if v is None or not np.isfinite(v) else f.format(v)


def _report(designs, comparison, summary, sens, onset, aligned, positions):
    L = [f"# Reproduction of Zhu, Song, Lim & Peng (MMT 59, 2013): {CONTENTS}", "",
         "Generated by `beveloid paper`. Every number below is computed by this package from "
         "examples/case1.toml and examples/case2.toml; the paper's values appear only in the "
         "'printed' column. Conventions (flank names, frames, blank, b_c = 0) are in docs/validation.md.", ""]
    L += ["## Table 1", "", "| case | quantity | member | printed | computed | within 1 in the last printed digit |",
          "|---|---|---|---|---|---|"]
    for c, q, m, p, v, ok in comparison:
        L.append(f"| {c} | {q} | {m} | {p} | {v:.6f} | {'yes' if ok else '**no**'} |")
    n_ok = sum(r[5] for r in comparison)
    L += ["", f"{n_ok} of {len(comparison)} printed values reproduced to the last printed digit "
          "(the full tables: table1_case1.txt, table1_case2.txt; data: table1.csv).", ""]
    L += ["## Contact path and TE under the assembly errors (right flank)", "",
          "Mean contact z: the mean axial position of tooth pair 0's contact points (mm, toe -> heel) "
          "in each member's frame, i.e. where the path lies (not the path shift of `beveloid sweep`, which "
          "is the change from the aligned path). TE p-p: peak-to-peak of the contact envelope over the "
          "mesh window. Surface contacts: pair-positions (pinion positions x tooth pairs) where the two "
          "flanks touch inside both flank boundaries (status `ok`); edge contacts: pair-positions where a "
          "boundary of one tooth (its tip, toe, heel or form limit) bears on the other flank (status `edge`). "
          "The bearing patterns draw an ellipse at both kinds; the other pair-positions have no contact "
          "(`outside`: the flanks cannot touch there).", "",
          "| figure | case | errors | pinion mean contact z (mm) | gear mean contact z (mm) | surface contacts | "
          "edge contacts | TE p-p right (urad) | TE p-p left (urad) | backlash (um) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for fig, case, lab, pc, gc, n_surface, n_edge, n, ptp, bl, ptp_l in summary:
        L.append(f"| {fig} | {case} | {lab} | {_fmt(pc, '{:+.3f}')} | {_fmt(gc, '{:+.3f}')} | {n_surface}/{n} | "
                 f"{n_edge}/{n} | {_fmt(ptp, '{:.2e}')} | {_fmt(ptp_l, '{:.2e}')} | {_fmt(bl, '{:.3f}')} |")
    for st in STUDIES:
        L += ["", f"### Fig {st.figure} and Fig {st.te_figure}: {st.title}", "",
              f"![Fig {st.figure}](fig{st.figure}_contact_path.png)", "",
              f"![Fig {st.te_figure}](fig{st.te_figure}_transmission_error.png)", "",
              f"![bearing pattern, errors of Fig {st.figure}](fig{st.figure}_bearing_pattern.png)",
              "", f"Data: fig{st.figure}_fig{st.te_figure}.csv"]
    L += ["", "### Fig 22: aligned TE of both cases", "", "![Fig 22](fig22_transmission_error.png)", ""]
    for c, r in zip(("case1", "case2"), aligned):
        L.append(f"- {c}: TE peak-to-peak {r.flanks['right'].te_peak_to_peak * 1e6:.2e} urad (right), "
                 f"{r.flanks['left'].te_peak_to_peak * 1e6:.2e} urad (left); backlash {r.backlash_um:.2e} um "
                 f"(paper, {c}: {PAPER_ALIGNED_TE_URAD[c]:g} urad)")
    L += ["", "## Sensitivity of the path (first order, exact, at the pitch point)", "",
          "Axial shift of the contact point on each member per unit error (implicit-function theorem "
          "with the generated Jacobians), and the shift at the paper's error levels.", "",
          "| case | error | pinion dz/de | gear dz/de | unit | pinion shift at paper level (mm) |",
          "|---|---|---|---|---|---|"]
    levels = {"case1": (0.5, 0.5, 0.5, 0.2, 0.03), "case2": (0.5, 0.5, 0.5, 0.25, 0.04)}
    names = ("dx", "dy", "dz", "dgamma_v", "dgamma_h")
    for c, s in sens.items():
        for i, nm in enumerate(names):
            unit = "mm/mm" if i < 3 else "mm/deg"
            f = 1.0 if i < 3 else DEG
            dp, dg = s["pinion_contact_D_errors"][2, i] * f, s["gear_contact_D_errors"][2, i] * f
            L.append(f"| {c} | {nm} | {dp:+.4f} | {dg:+.4f} | {unit} | {dp * levels[c][i]:+.3f} |")
    L += ["", "## Edge contact under dq = dx = dy = dz", ""]
    for c, (up, down) in onset.items():
        paper = (f"paper, {c}: edge contact begins at dq = {PAPER_EDGE_ONSET_MM[c]:g} mm" if c in PAPER_EDGE_ONSET_MM
                 else f"the paper gives no onset for {c}")
        L.append(f"- {c}: the path reaches the toe or heel at dq = +{_fmt(up, '{:.3f}')} mm and "
                 f"dq = -{_fmt(down, '{:.3f}')} mm ({paper}).")
    L += ["", f"Unloaded TCA: {positions} pinion positions x 3 tooth pairs per error set (`--positions`).", ""]
    return "\n".join(L)
