"""The CalculiX pipeline (deck, ccx, .frd/.dat reader) against Hertz: a spherical cap on a block."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fecheck import ccx_path, run_ccx, write_deck
from beveloid.fecheck.results import contact_pressure, read_dat, read_frd, write_vtu
from beveloid.fecheck.sphere_block import SphereBlock, sphere_block_deck

needs_ccx = pytest.mark.skipif(ccx_path() is None, reason="needs CalculiX (ccx, Debian package calculix-ccx)")

#: the case: a = 0.51 mm under 2000 N (R = 10 mm); contact mesh 0.15 mm, a quarter model
CASE = SphereBlock(fine_mm=0.15, far_over_fine=10.0, cap_mm=1.5, block_half_mm=3.0, block_depth_mm=3.0)


@pytest.mark.slow
@needs_ccx
def test_sphere_on_block_matches_hertz(tmp_path):
    deck = sphere_block_deck(CASE)
    write_deck(deck, tmp_path / "sphere.inp")
    run = run_ccx(tmp_path / "sphere.inp")
    frd = read_frd(run.file("frd"))
    dat = read_dat(run.file("dat"))
    hertz = CASE.hertz()
    # Hertz (Johnson 4.2): p0 = 3 P / (2 pi a^2), area pi a^2; the coarse quarter model within 5 %
    p_max = contact_pressure(frd).values.max()
    assert p_max == pytest.approx(hertz.max_pressure_mpa, rel=0.05)
    (cf,) = dat.contact
    assert 4.0 * cf.area_mm2 == pytest.approx(hertz.area_mm2, rel=0.05)
    # the contact carries the load (the quarter's P / 4, along +z on the cap)
    np.testing.assert_allclose(cf.force_n, [0.0, 0.0, CASE.load_n / 4.0], atol=1e-3 * CASE.load_n)
    cap = deck.bodies[0]
    write_vtu(tmp_path / "cap.vtu", cap.nodes_mm, cap.tets, frd)
    import meshio

    back = meshio.read(tmp_path / "cap.vtu")
    assert back.cells[0].type == "tetra10" and back.point_data["contact_pressure_mpa"].max() > 0.0
