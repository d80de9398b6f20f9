"""The FE data cache: hit, miss, stale and corrupt entries (beveloid.fe.cache)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from beveloid.fe import cache, tooth

pytestmark = pytest.mark.xdist_group(name="fe_case1")


@pytest.fixture
def counted(monkeypatch, tmp_path, coarse_teeth):
    """The cache in tmp_path (BEVELOID_CACHE_DIR); the FE computation replaced by the session's
    coarse data, counting its calls (the cache's logic is what is tested here)."""
    monkeypatch.setenv("BEVELOID_CACHE_DIR", str(tmp_path))
    calls = []

    def compute(pair, member, e_mpa, nu, refinement=1, progress=None, coarsen=1.0, smooth=True):
        calls.append(member)
        return coarse_teeth[member]

    monkeypatch.setattr(tooth, "tooth_data", compute)
    return calls


def _get(case1, member="pinion", e=2.06e5):
    return cache.cached_tooth_data(case1, member, e, 0.3, 1)


def test_miss_then_hit_in_the_folder_named_by_the_environment(counted, case1, tmp_path):
    data, how = _get(case1)
    assert how == "miss" and counted == ["pinion"]
    files = list((tmp_path / "fe").glob("pinion-*.npz"))
    assert len(files) == 1
    again, how = _get(case1)
    assert how == "hit" and counted == ["pinion"]
    assert np.array_equal(again.compliance_mm_per_n, data.compliance_mm_per_n)
    assert np.array_equal(again.stress_mpa_per_n, data.stress_mpa_per_n)


def test_a_read_by_another_process_keeps_this_processs_copy(counted, case1, monkeypatch):
    """The workers of one command read the same entry: a read marks the entry used (for the size limit)
    without changing what says it was rewritten, so the other workers keep their copies in memory (issue
    59: two optimize workers each read a ~100 MB entry again on most of their calls).  The other process
    is emulated here: this process's copy set aside, the entry read from the file as a second process does,
    then this process's copy put back."""
    reads = []
    read = cache._read
    monkeypatch.setattr(cache, "_read", lambda *a: reads.append(1) or read(*a))
    mine, _ = _get(case1)  # computed and written: kept in this process
    kept = dict(cache._KEPT)
    cache._KEPT.clear()
    other, how = _get(case1)  # "another process": read from the file, marked used
    assert how == "hit" and len(reads) == 2 and other is not mine
    cache._KEPT.clear()
    cache._KEPT.update(kept)
    again, how = _get(case1)
    assert how == "hit" and again is mine and len(reads) == 2  # no third read of the file
    assert counted == ["pinion"]


def test_every_input_is_in_the_key(counted, case1):
    _get(case1)
    _get(case1, e=2.0e5)  # another material: another entry
    _get(case1, member="gear")
    assert counted == ["pinion", "pinion", "gear"]
    key = json.loads(cache.cache_key(case1, "pinion", 2.06e5, 0.3, 2))
    assert key["refinement"] == 2 and key["version"] and key["surface_params"] and key["fillet_params"]


def test_a_stale_entry_is_recomputed_not_used(counted, case1):
    _get(case1)
    path = cache.entry_path(cache.cache_key(case1, "pinion", 2.06e5, 0.3, 1))
    with np.load(path) as z:
        stored = {k: z[k] for k in z.files}
    stored["key"] = np.array(str(stored["key"]).replace('"fe_data_version": ', '"fe_data_version": -'))
    stored["compliance_mm_per_n"] = stored["compliance_mm_per_n"] * 0 + 1.0  # what a stale entry would hold
    np.savez(path, **stored)
    data, how = _get(case1)
    assert how == "stale" and counted == ["pinion", "pinion"]
    assert not np.all(data.compliance_mm_per_n == 1.0)
    assert _get(case1)[1] == "hit"


def test_an_entry_keeps_the_fe_tooth_arrays_and_a_tooth_built_from_them_is_the_same(counted, case1):
    """The arrays the FE tooth derives from the data (eigenvalue bounds, reading-depth matrix, the
    compliance made semi-definite) are written into the entry and read back with it (issue 59: the tooth
    is built without making them); a tooth built from the stored arrays equals one that makes its own:
    every array, its compliances and its root stresses."""
    from beveloid.fe.contact import FeTooth, tooth_arrays
    from beveloid.names import FLANKS

    _get(case1)
    cache._KEPT.clear()  # as a new process: the entry read from the file
    data, how = _get(case1)
    assert how == "hit"
    assert cache.stored_tooth_arrays(object(), "left") is None  # data the cache did not give
    grid = np.asarray(data.points_mm[0]).reshape(-1, 3)
    rng = np.random.default_rng(7)
    pts = np.stack([grid[rng.choice(len(grid), 6, replace=False)] for _ in range(4)])
    forces = rng.uniform(10.0, 400.0, (4, 6))
    for flank in FLANKS:
        kept, fresh = cache.stored_tooth_arrays(data, flank), tooth_arrays(data, flank)
        assert kept is not None and sorted(kept) == sorted(fresh)
        assert all(np.array_equal(kept[k], fresh[k]) for k in fresh)
        a, b = FeTooth(data, flank, kept), FeTooth(data, flank)
        assert np.array_equal(a.line_compliances(pts), b.line_compliances(pts))
        assert all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a.root_stresses(pts, forces),
                                                                         b.root_stresses(pts, forces)))


@pytest.mark.parametrize("damage", ["truncate", "garbage", "nan"])
def test_a_corrupt_entry_is_recomputed_not_used(counted, case1, damage):
    _get(case1)
    path = cache.entry_path(cache.cache_key(case1, "pinion", 2.06e5, 0.3, 1))
    if damage == "truncate":
        path.write_bytes(path.read_bytes()[:1000])
    elif damage == "garbage":
        path.write_bytes(b"not an npz file")
    else:  # written again in place: the check mark of the file as first written stays beside it
        assert path.with_suffix(cache.MARK_SUFFIX).is_file()
        with np.load(path) as z:
            stored = {k: z[k] for k in z.files}
        stored["stress_mpa_per_n"] = stored["stress_mpa_per_n"] * np.nan
        np.savez(path, **stored)
    data, how = _get(case1)
    assert how == "corrupt" and counted == ["pinion", "pinion"]
    assert np.all(np.isfinite(data.stress_mpa_per_n))
    assert _get(case1)[1] == "hit"


def test_an_entry_is_checked_finite_once_then_read_by_its_check_mark(counted, case1, monkeypatch):
    """Issue 59: every array of an entry is checked finite when it is written (in memory) or at its first
    read, and a check mark beside it names the file so checked (size, modification time, inode): a read of
    that file skips the pass over its arrays; without a mark, or with one naming another file, the pass runs
    (and a passing entry gets its mark)."""
    _get(case1)
    path = cache.entry_path(cache.cache_key(case1, "pinion", 2.06e5, 0.3, 1))
    mark = path.with_suffix(cache.MARK_SUFFIX)
    assert mark.read_text() == cache._file_id(path)
    checked = []
    finite = cache._finite
    monkeypatch.setattr(cache, "_finite", lambda a: checked.append(1) or finite(a))

    def read():
        cache._KEPT.clear()  # as a new process
        checked.clear()
        return _get(case1)[1]

    assert read() == "hit" and checked == []
    mark.unlink()
    assert read() == "hit" and checked and mark.read_text() == cache._file_id(path)
    mark.write_text("1 2 3")
    assert read() == "hit" and checked and mark.read_text() == cache._file_id(path)
    assert counted == ["pinion"]
    path.unlink()
    cache.prune()
    assert not mark.exists()


def test_the_folder_keeps_to_its_size_limit_dropping_the_least_recently_used(counted, case1, monkeypatch, tmp_path):
    """Each entry written prunes the folder to $BEVELOID_FE_CACHE_MB: the entries used longest ago go
    first (a read counts as a use), never the one just written; an orphaned temporary file goes too."""
    import os
    import time

    folder = tmp_path / "fe"
    _get(case1, "pinion")
    (entry,) = folder.glob("pinion-*.npz")
    size_mb = entry.stat().st_size / 1e6
    monkeypatch.setenv(cache.LIMIT_ENV, f"{2.5 * size_mb:.6f}")  # room for two of these entries
    orphan = folder / "x.tmp"
    orphan.write_bytes(b"half")
    old = time.time() - 2 * cache.ORPHAN_AGE_S
    os.utime(orphan, (old, old))
    os.utime(entry, (old, old))
    _get(case1, "pinion", e=2.1e5)  # a second entry: both fit
    assert len(list(folder.glob("*.npz"))) == 2 and not orphan.exists()
    _get(case1, "pinion")  # read: the first entry is now the most recently used (its access time)
    assert entry.stat().st_atime > old + 1
    _get(case1, "pinion", e=2.2e5)  # a third: the least recently used (the second) goes
    names = {p.name for p in folder.glob("*.npz")}
    assert len(names) == 2 and entry.name in names
    assert cache.entry_path(cache.cache_key(case1, "pinion", 2.1e5, 0.3, 1)).name not in names
    monkeypatch.setenv(cache.LIMIT_ENV, "0")  # even a limit of 0 keeps the entry just written
    _get(case1, "gear")
    assert [p.name.split("-")[0] for p in folder.glob("*.npz")] == ["gear"]


def test_a_bad_size_limit_is_one_line_naming_the_variable(counted, case1, monkeypatch):
    from beveloid.errors import UserError

    monkeypatch.setenv(cache.LIMIT_ENV, "lots")
    with pytest.raises(UserError, match=r"^BEVELOID_FE_CACHE_MB = 'lots': must be a number of MB >= 0"):
        _get(case1)
    assert counted == []


def test_a_tuple_of_read_outs_computes_only_the_missing_ones_together(monkeypatch, tmp_path, case1, coarse_teeth):
    """cached_tooth_data with a tuple of read-outs (the rating's default and its check's same window): the
    entries not in the folder computed by one call of the FE computation, each written under its own key;
    those already there read, not computed again."""
    monkeypatch.setenv("BEVELOID_CACHE_DIR", str(tmp_path))
    calls = []

    def compute(pair, member, e_mpa, nu, refinement=1, progress=None, coarsen=1.0, smooth=True):
        calls.append(smooth)
        return tuple(coarse_teeth[member] for _ in smooth) if isinstance(smooth, tuple) else coarse_teeth[member]

    monkeypatch.setattr(tooth, "tooth_data", compute)
    _, how = cache.cached_tooth_data(case1, "pinion", 2.06e5, 0.3, 1)  # the default's entry alone
    assert how == "miss" and calls == [True]
    both, how = cache.cached_tooth_data(case1, "pinion", 2.06e5, 0.3, 1, smooth=(True, 2.0))
    assert how == "miss" and calls == [True, (2.0,)] and len(both) == 2
    assert len(list((tmp_path / "fe").glob("pinion-*.npz"))) == 2
    cache._KEPT.clear()  # read from the folder, as another process does
    again, how = cache.cached_tooth_data(case1, "pinion", 2.06e5, 0.3, 1, smooth=(True, 2.0))
    assert how == "hit" and len(calls) == 2
    assert all(np.array_equal(a.stress_mpa_per_n, b.stress_mpa_per_n) for a, b in zip(again, both))
    _, how = cache.cached_tooth_data(case1, "pinion", 2.06e5, 0.3, 1, smooth=(True, 4.0))
    assert how == "miss" and calls[-1] == (4.0,)
