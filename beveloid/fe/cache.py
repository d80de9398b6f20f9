"""The FE tooth's data, computed once per member design and kept in the user cache folder.

Folder: ``$BEVELOID_CACHE_DIR/fe`` when set, else ``platformdirs.user_cache_dir("beveloid")/fe``.
An entry is one ``.npz`` per (member design, material, refinement), named by a SHA-256 digest of
its key: everything the data depends on (the member's generated-surface and fillet parameters, its
teeth, face, tip and bore, E and nu, the refinement, the load grid and reading depth constants) plus
:data:`FE_DATA_VERSION` and :func:`code_digest`, a SHA-256 of the source of every module that can
produce the data (the package minus :data:`NOT_FE_SOURCES`): a change to the FE code, the sampled
tooth or the generated kernels invalidates cached data by construction.  The member is its **body**
(:func:`beveloid.tooth.body.body_pair`): the key holds no flank modification, so one entry serves
every crowning, relief and user flank model of a macro geometry.  The key is stored inside the entry
and compared on reading: an entry whose key differs (stale) or that cannot be read (corrupt, truncated) is computed
again and replaced, never used.  Entries are written to a temporary file and renamed into place.

An entry also holds, per flank, the arrays the FE tooth derives from the data
(:func:`beveloid.fe.contact.tooth_arrays`: the fillets' eigenvalue bounds, the reading-depth matrix; ~0.3 s
of CPU a member to make, issue 59), so that ``FeTooth(data, flank, arrays)`` is built without that work
(:func:`stored_tooth_arrays`).  Its large arrays (the stress operator, ~100 MB) are mapped, not read: a
run reads the pages it uses (the loaded flank's fillet nodes its root stresses visit).  Every array of an
entry is checked finite (a NaN or an infinity: the entry is "corrupt", computed again) once: when it is written,
or the first time it is read without a **check mark** (a small file beside it, ``<entry>.finite``, holding the
entry's size, modification time and inode at that check): an entry whose file still matches its mark is read
without the pass over its ~100-400 MB (0.1-0.15 s of CPU in every process that read it, issue 59); an entry
written again by anything else (another size, modification time or inode) is checked in full again.
"""
from __future__ import annotations

import collections
import contextlib
import functools
import hashlib
import json
import os
import tempfile
import time
from dataclasses import fields
from pathlib import Path

import numpy as np

from ..errors import UserError
from . import tooth

__all__ = ["CACHE_ENV", "DEFAULT_LIMIT_MB", "FE_DATA_VERSION", "LIMIT_ENV", "NOT_FE_SOURCES", "cache_dir", "cache_key",
           "cached_tooth_data", "code_digest", "entry_path", "limit_bytes", "prune", "stored_tooth_arrays"]

CACHE_ENV = "BEVELOID_CACHE_DIR"
#: the FE cache folder's size limit in MB, when set (default :data:`DEFAULT_LIMIT_MB`)
LIMIT_ENV = "BEVELOID_FE_CACHE_MB"
#: an entry of the default mesh is ~135 MB (case 1's members; ~20 MB of it the FE tooth's arrays): room for
#: about 15 member designs
DEFAULT_LIMIT_MB = 2000
#: a temporary file of an interrupted write older than this (s) is removed when the folder is pruned
ORPHAN_AGE_S = 3600.0
#: raise when the FE data's meaning changes without a change of its inputs
FE_DATA_VERSION = 4  # 2: isoparametric (curved) P2 tets, stresses from them; 3: the fillet stresses smoothed;
# 4: the fillet stresses read on a grid fixed by the geometry (fe.contact.readout_matrix)


#: the package's folders whose code never runs while FE data is made (the analyses above the FE
#: tooth, the commands, the derivations): left out of :func:`code_digest` so that editing them keeps
#: the cache; tests/fe holds this list to what a real computation executes
NOT_FE_SOURCES = ("cli", "derivations", "explore", "fecheck", "ltca", "optimize", "rating", "studies", "tca", "design")


def source_files() -> list:
    """The package's source files that can produce FE data (sorted, relative to the package)."""
    from .. import generated

    root = Path(__file__).resolve().parents[1]
    files = [p for p in root.rglob("*.py") if p.relative_to(root).parts[0] not in NOT_FE_SOURCES]
    gen = Path(generated.__file__).resolve().parent
    if not gen.is_relative_to(root):  # a checkout: generated/ beside the package
        files += list(gen.rglob("*.py"))
    return sorted(set(files))


@functools.lru_cache(maxsize=1)
def code_digest() -> str:
    """SHA-256 (hex, 16 digits) over the names and bytes of :func:`source_files`."""
    h = hashlib.sha256()
    for p in source_files():
        h.update(p.name.encode() + b"\0" + p.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def cache_dir() -> Path:
    root = os.environ.get(CACHE_ENV)
    if not root:
        import platformdirs

        root = platformdirs.user_cache_dir("beveloid")
    return Path(root) / "fe"


def _floats(values) -> list:
    return [float(v) for v in np.asarray(values, dtype=float).ravel()]


def cache_key(pair, member: str, e_mpa: float, nu: float, refinement: int, coarsen: float = 1.0,
              smooth: bool = True, window_coarsen: float | None = None) -> str:
    """The entry's key, a JSON text (see the module docstring); ``window_coarsen`` (tooth_data's) only where given."""
    from .. import __version__
    from ..tooth import fillet
    from . import contact, mesh

    from ..tooth.body import body_pair

    pair = body_pair(pair, member)
    geometry = getattr(pair, "geometry", pair)
    spec = getattr(pair, "spec", None)
    bore = float(getattr(getattr(spec, member, None), "bore_diameter_mm", 0.0) or 0.0) if spec else 0.0
    m = geometry.member(member)
    data = {
        "version": __version__, "fe_data_version": FE_DATA_VERSION, "code": code_digest(), "member": member,
        "tooth_surface": str(m.tooth_surface), "surface_params": _floats(geometry.surface_params(member)),
        "fillet_params": _floats(fillet.fillet_params(geometry, member)), "teeth": int(m.teeth),
        "face_limits_mm": _floats(m.face_limits), "tip_radius_mm": _floats(m.tip_radius(np.array(m.face_limits))),
        "normal_module_mm": float(geometry.normal_module_mm), "bore_diameter_mm": bore,
        "e_mpa": float(e_mpa), "nu": float(nu), "refinement": int(refinement), "coarsen": float(coarsen),
        "grid": list(tooth.GRID), "face_fractions": list(tooth.FACE_FRACTIONS), "depth": [tooth.DEPTH_PER_MODULE, tooth.DEPTH_PER_THICKNESS],
        "mesh_rules": mesh.MESH_RULES_VERSION,
        "mesh": [mesh.FLANK_SIZE_PER_MODULE, mesh.FAR_GROWTH, mesh.FILLET_GROWTH, mesh.FAR_SIZE_PER_MODULE, mesh.FILLET_SIZE_PER_RADIUS,
                 mesh.FILLET_SIZE_MIN_PER_MODULE, mesh.FILLET_RADIUS_ELEMENTS, mesh.FILLET_SIZE_NOTCH_PER_MODULE,
                 mesh.RIM_DEPTH_PER_HEIGHT, mesh.SECTIONS, mesh.SEGMENT_POINTS],
        "smooth": [contact.READ_FACE_PER_MODULE, contact.READ_PROFILE_PER_FILLET_SIZE, contact.READ_STEP_FACE_PER_MODULE,
                   contact.READ_STEP_PROFILE_PER_FILLET_SIZE, contact.READ_MIN_NODES,
                   contact.READ_MIN_MESH_ELEMENTS] if smooth else None,
    }
    if window_coarsen is not None:
        data["window_coarsen"] = float(window_coarsen)
    return json.dumps(data, sort_keys=True)


def entry_path(key: str) -> Path:
    member = json.loads(key)["member"]
    return cache_dir() / f"{member}-{hashlib.sha256(key.encode()).hexdigest()[:24]}.npz"


#: the name of flank f's array n (:func:`beveloid.fe.contact.tooth_arrays`) in an entry
TOOTH_ARRAY = "tooth.{}.{}"
#: members of an entry larger than this (bytes) are mapped (copy on write), not read
MAP_BYTES = 1 << 20


def _finite(a) -> bool:
    """Every entry of ``a`` finite, in one pass without a temporary: the sum of finite stresses and
    coordinates (far below 1e300) is finite, a NaN or an infinity makes it NaN or infinite."""
    a = np.asarray(a)
    return a.dtype.kind in "biu" or bool(np.isfinite(np.sum(a, dtype=float)))


def _all_finite(data, arrays: dict) -> bool:
    """Every array of an entry's data and FE tooth arrays finite (:func:`_finite`)."""
    return all(_finite(a) for a in [getattr(data, f.name) for f in fields(tooth.ToothData)]
               + [a for d in arrays.values() for a in d.values()])


#: the suffix of an entry's check mark (see the module docstring)
MARK_SUFFIX = ".finite"


def _file_id(path: Path) -> str | None:
    """The entry file's size, modification time (ns) and inode as a text, None when it is not there: any
    write of the file changes it (a write in place its time, a replacement its inode), a read does not
    (:func:`_used` keeps the modification time)."""
    try:
        st = path.stat()
    except OSError:
        return None
    return f"{st.st_size} {st.st_mtime_ns} {st.st_ino}"


def _marked(path: Path) -> bool:
    """The entry's check mark names its file as it is now: its arrays were found finite in this file."""
    try:
        mark = path.with_suffix(MARK_SUFFIX).read_text()
    except OSError:
        return False
    now = _file_id(path)
    return now is not None and mark == now


def _mark(path: Path, file_id: str | None = None) -> None:
    """Write the entry's check mark (its :func:`_file_id`, or ``file_id``: the file's before it was renamed into
    place, the same size, time and inode); a folder that cannot be written keeps no mark (the entry is then
    checked at each read)."""
    file_id = file_id or _file_id(path)
    if file_id is None:
        return
    with contextlib.suppress(OSError):
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        try:
            with os.fdopen(fd, "w") as f:
                f.write(file_id)
            os.replace(tmp, path.with_suffix(MARK_SUFFIX))
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise


def _read(path: Path, key: str):
    """(the stored data, {flank: its FE tooth arrays} or None, how); data None when absent, stale (another
    key), unreadable or not finite (checked in full unless the entry's check mark names its file: :func:`_marked`)."""
    from ..names import FLANKS

    if not path.is_file():
        return None, None, "miss"
    try:
        marked = _marked(path)
        z = _stored_arrays(path)
        if str(z["key"]) != key:
            return None, None, "stale"
        data = tooth.ToothData(**{f.name: z[f.name] for f in fields(tooth.ToothData)})
        arrays = {fl: {n.split(".", 2)[2]: a for n, a in z.items() if n.startswith(TOOTH_ARRAY.format(fl, ""))}
                  for fl in FLANKS}
        if not (marked and _marked(path)):  # the mark names the file both before and after its reading
            if not _all_finite(data, arrays):
                return None, None, "corrupt"
            _mark(path)
        return data, (arrays if all(arrays.values()) else None), "hit"
    except Exception:  # noqa: BLE001 - any unreadable entry is recomputed
        return None, None, "corrupt"


def _stored_arrays(path: Path) -> dict:
    """{name: array} of an uncompressed ``.npz`` (as :func:`_write` makes it), each member read in one
    piece from its place in the file, or mapped (copy on write) when larger than :data:`MAP_BYTES`: no
    second copy and no checksum pass over the ~100 MB of an entry (``numpy.load`` does both; the key and
    the finite check of :func:`_read` guard the content)."""
    import zipfile

    out = {}
    with zipfile.ZipFile(path) as zf, open(path, "rb") as f:
        for info in zf.infolist():
            if info.compress_type != zipfile.ZIP_STORED or not info.filename.endswith(".npy"):
                raise ValueError(f"{info.filename}: not a stored .npy member")
            f.seek(info.header_offset)
            local = f.read(30)
            if local[:4] != b"PK\x03\x04":
                raise ValueError(f"{info.filename}: no local header")
            f.seek(info.header_offset + 30 + int.from_bytes(local[26:28], "little")
                   + int.from_bytes(local[28:30], "little"))
            name = info.filename[:-4]
            if info.file_size <= MAP_BYTES:
                out[name] = np.lib.format.read_array(f, allow_pickle=False)
                continue
            version = np.lib.format.read_magic(f)
            header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, fortran, dtype = header(f)
            if dtype.hasobject:
                raise ValueError(f"{info.filename}: an object array")
            out[name] = np.memmap(path, dtype=dtype, mode="c", offset=f.tell(), shape=shape,
                                  order="F" if fortran else "C").view(np.ndarray)
    return out


def _write(path: Path, key: str, data, arrays: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    derived = {TOOTH_ARRAY.format(fl, n): a for fl, d in arrays.items() for n, a in d.items()}
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, key=np.array(key), **{fl.name: getattr(data, fl.name) for fl in fields(tooth.ToothData)},
                     **derived)
        file_id = _file_id(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    if _all_finite(data, arrays):  # checked here, in memory: a reader of this file need not
        _mark(path, file_id)


#: the data (and FE tooth arrays) of the last few keys read or computed in this process ("compute once per
#: pair and reuse": an analysis repeated on the same macro geometry does not read the file again)
_KEPT: "collections.OrderedDict" = collections.OrderedDict()
KEPT_ENTRIES = 4


def cached_tooth_data(pair, member: str, e_mpa: float, nu: float, refinement: int = 1, progress=None,
                      coarsen: float = 1.0, smooth: bool | float | tuple = True):
    """(ToothData, how: "hit" | "miss" | "stale" | "corrupt") from the cache, computing on a miss
    (``smooth``: :func:`beveloid.fe.tooth.tooth_data`'s; False for the nodal means, a benchmark's comparison;
    a number: read through the window of the mesh coarsened that many times, the rating's convergence check;
    a tuple of these: a tuple of ToothData, one entry each, those missing computed together from one solve,
    and how: "hit" where every one was).
    A cache folder that cannot be written is not an error: the data is then computed each time.
    The data of a key already read in this process is returned again ("hit") while its file is
    unchanged (same size and modification time)."""
    limit_bytes()  # a bad $BEVELOID_FE_CACHE_MB: one line before any work
    reads = smooth if isinstance(smooth, tuple) else (smooth,)
    keys = []
    for one in reads:
        window = None if isinstance(one, bool) else float(one)
        keys.append(cache_key(pair, member, e_mpa, nu, refinement, coarsen, True if window is not None else one,
                              window))
    found = [_look_up(key) for key in keys]
    missing = [i for i, (data, _) in enumerate(found) if data is None]
    if missing:
        if isinstance(smooth, tuple):
            made = tooth.tooth_data(pair, member, e_mpa, nu, refinement, progress=progress, coarsen=coarsen,
                                    smooth=tuple(reads[i] for i in missing))
        else:
            made = (tooth.tooth_data(pair, member, e_mpa, nu, refinement, progress=progress, coarsen=coarsen,
                                     smooth=smooth),)
        for i, data in zip(missing, made):
            _store(keys[i], data)
            found[i] = (data, found[i][1])
    how = next((h for _, h in found if h != "hit"), "hit")
    datas = tuple(data for data, _ in found)
    return (datas if isinstance(smooth, tuple) else datas[0]), how


def _look_up(key: str):
    """(the data of ``key`` kept in this process or read from its entry, or None; how)."""
    path = entry_path(key)
    stamp = _stamp(path)
    kept = _KEPT.get((path, key))
    if kept is not None and stamp is not None and kept[0] == stamp:
        _KEPT.move_to_end((path, key))
        return kept[1], "hit"
    data, arrays, how = _read(path, key)
    if data is not None:
        _used(path)
        _keep(path, key, data, arrays)
    return data, how


def _store(key: str, data) -> None:
    """Write new data under ``key`` (a folder that cannot be written: not kept) and keep it in this process."""
    path = entry_path(key)
    arrays = _tooth_arrays(data)
    try:
        _write(path, key, data, arrays)
        prune(keep=path)
    except OSError:
        pass
    _keep(path, key, data, arrays)


def _keep(path: Path, key: str, data, arrays) -> None:
    stamp = _stamp(path)
    if stamp is not None:
        _KEPT[path, key] = (stamp, data, arrays)
        while len(_KEPT) > KEPT_ENTRIES:
            _KEPT.popitem(last=False)


def _tooth_arrays(data) -> dict:
    """{flank: :func:`beveloid.fe.contact.tooth_arrays`} of new data, under one BLAS thread (as the
    analyses build their teeth: the same eigendecomposition)."""
    from ..names import FLANKS
    from .contact import tooth_arrays

    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional: without it BLAS keeps its own thread count
        limit = contextlib.nullcontext()
    else:
        limit = threadpool_limits(limits=1, user_api="blas")
    with limit:
        return {fl: tooth_arrays(data, fl) for fl in FLANKS}


def stored_tooth_arrays(data, flank: str) -> dict | None:
    """The FE tooth arrays of ``flank`` (:func:`beveloid.fe.contact.tooth_arrays`) kept with ``data`` (as
    :func:`cached_tooth_data` returned it, the same object) in this process; None when not known (data
    the cache did not give)."""
    for _, kept, arrays in _KEPT.values():
        if kept is data:
            return None if arrays is None else arrays.get(flank)
    return None


def limit_bytes() -> int:
    """The folder's size limit: ``$BEVELOID_FE_CACHE_MB`` (a number of MB >= 0) or :data:`DEFAULT_LIMIT_MB`."""
    text = os.environ.get(LIMIT_ENV, "").strip()
    if not text:
        return DEFAULT_LIMIT_MB * 10**6
    try:
        mb = float(text)
    except ValueError:
        mb = -1.0
    if not mb >= 0.0:
        raise UserError(f"{LIMIT_ENV} = {text!r}: must be a number of MB >= 0 (the FE cache folder's size limit)")
    return int(mb * 10**6)


def prune(keep: Path | None = None) -> list:
    """Remove the least recently used entries (by access time: written or read, :func:`_used`) until the
    folder's ``.npz`` files fit in :func:`limit_bytes`, never ``keep`` (the entry just written), and
    the temporary files of interrupted writes older than :data:`ORPHAN_AGE_S` (and the check marks of entries no
    longer there).  Entries made by
    other code (another :func:`code_digest`) are never read again by this install and age out this
    way.  Returns the paths removed."""
    folder = cache_dir()
    removed = []
    now = time.time()
    entries = []
    for p in folder.glob("*"):
        try:
            st = p.stat()
        except OSError:
            continue
        if p.suffix == ".tmp" and now - st.st_mtime > ORPHAN_AGE_S:
            with contextlib.suppress(OSError):
                p.unlink()
                removed.append(p)
        elif p.suffix == ".npz":
            entries.append((max(st.st_atime, st.st_mtime), st.st_size, p))
        elif p.suffix == MARK_SUFFIX and not p.with_suffix(".npz").exists():  # its entry removed
            with contextlib.suppress(OSError):
                p.unlink()
    total, limit = sum(e[1] for e in entries), limit_bytes()
    for _, size, p in sorted(entries, key=lambda e: e[0]):
        if total <= limit:
            break
        if keep is not None and p == keep:
            continue
        with contextlib.suppress(OSError):
            p.unlink()
            removed.append(p)
            total -= size
            p.with_suffix(MARK_SUFFIX).unlink(missing_ok=True)
    return removed


def _used(path: Path) -> None:
    """Mark an entry read now: its access time (what :func:`prune` orders by), not its modification time,
    which stays the entry's :func:`_stamp`: a read by one process (another worker of the same command)
    must not make every other process's copy of the entry look changed (issue 59: the two workers of
    ``optimize --workers 2`` read a ~100 MB entry again on most of their calls, each read marking it)."""
    with contextlib.suppress(OSError):
        os.utime(path, ns=(time.time_ns(), path.stat().st_mtime_ns))


def _stamp(path: Path):
    """(size, mtime_ns) of a cache entry, None when it is not there: it changes when the entry is written
    (replaced or rewritten), not when it is read (:func:`_used`)."""
    try:
        st = path.stat()
    except OSError:
        return None
    return st.st_size, st.st_mtime_ns
