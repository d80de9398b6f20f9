"""Fixtures of the export tests: a small pair (cheap to export) and its exports (export_checks.py
holds the measurements)."""
from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def small_pair():
    """A pair of 15 and 19 teeth, module 2, narrow faces, a bore in the pinion: exports in seconds."""
    from beveloid.pair import Pair
    from beveloid.spec import load_example, spec_to_dict

    data = spec_to_dict(load_example("case1"))
    data["pair"].update(normal_module_mm=2.0, offset_mm=36.0)
    data["pinion"].update(teeth=15, face_width_mm=8.0, profile_shift=0.3, bore_diameter_mm=12.0)
    data["gear"].update(teeth=19, face_width_mm=10.0)
    return Pair.from_spec(data)


@pytest.fixture(scope="session")
def small_exports(small_pair, tmp_path_factory):
    """{format: ExportResult} of both members of the small pair, each in its own frame."""
    from beveloid.export import ExportOptions, export

    out = tmp_path_factory.mktemp("small_export")
    return {fmt: export(small_pair, ExportOptions(format=fmt, out_dir=out, stem="small")) for fmt in ("step", "stl")}


@pytest.fixture(scope="session")
def small_step_shapes(small_exports):
    """{member: the shape read back from its STEP file}, read once (~0.4 s each) for the tests that only
    inspect it."""
    from beveloid.export import occ

    return {f.members[0]: occ.read_step(f.path) for f in small_exports["step"].files}
