"""Where the verdict reads S_H: the largest surface pressure beyond a band from the flank edges, against the grid.

For design E of ``benchmarks/rating_invariance.py`` at 600 N m (FE and plate tooth), design M at 230 and 1150 N m
(FE tooth: a patch pushed into the corner of a tip and an end) and case 1 at 1500 N m (plate tooth), the LTCA at
21 positions on the grids 7x11 / 11x17 / 15x25 / 21x33, and the largest pressure (MPa) over the cells more than
``rating.edge.SURFACE_REACH`` cell from the blank whose footprint lies farther than 0.05 m_n (the edge rule's
band), 0.1, 0.2, 0.3 m_n and ``rating.edge.SURFACE_BAND_MODULES`` (0.5 m_n, where the verdict reads it) from
every edge of both members (docs/rating.md 5).

    python benchmarks/surface_band_convergence.py
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

GRIDS = ((7, 11), (11, 17), (15, 25), (21, 33))
BANDS_MODULES = (0.05, 0.1, 0.2, 0.3, 0.5)


def main() -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from rating_invariance import DESIGNS

    from beveloid import ltca
    from beveloid.pair import Pair
    from beveloid.rating.edge import surface_peaks
    from beveloid.spec import spec_from_toml_bytes

    def design(letter):
        return Pair.from_spec(spec_from_toml_bytes(DESIGNS[next(n for n in DESIGNS if n.startswith(letter + " "))].encode()))

    design_e, design_m = design("E"), design("M")
    cases = (("E", design_e, 600.0, "fe"), ("E", design_e, 600.0, "plate"), ("M", design_m, 230.0, "fe"),
             ("M", design_m, 1150.0, "fe"), ("case 1", Pair.example("case1"), 1500.0, "plate"))
    print("| design | T (N m) | tooth | band (m_n) | " + " | ".join(f"{a}x{b}" for a, b in GRIDS) + " |")
    print("|---|---|---|---|" + "---|" * len(GRIDS))
    for name, pair, torque, tooth in cases:
        m = pair.geometry.normal_module_mm
        read = {band: [] for band in BANDS_MODULES}
        for grid in GRIDS:
            r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(positions=21, grid=grid, tooth_model=tooth))
            for band in BANDS_MODULES:
                read[band].append(float(np.nanmax(surface_peaks(r, pair.geometry, band_mm=band * m))))
        for band, values in read.items():
            print(f"| {name} | {torque:g} | {tooth} | {band:g} | " + " | ".join(f"{v:.0f}" for v in values) + " |",
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
