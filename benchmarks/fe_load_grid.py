"""The FE tooth's load grid along the face against the root stress it reads (beveloid/fe/tooth.py
FACE_FRACTIONS).

    python benchmarks/fe_load_grid.py [--design case1] [--torque-nm 1500] [--fe-coarsen 2]

The LTCA lumps its contact onto the FE tooth's load-grid nodes; a fillet node just beyond the reading
depth of a loaded node reads that lumped force's local stress.  Where a face end carries load, the
root stress read there depends on the column spacing.  Per layout of the columns (equal spans, or the
equal spans with extra columns in the end spans), the same LTCA (``ltca.analyze`` at the torque,
the default grid and positions) with that FE tooth: the largest root stress of each member, where it
is, and the loaded TE's mean; each layout's FE data is computed in a temporary cache folder
(minutes per layout at --fe-coarsen 2).
"""
from __future__ import annotations

import argparse
import functools
import os
import tempfile

import numpy as np

#: (label, face fractions of the columns)
LAYOUTS = (
    ("9 equal", tuple(np.linspace(0.0, 1.0, 9))),
    ("17 equal", tuple(np.linspace(0.0, 1.0, 17))),
    ("11: 9 equal + 1/16 at each end", None),
    ("13: 9 equal + 1/32, 1/16 at each end", None),
    ("15: 9 equal + 1/48, 1/24, 1/12 at each end", None),
)


def graded(extra) -> tuple:
    """Nine equal columns and ``extra`` fractions from each end."""
    e = np.asarray(extra, dtype=float)
    return tuple(np.sort(np.concatenate([np.linspace(0.0, 1.0, 9), e, 1.0 - e])))


def layouts():
    extras = {2: (1 / 16,), 3: (1 / 32, 1 / 16), 4: (1 / 48, 1 / 24, 1 / 12)}
    out = []
    for i, (label, fractions) in enumerate(LAYOUTS):
        out.append((label, fractions if fractions is not None else graded(extras[i])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", default="case1", help="an example's name or a spec file")
    ap.add_argument("--torque-nm", type=float, default=1500.0)
    ap.add_argument("--fe-coarsen", type=float, default=2.0)
    a = ap.parse_args()
    os.environ.setdefault("BEVELOID_CACHE_DIR", tempfile.mkdtemp(prefix="fe_load_grid_"))

    from beveloid import ltca
    from beveloid.fe import tooth
    from beveloid.ltca.model import teeth
    from beveloid.pair import Pair

    pair = Pair.example(a.design) if a.design in ("case1", "case2") else Pair.from_spec(a.design)
    print(f"{a.design}, {a.torque_nm:g} N m, --fe-coarsen {a.fe_coarsen:g}; profile points {tooth.GRID[0]};"
          f" today's columns: {len(tooth.FACE_FRACTIONS)}")
    print("| columns | member | root stress max (MPa) | face z (mm) | height (mm) | position, pair | loaded TE mean (µrad) |")
    print("|---|---|---|---|---|---|---|")
    default_grid = tooth.load_grid
    for label, fractions in layouts():
        tooth.GRID = (tooth.GRID[0], len(fractions))  # the cache key holds both
        tooth.FACE_FRACTIONS = fractions
        tooth.load_grid = functools.partial(default_grid, grid=tooth.GRID)
        tooth.flank_grid.__defaults__ = (tooth.GRID, fractions)
        teeth._FE_TEETH.clear()
        r = ltca.analyze(pair, ltca.LoadCase(a.torque_nm), ltca.Options(fe_coarsen=a.fe_coarsen, tooth_model="fe"))
        top, where = r.root_stress_max_mpa(), r.root_stress_location()
        te = float(np.nanmean(r.loaded_te)) * 1e6
        for m in top:
            w = where[m]
            print(f"| {label} | {m} | {top[m]:.1f} | {w['z_mm']:.2f} | {w['height_mm']:.2f} | {w['position']}, {w['pair']} |"
                  f" {te:.2f} |", flush=True)


if __name__ == "__main__":
    main()
