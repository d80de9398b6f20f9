"""Where the verdict reads S_H: the largest surface pressure beyond a band from the flank edges, against the grid.

For design E of ``benchmarks/rating_invariance.py`` at 600 N m (FE and plate tooth) and case 1 at 1500 N m
(plate tooth), the LTCA at 21 positions on the grids 7x11 / 11x17 / 15x25 / 21x33, and the largest surface cell
pressure (MPa) farther than 0.05 m_n (the edge rule's band) and 0.1 m_n (``rating.edge.SURFACE_BAND_MODULES``,
where the verdict reads it) from every edge of both members (docs/rating.md 5).

    python benchmarks/surface_band_convergence.py
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

GRIDS = ((7, 11), (11, 17), (15, 25), (21, 33))
BANDS_MODULES = (0.05, 0.1)


def main() -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from rating_invariance import DESIGNS

    from beveloid import ltca
    from beveloid.pair import Pair
    from beveloid.rating.edge import surface_peaks
    from beveloid.spec import spec_from_toml_bytes

    e = next(name for name in DESIGNS if name.startswith("E "))
    design_e = Pair.from_spec(spec_from_toml_bytes(DESIGNS[e].encode()))
    cases = (("E", design_e, 600.0, "fe"), ("E", design_e, 600.0, "plate"),
             ("case 1", Pair.example("case1"), 1500.0, "plate"))
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
