"""Tooth-surface models beyond the built-in ones: the user model folder and packages.

``beveloid derive --model FILE --name NAME`` (derivations/user_model.py) generates a model's
kernels and interface into a model folder; :mod:`.catalog` finds the models (user folder,
``beveloid.models`` entry points) and tells stale ones; :mod:`.hook` composes the glue so that
every analysis reaches them by name (numpy) and by index (the solver core, either backend).
docs/models.md is the user's guide.
"""
from .catalog import ENTRY_POINT_GROUP, MODELS_ENV, Catalog, ModelInfo, models_dir, package_folder, package_stamp
from .hook import builtin_models, catalog, install, render_glue, served_files

__all__ = ["ENTRY_POINT_GROUP", "MODELS_ENV", "Catalog", "ModelInfo", "builtin_models", "catalog", "install",
           "models_dir", "package_folder", "package_stamp", "render_glue", "served_files"]
