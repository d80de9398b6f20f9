"""The FE tooth's root stress held to a notch benchmark of its own: the 2D plane-strain model of the
same section (``beveloid.fe.plane_strain``; the converged runs and the ISO matrix:
``python benchmarks/notch_benchmark.py``, docs/validation.md 12)."""
from __future__ import annotations


import numpy as np
import pytest

from beveloid.fe import plane_strain as ps
from beveloid.pair import Pair
from beveloid.spec import load_example, spec_from_dict, spec_to_dict

E, NU = 206_000.0, 0.3


def test_the_plane_strain_model_reproduces_kirsch_at_a_hole():
    """A hole of radius a in a plate 40 a wide and 160 a long, clamped at one end and pulled at the
    other by 1 MPa: the hole's edge peaks at 3 MPa (Kirsch; a plate width of 20 hole diameters adds
    about 0.3 %, Howland)."""
    import gmsh

    a, w, half_length = 1.0, 20.0, 80.0
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        occ.cut([(2, occ.addRectangle(-half_length, -w, 0, 2 * half_length, 2 * w))], [(2, occ.addDisk(0, 0, 0, a, a))])
        occ.synchronize()
        curves = {}
        for _, tag in gmsh.model.getEntities(1):
            x0, _, _, x1, _, _ = gmsh.model.getBoundingBox(1, tag)
            kind = "end" if x1 - x0 < 1e-6 else "hole" if x1 - x0 <= 2 * a + 1e-6 else "side"
            curves[f"{kind}_{'left' if x0 < -half_length + 1e-6 else tag}"] = tag
        field = gmsh.model.mesh.field
        d = field.add("Distance")
        field.setNumbers(d, "CurvesList", [t for n, t in curves.items() if n.startswith("hole")])
        t = field.add("Threshold")
        for key, value in (("InField", d), ("SizeMin", a / 16), ("SizeMax", w / 2), ("DistMin", 0.0), ("DistMax", 2 * w)):
            field.setNumber(t, key, value)
        field.setAsBackgroundMesh(t)
        for key in ("MeshSizeFromCurvature", "MeshSizeExtendFromBoundary", "MeshSizeFromPoints"):
            gmsh.option.setNumber(f"Mesh.{key}", 0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        mesh, facets = ps.tri6_mesh(gmsh, curves)
    finally:
        gmsh.finalize()
    corners = mesh.doflocs[:, :mesh.t.max() + 1]
    pulled = np.nonzero(np.isclose(corners[0], half_length))[0]
    pulled = pulled[np.argsort(corners[1, pulled])]
    share = np.gradient(corners[1, pulled])  # each vertex's part of the end (1 MPa x its length)
    share[[0, -1]] = 0.5 * np.diff(corners[1, pulled])[[0, -1]]
    forces = np.zeros((len(pulled), 2))
    forces[:, 0] = share
    u = ps.solve_point_loads(mesh, facets["end_left"], list(pulled), forces, (E, NU)).sum(axis=1, keepdims=True)
    edge = ps.edge_stresses(mesh, np.concatenate([f for n, f in facets.items() if n.startswith("hole")]), u,
                            (E, NU))
    assert edge.max_principal_mpa.max() == pytest.approx(3.0, rel=0.01)


#: the FE tooth of the test: every element size x 1.25 (its fillet 1.3 mm on a 2.05 mm fillet radius);
#: at x 1.5 its level is 1 to 7 % lower, at x 2 to 3 it does not resolve the fillet (level 0.77-0.97
#: of the 2D, the peak up to 0.6 mm too deep), measured on this design
COARSEN = 1.25


@pytest.fixture(scope="module")
def near_spur():
    """Case 1's pinion made near-spur (helix 0, cone angles 0.05 deg, shaft angle 3 deg), a rack tip round
    of 0.3 m_n, face 24 mm (4 m_n): its FE tooth and the 2D model of its mid-face section, both under a
    line load at the tip and at the pitch circle."""
    from beveloid.fe.tooth import tooth_data

    d = spec_to_dict(load_example("case1"))
    d["pair"]["shaft_angle_deg"] = 3.0
    d["pinion"].update(cone_angle_deg=0.05, helix_angle_deg=0.0, cutter_tip_radius_coefficient=0.3, face_width_mm=24.0)
    d["gear"].update(cone_angle_deg=0.05, cutter_tip_radius_coefficient=0.3)
    pair = Pair.from_spec(spec_from_dict(d))
    g = pair.geometry
    loads = (ps.SectionLoad("right", ps.TIP), ps.SectionLoad("right", g.pinion.pitch_radius_mm))
    flat = {ref: ps.notch_stress(pair, "pinion", loads, ps.NotchOptions(refinement=ref), material=(E, NU))
            for ref in (0.5, 1.0)}
    data = tooth_data(pair, "pinion", E, NU, coarsen=COARSEN)
    return g, loads, flat, [ps.fe_tooth_line_load(data, g, "pinion", ld) for ld in loads]


def test_the_2d_notch_stress_has_converged(near_spur):
    """Every element size halved moves the 2D notch stress by well under 1 % (measured here 0.19 % at the
    tip, 0.25 % at the pitch circle from refinement 0.5 to 1; on the benchmark's pinion 0.17, 0.04 and
    0.005 % from 0.5 to 1, 2 and 4: docs/validation.md 12.1)."""
    _, _, flat, _ = near_spur
    for coarse, fine in zip(flat[0.5], flat[1.0]):
        assert coarse.tension_mpa_per_n_mm == pytest.approx(fine.tension_mpa_per_n_mm, rel=0.005)
        assert fine.compression_mpa_per_n_mm < -0.5 * fine.tension_mpa_per_n_mm  # the other fillet: compression
        assert 0.0 < fine.height_above_root_mm < 1.5  # low in the fillet (its top: 2.53 mm above the root here)


def test_the_fe_tooth_reads_the_2d_notch_stress(near_spur):
    """The FE tooth under the same line load, uniform along the face (docs/validation.md 12.2).

    * Its mid-face level (plane_strain.fillet_level: its read fillet stresses averaged along the face in
      bands of height) within 0.97 to 1.12 of the 2D: its free tooth ends raise the mid-face stress
      over plane strain by 4-7 % (measured in its own sector with the ends held axially), and with the
      ends held its elements read within -5 to +1 % of the 2D (measured here: 1.033 at the tip, 1.013 at
      the pitch circle);
    * its largest value (the read-out's, what the LTCA reads: fe.contact.readout_matrix) within 1.0 to 1.15
      (measured 1.083, 1.062; the nodal means' largest, before FE_DATA_VERSION 4, read 1.139, 1.155: the
      node-to-node scatter of a tet mesh's nodal stresses on top);
    * the peak in the fillet where the 2D puts it, within 1 mm (half a fillet radius; measured 0.64
      against 0.87 mm at the tip, 0.44 against 0.51 mm at the pitch circle: the stress is flat about
      its peak)."""
    _, loads, flat, fe = near_spur
    for ld, two, three in zip(loads, flat[1.0], fe):
        level = three.level_mpa_per_n_mm / two.tension_mpa_per_n_mm
        top = three.max_mpa_per_n_mm / two.tension_mpa_per_n_mm
        assert 0.97 <= level <= 1.12, (ld, level)
        assert 1.0 <= top <= 1.15, (ld, top)
        assert abs(three.height_above_root_mm - two.height_above_root_mm) < 1.0
