"""Which tooth-surface models there are: built-in, the user model folder, and installed packages.

A model made by ``beveloid derive --model FILE --name NAME`` is a folder ``<models dir>/NAME/``
holding its generated kernels (``surface_NAME.py``, ``surface_NAME_scalar.py``), its parameter
layout (``layout.py``) and its interface (``model.json``: keys, units, ranges, the glue entry the
runtime composes the dispatch from, the derivation module's SHA-256 and the package stamp it was
generated for).  Nothing here imports or runs a derivation module: the catalog reads model.json
files and, to tell a stale model, hashes the derivation module's bytes.

Where models come from, in this order (a name found twice is taken from the first place):

1. the built-in models (generated/surface_models.py);
2. the user model folder: ``BEVELOID_MODELS_DIR`` or ``platformdirs.user_data_dir("beveloid")/models``;
3. packages that declare an entry point in the group ``beveloid.models`` whose value names a
   module or package: the model folders below its folder (a lab ships ``derive --out`` output).

A model is *stale* when its derivation module changed since it was generated (its file still
exists and hashes differently) or when it was generated for another package (version, glue
templates or built-in glue changed): it is left out of the dispatch, and a spec naming it gets one
line saying so and how to regenerate it.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

#: the environment variable naming the user model folder
MODELS_ENV = "BEVELOID_MODELS_DIR"
#: the entry-point group of packages that ship models
ENTRY_POINT_GROUP = "beveloid.models"
#: the interface file of a model folder
INTERFACE = "model.json"
#: what model.json's "format" must be
FORMAT = 1
#: a model's name: a Python identifier in lower case (it names modules and TOML values)
NAME_PATTERN = re.compile(r"^[a-z][a-z0-9_]{0,39}$")
#: the templates the runtime composes the glue from, and the built-in glue they must reproduce
GLUE_TEMPLATES = {"tca_kernels": "tca_kernels.py.jinja", "tca_kernels_scalar": "tca_kernels_scalar.py.jinja",
                  "surface_models": "surface_models.py.jinja"}
_STAMPED_TEMPLATES = tuple(GLUE_TEMPLATES.values()) + ("module.py.jinja", "scalar_module.py.jinja", "layouts.py.jinja")


@dataclass(frozen=True)
class ModelInfo:
    """One model: its name, where it comes from, its folder (None: built-in), its interface."""

    name: str
    origin: str  # "built-in", "user folder" or "package <entry point>"
    folder: Path | None
    interface: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def entry(self) -> dict:
        """Its entry of the glue context (derivations/kernels.model_entry)."""
        return self.interface["glue"]["model"]

    def regenerate_hint(self) -> str:
        src = self.interface.get("source", {}).get("path") or "FILE"
        out = "" if self.folder is None or self.folder.parent == models_dir() else f" --out {self.folder.parent}"
        return f"beveloid derive --model {src} --name {self.name}{out}"


@dataclass(frozen=True)
class Catalog:
    """The models found: ``user`` (usable, in dispatch order after the built-in ones) and ``stale``
    ({name: (ModelInfo, reason)}); ``builtin`` the names of the built-in models."""

    builtin: tuple[str, ...]
    user: tuple[ModelInfo, ...]
    stale: dict

    def problem(self, name: str) -> str | None:
        """Why a model name cannot be used (None when it can): unknown or stale, and what to do."""
        if name in self.builtin or any(m.name == name for m in self.user):
            return None
        if name in self.stale:
            info, reason = self.stale[name]
            return (f"the model \"{name}\" ({info.origin}, {info.folder}) is stale: {reason}; regenerate it:"
                    f" {info.regenerate_hint()}")
        known = ", ".join(f'"{m}"' for m in (*self.builtin, *(m.name for m in self.user)))
        return (f"no such tooth-surface model (models: {known}); make one with"
                f" beveloid derive --model FILE --name {name} (docs/models.md), list them with beveloid models")


def models_dir() -> Path:
    """The user model folder: BEVELOID_MODELS_DIR, else platformdirs' user data folder + /models."""
    env = os.environ.get(MODELS_ENV)
    if env:
        return Path(env).expanduser()
    try:
        import platformdirs

        return Path(platformdirs.user_data_dir("beveloid")) / "models"
    except ImportError:  # platformdirs is a dependency; its XDG default otherwise
        base = os.environ.get("XDG_DATA_HOME") or os.path.join(os.path.expanduser("~"), ".local", "share")
        return Path(base) / "beveloid" / "models"


def package_folder(sub: str) -> Path:
    """The folder of beveloid.<sub> (generated or derivations) without importing its modules."""
    import importlib.util

    spec = importlib.util.find_spec(f"beveloid.{sub}")
    return Path(list(spec.submodule_search_locations)[0])


def package_stamp() -> str:
    """What a generated model must have been made for: the package version, the glue and kernel
    templates and the built-in glue (a digest; a model with another stamp is stale)."""
    from .. import __version__

    digest = hashlib.sha256(__version__.encode())
    templates = package_folder("derivations") / "templates"
    for name in _STAMPED_TEMPLATES:
        digest.update((templates / name).read_bytes())
    generated = package_folder("generated")
    for name in ("surface_models.py", "tca_kernels.py", "tca_kernels_scalar.py", "layouts.py"):
        digest.update((generated / name).read_bytes())
    return digest.hexdigest()[:16]


def file_sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def read_interface(folder: Path) -> dict | None:
    """A model folder's model.json (None when it is not a model folder or unreadable)."""
    try:
        data = json.loads((folder / INTERFACE).read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and data.get("format") == FORMAT else None


#: what a model's glue entry holds (derivations/kernels.model_entry)
ENTRY_FIELDS = ("name", "module", "layout", "nparams", "input_keys", "selected_by", "choice_keys")


def name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a model (its modules would clash with the glue's), None if it can."""
    if not NAME_PATTERN.match(name):
        return "must be lower-case letters, digits and _ starting with a letter (at most 40)"
    if name == "models" or name.endswith("_scalar"):
        return "names a module of the glue (surface_models) or a scalar twin (surface_*_scalar); choose another"
    return None


def _staleness(info: ModelInfo, stamp: str) -> str | None:
    face = info.interface
    name = info.name
    if name_problem(name) or face.get("name") != name:
        return f"its folder name and model.json name differ ({face.get('name')!r}) or cannot name a model"
    glue = face.get("glue")
    if not isinstance(glue, dict) or not {"base", "builtin", "model"} <= set(glue) or not all(
            k in glue["model"] for k in ENTRY_FIELDS):
        return "its model.json is incomplete (not written by beveloid derive --model)"
    if face.get("package_stamp") != stamp:
        return (f"it was generated for beveloid {face.get('beveloid_version')} (stamp {face.get('package_stamp')}),"
                f" this is another build (stamp {stamp})")
    for fname, sha in face.get("files", {}).items():
        path = info.folder / fname
        if not path.is_file() or file_sha256(path) != sha:
            return f"its generated file {fname} is missing or was edited"
    src = face.get("source", {})
    path = src.get("path")
    if path and os.path.isfile(path) and file_sha256(path) != src.get("sha256"):
        return f"its derivation module {path} changed since it was generated"
    return None


def _entry_point_folders():
    """(entry point name, folder) of every installed package that ships models."""
    import importlib.metadata
    import importlib.util

    out = []
    for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        module = ep.value.split(":")[0].strip()
        try:
            spec = importlib.util.find_spec(module)
        except (ImportError, ValueError):
            spec = None
        if spec is None:
            continue
        if spec.submodule_search_locations:
            out.append((ep.name, Path(list(spec.submodule_search_locations)[0])))
        elif spec.origin:
            out.append((ep.name, Path(spec.origin).parent))
    return out


def _folder_models(root: Path, origin: str):
    try:
        subs = sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith("."))
    except OSError:
        return []
    out = []
    for sub in subs:
        face = read_interface(sub)
        if face is not None:
            out.append(ModelInfo(sub.name, origin, sub, face))
    return out


def discover(builtin: tuple[str, ...]) -> Catalog:
    """Every model of the user folder and of the packages, usable or stale (built-in names win)."""
    found = _folder_models(models_dir(), "user folder")
    for ep_name, folder in _entry_point_folders():
        found += _folder_models(folder, f"package {ep_name}")
    if not found:
        return Catalog(tuple(builtin), (), {})
    stamp = package_stamp()
    user, stale, seen = [], {}, set(builtin)
    for info in found:
        if info.name in seen:
            continue
        seen.add(info.name)
        reason = _staleness(info, stamp)
        if reason is None:
            user.append(info)
        else:
            stale[info.name] = (info, reason)
    return Catalog(tuple(builtin), tuple(user), stale)
