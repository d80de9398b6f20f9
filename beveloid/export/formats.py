"""The export formats: one :class:`Writer` per format name in :data:`WRITERS` (issue 30, item 6).

A writer says what its files end in, which extra of the package it needs (and the modules that
extra brings, to check before any work), how to build one member, place it in the fixed frame, and
write one or several members to a file.  ``beveloid export --format`` offers exactly the names of
:data:`WRITERS`, and :func:`install_hint` says what to install for a writer's extra, worded for how
the package runs (a source checkout, or an installed copy).  A new format (a CalculiX deck, a VTU
of the tooth) is one more ``register(Writer(...))`` here.
"""
from __future__ import annotations

import importlib
import importlib.metadata
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Writer", "WRITERS", "register", "install_hint", "missing_modules", "source_checkout"]


@dataclass(frozen=True)
class Writer:
    """One export format."""

    name: str  # the --format value
    extension: str  # of the files written, without the dot
    extra: str  # the package extra that brings its modules
    modules: tuple  # modules that must import (from the extra)
    help: str  # one phrase for --help
    accuracy: str  # what its error figure measures, for the CLI's line ("surfaces", "chord")
    build: Callable  # (geometry, member, bore_mm, options) -> built member (.teeth, .max_error_um)
    place: Callable  # (built member, assembly.Placement or None) -> its shape (placed when given)
    write: Callable  # (shapes, path) -> (volume_mm3, triangles or None)


WRITERS: dict[str, Writer] = {}


def register(writer: Writer) -> Writer:
    WRITERS[writer.name] = writer
    return writer


def missing_modules(writer: Writer) -> list:
    """The writer's modules that do not import here."""
    out = []
    for name in writer.modules:
        try:
            importlib.import_module(name)
        except ImportError:
            out.append(name)
    return out


def source_checkout() -> Path | None:
    """The source tree this package runs from (a folder whose pyproject.toml names the project
    beveloid and holds this package), or None for an installed copy."""
    root = Path(__file__).resolve().parents[2]
    try:
        project = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8")).get("project", {})
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return None
    return root if project.get("name") == "beveloid" else None


def _extra_requirements(extra: str) -> list:
    """The installed distribution's requirements of an extra (its metadata), or []."""
    try:
        requires = importlib.metadata.requires("beveloid") or []
    except importlib.metadata.PackageNotFoundError:
        return []
    marker = f'extra == "{extra}"'
    return [r.split(";")[0].strip() for r in requires if marker in r.replace("'", '"')]


def install_hint(writer: Writer) -> str:
    """One line: what ``--format <name>`` needs and the command that installs it here."""
    need = f"beveloid export --format {writer.name} needs {', '.join(m.split('.')[0] for m in writer.modules)}"
    checkout = source_checkout()
    if checkout is not None:
        return f'{need}: pip install ".[{writer.extra}]" in the source checkout {checkout}'
    reqs = _extra_requirements(writer.extra)
    if reqs:  # an installed copy: its own metadata names what the extra brings (no package index needed)
        return f"{need}: pip install {' '.join(repr(r) for r in reqs)} (the {writer.extra!r} extra)"
    return f'{need}: pip install "beveloid[{writer.extra}]" (or the {writer.extra!r} extra of its source)'


# ---------------------------------------------------------------------------------------- STEP


def _step_build(geometry, member, bore_mm, options):
    from . import solid

    return solid.build_member(geometry, member, bore_mm)


def _step_place(built, placement):
    from . import occ

    return built.shape if placement is None else occ.transformed(built.shape, placement.trsf)


def _step_write(shapes, path):
    from . import occ

    shape = occ.compound(list(shapes)) if len(shapes) > 1 else shapes[0]
    occ.write_step(shape, path)
    return sum(occ.volume_mm3(s) for s in occ.solids_of(shape)), None


register(Writer("step", "step", "cad", ("OCP.BRepBuilderAPI",),
                "STEP (B-spline faces within 1 um of the generated surfaces, OpenCASCADE)", "surfaces",
                _step_build, _step_place, _step_write))


# ---------------------------------------------------------------------------------------- STL


def _stl_build(geometry, member, bore_mm, options):
    from . import mesh

    return mesh.build_mesh(geometry, member, bore_mm, options.chord_um)


def _stl_place(built, placement):
    from . import mesh

    return built.mesh if placement is None else mesh.placed(built.mesh, *placement.matrix)


def _stl_write(shapes, path):
    from . import mesh

    joined = mesh.joined(list(shapes))
    mesh.write(joined, path)
    return mesh.enclosed_volume_mm3(joined), len(joined.faces)


register(Writer("stl", "stl", "cad", ("trimesh",), "STL (a closed mesh within 5 um, trimesh)", "chord",
                _stl_build, _stl_place, _stl_write))
