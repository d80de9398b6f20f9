"""Which fillet nodes a load set's root stress leaves out (issue 57).

The LTCA's contact is lumped onto the FE load grid's nodes (bilinear weights), and a fillet node
within the reading depth of a loaded node sees that point force's local stress, not the tooth's: it
is left out.  A contact lumped onto a node stands for a load spread over the grid rows beside it, and
whether the row below (the form limit's) gets a weight depends on where the contact grid's cells
fall.  A fillet node just beyond the depth of the loaded node but within that of the row below then
read the point force on one contact grid and not on another: design G of
benchmarks/rating_invariance.py at 290 N m, pinion root stress 1086 MPa on the 7x11 grid against
685 MPa on the default one.  The node is now left out for the loaded node's neighbours up and down
the profile too."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from beveloid.fe.contact import tooth_arrays


def _data(ns=4, nz=3):
    r = 10.0 + 0.4 * np.arange(ns)
    z = np.array([0.0, 5.0, 10.0])[:nz]
    pts = np.stack(np.broadcast_arrays(r[:, None], 0.0 * r[:, None] + 0.0 * z[None, :], z[None, :]), axis=-1)
    pts = np.broadcast_to(pts, (2, ns, nz, 3)).copy()
    # fillet node 0 lies 0.25 mm below row 0's middle node (within its depth, 0.65 mm from row 1's),
    # node 1 far from every node
    fillet = np.array([[9.75, 0.0, 5.0], [5.0, 0.0, 5.0]])
    G = ns * nz
    rng = np.random.default_rng(0)
    return SimpleNamespace(points_mm=pts, depth_mm=np.full((2, ns, nz), 0.35),
                           compliance_mm_per_n=np.broadcast_to(np.eye(G), (2, G, G)).copy(),
                           fillet_points_mm=np.broadcast_to(fillet, (2, 2, 3)).copy(),
                           fillet_height_mm=np.array([[0.1, 0.0], [0.1, 0.0]]),
                           stress_mpa_per_n=rng.normal(size=(2, 2, 2, 6, G)), smoothing_mm=np.zeros(2))


@pytest.mark.parametrize("flank", ["left", "right"])
def test_a_fillet_node_near_a_loaded_nodes_row_neighbour_is_left_out(flank):
    near = tooth_arrays(_data(), flank)["near"]  # (2 fillets, G nodes, nf), nodes profile-major
    nz = 3
    node = lambda row, col: row * nz + col  # noqa: E731
    for s in range(2):
        assert near[s][node(0, 1), 0]  # within the depth of row 0's node
        assert near[s][node(1, 1), 0]  # a load on row 1: its neighbour below is row 0
        assert not near[s][node(2, 1), 0]  # two rows up: counted
        assert not near[s][node(1, 0), 0] and not near[s][node(1, 2), 0]  # the columns beside: counted
        assert not near[s][:, 1].any()  # far from every node


#: design G of benchmarks/rating_invariance.py (m_n 2, 23/45 teeth at 22.5 deg, a wide crowned pinion)
DESIGN_G = {
    "pair": {"normal_module_mm": 2.0, "normal_pressure_angle_deg": 22.5, "shaft_angle_deg": 10.0, "offset_mm": 67.0},
    "pinion": {"teeth": 23, "cone_angle_deg": 2.0, "helix_angle_deg": 20.0, "profile_shift": 0.35,
               "face_width_mm": 36.0, "lead_crowning_um": 15.0},
    "gear": {"teeth": 45, "cone_angle_deg": 1.0, "face_width_mm": 34.0},
}


@pytest.mark.slow
def test_the_root_stress_does_not_read_a_lumped_force_on_a_coarse_contact_grid():
    """Design G at 290 N m, the FE tooth at its defaults: the pinion's largest root stress over the cycle on
    the 7x11 contact grid against the default grid (1086 against 685 MPa before the row neighbours)."""
    from beveloid import ltca
    from beveloid.pair import Pair

    pair = Pair.from_spec(DESIGN_G)
    root = []
    for grid in ((7, 11), (11, 17)):
        r = ltca.analyze(pair, ltca.LoadCase(290.0), ltca.Options(positions=21, grid=grid))
        assert np.all(r.converged)
        root.append(r.root_stress_max_mpa()["pinion"])
    assert abs(root[0] / root[1] - 1.0) < 0.05, root
