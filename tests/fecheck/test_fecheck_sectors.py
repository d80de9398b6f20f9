"""fe-check's sectors: SECTOR_TEETH teeth, every tooth of a modelled tooth pair meshed at the loaded
tooth's sizes (``sector_mesh``'s ``fine_teeth``), the others at the far size (docs/fe_check.md 2)."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe.mesh import sector_mesh
from beveloid.fecheck.pair_model import LEVEL_1_COARSEN, SECTOR_TEETH, sector_meshes
from beveloid.pair import Pair


def _edge_mm(mesh, name):
    """The mean corner-to-corner edge length of a named surface's facets (mm)."""
    tri = mesh.facets[name][:, :3]
    p = mesh.nodes[tri]
    return float(np.mean(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2)))


def test_the_sectors_refine_the_teeth_of_the_tooth_pairs(monkeypatch):
    """sector_meshes asks sector_mesh for SECTOR_TEETH teeth, each member's teeth of the modelled pairs fine."""
    import beveloid.fe.mesh

    calls = {}
    monkeypatch.setattr(beveloid.fe.mesh, "sector_mesh", lambda pair, m, n, **k: calls.setdefault(m, (n, k)))
    sector_meshes("pair", 1, coarsen=1.5, teeth=[(1, -1), None, (0, 0), (-1, 1)])
    assert {m: (n, k["teeth"], k["fine_teeth"], k["coarsen"]) for m, (n, k) in calls.items()} == {
        m: (1, SECTOR_TEETH, (-1, 0, 1), 1.5 * LEVEL_1_COARSEN) for m in ("pinion", "gear")}


@pytest.mark.slow
def test_the_fine_teeth_are_meshed_as_the_loaded_tooth():
    # the pinion at the FE tooth's sizes x 8 (the coarsest sector_mesh makes), teeth -1, 0, 1 fine
    mesh = sector_mesh(Pair.example("case1"), "pinion", teeth=SECTOR_TEETH, coarsen=8.0, fine_teeth=(-1, 0, 1))
    assert mesh.tooth_indices == tuple(range(-(SECTOR_TEETH // 2), SECTOR_TEETH // 2 + 1))
    outer = SECTOR_TEETH // 2
    for face in ("flank_right", "fillet_left"):
        fine = [_edge_mm(mesh, f"{face}_{k}") for k in (-1, 0, 1)]
        # the fine teeth's facets are alike (gmsh's sizes within 10 %); the outer tooth's, grown towards the
        # far size (1.0 m_n x 8 = 48 mm, three times the flank's), are coarser
        assert max(fine) < 1.1 * min(fine)
        assert _edge_mm(mesh, f"{face}_{outer}") > 1.3 * max(fine)


def test_fine_teeth_outside_the_sector_are_refused():
    with pytest.raises(ValueError, match=r"fine_teeth = \(0, 2\): must hold tooth 0 and only teeth of \(-1, 0, 1\)"):
        sector_mesh(Pair.example("case1"), "pinion", teeth=3, fine_teeth=(0, 2))


@pytest.mark.parametrize("fine, fillet_coarsen", [(False, None), (True, 1.5)])
def test_fine_fillets_are_not_coarsened_with_the_rest(monkeypatch, fine, fillet_coarsen):
    """With fine_fillets the fillets of the sectors' teeth in tooth pairs at the FE tooth's sizes x coarsen,
    every other size x LEVEL_1_COARSEN more (sector_mesh's fillet_coarsen); without, as the rest."""
    import beveloid.fe.mesh

    calls = {}
    monkeypatch.setattr(beveloid.fe.mesh, "sector_mesh", lambda pair, m, n, **k: calls.setdefault(m, (n, k)))
    sector_meshes("pair", 2, coarsen=1.5, fine_fillets=fine)
    assert {m: (k["coarsen"], k["fillet_coarsen"]) for m, (n, k) in calls.items()} == {
        m: (1.5 * LEVEL_1_COARSEN, fillet_coarsen) for m in ("pinion", "gear")}


@pytest.mark.slow
def test_fe_checks_fine_fillets_are_the_fe_tooths_at_the_same_settings():
    """fe-check's sectors at refinement 1 with fine_fillets and the FE tooth (``fe.tooth``: ``sector_mesh(pair,
    member, refinement, coarsen)``) read the root on the same fillet elements: the rule's size and the facets'
    edges alike, while the sectors' flanks are LEVEL_1_COARSEN times the tooth's (both coarsened x 2.5 to stay
    cheap)."""
    pair = Pair.example("case1")
    coarsen = 2.5
    sectors = sector_meshes(pair, 1, coarsen=coarsen, fine_fillets=True)
    for m in ("pinion", "gear"):
        tooth = sector_mesh(pair, m, 1, coarsen=coarsen)
        here = sectors[m]
        assert here.sizes.fillet_mm == pytest.approx(tooth.sizes.fillet_mm, rel=1e-12)
        assert here.sizes.flank_mm == pytest.approx(LEVEL_1_COARSEN * tooth.sizes.flank_mm, rel=1e-12)
        for side in ("left", "right"):
            a, b = _edge_mm(here, f"fillet_{side}_0"), _edge_mm(tooth, f"fillet_{side}_0")
            assert abs(a / b - 1.0) < 0.15, (m, side, a, b)
