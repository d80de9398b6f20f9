"""The patch-clearance pre-check of edge contact (derivations/patch_clearance.py,
beveloid/solver/patch_cover.py, core.patches_apart): its derivation, the cover's soundness, and that
what it calls OUTSIDE really cannot touch."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid import tca
from beveloid.solver import Solver, patch_cover
from beveloid.derivations import patch_clearance
from beveloid.generated import flank_boundaries, layouts, patch_clearance as pc_kernels, placement
from beveloid.solver import backends
from beveloid.status import Status

ROOT = Path(__file__).resolve().parents[2]
COLS = {name: i for i, name in enumerate(patch_cover.CELL_FIELDS)}


def test_gear_angle_only_turns_the_gear_frame_about_its_axis():
    """M_2f(phi'_2) M_f1 = R_z(-phi'_2) M_21: the gear blank's margins of a pinion point do not
    depend on the gear angle, so phi'_2 = 0 covers all (symbolically)."""
    r = patch_clearance.invariance_residual()
    assert sp.simplify(sp.expand_trig(r)) == sp.zeros(4, 4)


def test_margin_slopes_are_constant():
    """|grad g| of the tip, toe and heel margins is the same at every point (the Lipschitz
    constants the sphere test uses)."""
    got = patch_clearance.margin_slopes()
    assert all(sp.simplify(g - e) == 0 for g, e in zip(got, patch_clearance.expected_slopes()))
    # and the generated kernel gives it at random points
    rng = np.random.default_rng(3)
    blank = np.asarray(layouts.FlankBlank.pack(dict(pitch_radius_mm=100.0, tip_height_mm=6.0, rack_shift_mm=1.0,
                                                    cone_angle=math.radians(7.0), toe_z_mm=-20.0, heel_z_mm=30.0,
                                                    form_limit_l_mm=0.0)))
    p = rng.uniform(-150, 150, (50, 3))
    slopes = np.linalg.norm(flank_boundaries.flank_margins(p, 0.0, blank).margins_D_point, axis=-1)
    assert np.allclose(slopes[:, 1], 1 / math.cos(math.radians(7.0)), rtol=1e-12)
    assert np.allclose(slopes[:, 2:], 1.0, rtol=1e-12)


def test_generated_map_is_the_composed_placement():
    """pinion_in_gear_frame = M_f2(0)^-1 M_f1(phi'_1), from the generated placements."""
    rng = np.random.default_rng(5)
    pair = np.asarray(layouts.PairPlacement.pack(dict(offset_mm=229.0, shaft_angle=math.radians(13.0),
                                                      pinion_axial_placement_mm=120.0, gear_axial_placement_mm=-35.0)))
    for _ in range(5):
        phi1, e = rng.uniform(-3, 3), rng.uniform(-0.5, 0.5, 5) * [1, 1, 1, 0.01, 0.01]
        m = pc_kernels.pinion_in_gear_frame(phi1, e, pair)
        p1, g = placement.pinion_placement(phi1, pair), placement.gear_placement(0.0, e, pair)
        p = rng.uniform(-50, 50, 3)
        expect = g.rotation.T @ (p1.rotation @ p + p1.translation - g.translation)
        assert np.allclose(m.rotation @ p + m.translation, expect, atol=1e-10)


@pytest.mark.parametrize("flank", ["left", "right"])
def test_cover_holds_every_patch_point(geom1, flank):
    """Every point of the pinion patch (dense samples) lies in its root cell's sphere, and every
    point of a cell split three times lies in the sphere of its part (the radius the core uses)."""
    cover = patch_cover.patch_cover(geom1, "pinion", flank)
    cells = cover.cells
    rng = np.random.default_rng(11)
    l0, l1, u0, u1 = cover.box
    L, U = rng.uniform(l0 - 1, l1 + 1, 200_000), rng.uniform(u0 - 3, u1 + 3, 200_000)
    pts = geom1.surface("pinion", flank, L, U).point
    on = (flank_boundaries.flank_margins(pts, L, geom1.pinion.blank()).margins >= 0).all(-1)
    assert on.sum() > 50_000
    L, U, pts = L[on], U[on], pts[on]
    # the root cell of each point
    hit = ((np.abs(L[:, None] - cells[None, :, COLS["l_mm"]]) <= cells[None, :, COLS["half_l_mm"]])
           & (np.abs(U[:, None] - cells[None, :, COLS["u_mm"]]) <= cells[None, :, COLS["half_u_mm"]]))
    assert hit.any(axis=1).all(), "a patch point outside every kept root cell"
    k = hit.argmax(axis=1)
    c = cells[k]
    radius = np.hypot(c[:, COLS["half_l_mm"]], c[:, COLS["half_u_mm"]]) * c[:, COLS["stretch"]]
    assert (np.linalg.norm(pts - c[:, :3], axis=1) <= radius).all()
    # three splits: the part of the cell holding the point, its centre and radius
    hl, hu = c[:, COLS["half_l_mm"]] / 8, c[:, COLS["half_u_mm"]] / 8
    il = np.floor((L - (c[:, COLS["l_mm"]] - c[:, COLS["half_l_mm"]])) / (2 * hl))
    iu = np.floor((U - (c[:, COLS["u_mm"]] - c[:, COLS["half_u_mm"]])) / (2 * hu))
    lc = c[:, COLS["l_mm"]] - c[:, COLS["half_l_mm"]] + (2 * il + 1) * hl
    uc = c[:, COLS["u_mm"]] - c[:, COLS["half_u_mm"]] + (2 * iu + 1) * hu
    centre = geom1.surface("pinion", flank, lc, uc).point
    assert (np.linalg.norm(pts - centre, axis=1) <= np.hypot(hl, hu) * c[:, COLS["stretch"]]).all()


@pytest.mark.parametrize("backend", ["numpy", "compiled"] if backends.AVAILABLE else ["numpy"])
def test_apart_means_no_patch_point_inside_the_gear_blank(geom1, backend):
    """Over the out-of-mesh positions of a mesh study, whenever patches_apart says the patches
    cannot touch, no sampled pinion patch point lies inside the gear blank (at any gear angle);
    and it does say so for the pinion teeth far from the mesh."""
    core_ns = backends.namespace(backend)
    flank = "right"
    cells = patch_cover.patch_cover(geom1, "pinion", flank).cells
    ref = tca.reference_contact(geom1, flank)
    p1 = geom1.pitch_angles[0]
    L, U = np.meshgrid(np.linspace(0, 16, 60), np.linspace(-32, 32, 200), indexing="ij")
    pts = geom1.surface("pinion", flank, L, U).point
    on = (flank_boundaries.flank_margins(pts, L, geom1.pinion.blank()).margins >= 0).all(-1)
    P = pts[on]
    problem = geom1.problem(flank)
    apart = []
    for phi in ref.pinion_angle + np.linspace(-3.0, 3.0, 41) * p1:
        a = core_ns.patches_apart(problem, cells, phi, np.zeros(5), 1e-9,
                                  core_ns.clearance_scratch())
        m = pc_kernels.pinion_in_gear_frame(phi, np.zeros(5), geom1.placement())
        q = P @ m.rotation.T + m.translation
        g = flank_boundaries.flank_margins(q, 0.0, geom1.gear.blank()).margins[:, 1:]
        inside = (g >= 0).all(-1).any()
        assert not (a and inside)
        apart.append(a)
    assert sum(apart) >= 10 and not all(apart)


def test_outside_points_of_a_mesh_study_cannot_touch(geom1):
    """In the aligned mesh study (3 pairs), every OUTSIDE point of the neighbour pairs has no
    sampled pinion patch point inside the gear blank (so no gear angle brings the patches
    together), and nearly all of them are proven so by patches_apart (the rest lie closer to the
    gear blank than its finest sphere and are left to the candidate search)."""
    res = tca.analyze(geom1, tca.Options(flanks=("right",), positions=200, pairs=3, approach_mm=None))
    fr = res.flanks["right"]
    outside = np.array(fr.status) == Status.OUTSIDE.label
    assert outside.sum() >= 20
    core_ns = Solver().core
    cells = patch_cover.patch_cover(geom1, "pinion", "right").cells
    p1 = geom1.pitch_angles[0]
    L, U = np.meshgrid(np.linspace(0, 16, 150), np.linspace(-32, 32, 500), indexing="ij")
    pts = geom1.surface("pinion", "right", L, U).point
    P = pts[(flank_boundaries.flank_margins(pts, L, geom1.pinion.blank()).margins >= 0).all(-1)]
    proven = 0
    for phi, k in zip(fr.pinion_angle[outside], fr.tooth_pair[outside]):
        m = pc_kernels.pinion_in_gear_frame(phi - k * p1, np.zeros(5), geom1.placement())
        g = flank_boundaries.flank_margins(P @ m.rotation.T + m.translation, 0.0, geom1.gear.blank()).margins[:, 1:]
        assert not (g >= 0).all(-1).any()
        proven += core_ns.patches_apart(geom1.problem("right"), cells,
                                        phi - k * p1, np.zeros(5), 1e-9, core_ns.clearance_scratch())
    assert proven >= 0.9 * outside.sum()
