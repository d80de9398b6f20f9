"""K_H_beta from the loaded contact's line load along the face (docs/rating.md 2.3; ISO 6336-1, 7.1:
peak over mean line load over the face width).

The synthetic fields are laid on a flat grid whose cell points sit at face coordinate
z = s_x x + s_y y of the case 1 pinion (the contact line along the face, or oblique to it), so the
line load along the face is known in closed form: a uniform strip gives w = F / L, a Hertz ellipse
the parabola (3F / 4a)(1 - z^2 / a^2), whose peak is 1.5 times its mean over the length 2a.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from beveloid.ltca.model.grid import PairGrid, centres
from beveloid.pair import Pair
from beveloid.rating.face_load import face_load, line_load_on_face
from beveloid.tooth import sections

GEOM = Pair.example("case1").geometry


def field(pressure, half_x, half_y, slope_x=0.0, slope_y=1.0, member="pinion"):
    """A one-position, one-pair LTCA-like result with ``pressure(x, y)`` on an (nx, ny) grid."""
    nx, ny = 41, 81
    x, y = centres(half_x, nx), centres(half_y, ny)
    X, Y = np.meshgrid(x, y, indexing="ij")
    p = np.maximum(pressure(X, Y), 0.0).reshape(1, 1, -1)
    z_face = slope_x * X + slope_y * Y
    pts = np.zeros((1, 1, nx * ny, 3))
    pts[..., 2] = sections.member_z(GEOM, member, z_face).reshape(-1)
    grid = PairGrid(nx, ny, np.array([[half_x]]), np.array([[half_y]]))
    area = grid.cell_area_mm2()
    gap = SimpleNamespace(pinion_point=pts, gear_point=pts, in_flank=np.ones((1, 1, nx * ny), bool))
    load = p.sum(axis=-1) * area
    return SimpleNamespace(pressure_mpa=p, gap=gap, grid=grid, cell_area_mm2=area, converged=np.array([True]),
                           pair_load_n=load, cell_coordinates_mm=lambda j, k: (X, Y)), float(load.sum())


def test_a_uniform_line_load_over_the_face_has_k_h_beta_one():
    b = 40.0
    result, load = field(lambda x, y: np.full_like(x, 800.0), 0.5, b / 2)
    fl = face_load(result, GEOM, "pinion", b)
    # the plateau of a cell-wise constant field is exact; only the two end ramps (half a cell) are smeared
    assert fl.K_H_beta == pytest.approx(1.0, rel=1e-9)
    assert fl.mean_line_load_n_per_mm == pytest.approx(load / b)
    assert fl.loaded_length_mm == pytest.approx(b, rel=0.02)  # within a bin or two of the ends


def test_an_oblique_uniform_strip_spreads_its_load_over_its_face_length():
    """A contact line at 30 deg to the face: the strip's 2Y along it covers 2Y cos 30 deg of the face; the
    across width (2X sin 30 deg of face) only rounds its ends."""
    b, half_y = 50.0, 20.0
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    result, load = field(lambda x, y: np.full_like(x, 800.0), 0.5, half_y, slope_x=s, slope_y=c)
    fl = face_load(result, GEOM, "pinion", b)
    assert fl.peak_line_load_n_per_mm == pytest.approx(load / (2 * half_y * c), rel=1e-9)
    assert fl.K_H_beta == pytest.approx(b / (2 * half_y * c), rel=1e-9)


@pytest.mark.parametrize("half_y", [25.0, 10.0])
def test_a_hertz_ellipse_gives_its_parabola_peak_over_mean(half_y):
    """Over the full face (2a = b) K_H_beta = 1.5; shorter, 1.5 b / 2a (issue 41: b / loaded length
    understated it by 1.5).  Tolerance: the midpoint sums of the ellipse's square-root rim on 41 x 81
    cells (0.3 % measured)."""
    b, half_x = 50.0, 1.2
    result, load = field(lambda x, y: 1500.0 * np.sqrt(np.clip(1 - (x / half_x) ** 2 - (y / half_y) ** 2, 0, None)),
                         half_x, half_y)
    fl = face_load(result, GEOM, "pinion", b)
    assert fl.K_H_beta == pytest.approx(1.5 * b / (2 * half_y), rel=0.01)
    assert fl.face_z_mm == pytest.approx(0.0, abs=b / 200)


def test_the_line_load_carries_every_pair_load_of_the_ltca():
    """On a real loaded contact (case 1, plate tooth): the line load integrates to the positions' loads."""
    from beveloid import ltca
    from beveloid.solver import Solver

    pair = Pair.example("case1")
    lt = ltca.analyze(pair, ltca.LoadCase(800.0), ltca.Options(positions=2, tooth_model="plate"), solver=Solver())
    for j in np.flatnonzero(lt.converged):
        for member in ("pinion", "gear"):
            edges, w = line_load_on_face(lt, pair.geometry, member, j)
            assert (w * np.diff(edges)).sum() == pytest.approx(np.nansum(lt.pair_load_n[j]), rel=1e-9)
            half = sections.half_face(pair.geometry, member)
            assert edges[0] > -half - 2.0 and edges[-1] < half + 2.0  # on the member's face (a cell of margin)


def test_a_pair_with_two_loaded_cells_on_one_grid_line_spreads_them_over_their_own_face_length():
    """Issue 57.1: an entering pair with two loaded (and in-flank) cells side by side across the contact
    line.  A plane fit of the face coordinate over those two cells is underdetermined (its minimum-norm
    answer had no slope along the line, so the footprint was a thousandth of a cell and K_H_beta ran to
    hundreds).  Over the pair's whole grid the slope is the grid's: the two cells cover one cell length
    dy of the face, so K_H_beta = b / dy exactly."""
    b, half_y, ny = 50.0, 25.0, 81
    middle = ny // 2  # the row at y = 0, where the minimum-norm fit had z = 0 and no slope
    result, load = field(lambda x, y: np.where((np.abs(y) < 1e-9) & (x > -1e-9) & (x < 0.03), 800.0, 0.0), 0.5, half_y)
    in_flank = np.zeros((41, ny), bool)
    in_flank[20:23, middle] = True  # the loaded cells and one unloaded neighbour, all on one grid line
    result.gap.in_flank = in_flank.reshape(1, 1, -1)
    fl = face_load(result, GEOM, "pinion", b)
    assert np.count_nonzero(result.pressure_mpa) == 2
    assert fl.K_H_beta == pytest.approx(b / (2 * half_y / ny), rel=1e-6)


@pytest.mark.parametrize("round_off", [1e-13, -1e-13])
def test_two_positions_whose_peaks_differ_by_round_off_report_the_first(round_off):
    """The instant and place of the peak do not follow the sign of a round-off between equal peaks (a tie read
    on another machine or backend would move the reported place): the first position keeps it."""
    edges = np.linspace(-10.0, 10.0, 201)
    w = np.exp(-0.5 * (0.5 * (edges[1:] + edges[:-1]) - 3.0) ** 2)
    later = np.exp(-0.5 * (0.5 * (edges[1:] + edges[:-1]) + 2.0) ** 2) * (1.0 + round_off)
    result = SimpleNamespace(converged=np.array([True, True]), pair_load_n=np.array([[10.0], [10.0]]))
    fl = face_load(result, GEOM, "pinion", 20.0, lines={0: (edges, w), 1: (edges, later)})
    assert fl.face_z_mm == pytest.approx(3.0, abs=0.1)
    assert fl.position == 0
