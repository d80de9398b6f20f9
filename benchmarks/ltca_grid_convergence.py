"""docs/validation.md 7.2: case 1, 200 N m, right flank, 5 positions, the middle one, on grids of
increasing cell counts (the extents follow the Hertz rule), with the LTCA's default tooth (the FE
tooth; its data computed once and cached).  Not a test.

    python benchmarks/ltca_grid_convergence.py
"""
import numpy as np

from beveloid import ltca
from beveloid.pair import Pair

pair = Pair.example("case1")
for grid in ((7, 11), (11, 17), (15, 25), (21, 35)):
    r = ltca.analyze(pair, ltca.Options(torque_nm=200.0, positions=5, grid=grid))
    j = 2
    print(f"{grid[0]} x {grid[1]} | {' / '.join(f'{v:.1f}' for v in r.pair_load_n[j])} | "
          f"{' / '.join('-' if np.isnan(v) else f'{v:.0f}' for v in r.pair_surface_max_pressure_mpa[j])} | "
          f"{' / '.join('-' if np.isnan(v) else f'{v:.0f}' for v in r.pair_edge_max_pressure_mpa[j])} | "
          f"{r.loaded_te[j] * 1e6:.3f} | {r.convergence.pressure_change[j]:.3f} / {r.convergence.load_change[j]:.4f}")
