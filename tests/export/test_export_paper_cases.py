"""Both members of the paper's two cases (Table 1) export as valid STEP and watertight STL."""
from __future__ import annotations

import time

import numpy as np
import pytest
import trimesh
from export_checks import distances_to_mesh, distances_to_step_faces, off_fit_points, section_crossings, tooth_probe

from beveloid.export import ExportOptions, export, occ
from beveloid.pair import Pair


@pytest.mark.slow
@pytest.mark.long_running
@pytest.mark.parametrize("case", ["case1", "case2"])
def test_paper_case_exports_whole_valid_gears(case, tmp_path):
    pair = Pair.example(case)
    start = time.perf_counter()
    step = export(pair, ExportOptions(format="step", out_dir=tmp_path, stem=case))
    stl = export(pair, ExportOptions(format="stl", out_dir=tmp_path, stem=case))
    print(f"{case}: both members, STEP and STL, in {time.perf_counter() - start:.1f} s")
    for member in ("pinion", "gear"):
        teeth = pair.geometry.member(member).teeth
        (s,) = [f for f in step.files if f.members == (member,)]
        (m,) = [f for f in stl.files if f.members == (member,)]
        shape = occ.read_step(s.path)
        (solid,) = occ.solids_of(shape)
        assert occ.is_valid(solid)
        mesh = trimesh.load(m.path, file_type="stl")
        assert mesh.is_watertight and mesh.is_winding_consistent
        assert abs(mesh.volume - s.volume_mm3) <= 2e-3 * s.volume_mm3
        points = np.concatenate(list(off_fit_points(pair.geometry, member, seed=3, per_face=2).values()))
        assert np.max(distances_to_step_faces(shape, points)) <= 1e-3
        assert np.max(distances_to_mesh(mesh, points)) <= 5e-3
        z, radius, _ = tooth_probe(pair.geometry, member)
        assert section_crossings(mesh, z, radius) == 2 * teeth
        assert len(occ.faces_of(solid)) == 6 * teeth + 2  # six per tooth and gap, toe and heel (no bore)
