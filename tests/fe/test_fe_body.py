"""The FE tooth is built on the member's body (beveloid.tooth.body), whatever its flank modification;
its cache entry is shared by every modification and renewed by a change of its code; points off the
surfaces carry no load (issues 41, 46, 48)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from beveloid.fe import cache, tooth
from beveloid.fe.contact import FeTooth
from beveloid.pair import Pair
from beveloid.spec import example_text
from beveloid.tooth.body import body_pair, is_body
from beveloid.tooth.departure import DEPARTURE_LIMIT, flank_departure

pytestmark = pytest.mark.xdist_group(name="fe_case1")

RELIEVED = {"profile_crowning_um": 12.7, "tip_relief_um": 23.2, "tip_relief_height_mm": 1.73, "end_relief_um": 5.1,
            "end_relief_length_mm": 3.0, "lead_crowning_um": 8.0}


def _case1(**members):
    import tomllib

    doc = tomllib.loads(example_text("case1"))
    for member, values in members.items():
        doc[member].update(values)
    return Pair.from_spec(doc)


@pytest.fixture(scope="module")
def relieved():
    return _case1(pinion=RELIEVED, gear={"profile_crowning_um": 20.0})


@pytest.fixture
def counted(monkeypatch, tmp_path, coarse_teeth):
    """The cache in tmp_path; the FE computation replaced by the session's coarse data, counted."""
    monkeypatch.setenv("BEVELOID_CACHE_DIR", str(tmp_path))
    calls = []

    def compute(pair, member, e_mpa, nu, refinement=1, progress=None, coarsen=1.0, smooth=True):
        calls.append((member, getattr(pair, "geometry", pair).member(member).tooth_surface))
        return coarse_teeth[member]

    monkeypatch.setattr(tooth, "tooth_data", compute)
    return calls


def test_the_body_is_the_member_cut_by_the_unmodified_rack(case1, relieved):
    assert relieved.geometry.pinion.tooth_surface == "micro_geometry"
    body = body_pair(relieved, "pinion")
    assert is_body(body.geometry, "pinion") and not is_body(relieved.geometry, "pinion")
    assert body.geometry.pinion.surface_options == () and body.geometry.gear == relieved.geometry.gear
    assert body.geometry.pinion == case1.geometry.pinion  # the body of a modified case 1 is case 1's
    assert body_pair(case1, "pinion") is case1


def test_a_modification_shares_the_bodys_entry_and_a_face_width_does_not(counted, case1, relieved):
    cache.cached_tooth_data(case1, "pinion", 2.06e5, 0.3, 1)
    _, how = cache.cached_tooth_data(relieved, "pinion", 2.06e5, 0.3, 1)
    assert how == "hit" and counted == [("pinion", "involute")]
    assert cache.cache_key(relieved, "gear", 2.06e5, 0.3, 1) == cache.cache_key(case1, "gear", 2.06e5, 0.3, 1)
    wider = _case1(pinion={"face_width_mm": 52.0})
    _, how = cache.cached_tooth_data(wider, "pinion", 2.06e5, 0.3, 1)
    assert how == "miss" and counted == [("pinion", "involute")] * 2


def test_the_fe_data_a_modified_pair_reads_is_on_disk_once_its_bodys_is(counted, case1, relieved):
    """ltca.model.teeth.fe_data_on_disk (optimize evaluates its unmodified design on the workers only where no FE
    data is to be made): both members' bodies' entries, whatever the flank modification; the plate reads none."""
    from beveloid import ltca
    from beveloid.ltca.model.teeth import fe_data_on_disk

    fe, m = ltca.Options(tooth_model="fe"), ltca.Material.from_spec(case1.spec)
    assert not fe_data_on_disk(relieved, fe, m) and fe_data_on_disk(relieved, ltca.Options(tooth_model="plate"), m)
    cache.cached_tooth_data(case1, "pinion", m.pinion_e_mpa, m.pinion_nu, fe.fe_refinement)
    assert not fe_data_on_disk(relieved, fe, m)  # the gear's still to be made
    cache.cached_tooth_data(case1, "gear", m.gear_e_mpa, m.gear_nu, fe.fe_refinement)
    assert fe_data_on_disk(relieved, fe, m) and fe_data_on_disk(case1, fe, m)
    assert not fe_data_on_disk(relieved, ltca.Options(tooth_model="fe", fe_coarsen=2.0), m)  # another entry
    assert len(counted) == 2


def test_the_key_holds_the_code_that_made_the_data(case1, monkeypatch, tmp_path):
    key = json.loads(cache.cache_key(case1, "pinion", 2.06e5, 0.3, 1))
    assert key["code"] == cache.code_digest()
    files = cache.source_files()
    assert any(p.name == "tooth.py" and p.parent.name == "fe" for p in files)
    assert any(p.name == "root_fillet.py" for p in files)  # the generated kernels
    # a byte changed in one of them changes the digest
    copy = tmp_path / files[0].name
    copy.write_bytes(files[0].read_bytes() + b"\n")
    monkeypatch.setattr(cache, "source_files", lambda: [copy, *files[1:]])
    cache.code_digest.cache_clear()
    try:
        assert cache.code_digest() != key["code"]
    finally:
        cache.code_digest.cache_clear()


def test_no_code_outside_the_digest_runs_while_fe_data_is_made(case1):
    """Every file of the package that executes while FE data is computed is hashed by code_digest
    (NOT_FE_SOURCES may leave out only folders whose code does not run)."""
    root = Path(cache.__file__).resolve().parents[1]
    ran = set()

    def profile(frame, event, arg):
        if event == "call":
            ran.add(frame.f_code.co_filename)

    sys.setprofile(profile)
    try:
        tooth.tooth_data(case1, "gear", 2.06e5, 0.3, coarsen=8.0)
    finally:
        sys.setprofile(None)
    hashed = {str(p) for p in cache.source_files()}
    ours = {f for f in ran if f.startswith(str(root)) or "/generated/" in f}
    assert ours and ours <= hashed, sorted(ours - hashed)


def test_points_off_the_surfaces_carry_no_load(coarse_teeth):
    t = FeTooth(coarse_teeth["pinion"], "right")
    grid = np.asarray(coarse_teeth["pinion"].points_mm[1]).reshape(-1, 3)
    pts = grid[[10, 20, 30]]
    bad = np.vstack([pts, [[np.nan] * 3], [[np.inf, 0.0, np.nan]]])
    W = t.weights(bad)
    assert np.all(np.isfinite(W)) and np.all(W[3:] == 0.0)
    assert np.allclose(W[:3].sum(axis=1), 1.0)
    assert np.array_equal(W[:3], t.weights(pts))
    forces = np.array([100.0, 200.0, 50.0, np.nan, 0.0])
    assert t.root_stress(bad, forces) == t.root_stress(pts, forces[:3])


def test_a_relieved_flank_departs_from_its_body_by_micrometres(relieved, coarse_teeth):
    data = coarse_teeth["pinion"]
    d = flank_departure(relieved, "pinion", data.points_mm, data.normals)
    # about every modification at once, at a tip corner: 23.2 + 12.7 + 5.1 + 8.0 = 49.0 um (the
    # crownings are defined over the nominal profile and face; the grid's corners reach a little past)
    assert 10.0 < d.max_um <= 1.1 * 49.0
    assert d.rms_over_thickness < DEPARTURE_LIMIT and d.note("pinion") is None
    sloped = _case1(pinion={"lead_slope_um": 200.0})  # the whole flank turned by 200 um over the face
    far = flank_departure(sloped, "pinion", data.points_mm, data.normals)
    assert far.max_um > 90.0 and far.rms_over_thickness > DEPARTURE_LIMIT
    assert far.note("pinion").startswith("pinion: the ")
