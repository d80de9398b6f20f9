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
from beveloid.rating.face_load import WINDOW_MODULES, face_load, line_load_on_face
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
    dy of the face, so the line load's peak is b / dy times its mean exactly, and K_H_beta, its mean over
    the window of face_load.WINDOW_MODULES m_n (longer than dy here), is b / window."""
    b, half_y, ny = 50.0, 25.0, 81
    dy = 2 * half_y / ny
    middle = ny // 2  # the row at y = 0, where the minimum-norm fit had z = 0 and no slope
    result, load = field(lambda x, y: np.where((np.abs(y) < 1e-9) & (x > -1e-9) & (x < 0.03), 800.0, 0.0), 0.5, half_y)
    in_flank = np.zeros((41, ny), bool)
    in_flank[20:23, middle] = True  # the loaded cells and one unloaded neighbour, all on one grid line
    result.gap.in_flank = in_flank.reshape(1, 1, -1)
    assert np.count_nonzero(result.pressure_mpa) == 2
    _, w = line_load_on_face(result, GEOM, "pinion", 0)
    assert float(np.max(w)) / (load / b) == pytest.approx(b / dy, rel=1e-6)
    window = WINDOW_MODULES * GEOM.normal_module_mm
    assert dy < window
    fl = face_load(result, GEOM, "pinion", b)
    assert fl.K_H_beta == pytest.approx(b / window, rel=1e-6)
    assert fl.loaded_length_mm == pytest.approx(dy, rel=0.3)  # within a bin of the footprint, not a thousandth


def test_a_load_run_into_a_corner_has_a_line_load_peak_that_grows_with_the_grid_and_k_h_beta_that_does_not():
    """Issue 57.1 (a random design's gear, docs/rating.md 2.3): where a pair's pressure is singular at the end of
    its contact (a sharp corner), the line load at the cells' resolution peaks higher on every finer grid; its
    mean over face_load.WINDOW_MODULES m_n, which K_H_beta reads, converges.  The field: a strip along the face
    whose pressure rises as 1 / sqrt(distance) towards its end z = 0 and towards its edge x = 0 (the product of
    two edge singularities: a corner), summed on grids of 41 x 81, 81 x 161 and 161 x 321 cells."""
    b = 40.0

    def corner(x, y):
        return 100.0 / np.sqrt(np.maximum(x + 0.5, 1e-6) * np.maximum(y + 10.0, 1e-6)) * ((y > -10.0) & (y < 10.0))

    peaks, factors = [], []
    for n in (1, 2, 4):
        nx, ny = 41 * n - (n - 1), 81 * n - (n - 1)
        x, y = centres(0.5, nx), centres(10.0, ny)
        X, Y = np.meshgrid(x, y, indexing="ij")
        p = np.maximum(corner(X, Y), 0.0).reshape(1, 1, -1)
        pts = np.zeros((1, 1, nx * ny, 3))
        pts[..., 2] = sections.member_z(GEOM, "pinion", Y).reshape(-1)
        grid = PairGrid(nx, ny, np.array([[0.5]]), np.array([[10.0]]))
        area = grid.cell_area_mm2()
        gap = SimpleNamespace(pinion_point=pts, gear_point=pts, in_flank=np.ones((1, 1, nx * ny), bool))
        result = SimpleNamespace(pressure_mpa=p, gap=gap, grid=grid, cell_area_mm2=area, converged=np.array([True]),
                                 pair_load_n=p.sum(axis=-1) * area, cell_coordinates_mm=lambda j, k, X=X, Y=Y: (X, Y))
        mean = float(result.pair_load_n.sum()) / b
        _, w = line_load_on_face(result, GEOM, "pinion", 0)
        peaks.append(float(np.max(w)) / mean)
        factors.append(face_load(result, GEOM, "pinion", b).K_H_beta)
    # the continuum: w(z) = 200 / sqrt(z + 10) N/mm over the strip, F = 400 sqrt(20) N; the window's largest
    # mean is the one that starts at the end, (1 / L) 400 sqrt(L): K_H_beta = b / sqrt(20 L)
    exact = b / np.sqrt(20.0 * WINDOW_MODULES * GEOM.normal_module_mm)
    assert peaks[1] > 1.3 * peaks[0] and peaks[2] > 1.3 * peaks[1]  # the cells' peak: ~sqrt(2) a halving
    assert abs(factors[2] - factors[1]) < abs(factors[1] - factors[0])  # K_H_beta converges
    # the cells' midpoint sums of the singular strip fall short of it as sqrt(h): 6.1, 4.3 and 3.0 % below
    assert factors[2] == pytest.approx(exact, rel=0.05)
    assert max(factors) < 0.3 * peaks[2]


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
