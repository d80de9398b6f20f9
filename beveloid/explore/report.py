"""What an exploration writes: the CSV of every design, a JSON summary and the figures.

Files in DIR: ``explore.csv`` (one row per design, units in the column names, empty cells where a
design or flank carries no number), ``pareto.csv`` (the Pareto designs), ``summary.json``, and
``heatmap_fpd.png`` / ``heatmap_sensitivity.png`` (over the first two varied keys),
``pareto.png`` (the objectives, the front and the base design), ``pareto_table.png``.
Floats are written with repr (17 significant digits): the same rows give the same files.
"""
from __future__ import annotations

import csv
import json
import math
import os
import textwrap

import numpy as np

from . import pareto

FIGURES = ("heatmap_fpd.png", "heatmap_sensitivity.png", "pareto.png", "pareto_table.png")
#: columns of the Pareto table (figure and JSON), besides the varied keys
TABLE = ("max_fpd_angle_deg", "worst_path_shift_mm", "mc_edge_fraction", "working_normal_pressure_angle_deg",
         "gear_helix_angle_deg", "gear_profile_shift")


def _cell(v):
    if isinstance(v, (str, np.str_)):
        return str(v)
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    v = float(v)
    return repr(v) if math.isfinite(v) else ""


def _json_value(v):
    if isinstance(v, (str, np.str_)):
        return str(v)
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    v = float(v)
    return v if math.isfinite(v) else None


def records(table: dict, idx=None) -> list[dict]:
    """Rows as JSON-ready dicts (None where a design carries no number)."""
    n = len(table["design"]) if table else 0
    idx = range(n) if idx is None else idx
    return [{k: _json_value(v[i]) for k, v in table.items()} for i in idx]


def mark_pareto(table: dict, mc: bool) -> None:
    """Add the ``pareto`` column (True on the front)."""
    ok = table["status"] == "ok"
    P = np.stack([np.where(ok, table[k], np.nan) for k in pareto.objectives(mc)], axis=1)
    table["pareto"] = pareto.front(P)


def write_csv(path: str, table: dict, idx=None) -> None:
    keys = list(table)
    n = len(table["design"])
    idx = range(n) if idx is None else idx
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for i in idx:
            w.writerow([_cell(table[k][i]) for k in keys])


def summary(req, table: dict, base_row: dict, complete: bool, why: str, seconds: float, where: str) -> dict:
    statuses, counts = np.unique(table["status"], return_counts=True) if table else ((), ())
    front = np.nonzero(table["pareto"])[0] if table else []
    return {
        "file": req.source,
        "varied": [{"key": v.key, "start": v.start, "stop": v.stop, "count": v.count} for v in req.plan.varies],
        "sampling": ({"method": "latin hypercube (scipy.stats.qmc.LatinHypercube)", "samples": req.plan.samples,
                      "seed": req.plan.seed} if req.plan.samples else {"method": "grid"}),
        "tolerances": req.tolerances,
        "monte_carlo": ({"sets": req.mc, "positions": req.mc_positions, "flank": req.mc_flank, "seed": req.plan.seed}
                        if req.mc else None),
        "designs": req.plan.count,
        "designs_done": int(len(table["design"])) if table else 0,
        "complete": complete,
        "stopped": why or None,
        "status_counts": {str(s): int(c) for s, c in zip(statuses, counts)},
        "objectives": list(pareto.objectives(bool(req.mc))),
        "pareto_designs": records(table, front),
        "base_design": base_row,
        "seconds": seconds,
        "executor": where,
    }


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _grid2(req, table, column):
    """(values of key 1, of key 2, Z (n1, n2)) over the first two varied keys: the other keys at their
    middle value; None when the run is a sample or varies fewer than two keys."""
    v = req.plan.varies
    if req.plan.samples or len(v) < 2:
        return None
    shape = tuple(x.count for x in v)
    mid = [c // 2 for c in shape]
    Z = np.full(shape[:2], np.nan)
    pos = np.unravel_index(table["design"], shape)
    sel = np.ones(len(table["design"]), dtype=bool)
    for k in range(2, len(v)):
        sel &= pos[k] == mid[k]
    vals = np.where(table["status"] == "ok", table[column], np.nan).astype(float)
    Z[pos[0][sel], pos[1][sel]] = vals[sel]
    return v[0].values(), v[1].values(), Z


def heatmap(path, req, table, column, label, base_row, log=False):
    plt = _plt()
    from matplotlib.colors import LogNorm

    shown = np.asarray(table[column], dtype=float)[table["status"] == "ok"]
    shown = shown[np.isfinite(shown)]
    norm = LogNorm() if log and (shown > 0).any() else None  # no ok design: an empty map, no colour scale
    g = _grid2(req, table, column)
    fig, ax = plt.subplots(figsize=(6.0, 4.4))
    if g is None:  # a sample: scatter over the first two keys (or one key against the value)
        k1 = req.plan.keys[0]
        ok = table["status"] == "ok"
        y = table[req.plan.keys[1]] if len(req.plan.keys) > 1 else table[column]
        sc = ax.scatter(table[k1][ok], y[ok], c=table[column][ok], s=12, cmap="viridis", norm=norm)
        ax.scatter(table[k1][~ok], y[~ok], c="0.8", s=8, marker="x", label="no design")
        ax.set_ylabel(req.plan.keys[1] if len(req.plan.keys) > 1 else label)
    else:
        x1, x2, Z = g
        masked = np.ma.masked_invalid(Z.T)
        ax.set_facecolor("0.85")
        sc = ax.pcolormesh(x1, x2, masked, shading="nearest", cmap="viridis", norm=norm)
        ax.set_ylabel(req.plan.keys[1])
    ax.set_xlabel(req.plan.keys[0])
    k = req.plan.keys
    if base_row and len(k) > 1:
        bx, by = base_row.get(k[0]), base_row.get(k[1])
        if bx is not None and by is not None:
            ax.plot([bx], [by], marker="*", color="red", ms=12, ls="", label="base design")
            ax.legend(loc="best", fontsize=8)
    if shown.size:
        fig.colorbar(sc, ax=ax, label=label)
    ax.set_title(f"{label}\n(grey: no ok design, or no surface contact at P)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def pareto_scatter(path, req, table, base_row):
    plt = _plt()
    ok = table["status"] == "ok"
    x, y = table["max_fpd_angle_deg"], table["worst_path_shift_mm"]
    fig, ax = plt.subplots(figsize=(6.0, 4.4))
    if req.mc:
        sc = ax.scatter(x[ok], y[ok], c=table["mc_edge_fraction"][ok], s=10, cmap="magma_r", label="designs")
        fig.colorbar(sc, ax=ax, label="fraction of MC error sets with edge contact")
    else:
        ax.scatter(x[ok], y[ok], c="0.6", s=10, label="designs")
    front = np.nonzero(table["pareto"])[0]
    front = front[np.argsort(x[front])]
    # with a third objective (the MC edge fraction) the front is not a curve in this plane: points only
    ax.plot(x[front], y[front], "o" if req.mc else "o-", color="tab:blue", ms=5, lw=1, mfc="none" if req.mc else None,
            mew=1.5, label=f"Pareto front ({front.size})")
    if base_row and base_row.get("status") == "ok":
        ax.plot([base_row["max_fpd_angle_deg"]], [base_row["worst_path_shift_mm"]], "*", color="red", ms=14,
                label="base design")
    ax.set_xlabel("largest FPD angle max(|xi_L|, |xi_R|) (deg)")
    ax.set_ylabel("worst first-order path shift in the tolerance box (mm)")
    ax.set_yscale("log")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def pareto_table(path, req, table, limit=20):
    plt = _plt()
    front = np.nonzero(table["pareto"])[0]
    front = front[np.argsort(table["max_fpd_angle_deg"][front])][:limit]
    cols = list(req.plan.keys) + [c for c in TABLE if c in table and (req.mc or not c.startswith("mc_"))]
    cells = [[f"{float(table[c][i]):.4g}" for c in cols] for i in front]
    labels = ["\n".join(textwrap.wrap(c.replace(".", " ").replace("_", " ").replace(" deg", " (deg)")
                                       .replace(" mm", " (mm)"), 13)) for c in cols]
    fig = plt.figure(figsize=(1.0 + 1.05 * len(cols), 0.9 + 0.2 * max(1, len(cells))))
    ax = fig.add_axes([0.01, 0.01, 0.98, 0.86])
    ax.axis("off")
    if cells:
        t = ax.table(cellText=cells, colLabels=labels, bbox=[0, 0, 1, 1])
        t.auto_set_font_size(False)
        t.set_fontsize(7)
        for (r, _), cell in t.get_celld().items():
            cell.set_height(3.0 if r == 0 else 1.0)
    ax.set_title(f"Pareto designs ({np.count_nonzero(table['pareto'])}; the first {len(cells)} by FPD angle)",
                 fontsize=9, pad=4)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write(out_dir: str, req, table: dict, summ: dict) -> list[str]:
    """Every output file of a finished (or stopped) run; returns their paths."""
    paths = [os.path.join(out_dir, "explore.csv"), os.path.join(out_dir, "pareto.csv"),
             os.path.join(out_dir, "summary.json")]
    write_csv(paths[0], table)
    write_csv(paths[1], table, np.nonzero(table["pareto"])[0])
    with open(paths[2], "w") as f:
        json.dump(summ, f, indent=1, allow_nan=False)
    base = summ.get("base_design") or {}
    figs = [os.path.join(out_dir, name) for name in FIGURES]
    heatmap(figs[0], req, table, "max_fpd_angle_deg", "largest FPD angle (deg)", base)
    heatmap(figs[1], req, table, "worst_path_shift_mm", "worst path shift in the tolerance box (mm)", base,
            log=True)
    pareto_scatter(figs[2], req, table, base)
    pareto_table(figs[3], req, table)
    return paths + figs
