"""docs/validation.md 7.2: case 1, 200 N m, right flank, 5 positions, the middle one, on grids of
increasing cell counts (the extents follow the Hertz rule), with the LTCA's default tooth (the FE
tooth; its data computed once and cached).  Not a test.

    python benchmarks/ltca_grid_convergence.py

Prints the page's table rows (`python docs/readme_numbers.py --record ltca_tables` records them).
"""
import numpy as np

from beveloid import ltca
from beveloid.ltca.options import DEFAULT_GRID
from beveloid.pair import Pair

GRIDS = ((7, 11), (11, 17), (15, 25), (21, 35))


def _cells(values, fmt):
    return " / ".join("-" if np.isnan(v) else format(v, fmt) for v in values)


def rows() -> list[str]:
    pair = Pair.example("case1")
    out = []
    for grid in GRIDS:
        r = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(positions=5, grid=grid))
        j = 2
        label = f"{grid[0]} × {grid[1]}" + (" (default)" if tuple(grid) == tuple(DEFAULT_GRID) else "")
        out.append(f"| {label} | {_cells(r.pair_load_n[j], '.1f')} | {_cells(r.pair_surface_max_pressure_mpa[j], '.0f')} | "
                   f"{_cells(r.pair_edge_max_pressure_mpa[j], '.0f')} | {r.loaded_te[j] * 1e6:.3f} | "
                   f"{r.convergence.pressure_change[j]:.3f} / {r.convergence.load_change[j]:.4f} |")
    return out


if __name__ == "__main__":
    print("\n".join(rows()))
