"""Issue 57.2: the edge rule's band share converges with the grid at a face end too.  A cell's force acts on
the flank: the part of its footprint beyond the edge carries none (``rating.edge.band_fractions``).  Counted in
the band, that part put up to half an edge cell's force within 0.05 m_n of a face end, where a cell's
footprint in the distance runs along the contact line (1.5-6 mm against the band's 0.25 mm on design K), so
the share followed the cell's length and the verdict's status the grid."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from beveloid import ltca
from beveloid.rating.edge import band_fractions, edge_loads


def test_a_cells_force_is_spread_over_its_footprint_on_the_flank():
    # a footprint from 0.5 mm beyond the edge to 0.5 mm on the flank (one width; the other vanishing), a
    # band of 0.25 mm: half the flank part is in it; by distance^-1/2, sqrt(0.25 / 0.5) of the force
    force, area = band_fractions(np.array([0.0]), 0.25, np.array([1.0]), np.array([0.0]))
    assert force[0] == pytest.approx(0.5, abs=2e-3) and area[0] == pytest.approx(0.25, abs=2e-3)
    punch, _ = band_fractions(np.array([0.0]), 0.25, np.array([1.0]), np.array([0.0]), "punch")
    assert punch[0] == pytest.approx(np.sqrt(0.5), abs=5e-3)
    # a footprint wholly on the flank: the uniform spread is the footprint's CDF, the punch weight puts more
    # near the edge; far from the edge the two agree
    d, a, b = np.array([0.8, 8.0]), np.array([1.0, 1.0]), np.array([0.4, 0.4])
    force, area = band_fractions(d, np.array([0.25, 8.1]), a, b)
    assert force == pytest.approx(area) and force[0] == pytest.approx(0.5 * 0.15 * 0.15 / 0.4, rel=1e-6)
    punch, _ = band_fractions(d, np.array([0.25, 8.1]), a, b, "punch")
    assert punch[0] > force[0] and punch[1] == pytest.approx(force[1], abs=0.01)
    with pytest.raises(ValueError, match="profile = 'flat': valid are uniform, punch"):
        band_fractions(d, 0.25, a, b, "flat")


def test_the_share_at_a_face_end_converges_with_the_grid():
    """Design K (random R3-2: an uncrowned gear, the line contact reaching its toe and heel) on the plate tooth
    at 300 N m: its gear's toe carried 0.049 of the mesh's load on the 7x11 grid against 0.028 on 15x25 when the
    footprint beyond the edge counted in the band; on the flank only 0.020 / 0.021 (21 positions; the FE tooth
    0.013 / 0.013, ``benchmarks/edge_band_convergence.py``)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from rating_invariance import DESIGNS, _pair

    pair = _pair(next(name for name in DESIGNS if name.startswith("K ")))
    shares = []
    for grid in ((7, 11), (15, 25)):
        r = ltca.analyze(pair, ltca.LoadCase(300.0), ltca.Options(positions=21, grid=grid, tooth_model="plate"))
        e = edge_loads(r, pair.geometry)
        assert (e.member, e.edge) == ("gear", "toe")
        shares.append(e.share)
    assert shares[0] / shares[1] == pytest.approx(1.0, abs=0.1)


def test_at_edge_reads_the_top_of_a_cells_passage_over_the_edge():
    """Case 1's pareto design (tests/data/case1_toe_on_limit.toml, 200 N m, plate tooth) as its pattern runs onto
    the pinion's toe: within one cell's passage over the toe (0.1510-0.1520 rad) the share rises several times
    over as the cell nears the edge; ``edge_shares(..., at_edge=True)`` reads each position with the band on
    its nearest loaded cell, the passage's last instant: never below the share, and nearly the same at each of
    the passage's positions (the pressures move little within one cell)."""
    from beveloid.pair import Pair
    from beveloid.rating.edge import edge_shares
    from beveloid.spec import load_spec

    pair = Pair.from_spec(load_spec(Path(__file__).resolve().parents[1] / "data" / "case1_toe_on_limit.toml"))
    r = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(tooth_model="plate", angles=(0.1510, 0.1515, 0.1520)))
    share = edge_shares(r, pair.geometry)["pinion", "toe"]
    top = edge_shares(r, pair.geometry, at_edge=True)["pinion", "toe"]
    assert r.converged.all() and (np.diff(share) > 0).all() and share.max() > 2.0 * share.min()
    assert (top >= share).all() and top.max() < 1.05 * top.min() and top.min() > share.max()
