"""Tooth-surface models beyond the built-in ones: the user model folder and packages.

``beveloid derive --model FILE --name NAME`` (derivations/user_model.py) generates a model's
kernels and interface into a model folder; :mod:`.discovery` finds the models (user folder,
``beveloid.models`` entry points) and tells stale ones; :mod:`.hook` composes the glue so that
every analysis reaches them by name (numpy) and by index (the solver core, either backend);
:mod:`.finder` is the import hook's cheap entry.  docs/models.md is the user's guide.

The names below are imported on first use (``import beveloid`` imports only the finder).
"""
from .finder import install

__all__ = ["ENTRY_POINT_GROUP", "MODELS_ENV", "Catalog", "ModelInfo", "builtin_models", "catalog", "install",
           "models_dir", "package_folder", "package_stamp", "render_glue", "served_files"]

_FROM_CATALOG = ("ENTRY_POINT_GROUP", "MODELS_ENV", "Catalog", "ModelInfo", "models_dir", "package_folder",
                 "package_stamp")


def __getattr__(name):
    if name in _FROM_CATALOG:
        from . import discovery as module
    elif name in __all__:
        from . import hook as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)
