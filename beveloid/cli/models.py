"""``beveloid models [--json]``: every tooth-surface model there is, with its keys, units and ranges.

Built-in models, the user model folder's (``beveloid derive --model``) and those of installed
packages (entry points ``beveloid.models``); stale models are listed with the reason and the
command that regenerates them.  docs/models.md is the guide.
"""
from __future__ import annotations

import argparse
import json
import sys


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="print the list as JSON")


def _keys(model, surface_models) -> list:
    keys = [dict(key=k, unit=unit, default=d, lowest=lo, highest=hi, description=doc)
            for k, (unit, d, lo, hi, doc) in surface_models.MODEL_KEYS.get(model, {}).items()]
    keys += [dict(key=k, unit="", default=d, choices=sorted(ch), description=doc)
             for k, (d, ch, doc) in surface_models.MODEL_CHOICES.get(model, {}).items()]
    return keys


def _entry_keys(info) -> list:
    """The keys a (stale) model's model.json states ([] when it states none readable)."""
    try:
        return _glue_keys(info.entry)
    except (KeyError, TypeError):
        return []


def _glue_keys(entry) -> list:
    keys = [dict(key=k["name"], unit=k["unit"], default=k["default"], lowest=k["lo"], highest=k["hi"],
                 description=k["doc"]) for k in entry["input_keys"]]
    keys += [dict(key=k["name"], unit="", default=k["default"], choices=sorted(c["name"] for c in k["choices"]),
                  description=k["doc"]) for k in entry["choice_keys"]]
    return keys


def listing() -> dict:
    """{"models": [...], "stale": [...], "user_folder": path}: what ``beveloid models`` prints."""
    from ..generated import surface_models
    from ..models import catalog, models_dir

    cat = catalog()
    user = {m.name: m for m in cat.user}
    rows = []
    for name in surface_models.MODELS:
        m = user.get(name)
        row = dict(name=name, origin="built-in" if m is None else m.origin, keys=_keys(name, surface_models))
        if m is not None:
            row.update(folder=str(m.folder), source=m.interface.get("source", {}).get("path"),
                       beveloid_version=m.interface.get("beveloid_version"))
        rows.append(row)
    stale = [dict(name=name, origin=info.origin, folder=str(info.folder), reason=reason,
                  regenerate=info.regenerate_hint(), keys=_entry_keys(info))
             for name, (info, reason) in cat.stale.items()]
    return dict(models=rows, stale=stale, user_folder=str(models_dir()))


def _key_text(k) -> str:
    if "choices" in k:
        return f"    {k['key']}: one of {', '.join(k['choices'])} (default {k['default']}); {k['description']}"
    unit = f" {k['unit']}" if k["unit"] else ""
    return (f"    {k['key']}: {k['lowest']:g} to {k['highest']:g}{unit} (default {k['default']:g});"
            f" {k['description']}")


def run(args: argparse.Namespace) -> int:
    """List every tooth-surface model (built-in, user folder, packages) with its keys, units and ranges."""
    out = listing()
    if args.json:
        sys.stdout.write(json.dumps(out, indent=1, allow_nan=False) + "\n")
        return 0
    lines = []
    for row in out["models"]:
        where = "" if row["origin"] == "built-in" else f" ({row['folder']}, from {row['source']})"
        lines.append(f"{row['name']}: {row['origin']}{where}" + ("" if row["keys"] else "; no keys of its own"))
        lines += [_key_text(k) for k in row["keys"]]
    for row in out["stale"]:
        lines.append(f"{row['name']}: STALE, {row['origin']} ({row['folder']}): {row['reason']}; regenerate:"
                     f" {row['regenerate']}")
    lines.append(f"user model folder: {out['user_folder']} (BEVELOID_MODELS_DIR overrides; beveloid derive --model"
                 " FILE --name NAME adds one; docs/models.md)")
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
