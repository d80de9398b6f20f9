"""The local size field over a contact strip (beveloid.fe.sizes, fe-check's refinement): elements
of the requested size inside the strip, the face-wide sizes away from it, the element cap."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from beveloid.tooth.sampling import ToothSampler
from beveloid.fe.mesh import sector_mesh
from beveloid.fe.sizes import (STRIP_SIZE_MIN_MM, ContactStrip, ContactStrips, TETS_PER_H3, estimated_elements,
                               strip_sizes)

pytestmark = pytest.mark.xdist_group(name="fe_case1")

COARSEN = 3.0
SIZE_MM = 0.25  #: the strip's target at refinement 1: 0.75 mm at COARSEN 3 (flank size there 5.4 mm)
HALF_WIDTH_MM = 0.8


@pytest.fixture(scope="module")
def strip(case1):
    """A strip along the middle of the loaded tooth's right flank, over the face width."""
    sampler = ToothSampler(case1.geometry, "pinion")
    z = np.linspace(*sorted(sampler.z_range_mm), 25)
    line = sampler.face_points("flank_right", np.array([0.5]), z)[0]
    return ContactStrip(line, HALF_WIDTH_MM, SIZE_MM)


@pytest.fixture(scope="module")
def refined(case1, strip):
    return sector_mesh(case1, "pinion", coarsen=COARSEN, strips=ContactStrips((strip,), max_elements=10**6))


def _edges(nodes, corners):
    """Lengths of every edge of the given corner arrays (k, c)."""
    c = corners.shape[1]
    pairs = [(i, j) for i in range(c) for j in range(i + 1, c)]
    return np.concatenate([np.linalg.norm(nodes[corners[:, i]] - nodes[corners[:, j]], axis=1) for i, j in pairs])


def _distance(points, strip):
    dense = np.concatenate([np.linspace(a, b, 50) for a, b in zip(strip.points_mm[:-1], strip.points_mm[1:])])
    return cKDTree(dense).query(points)[0]


def test_the_strip_is_meshed_at_its_size_and_the_flank_elsewhere_at_the_flank_size(refined, strip):
    h = SIZE_MM * COARSEN
    assert refined.strip_sizes_mm == pytest.approx((h,))
    centroid = refined.nodes[refined.tets[:, :4]].mean(axis=1)
    inside = _distance(centroid, strip) < 0.5 * HALF_WIDTH_MM
    assert inside.sum() > 50
    edge = _edges(refined.nodes, refined.tets[inside][:, :4])
    assert 0.6 * h < np.median(edge) < 1.3 * h
    # on the flank: the strip's size on the strip; the neighbour teeth's flanks are not refined
    flank = refined.sizes.flank_mm
    assert flank > 5 * h
    tri = refined.facets["flank_right_0"][:, :3]
    near = _distance(refined.nodes[tri].mean(axis=1), strip) < 0.5 * HALF_WIDTH_MM
    assert near.sum() > 20 and 0.6 * h < np.median(_edges(refined.nodes, tri[near])) < 1.3 * h
    for name in ("flank_right_1", "flank_right_-1"):
        tri = refined.facets[name][:, :3]
        assert _distance(refined.nodes[tri].mean(axis=1), strip).min() > 8.0
        assert np.median(_edges(refined.nodes, tri)) > 0.8 * flank  # not refined: graded from the flank size
    # the rim, far from everything fine: the far size
    tri = refined.facets["rim"][:, :3]
    assert 0.5 * refined.sizes.far_mm < np.median(_edges(refined.nodes, tri)) < 1.5 * refined.sizes.far_mm


def test_the_cap_scales_the_sizes_up_and_the_floor_holds(strip):
    far = 6.0
    free = ContactStrips((strip,), max_elements=10**9)
    assert strip_sizes(free, 1.0, far) == pytest.approx((SIZE_MM,))
    capped = ContactStrips((strip,), max_elements=2000)
    (h,) = strip_sizes(capped, 1.0, far)
    assert h > SIZE_MM and estimated_elements(capped, h / SIZE_MM, far) <= 2000
    # the estimate's tube alone, independently: half a cylinder of the strip at the size
    tube = 0.5 * np.pi * HALF_WIDTH_MM ** 2 * strip.length_mm() * TETS_PER_H3 / SIZE_MM ** 3
    assert estimated_elements(free, 1.0, far) > tube
    tiny = ContactStrip(strip.points_mm, HALF_WIDTH_MM, 1e-4)
    assert strip_sizes(ContactStrips((tiny,), max_elements=10**9), 1.0, far) == (STRIP_SIZE_MIN_MM,)


def test_a_refined_or_coarsened_sector_scales_the_capped_strips_with_every_other_size(strip):
    """The cap sizes the strips at divide 1 (fe-check's refinement 2); refinement 1 (divide 1/2) doubles
    them exactly and divide 2 halves them, as it does the far size: not a new cap x divide^3."""
    capped = ContactStrips((strip,), max_elements=2000)
    (h,) = strip_sizes(capped, 1.0, 6.0)
    assert h > SIZE_MM  # the cap binds
    assert strip_sizes(capped, 0.5, 12.0) == pytest.approx((2.0 * h,), rel=1e-12)
    assert strip_sizes(capped, 2.0, 3.0) == pytest.approx((0.5 * h,), rel=1e-12)


@pytest.mark.parametrize("kwargs, key", [({"points_mm": np.zeros((3, 2))}, "points_mm"),
                                         ({"half_width_mm": 0.0}, "half_width_mm"),
                                         ({"size_mm": float("nan")}, "size_mm")])
def test_a_bad_strip_names_its_key(kwargs, key):
    args = {"points_mm": np.zeros((2, 3)), "half_width_mm": 1.0, "size_mm": 0.1, **kwargs}
    with pytest.raises(ValueError, match=key):
        ContactStrip(**args)
