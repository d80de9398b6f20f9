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
