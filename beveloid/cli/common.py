"""What several commands share: the five assembly-error flags (``--dx`` ... ``--horizontal``,
overriding the spec's ``[misalignment]``), the one-line label of a spec's errors, and how a table
writes a number (:func:`number`: no ``-0.000``)."""
from __future__ import annotations

import argparse

import numpy as np

from .. import assembly_errors
from ..errors import UserError

FLAG_OF_KEY = {e.key: e.flag for e in assembly_errors.ERRORS}


def add_error_flags(p: argparse.ArgumentParser) -> None:
    """--dx ... --horizontal: the five assembly errors, overriding the file's [misalignment]."""
    for e in assembly_errors.ERRORS:
        p.add_argument(e.flag, dest=e.key, type=float, metavar=e.unit.upper(),
                       help=f"{e.description} ({e.unit}); overrides [misalignment]")


def apply_error_flags(spec, args: argparse.Namespace):
    """The spec with the error flags given on the command line; errors name the flag."""
    from ..spec import SpecError, misalignment_with

    try:
        return misalignment_with(spec, **{k: getattr(args, k) for k in assembly_errors.KEYS})
    except SpecError as exc:  # name the flag the user typed, not the TOML key
        msg = str(exc)
        for key, flag in FLAG_OF_KEY.items():
            msg = msg.replace(f"misalignment.{key}", flag)
        raise UserError(msg) from None


def error_vector(spec) -> np.ndarray:
    """The spec's [misalignment] as the kernels' (5,) error vector (mm, rad)."""
    return assembly_errors.to_layout(spec.misalignment)


def errors_label(spec) -> str:
    """The spec's assembly errors in one line (titles and summaries)."""
    return assembly_errors.label(spec.misalignment)


def number(value, spec: str, missing: str = "-") -> str:
    """``value`` formatted by ``spec`` for a table: ``missing`` for None or a non-finite value, and a
    value that rounds to zero written without a sign (``0.000``, not ``-0.000``)."""
    import math

    if value is None or not math.isfinite(value):
        return missing
    text = format(value, spec)
    if text.lstrip().startswith("-") and float(text) == 0.0:
        text = format(0.0, spec)
    return text


def solver_of(backend: str):
    """The :class:`beveloid.solver.Solver` of a ``--backend`` name: the one conversion of a user's backend
    name (one line naming the flag, the value and what is valid: a UserError)."""
    from ..solver import Solver
    from ..solver.backends import BackendError

    try:
        return Solver(backend)
    except BackendError as exc:
        raise UserError(f"--backend = {backend}: {exc.requirement}") from None


# ---------------------------------------------------------------------------------------------
# the loaded analyses' options and load case: declared once, read by every command that takes them
# ---------------------------------------------------------------------------------------------

def _grid_help(default):
    from ..ltca.options import DEFAULT_GRID

    return (f"contact cells across x along the contact line per tooth pair (default {DEFAULT_GRID[0]}x{DEFAULT_GRID[1]}, "
            "each cell a fixed fraction of the pair's Hertz semi-axes)")


def _positions_help(default):
    from ..mesh import cycle_positions_help

    return cycle_positions_help(default)


#: every field of ltca.Options a command line sets: (field, flag, argparse keywords, help(default)); the one
#: declaration of these flags (``ltca``, ``rating``, ``optimize``, ``fe-check``: :func:`add_ltca_flags`)
LTCA_FLAGS = (
    ("flank", "--flank", {"choices": ("left", "right")}, lambda d: f"loaded flank pair (default {d})"),
    ("positions", "--positions", {"type": int, "metavar": "N"}, _positions_help),
    ("pairs", "--pairs", {"type": int, "metavar": "K"}, lambda d: f"neighbouring tooth pairs (default {d})"),
    ("grid", "--grid", {"metavar": "ACROSSxALONG"}, _grid_help),
    ("tooth_model", "--tooth-model", {"choices": ("fe", "plate")},
     lambda d: "how the teeth bend: fe = finite-element tooth from the real geometry with root stress (default when "
               "gmsh and scikit-fem are installed; its data is cached per design), plate = the "
               "equivalent-spur-tooth plate (no FE data to compute, no root stress; slower per analysis than "
               "a cached FE tooth)"),
    ("fe_refinement", "--fe-refinement", {"type": int, "metavar": "N"},
     lambda d: f"FE tooth mesh refinement, 1-4 (default {d}; 2 halves every element size)"),
    ("fe_coarsen", "--fe-coarsen", {"type": float, "metavar": "F"},
     lambda d: f"every FE tooth element size times F, 1-8 (default {d:g}; 2-4: a quick, rougher tooth)"),
)
#: the flag of each ltca.Options field a command line sets
LTCA_FLAG_OF_KEY = {key: flag for key, flag, _, _ in LTCA_FLAGS}


def add_ltca_flags(p: argparse.ArgumentParser, only=None, **defaults) -> None:
    """The flags of :data:`LTCA_FLAGS` (``only``: those fields) with ltca.Options' defaults, or a command's own
    (``positions=10``)."""
    import dataclasses

    from ..ltca.options import Options

    base = {f.name: f.default for f in dataclasses.fields(Options)}
    unknown = set(defaults) - set(LTCA_FLAG_OF_KEY)
    assert not unknown, f"not flags of ltca.Options: {sorted(unknown)}"
    for key, flag, kwargs, text in LTCA_FLAGS:
        if only is not None and key not in only:
            continue
        default = defaults.get(key, base[key])
        p.add_argument(flag, dest=key, default=default, help=text(default), **kwargs)


def parse_grid(text):
    """(across, along) from 'AxB', None when not given; the range is ltca.options' (one line if bad)."""
    import re

    from ..errors import OptionError
    from ..ltca.options import check_grid

    if text is None or isinstance(text, tuple):
        return text
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text)
    try:
        return check_grid((int(m[1]), int(m[2])) if m else text, key="--grid")
    except OptionError as exc:  # named by its fields: the flag and the text as typed
        raise UserError(exc.for_flag("--grid", shown=text)) from None


class named_by_flag:
    """``with named_by_flag(flags): ...``: an OptionError becomes a UserError naming the command-line flag of
    its key (``flags``, else an ltca.Options flag, else ``--key-with-dashes``)."""

    def __init__(self, flags=None):
        self.flags = {**LTCA_FLAG_OF_KEY, "torque_nm": "--torque-nm", **(flags or {})}

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        from ..errors import OptionError

        if isinstance(exc, OptionError):
            flag = self.flags.get(exc.key, "--" + str(exc.key).replace("_", "-"))
            raise UserError(exc.for_flag(flag)) from None
        return False


def ltca_options(args: argparse.Namespace, **over):
    """The ltca.Options of the flags of :func:`add_ltca_flags` (``over``: fields set by the command),
    checked against its range table and the memory; a bad value: one line naming the flag."""
    from ..ltca.options import Options

    values = {key: getattr(args, key) for key in LTCA_FLAG_OF_KEY}
    values["grid"] = parse_grid(values["grid"])
    values.update(over)
    with named_by_flag({"grid": "--grid"}):
        options = Options(**values)
        options.check_memory()
    return options


def parse_torques(text) -> list:
    """The torques of ``--torque-nm`` (one or a comma list), each checked as ltca.LoadCase does."""
    from ..errors import OptionError
    from ..ltca.options import check_torque

    out = []
    for part in str(text).split(","):
        try:
            value = float(part)
        except ValueError:
            value = part.strip()
        try:
            out.append(check_torque(value, key="--torque-nm"))
        except OptionError as exc:
            raise UserError(exc.for_flag("--torque-nm", shown=text)) from None
    return out


def load_case(torque, errors=None):
    """The ltca.LoadCase of ``--torque-nm`` (a number, or a text with one torque or a comma list: a map)."""
    from ..ltca.load import LoadCase

    if isinstance(torque, str):
        torques = parse_torques(torque)
        torque = torques[0] if len(torques) == 1 else torques
    with named_by_flag():
        return LoadCase(torque, errors)
