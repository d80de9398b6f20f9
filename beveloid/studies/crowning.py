"""The crowning study of ``beveloid paper`` (issue 10): TE of crowned case 1 and case 2 pairs.

Both members of each case get the double-crowned flanks of the "crowned" tooth-surface model
(derivations/crowned_flank.py) with C_alpha = C_beta = C.  For each amount in AMOUNTS_UM the
right-flank TE is computed aligned and under every error set of the paper's Figs 13-15
(case 1) and 19-21 (case 2), as in the unmodified study.  The crowning that makes the aligned
TE peak-to-peak equal to the paper's 7.5 urad (case 1) and 14.3 urad (case 2) is found by
scipy.optimize.toms748, for equal profile and lead crowning and for each alone.  These are findings:
the paper does not say its flanks were crowned.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

AMOUNTS_UM = (10.0, 25.0)  # C_alpha = C_beta on both members
PAPER_ALIGNED_TE_URAD = {"case1": 7.5, "case2": 14.3}
# which keys the amount goes to: equal profile and lead crowning, or one of them alone
KINDS = {"equal": ("profile_crowning_um", "lead_crowning_um"), "profile only": ("profile_crowning_um",),
         "lead only": ("lead_crowning_um",)}
CASES = ("case1", "case2")


def crowned_geometry(case: str, amount_um: float, keys=KINDS["equal"]):
    """PairGeometry of a paper case with both members crowned by ``amount_um`` on ``keys``."""
    from ..pair import Pair
    from ..spec import load_example, spec_to_dict

    data = spec_to_dict(load_example(case))
    for member in ("pinion", "gear"):
        data[member]["tooth_surface"] = "crowned"
        for key in keys:
            data[member][key] = float(amount_um)
    return Pair.from_spec(data).geometry


def aligned_te_urad(case, amount_um, keys=KINDS["equal"], flank="right", positions=200):
    from .. import tca

    fr = tca.mesh_flank(crowned_geometry(case, amount_um, keys), flank, positions=positions)
    return fr.te_peak_to_peak * 1e6


#: the crowning searched for the paper's aligned TE lies in (0, MAX_AMOUNT_UM] um
MAX_AMOUNT_UM = 200.0


def amount_for_te(case, target_urad, keys=KINDS["equal"], flank="right", positions=200, rtol=1e-5):
    """Crowning (um) whose aligned TE peak-to-peak is ``target_urad``, and the TE it gives.

    scipy.optimize.toms748 on (0, MAX_AMOUNT_UM] (the TE grows with the crowning from the
    uncrowned pair's ~0), to ``rtol`` of the amount; (None, None) when the TE at MAX_AMOUNT_UM is
    still below the target, the TE is not finite, or the TE jumps across the target instead of
    reaching it within 1e-4 (with few positions a single position can spoil the peak-to-peak).
    """
    from scipy.optimize import toms748

    te = {}  # amount -> TE p-p (urad); every amount is evaluated once

    def excess(amount):
        if amount not in te:
            te[amount] = aligned_te_urad(case, amount, keys, flank, positions)
        return te[amount] - target_urad

    lo, hi = 0.0, MAX_AMOUNT_UM
    f_lo, f_hi = excess(lo), excess(hi)
    if not (np.isfinite(f_lo) and np.isfinite(f_hi)) or f_lo >= 0.0 or f_hi < 0.0:
        return None, None
    try:
        amount = float(toms748(excess, lo, hi, xtol=1e-9, rtol=rtol))
    except (ValueError, RuntimeError):  # a non-finite TE inside the interval
        return None, None
    if not abs(excess(amount)) <= 1e-4 * target_urad:  # a jump of the TE across the target, not a root
        return None, None
    return amount, te[amount]


def _te_shape(fr):
    """(p-p urad, mean urad, end-to-end tilt urad) of the TE envelope over the window."""
    pairs = len(set(fr.tooth_pair.tolist()))
    te = np.where(fr.active, fr.transmission_error, np.nan).reshape(pairs, -1)
    carried = np.isfinite(te).any(axis=0)
    if not carried.any():
        return math.nan, math.nan, math.nan
    env = np.array([c[np.isfinite(c)][0] for c in te.T[carried]]) * 1e6  # active pairs share the envelope value
    return fr.te_peak_to_peak * 1e6, float(env.mean()), float(env[-1] - env[0])


def case_rows(out_dir, case, studies, error_vector, write_csv, positions=200, flank="right", progress=print):
    """One case of :func:`run` (``beveloid paper`` runs the cases on worker processes): its figures and
    CSV into out_dir; returns (its rows of crowning_study.csv, {(case, kind): (amount, TE)})."""
    from .. import plots, tca

    out = Path(out_dir)
    rows = []  # (case, amount, figure, label, ptp, mean, tilt, backlash, newton its, other flank's ptp)
    for amount in AMOUNTS_UM:
        geom = crowned_geometry(case, amount)
        progress(f"    crowning study: {case}, C_alpha = C_beta = {amount:g} um")
        done = {}
        for st in (st for st in studies if st.case == case):
            fig, title, errors = st.te_figure, st.title, st.errors
            results = []
            for label, e in errors:
                if label not in done:
                    done[label] = tca.analyze(geom, tca.Options(positions=positions, approach_mm=None,
                                                             errors=error_vector(e)))
                    r = done[label]
                    fr = r.flanks[flank]
                    other = r.flanks["left" if flank == "right" else "right"]
                    rows.append((case, amount, fig, label, *_te_shape(fr), r.backlash_um,
                                 fr.newton_iterations_mean, other.te_peak_to_peak * 1e6))
                results.append(done[label])
            plots.transmission_error(
                results, [lab for lab, _ in errors], flank,
                out / f"crowned_{amount:g}um_fig{fig}_transmission_error.png",
                f"Fig {fig} with crowned flanks (C_alpha = C_beta = {amount:g} um) - {title} ({flank} flank)")
            write_csv(out / f"crowned_{amount:g}um_fig{fig}.csv", st, results)
    progress(f"    crowning study: {case}, the crowning that gives the paper's aligned TE")
    targets = {(case, kind): amount_for_te(case, PAPER_ALIGNED_TE_URAD[case], keys, flank, positions)
               for kind, keys in KINDS.items()}
    return rows, targets


def finish(out_dir, parts, flank="right", positions=200):
    """crowning_study.csv and the report's lines from :func:`case_rows`'s results (the cases in order)."""
    rows = [r for case_rows_, _ in parts for r in case_rows_]
    targets = {k: v for _, case_targets in parts for k, v in case_targets.items()}
    with open(Path(out_dir) / "crowning_study.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "crowning_um", "te_figure", "errors", "te_peak_to_peak_urad", "te_mean_urad",
                    "te_tilt_urad", "backlash_um", "newton_iterations_mean", "other_flank_te_peak_to_peak_urad"])
        w.writerows([r[:4] + tuple(_csv(v) for v in r[4:]) for r in rows])
    return _report(rows, targets, flank, positions)


def _csv(v):
    return "" if v is None or not np.isfinite(v) else repr(float(v))


def _f(v, fmt):
    return "-" if v is None or not np.isfinite(v) else fmt.format(v)


def _report(rows, targets, flank, positions):
    L = ["## Crowning study (issue 10)", "",
         "Both members crowned with the 'crowned' model (C_alpha = C_beta = C, see docs/validation.md); "
         f"{flank} flank, {positions} positions x 3 tooth pairs. TE p-p and mean of the contact envelope; tilt: "
         "envelope TE at the window's last contact minus its first (the asymmetry an error brings). Backlash: "
         "the smallest play over a mesh cycle.", "",
         "| case | C (um) | TE figure | errors | TE p-p (urad) | TE mean (urad) | tilt (urad) | backlash (um) | "
         "Newton its | TE p-p other flank (urad) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for case, amount, fig, label, ptp, mean, tilt, bl, its, other in rows:
        L.append(f"| {case} | {amount:g} | {fig} | {label} | {_f(ptp, '{:.2f}')} | {_f(mean, '{:+.2f}')} | "
                 f"{_f(tilt, '{:+.2f}')} | {_f(bl, '{:.2f}')} | {_f(its, '{:.2f}')} | {_f(other, '{:.2f}')} |")
    for amount in AMOUNTS_UM:
        figs = sorted({r[2] for r in rows}, key=int)
        L += ["", f"### C = {amount:g} um", ""]
        for fig in figs:
            L += [f"![Fig {fig}, crowned](crowned_{amount:g}um_fig{fig}_transmission_error.png)", "",
                  f"Data: crowned_{amount:g}um_fig{fig}.csv", ""]
    L += ["", "### Crowning that gives the paper's aligned TE", "",
          "| case | paper (urad) | crowning | amount (um) | TE p-p then (urad) |", "|---|---|---|---|---|"]
    for (case, kind), (amount, te) in targets.items():
        L.append(f"| {case} | {PAPER_ALIGNED_TE_URAD[case]} | {kind} | {_f(amount, '{:.3f}')} | {_f(te, '{:.3f}')} |")
    L += ["", "The table above as CSV: crowning_study.csv", ""]
    return L
