"""An undercut tooth exports as generated (issue 29, item 4): the fillet surface up to where it cuts the
involute, the flank above; a valid closed STEP solid and a watertight STL that agree, and the parts of the
generated flank and fillet that the other cut away lie outside the solid."""
from __future__ import annotations

import numpy as np
import pytest
import trimesh
from export_checks import distances_to_mesh, distances_to_step_faces

from beveloid.export import ExportOptions, export, occ
from beveloid.tooth.sampling import ToothSampler
from beveloid.pair import Pair
from beveloid.spec import load_example, spec_to_dict
from beveloid.tooth import fillet, profile, undercut


@pytest.fixture(scope="module")
def undercut_pair():
    """Eleven pinion teeth of module 2 with a negative profile shift: undercut 1.36 mm deep, along the whole face."""
    data = spec_to_dict(load_example("case1"))
    data["pair"].update(normal_module_mm=2.0, offset_mm=29.3)
    data["pinion"].update(teeth=11, face_width_mm=8.0, profile_shift=-0.2)
    data["gear"].update(teeth=17, face_width_mm=10.0)
    return Pair.from_spec(data)


@pytest.fixture(scope="module")
def exported(undercut_pair, tmp_path_factory):
    out = tmp_path_factory.mktemp("undercut")
    return {fmt: export(undercut_pair, ExportOptions(format=fmt, members=("pinion",), out_dir=out, stem="uc"))
            for fmt in ("step", "stl")}


@pytest.mark.slow
@pytest.mark.long_running
def test_undercut_pinion_is_a_valid_step_solid_and_a_watertight_stl(undercut_pair, exported):
    g = undercut_pair.geometry
    w = g.member("pinion").face_width_mm / 2
    for flank in ("left", "right"):  # the design is undercut over the whole face on both flanks
        cut = undercut.flank_undercut(g, "pinion", flank)
        assert cut is not None and cut.from_mm == -w and cut.to_mm == w
    (step,), (stl,) = exported["step"].files, exported["stl"].files
    shape = occ.read_step(step.path)
    (solid,) = occ.solids_of(shape)
    assert occ.is_valid(solid)
    assert len(occ.faces_of(solid)) == 6 * 11 + 2  # fillet, flank (x2), tip and root lands per tooth; toe, heel
    mesh = trimesh.load(stl.path, file_type="stl")
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert abs(mesh.volume - step.volume_mm3) <= 2e-3 * step.volume_mm3


@pytest.mark.slow
@pytest.mark.long_running
def test_the_solid_follows_the_generated_tooth_through_the_undercut(undercut_pair, exported):
    """In a section at mid-face: the flank above the crossing and the fillet below it are on the exported
    surfaces; the flank below the crossing (cut by the tip round) and the fillet above it (cut by the
    straight edge) lie outside the solid, in the tooth space."""
    g = undercut_pair.geometry
    sampler = ToothSampler(g, "pinion")
    z = float(np.mean(sampler.z_range_mm)) + 0.3  # not a grid row of either export
    mesh = trimesh.load(exported["stl"].files[0].path, file_type="stl")
    shape = occ.read_step(exported["step"].files[0].path)
    tr = fillet.tip_round(g, "pinion")
    for flank in ("left", "right"):
        form = profile.form_limit(g, "pinion", flank, z)
        assert form.l_mm > float(tr.junction_l) and form.psi < float(tr.junction_psi)  # a true crossing
        _, l_tip, _ = profile.flank_at_radius(g, "pinion", flank, z, float(sampler.tip_radius_mm(z)))
        t = np.linspace(0.1, 0.9, 5)
        kept = np.concatenate([profile.flank_in_section(g, "pinion", flank, z, form.l_mm + t * (l_tip - form.l_mm))[0],
                               profile.fillet_in_section(g, "pinion", flank, z, t * form.psi)[0]])
        assert np.max(distances_to_mesh(mesh, kept)) <= 5e-3
        assert np.max(distances_to_step_faces(shape, kept)) <= 1e-3
        l_t, psi_j = float(tr.junction_l), float(tr.junction_psi)
        t = np.linspace(0.3, 0.7, 5)  # away from the loop's ends, where the two branches meet the surfaces
        cut_away = np.concatenate([
            profile.flank_in_section(g, "pinion", flank, z, l_t + t * (form.l_mm - l_t))[0],
            profile.fillet_in_section(g, "pinion", flank, z, form.psi + t * (psi_j - form.psi))[0]])
        assert np.min(distances_to_mesh(mesh, cut_away, signed=True)) > 5e-3
