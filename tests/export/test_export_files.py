"""The written STEP and STL files: closed, accurate at points not used to build them, whole gears."""
from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from export_checks import distances_to_mesh, distances_to_step_faces, off_fit_points, section_crossings, tooth_probe

from beveloid.export import ExportOptions, export, occ
from beveloid.tooth.sampling import ExportGeometryError

MEMBERS = ("pinion", "gear")
#: one worker builds the small pair's exports (a session fixture) and runs every test that reads them
pytestmark = pytest.mark.xdist_group("export")


def _file(result, member):
    (f,) = [f for f in result.files if f.members == (member,)]
    return f


@pytest.mark.parametrize("member", MEMBERS)
def test_step_is_one_valid_solid_within_1um_of_the_generated_surfaces(small_pair, small_exports, small_step_shapes,
                                                                       member):
    f = _file(small_exports["step"], member)
    shape = small_step_shapes[member]
    solids = occ.solids_of(shape)
    assert len(solids) == 1 and occ.is_valid(solids[0])
    assert occ.volume_mm3(solids[0]) == pytest.approx(f.volume_mm3, rel=1e-9)
    points = off_fit_points(small_pair.geometry, member, seed=1)
    worst = {face: float(np.max(distances_to_step_faces(shape, p))) * 1e3 for face, p in points.items()}
    assert max(worst.values()) <= 1.0, worst  # um
    assert f.max_error_um <= 1.0


@pytest.mark.parametrize("member", MEMBERS)
def test_stl_is_watertight_within_5um_and_agrees_with_the_step_volume(small_pair, small_exports, member):
    f = _file(small_exports["stl"], member)
    mesh = trimesh.load(f.path, file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0
    assert len(mesh.faces) == f.triangles
    points = off_fit_points(small_pair.geometry, member, seed=2, per_face=6)
    worst = {face: float(np.max(distances_to_mesh(mesh, p))) * 1e3 for face, p in points.items()}
    assert max(worst.values()) <= 5.0, worst  # um
    step = _file(small_exports["step"], member)
    assert abs(mesh.volume - step.volume_mm3) <= 2e-3 * step.volume_mm3


@pytest.mark.parametrize("member", MEMBERS)
def test_every_tooth_is_there(small_pair, small_exports, small_step_shapes, member):
    """The STL's section at mid-face crosses the half-depth circle twice per tooth; the STEP solid has
    material at every tooth's middle and none in the middle of every gap."""
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_IN, TopAbs_OUT

    teeth = small_pair.geometry.member(member).teeth
    z, radius, angle = tooth_probe(small_pair.geometry, member)
    mesh = trimesh.load(_file(small_exports["stl"], member).path, file_type="stl")
    assert section_crossings(mesh, z, radius) == 2 * teeth
    (solid,) = occ.solids_of(small_step_shapes[member])
    pitch = 2 * math.pi / teeth
    probe = BRepClass3d_SolidClassifier(solid)  # one classifier for every point (it prepares the solid once)
    for k in range(teeth):
        for offset, expected in ((0.0, TopAbs_IN), (pitch / 2, TopAbs_OUT)):
            a = angle + k * pitch + offset
            probe.Perform(gp_Pnt(radius * math.cos(a), radius * math.sin(a), z), 1e-7)
            assert probe.State() == expected, (k, offset)


def test_bore_is_cut_as_given(small_pair, small_exports):
    """The pinion's 12 mm bore: the exported volumes are the no-bore volume less the cylinder."""
    from beveloid.export import mesh

    plain = mesh.build_mesh(small_pair.geometry, "pinion", 0.0).mesh.volume
    cylinder = math.pi * 6.0 ** 2 * small_pair.geometry.pinion.face_width_mm
    for fmt in ("step", "stl"):
        assert plain - _file(small_exports[fmt], "pinion").volume_mm3 == pytest.approx(cylinder, rel=2e-3), fmt


def test_a_bore_through_the_root_is_refused_in_one_line(small_pair, tmp_path):
    import dataclasses

    spec = small_pair.spec
    big = dataclasses.replace(spec, gear=dataclasses.replace(spec.gear, bore_diameter_mm=60.0))
    from beveloid.pair import Pair

    with pytest.raises(ExportGeometryError) as err:
        export(Pair.from_spec(big), ExportOptions(format="stl", members=("gear",), out_dir=tmp_path))
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith("gear.bore_diameter_mm = 60: must be below the smallest root diameter")


@pytest.mark.parametrize("misalignment", [pytest.param({}, marks=(pytest.mark.long_running, pytest.mark.slow)),
                                          {"dx_mm": 0.05, "vertical_deg": 0.02}], ids=["aligned", "misaligned"])
def test_assembled_pair_touches_without_interference(small_pair, tmp_path, misalignment):
    """--assembled: the members in mesh as designed (under the spec's [misalignment]): the pinion's
    surface touches the gear's within the export's accuracy and nowhere lies inside it; the STEP file
    holds the same two bodies at the same places."""
    import dataclasses

    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    from beveloid.pair import Pair

    spec = small_pair.spec
    pair = Pair.from_spec(dataclasses.replace(spec, misalignment=dataclasses.replace(spec.misalignment, **misalignment)))
    formats = ("stl", "step") if not misalignment else ("stl",)  # STEP placement: once (the same code)
    files = {fmt: export(pair, ExportOptions(format=fmt, assembled=True, out_dir=tmp_path, stem="p")).files[0]
             for fmt in formats}
    assert all(f.members == MEMBERS and f.path.name == f"p_pair.{fmt}" for fmt, f in files.items())
    parts = trimesh.load(files["stl"].path, file_type="stl").split(only_watertight=True)
    assert len(parts) == 2
    small, large = sorted(parts, key=lambda m: m.volume)  # the pinion is the smaller
    gap = distances_to_mesh(large, small.vertices, signed=True)  # pinion surface points vs the gear
    assert np.min(np.abs(gap)) <= 5e-3  # touching
    assert np.min(gap) >= -5e-3  # not through each other
    if "step" not in files:
        return
    solids = sorted(occ.solids_of(occ.read_step(files["step"].path)), key=occ.volume_mm3)
    assert len(solids) == 2 and all(occ.is_valid(s) for s in solids)
    for body, mesh in zip(solids, (small, large)):
        props = GProp_GProps()
        occ.static(BRepGProp, "VolumeProperties")(body, props)
        c = props.CentreOfMass()
        assert np.allclose([c.X(), c.Y(), c.Z()], mesh.center_mass, atol=2e-3)
