"""The FE tooth's data, computed once per member design and kept in the user cache folder.

Folder: ``$BEVELOID_CACHE_DIR/fe`` when set, else ``platformdirs.user_cache_dir("beveloid")/fe``.
An entry is one ``.npz`` per (member design, material, refinement), named by a SHA-256 digest of
its key: everything the data depends on (the member's generated-surface and fillet parameters, its
teeth, face, tip and bore, E and nu, the refinement, the load grid and reading depth constants) plus
the package version and :data:`FE_DATA_VERSION`.  The key is stored inside the entry and compared on
reading: an entry whose key differs (stale) or that cannot be read (corrupt, truncated) is computed
again and replaced, never used.  Entries are written to a temporary file and renamed into place.
"""
from __future__ import annotations

import hashlib
import json
import os
import tempfile
from dataclasses import fields
from pathlib import Path

import numpy as np

from . import tooth

__all__ = ["CACHE_ENV", "FE_DATA_VERSION", "cache_dir", "cache_key", "cached_tooth_data", "entry_path"]

CACHE_ENV = "BEVELOID_CACHE_DIR"
#: raise when the FE data's meaning changes without a change of its inputs
FE_DATA_VERSION = 2  # 2: isoparametric (curved) P2 tets, stresses from them


def cache_dir() -> Path:
    root = os.environ.get(CACHE_ENV)
    if not root:
        import platformdirs

        root = platformdirs.user_cache_dir("beveloid")
    return Path(root) / "fe"


def _floats(values) -> list:
    return [float(v) for v in np.asarray(values, dtype=float).ravel()]


def cache_key(pair, member: str, e_mpa: float, nu: float, refinement: int, coarsen: float = 1.0) -> str:
    """The entry's key, a JSON text (see the module docstring)."""
    from .. import __version__
    from ..tooth import fillet
    from . import mesh

    geometry = getattr(pair, "geometry", pair)
    spec = getattr(pair, "spec", None)
    bore = float(getattr(getattr(spec, member, None), "bore_diameter_mm", 0.0) or 0.0) if spec else 0.0
    m = geometry.member(member)
    data = {
        "version": __version__, "fe_data_version": FE_DATA_VERSION, "member": member,
        "tooth_surface": str(m.tooth_surface), "surface_params": _floats(geometry.surface_params(member)),
        "fillet_params": _floats(fillet.fillet_params(geometry, member)), "teeth": int(m.teeth),
        "face_limits_mm": _floats(m.face_limits), "tip_radius_mm": _floats(m.tip_radius(np.array(m.face_limits))),
        "normal_module_mm": float(geometry.normal_module_mm), "bore_diameter_mm": bore,
        "e_mpa": float(e_mpa), "nu": float(nu), "refinement": int(refinement), "coarsen": float(coarsen),
        "grid": list(tooth.GRID), "depth": [tooth.DEPTH_PER_MODULE, tooth.DEPTH_PER_THICKNESS],
        "mesh_rules": mesh.MESH_RULES_VERSION,
        "mesh": [mesh.FLANK_SIZE_PER_MODULE, mesh.FAR_GROWTH, mesh.FILLET_GROWTH, mesh.FAR_SIZE_PER_MODULE, mesh.FILLET_SIZE_PER_RADIUS,
                 mesh.FILLET_SIZE_MIN_PER_MODULE, mesh.RIM_DEPTH_PER_HEIGHT, mesh.SECTIONS, mesh.SEGMENT_POINTS],
    }
    return json.dumps(data, sort_keys=True)


def entry_path(key: str) -> Path:
    member = json.loads(key)["member"]
    return cache_dir() / f"{member}-{hashlib.sha256(key.encode()).hexdigest()[:24]}.npz"


def _read(path: Path, key: str):
    """The stored data, or None when absent, stale (another key) or unreadable."""
    if not path.is_file():
        return None, "miss"
    try:
        with np.load(path, allow_pickle=False) as z:
            if str(z["key"]) != key:
                return None, "stale"
            data = tooth.ToothData(**{f.name: np.array(z[f.name]) for f in fields(tooth.ToothData)})
        if not all(np.all(np.isfinite(getattr(data, f.name))) for f in fields(tooth.ToothData)):
            return None, "corrupt"
        return data, "hit"
    except Exception:  # noqa: BLE001 - any unreadable entry is recomputed
        return None, "corrupt"


def _write(path: Path, key: str, data) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, key=np.array(key), **{fl.name: getattr(data, fl.name) for fl in fields(tooth.ToothData)})
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def cached_tooth_data(pair, member: str, e_mpa: float, nu: float, refinement: int = 1, progress=None,
                      coarsen: float = 1.0):
    """(ToothData, how: "hit" | "miss" | "stale" | "corrupt") from the cache, computing on a miss.
    A cache folder that cannot be written is not an error: the data is then computed each time."""
    key = cache_key(pair, member, e_mpa, nu, refinement, coarsen)
    path = entry_path(key)
    data, how = _read(path, key)
    if data is not None:
        return data, how
    data = tooth.tooth_data(pair, member, e_mpa, nu, refinement, progress=progress, coarsen=coarsen)
    try:
        _write(path, key, data)
    except OSError:
        pass
    return data, how
