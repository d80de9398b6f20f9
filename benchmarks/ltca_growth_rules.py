"""Which loaded patches grow their grid: three rules on the tolerance box, time and numbers, in one run.

The LTCA grows a pair's grid where its loaded patch runs into the grid's outermost row
(``ltca.model.grid.reaches_edge``, docs/loaded_contact.md 8.1).  Rules compared:

* ``interior``: only cells more than ``INTERIOR_REACH`` cells from the blank's edge count (the rule
  before issue 57's corner fix);
* ``corner`` (the package's): also a patch with no interior cell carrying ``CORNER_SHARE`` of its
  position's load, where a loaded flank cell and its inward neighbour lie in the outermost row, and
  any patch where such cells carry ``EDGE_LINE_SHARE`` of the position's load;
* ``full``: any loaded flank cell with a loaded inward neighbour in the outermost row, for every patch.

Case 1 tilted by vertical_deg = 0.05 (docs/optimize.md's spec), 100 / 200 / 400 N m, the 16 error sets
``beveloid ltca --samples 16`` draws (seed 0, the default tolerances), FE tooth, in this process: the CPU
seconds of each rule's analyses (least of ``--rounds``) and the largest and mean relative differences of
each set's TE peak-to-peak, mean loaded TE and root stresses, and of the pair load shares, against ``full``.

    python benchmarks/ltca_growth_rules.py [--rounds 2]
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np


def interior_rule(p, in_flank, nx, ny, load_share=None):
    from beveloid.ltca.model import grid as grids

    q = grids.interior(p, in_flank, nx, ny)
    return np.stack([q[..., [0, -1], :].any(axis=(-1, -2)), q[..., :, [0, -1]].any(axis=(-1, -2))], axis=-1)


def full_rule(p, in_flank, nx, ny, load_share=None):
    from beveloid.ltca.model import grid as grids

    shape = p.shape[:-1] + (nx, ny)
    q = (p > 0).reshape(shape) & in_flank.reshape(shape)
    inner = grids.interior(p, in_flank, nx, ny)
    across = (q[..., [0, -1], :] & q[..., [1, -2], :]) | inner[..., [0, -1], :]
    along = (q[..., :, [0, -1]] & q[..., :, [1, -2]]) | inner[..., :, [0, -1]]
    return np.stack([across.any(axis=(-1, -2)), along.any(axis=(-1, -2))], axis=-1)


def _quantities(r):
    te = (r.loaded_te - r.unloaded_te)[r.converged]
    root = r.root_stress_max_mpa()
    share = r.pair_load_n / np.nansum(r.pair_load_n, axis=1, keepdims=True)
    return np.array([te.max() - te.min(), te.mean(), root["pinion"], root["gear"]]), share


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    a = ap.parse_args(argv)

    from beveloid import ltca, sweep
    from beveloid.cli.explore import add_tolerances_flag, parse_tolerances
    from beveloid.ltca import studies
    from beveloid.ltca.model import grid as grids
    from beveloid.ltca.passes import analysis
    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes

    case1 = (Path(ltca.__file__).resolve().parents[1] / "data" / "case1.toml").read_text()
    pair = Pair.from_spec(spec_from_toml_bytes(case1.replace("vertical_deg = 0.0 ", "vertical_deg = 0.05", 1).encode()))
    flags = argparse.ArgumentParser()
    add_tolerances_flag(flags)
    tol = parse_tolerances(flags.parse_args([]).tolerances)  # ltca --samples' default box
    nominal = {k: float(getattr(pair.spec.misalignment, k)) for k in tol}
    sets = sweep.draw_errors(16, ranges=tol, seed=0, nominal=nominal)
    load = ltca.LoadCase((100.0, 200.0, 400.0), errors=sets)
    options = ltca.Options()
    rules = {"interior": interior_rule, "corner": grids.reaches_edge, "full": full_rule}
    studies.box_results(pair, load, options)  # the FE data and the compiled code, once
    seconds, out = {}, {}
    try:
        for _ in range(a.rounds):
            for name, rule in rules.items():
                analysis.grids.reaches_edge = rule
                t = time.process_time()
                rows = studies.box_results(pair, load, options)
                seconds[name] = min(seconds.get(name, np.inf), time.process_time() - t)
                out[name] = [_quantities(r) for row in rows for r in row]
    finally:
        analysis.grids.reaches_edge = rules["corner"]
    print(f"48 analyses (16 sets x 3 torques), CPU s (least of {a.rounds}): "
          + ", ".join(f"{n} {s:.2f}" for n, s in seconds.items())
          + f"; against interior: corner {seconds['corner'] / seconds['interior']:.2f}x, "
            f"full {seconds['full'] / seconds['interior']:.2f}x")
    print("| rule | against full: TE p-p max / mean | TE mean max | root pinion max | root gear max | pair load share max change |")
    print("|---|---|---|---|---|---|")
    for name in ("interior", "corner"):
        d = np.abs(np.array([x[0] / y[0] - 1.0 for x, y in zip(out[name], out["full"])]))
        dl = max(float(np.nanmax(np.abs(x[1] - y[1]))) for x, y in zip(out[name], out["full"]))
        print(f"| {name} | {d[:, 0].max():.2%} / {d[:, 0].mean():.2%} | {d[:, 1].max():.2%} | {d[:, 2].max():.2%} | "
              f"{d[:, 3].max():.2%} | {dl:.4f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
