"""User models in ``beveloid.generated``: the glue composed over built-in and user models.

The runtime reaches every surface model through three generated glue modules:
``surface_models`` (names and keys, read by the spec), ``tca_kernels`` (numpy dispatch by name)
and ``tca_kernels_scalar`` (dispatch by model index, which the solver core calls and the
compiled backend compiles).  When the catalog (:mod:`.discovery`) holds usable user models, an
import hook serves these three modules from a composition rendered with the package's own glue
templates over the built-in models followed by the user models (``derive --model`` checks that
the same rendering of the built-in models alone is byte-identical to the committed glue), and
serves ``beveloid.generated.surface_<name>[_scalar]`` and ``layout_<name>`` from the model's
folder.  The composition is written once to the cache folder (``BEVELOID_CACHE_DIR`` or
platformdirs' user cache folder), under a digest of what it was rendered from, so that numba's
on-disk cache can key the compiled core by its sources (beveloid/solver/backends.py: every
compiled source is in the stamp, so a core compiled with other models is never reused).

Without user models nothing is served: the committed modules are imported as they are.  The hook
never imports a derivation module; it loads generated code only.
"""
from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.machinery
import importlib.util
import json
import os
import tempfile
from pathlib import Path

from ..errors import UserCodeError, UserError
from .discovery import GLUE_TEMPLATES, Catalog, discover

from .names import PACKAGE

#: the environment variable of the cache folder (shared with the compiled solver's cache)
CACHE_ENV = "BEVELOID_CACHE_DIR"
_STATE: dict = {}


def catalog() -> Catalog:
    """The models of this process (discovered once, on first use)."""
    _activate()
    return _STATE["catalog"]


def served_files() -> dict:
    """{module name in beveloid.generated: file} of what the hook serves ({} without user models)."""
    _activate()
    return dict(_STATE["files"])


@functools.lru_cache(maxsize=None)
def builtin_models() -> tuple[str, ...]:
    """The built-in model names, read from the committed surface_models.py (not the composed one)."""
    path = _generated_dir() / "surface_models.py"
    spec = importlib.util.spec_from_file_location(f"{PACKAGE}._builtin_surface_models", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return tuple(mod.MODELS)


def _generated_dir() -> Path:
    pkg = importlib.import_module(PACKAGE)
    return Path(list(pkg.__path__)[0])


def glue_environment(templates: Path):
    """The jinja2 environment of the glue templates (the generator's settings, derivations/codegen.py)."""
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(templates)), keep_trailing_newline=True,
                              trim_blocks=True, lstrip_blocks=False, undefined=jinja2.StrictUndefined)


def render_glue(context: dict) -> dict:
    """{module name: text} of the three glue modules for a glue context (kernels.glue_context)."""
    from .discovery import package_folder

    env = glue_environment(package_folder("derivations") / "templates")
    return {name: env.get_template(tpl).render(**context) for name, tpl in GLUE_TEMPLATES.items()}


def composed_context(cat: Catalog) -> dict:
    """The glue context of the built-in models followed by the catalog's usable user models."""
    glue = cat.user[0].interface["glue"]
    return dict(glue["base"], models=list(glue["builtin"]) + [m.entry for m in cat.user])


def _cache_root() -> Path:
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env).expanduser()
    try:
        import platformdirs

        return Path(platformdirs.user_cache_dir("beveloid"))
    except ImportError:
        return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "beveloid"


def _glue_folder(context: dict) -> Path:
    """The folder holding the composed glue of a context: rendered and written once (atomically,
    several processes may race), found again by a digest of the context and the templates."""
    from .discovery import package_folder

    templates = package_folder("derivations") / "templates"
    digest = hashlib.sha256(json.dumps(context, sort_keys=True).encode())
    for tpl in GLUE_TEMPLATES.values():
        digest.update((templates / tpl).read_bytes())
    name = f"glue-{digest.hexdigest()[:16]}"
    roots = (_cache_root(), Path(tempfile.gettempdir()) / f"beveloid-{os.getuid() if hasattr(os, 'getuid') else 'u'}")
    for root in roots:
        folder = root / "models" / name
        if all((folder / f"{m}.py").is_file() for m in GLUE_TEMPLATES):
            return folder
    texts = render_glue(context)
    for root in roots:
        folder = root / "models" / name
        try:
            folder.mkdir(parents=True, exist_ok=True)
            for module, text in texts.items():
                tmp = folder / f".{module}.{os.getpid()}.tmp"
                tmp.write_text(text)
                os.replace(tmp, folder / f"{module}.py")
            return folder
        except OSError:
            continue
    raise OSError("no writable folder for the composed model glue: set BEVELOID_CACHE_DIR to a writable folder")


def _activate() -> None:
    if "catalog" in _STATE:
        return
    pkg = importlib.import_module(PACKAGE)
    cat = discover(builtin_models())
    files: dict = {}
    if cat.user:
        try:
            files = _compose(pkg, cat)
        except Exception as exc:  # noqa: BLE001  (a broken composition must not break the built-in models)
            stale = dict(cat.stale, **{m.name: (m, f"its glue could not be composed ({exc})") for m in cat.user})
            cat, files = Catalog(cat.builtin, (), stale), {}
    _STATE["files"] = files
    _STATE["catalog"] = cat


def _compose(pkg, cat: Catalog) -> dict:
    """Write the composed glue; {module: file} of everything served; the package lists the user kernels."""
    folder = _glue_folder(composed_context(cat))
    files = {name: folder / f"{name}.py" for name in GLUE_TEMPLATES}
    for m in cat.user:
        module = m.entry["module"]
        files[module] = m.folder / f"{module}.py"
        files[f"{module}_scalar"] = m.folder / f"{module}_scalar.py"
        files[f"layout_{m.name}"] = m.folder / "layout.py"
    # the compiled backend compiles every scalar module the package lists (solver/backends.py)
    pkg.MODULES = tuple(pkg.MODULES) + tuple(m.entry["module"] for m in cat.user)
    pkg.SCALAR_MODULES = tuple(pkg.SCALAR_MODULES) + tuple(f"{m.entry['module']}_scalar" for m in cat.user)
    return files


class _Loader(importlib.machinery.SourceFileLoader):
    """Loads a served module; before the numpy glue runs, the user models' layout classes join
    beveloid.generated.layouts (the glue names each model's layout there).  A module of a user
    model that fails to load is the model's failure: UserCodeError (its file and line, the frames
    in its folder's files), whichever analysis loaded it first."""

    def exec_module(self, module):
        if module.__name__ == f"{PACKAGE}.tca_kernels":
            layouts = importlib.import_module(f"{PACKAGE}.layouts")
            for m in _STATE["catalog"].user:
                lay = importlib.import_module(f"{PACKAGE}.layout_{m.name}")
                setattr(layouts, m.entry["layout"], getattr(lay, m.entry["layout"]))
        try:
            super().exec_module(module)
        except UserError:  # a model module that this one imports (the glue imports every model's)
            raise
        except Exception as exc:
            model = next((m for m in _STATE["catalog"].user if Path(self.path).parent == m.folder), None)
            if model is None:
                raise
            files = [f for f in _STATE["files"].values() if f.parent == model.folder]
            err = UserCodeError.from_exception(
                exc, files, f"while loading the model \"{model.name}\" ({model.origin}, {model.folder});"
                            f" regenerate it: {model.regenerate_hint()}")
            if err is None:
                raise
            raise err from exc


def served_spec(fullname: str, short: str):
    """The module spec the hook serves for beveloid.generated.<short> (None: the committed module)."""
    _activate()
    where = _STATE["files"].get(short)
    if where is None:
        return None
    return importlib.util.spec_from_file_location(fullname, str(where), loader=_Loader(fullname, str(where)))
