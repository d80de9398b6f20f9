"""What an exploration writes: the CSV of every design, a JSON summary and the figures.

Files in DIR: ``explore.csv`` (one row per design, units in the column names, empty cells where a
design or flank carries no number), ``pareto.csv`` (the Pareto designs), ``summary.json``, and
``heatmap_fpd.png`` / ``heatmap_sensitivity.png`` (over the first two varied keys),
``pareto.png`` (the objectives, the front and the base design), ``pareto_table.png`` (the first
:data:`PARETO_ROWS` Pareto designs by FPD angle).  Each file is written under a temporary name and
renamed, so a stopped run leaves whole files or none.  The figures are drawn as tasks of the run's
executor (:func:`draw_figure`: the PNG's bytes, from the columns each figure shows), so that on
several workers they are drawn at once, while this process writes the data files.

The CSV text is made column by column (:func:`cell_texts`): text as it is (quoted as ``csv.writer``
quotes), ``true``/``false``, integers, floats by ``repr`` (17 significant digits: the same rows give
the same files), an empty cell for a non-finite float.  A chunk's rows are turned into text where the
chunk is computed (:func:`csv_rows`, on the workers); the files are then those texts joined, with the
``pareto`` cell, known only when every chunk is in, added to each row (:func:`csv_bytes`).
"""
from __future__ import annotations

import io
import itertools
import json
import os
import textwrap
from typing import NamedTuple

import numpy as np

from ..status import DesignStatus
from . import pareto

FIGURES = ("heatmap_fpd.png", "heatmap_sensitivity.png", "pareto.png", "pareto_table.png")
DATA_FILES = ("explore.csv", "pareto.csv", "summary.json")
#: columns of the Pareto table (figure and JSON), besides the varied keys
TABLE = ("max_fpd_angle_deg", "worst_path_shift_mm", "mc_edge_fraction", "working_normal_pressure_angle_deg",
         "gear_helix_angle_deg", "gear_profile_shift")
#: rows of the Pareto table figure (the rest: "... N more in pareto.csv")
PARETO_ROWS = 20
#: characters after which csv.writer quotes a cell (its default dialect, QUOTE_MINIMAL)
_QUOTE_IF = (",", '"', "\r", "\n")
ROW_END = b"\r\n"


def _quoted(text: str) -> str:
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in _QUOTE_IF) else text


def cell_texts(column) -> list[str]:
    """The CSV cells of one column (see the module's docstring), one per row."""
    v = np.asarray(column)
    kind = v.dtype.kind
    if kind == "b":
        return np.where(v, "true", "false").tolist()
    if kind in "iu":
        return list(map(str, v.tolist()))
    if kind == "f":
        cells = np.array(list(map(repr, v.tolist())), dtype=object)
        cells[~np.isfinite(v)] = ""
        return cells.tolist()
    words, where = np.unique(v.astype(str), return_inverse=True)  # text: few distinct values, quoted once each
    return np.array(list(map(_quoted, words.tolist())), dtype=object)[where.ravel()].tolist()


class CsvRows(NamedTuple):
    """Rows of CSV text: ``text`` the UTF-8 bytes (uint8) of the rows one after the other, each ending
    in ``ROW_END``; ``ends`` the end of each row in ``text`` (int64)."""

    text: np.ndarray
    ends: np.ndarray


def csv_rows(cols: dict) -> CsvRows:
    """The CSV text of rows (every column of ``cols``, in its order)."""
    cells = [cell_texts(v) for v in cols.values()]
    lines = list(map(str.encode, map(",".join, zip(*cells))))
    ends = np.cumsum(np.fromiter(map(len, lines), dtype=np.int64, count=len(lines)) + len(ROW_END))
    text = ROW_END.join(lines) + ROW_END if lines else b""
    return CsvRows(np.frombuffer(text, dtype=np.uint8), ends)


def csv_pieces(keys, parts, on_front: np.ndarray, keep: np.ndarray | None = None):
    """A CSV file as pieces of bytes: the header (``keys`` and ``pareto``), then the text of each row
    (``parts``: CsvRows of the rows in order, in parts; of the rows ``keep``, a boolean mask, if given)
    with its ``pareto`` cell (``on_front``) at its end."""
    yield (",".join(map(_quoted, [*keys, "pareto"])) + ROW_END.decode()).encode()
    on_front = np.asarray(on_front, dtype=bool)
    keep = np.ones(on_front.size, dtype=bool) if keep is None else np.asarray(keep, dtype=bool)
    first = 0
    for part in parts:
        n = part.ends.size
        idx = np.nonzero(keep[first:first + n])[0]
        starts = np.concatenate([[0], part.ends[:-1]])[idx]
        view = memoryview(np.ascontiguousarray(part.text))
        bodies = map(view.__getitem__, map(slice, starts.tolist(), (part.ends[idx] - len(ROW_END)).tolist()))
        cells = np.where(on_front[first:first + n][idx], b",true" + ROW_END, b",false" + ROW_END).tolist()
        yield from itertools.chain.from_iterable(zip(bodies, cells))
        first += n


def csv_bytes(keys, parts, on_front: np.ndarray, keep: np.ndarray | None = None) -> bytes:
    """The CSV file of :func:`csv_pieces` in one piece."""
    return b"".join(csv_pieces(keys, parts, on_front, keep))


def json_values(column) -> list:
    """A column's values for JSON: str, bool, int, float, and None for a non-finite float."""
    v = np.asarray(column)
    if v.dtype.kind in "biu":
        return v.tolist()
    if v.dtype.kind == "f":
        out = np.array(v.tolist(), dtype=object)
        out[~np.isfinite(v)] = None
        return out.tolist()
    return v.astype(str).tolist()


def records(table: dict, idx=None) -> list[dict]:
    """Rows as JSON-ready dicts (None where a design carries no number)."""
    if not table:
        return []
    keys = list(table)
    cols = [json_values(v if idx is None else np.asarray(v)[idx]) for v in table.values()]
    return list(map(dict, map(zip, itertools.repeat(keys), zip(*cols))))


def mark_pareto(table: dict, mc: bool) -> None:
    """Add the ``pareto`` column (True on the front)."""
    ok = table["status"] == DesignStatus.OK
    P = np.stack([np.where(ok, table[k], np.nan) for k in pareto.objectives(mc)], axis=1)
    table["pareto"] = pareto.front(P)


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


#: the plots' margins (fractions of the figure; fixed: a layout engine would lay out every text once more)
_MARGINS = {"left": 0.13, "right": 0.97, "bottom": 0.11}


def _figure(width_in: float, height_in: float):
    """A matplotlib Figure of its own (not pyplot's: nothing to close, no backend to choose; saved by Agg)."""
    from matplotlib.figure import Figure

    return Figure(figsize=(width_in, height_in))


def _save(fig, path) -> None:
    """The figure as a PNG at ``path``, written under a temporary name and renamed (whole or absent); into
    ``path`` when it is a binary file object (:func:`draw_figure`)."""
    if not isinstance(path, (str, os.PathLike)):
        fig.savefig(path, format="png", dpi=90, pil_kwargs={"compress_level": 1})
        return
    tmp = os.fspath(path) + ".tmp.png"
    try:
        fig.savefig(tmp, dpi=90, pil_kwargs={"compress_level": 1})  # (small files either way)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


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
    vals = np.where(table["status"] == DesignStatus.OK, table[column], np.nan).astype(float)
    Z[pos[0][sel], pos[1][sel]] = vals[sel]
    return v[0].values(), v[1].values(), Z


def _extent(values: np.ndarray) -> tuple[float, float]:
    """The edges of a row of equally spaced cells centred on ``values`` (one value: a unit-wide cell)."""
    half = (values[-1] - values[0]) / (2 * (values.size - 1)) if values.size > 1 else 0.5
    return float(values[0] - half), float(values[-1] + half)


def heatmap(path, req, table, column, label, base_row, log=False):
    from matplotlib.colors import LogNorm

    shown = np.asarray(table[column], dtype=float)[table["status"] == DesignStatus.OK]
    shown = shown[np.isfinite(shown)]
    norm = LogNorm() if log and (shown > 0).any() else None  # no ok design: an empty map, no colour scale
    g = _grid2(req, table, column)
    fig = _figure(6.0, 4.4)
    ax = fig.add_subplot()
    if g is None:  # a sample: scatter over the first two keys (or one key against the value)
        k1 = req.plan.keys[0]
        ok = table["status"] == DesignStatus.OK
        y = table[req.plan.keys[1]] if len(req.plan.keys) > 1 else table[column]
        sc = ax.scatter(table[k1][ok], y[ok], c=table[column][ok], s=12, cmap="viridis", norm=norm)
        ax.scatter(table[k1][~ok], y[~ok], c="0.6", s=8, marker="x")
        ax.set_ylabel(req.plan.keys[1] if len(req.plan.keys) > 1 else label)
        grey = "grey x: no ok design"
    else:  # a grid of equally spaced values: one image, a cell per design
        x1, x2, Z = g
        ax.set_facecolor("0.85")
        sc = ax.imshow(np.ma.masked_invalid(Z.T), origin="lower", extent=(*_extent(x1), *_extent(x2)),
                       aspect="auto", interpolation="nearest", cmap="viridis", norm=norm)
        ax.set_ylabel(req.plan.keys[1])
        grey = "grey: no ok design, or no surface contact at P"
    ax.set_xlabel(req.plan.keys[0])
    k = req.plan.keys
    star = ""
    if base_row and len(k) > 1:
        bx, by = base_row.get(k[0]), base_row.get(k[1])
        if bx is not None and by is not None:
            ax.plot([bx], [by], marker="*", color="red", ms=12, ls="")
            star = "; red star: the base design"
    if shown.size:
        fig.colorbar(sc, ax=ax, label=label)
    ax.set_title(f"{label}\n({grey}{star})", fontsize=9)
    fig.subplots_adjust(**_MARGINS, top=0.87)
    _save(fig, path)


def pareto_scatter(path, req, table, base_row):
    ok = table["status"] == DesignStatus.OK
    x, y = table["max_fpd_angle_deg"], table["worst_path_shift_mm"]
    fig = _figure(6.0, 4.4)
    ax = fig.add_subplot()
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
    if base_row and base_row.get("status") == DesignStatus.OK:
        ax.plot([base_row["max_fpd_angle_deg"]], [base_row["worst_path_shift_mm"]], "*", color="red", ms=14,
                label="base design")
    ax.set_xlabel("largest FPD angle max(|xi_L|, |xi_R|) (deg)")
    ax.set_ylabel("worst first-order path shift in the tolerance box (mm)")
    ax.set_yscale("log")
    ax.legend(loc="upper right", fontsize=8)  # (not "best": it scans every point of the scatter)
    fig.subplots_adjust(**_MARGINS, top=0.97)
    _keep_ylabel(fig, ax)
    _save(fig, path)


def _keep_ylabel(fig, ax, pad_px: float = 4.0) -> None:
    """Within less than a decade a log axis labels its minor ticks (2.05x10^-1, ...): plain numbers there,
    and the left margin widened until the y-axis label lies inside the figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.ticker import FuncFormatter

    lo, hi = ax.get_ylim()
    if lo > 0 and hi / lo < 10.0:
        plain = FuncFormatter(lambda v, _: f"{v:.3g}")
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(plain)
    FigureCanvasAgg(fig).draw()
    x0 = ax.yaxis.label.get_window_extent(fig.canvas.get_renderer()).x0
    if x0 < pad_px:
        left = fig.subplotpars.left + (pad_px - x0) / fig.bbox.width
        fig.subplots_adjust(left=min(left, 0.4))


def _label(column: str) -> list[str]:
    words = column.replace(".", " ").replace("_", " ").replace(" deg", " (deg)").replace(" mm", " (mm)")
    return textwrap.wrap(words, 12)


def pareto_table(path, req, table, limit=PARETO_ROWS):
    """The first ``limit`` Pareto designs by FPD angle as a table of text (one monospaced block: the
    rest are in pareto.csv, and a line says how many)."""
    front = np.nonzero(table["pareto"])[0]
    front = front[np.argsort(table["max_fpd_angle_deg"][front], kind="stable")]
    shown, more = front[:limit], max(0, front.size - limit)
    cols = list(req.plan.keys) + [c for c in TABLE if c in table and (req.mc or not c.startswith("mc_"))]
    labels = [_label(c) for c in cols]
    cells = [[f"{float(x):.4g}" for x in np.asarray(table[c], dtype=float)[shown]] for c in cols]
    widths = [max([len(w) for w in lab] + [len(s) for s in col]) for lab, col in zip(labels, cells)]
    depth = max(len(lab) for lab in labels)
    lines = ["  ".join(f"{(lab[::-1] + [''] * depth)[depth - 1 - r]:>{w}}" for lab, w in zip(labels, widths))
             for r in range(depth)]  # each label bottom-aligned over its column
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(f"{col[r]:>{w}}" for col, w in zip(cells, widths)) for r in range(shown.size)]
    if more:
        lines.append(f"... {more} more in pareto.csv")
    if not shown.size:
        lines.append("(no design on the front)")
    chars = max(len(s) for s in lines)
    fig = _figure(0.4 + 0.0685 * chars, 0.55 + 0.148 * len(lines))
    fig.text(0.5 * 0.4 / fig.get_figwidth(), 1 - 0.45 / fig.get_figheight(), "\n".join(lines), family="monospace",
             fontsize=8, va="top", ha="left", linespacing=1.3)
    fig.suptitle(f"Pareto designs ({front.size}; the first {shown.size} by FPD angle)", fontsize=9,
                 y=1 - 0.08 / fig.get_figheight(), va="top")
    _save(fig, path)


def _write_atomic(path: str, pieces) -> None:
    """Write the bytes ``pieces`` to ``path`` under a temporary name, then rename (whole or absent)."""
    tmp = path + ".tmp"
    try:
        with open(tmp, "wb") as f:
            f.writelines(pieces)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def write_data(out_dir: str, table: dict, parts: list, summ: dict) -> list[str]:
    """explore.csv, pareto.csv and summary.json of a finished (or stopped) run (``parts``: the CSV text of
    the table's rows, CsvRows in order); their paths."""
    paths = [os.path.join(out_dir, name) for name in DATA_FILES]
    keys = [k for k in table if k != "pareto"]
    _write_atomic(paths[0], csv_pieces(keys, parts, table["pareto"]))
    _write_atomic(paths[1], csv_pieces(keys, parts, table["pareto"], keep=table["pareto"]))
    _write_atomic(paths[2], [json.dumps(summ, indent=1, allow_nan=False).encode()])
    return paths


class FigureTask(NamedTuple):
    """What a worker gets to draw one figure: its name (of :data:`FIGURES`), the request's ``plan`` (a
    :class:`beveloid.explore.grid.Plan`) and ``mc`` (all a figure reads of the request), the table's
    columns the figure shows and the base design's row."""

    name: str
    plan: object
    mc: int
    table: dict
    base_row: dict


def _heatmap_fpd(path, req, table, base_row):
    heatmap(path, req, table, "max_fpd_angle_deg", "largest FPD angle (deg)", base_row)


def _heatmap_sensitivity(path, req, table, base_row):
    heatmap(path, req, table, "worst_path_shift_mm", "worst path shift in the tolerance box (mm)", base_row, log=True)


def _pareto_table(path, req, table, base_row):
    pareto_table(path, req, table)


#: each figure's drawing (path, req, table, base_row) and the columns it reads besides the varied keys
_DRAW = {"heatmap_fpd.png": (_heatmap_fpd, ("design", "status", "max_fpd_angle_deg")),
         "heatmap_sensitivity.png": (_heatmap_sensitivity, ("design", "status", "worst_path_shift_mm")),
         "pareto.png": (pareto_scatter, ("status", "max_fpd_angle_deg", "worst_path_shift_mm", "pareto",
                                         "mc_edge_fraction")),
         "pareto_table.png": (_pareto_table, ("pareto",) + TABLE)}


def figure_tasks(req, table: dict, base_row: dict) -> list[FigureTask]:
    """The :class:`FigureTask` of each of :data:`FIGURES`, in order."""
    out = []
    for name in FIGURES:
        names = (*req.plan.keys, *_DRAW[name][1])
        out.append(FigureTask(name, req.plan, req.mc, {k: table[k] for k in dict.fromkeys(names) if k in table},
                              base_row or {}))
    return out


def draw_figure(task: FigureTask) -> bytes:
    """The PNG of one figure (what a worker runs); the task stands for the request (its plan and mc)."""
    buf = io.BytesIO()
    _DRAW[task.name][0](buf, task, task.table, task.base_row)
    return buf.getvalue()


def drawn_figures(req, table: dict, base_row: dict, ex=None):
    """(name, PNG bytes) of each figure as it is drawn: on the executor ``ex`` (every figure handed to its
    workers at once; this process can write the data files meanwhile), else here, one after the other as
    they are asked for."""
    tasks = figure_tasks(req, table, base_row)
    if ex is None:
        return ((t.name, draw_figure(t)) for t in tasks)
    return ((tasks[k].name, png) for k, png in ex.map_unordered(draw_figure, tasks))


def write_figures(out_dir: str, drawn, go_on=lambda: True) -> list[str]:
    """The figures of ``drawn`` (:func:`drawn_figures`) written into ``out_dir`` while ``go_on()``, each whole
    or absent; the paths of those written, in the order of :data:`FIGURES`."""
    done = []
    for name, png in (() if not go_on() else drawn):
        _write_atomic(os.path.join(out_dir, name), [png])
        done.append(name)
        if not go_on():
            break
    return [os.path.join(out_dir, name) for name in FIGURES if name in done]
