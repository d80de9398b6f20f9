"""Solid models of a designed pair: STEP (OpenCASCADE) and STL (trimesh), issue 22.

``export(pair, options)`` builds each requested member as a closed OpenCASCADE solid whose flanks,
root fillets, tip and root lands are B-spline surfaces fitted through the generated surfaces
(:mod:`beveloid.export.solid`), and writes it:

* ``ExportOptions(format="step")``: a STEP file (AP214, mm) written by OpenCASCADE;
* ``ExportOptions(format="stl")``: a closed triangle mesh whose vertices are generated surface
  points, within ``chord_um`` of the surfaces (:mod:`beveloid.export.mesh`), written as a binary
  STL by trimesh (watertight: checked before writing).  No OpenCASCADE on this path: the two
  formats are built independently, and their volumes agree (tests/export).

The formats are the writers of :data:`formats.WRITERS` (name, extension, extra, build, place,
write): a new format is one entry there.

Each member is written in its own frame S_i (``<stem>_pinion.step``, ``<stem>_gear.step``); with
``assembled=True`` the requested members go into one file ``<stem>_pair.<ext>``, placed in the
fixed frame S_f as designed (generated/placement.py, Eqs 30-35, with the spec's [misalignment]).

Needs the ``cad`` extra: :func:`require_cad` says in one line what to install, worded for a source
checkout or an installed copy (:func:`formats.install_hint`).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from .. import interrupts
from ..errors import OptionError
from ..names import MEMBERS
from ..outputs import check_output_dir
from .formats import WRITERS, install_hint

__all__ = ["FORMATS", "MEMBERS", "CHORD_UM", "CadMissing", "require_cad", "ExportOptions", "WrittenFile",
           "ExportResult", "bore_diameters", "export", "WRITERS", "install_hint"]

FORMATS = tuple(WRITERS)
#: the STL's chord error aimed at (um) at the cells' centres; 5 um is promised anywhere
CHORD_UM = 3.0


class CadMissing(ImportError):
    """The ``cad`` extra is not installed (its message is one line: what to install)."""


def require_cad(format: str = "step") -> None:
    """Raise :class:`CadMissing` unless the modules of the format's writer import."""
    from .formats import missing_modules

    writer = WRITERS[format]
    if missing_modules(writer):
        raise CadMissing(install_hint(writer))


@dataclass(frozen=True)
class ExportOptions:
    """What to export; validated on construction (:class:`beveloid.errors.OptionError` naming the option)."""

    format: str = "step"
    members: tuple = MEMBERS
    assembled: bool = False
    out_dir: str | os.PathLike = "."
    stem: str = "beveloid"
    chord_um: float = CHORD_UM

    def __post_init__(self):
        if self.format not in FORMATS:
            raise OptionError("format", self.format, f"must be one of {', '.join(FORMATS)}")
        if not self.members or any(m not in MEMBERS for m in self.members) or len(set(self.members)) != len(self.members):
            raise OptionError("members", self.members, "must be pinion, gear or both, each once")
        if not (isinstance(self.chord_um, (int, float)) and 0.5 <= self.chord_um <= 4.0):
            raise OptionError("chord_um", self.chord_um, "must be from 0.5 to 4 (um)")


@dataclass(frozen=True)
class WrittenFile:
    """One file the export wrote."""

    path: Path
    members: tuple
    volume_mm3: float  # of the solid(s) (STEP) or of the mesh (STL)
    teeth: tuple  # per member
    #: STEP: the fitted faces' largest distance to the generated surfaces; STL: the mesh's largest
    #: chord error; both at the grid cells' centres (points not used to build them)
    max_error_um: float
    triangles: int | None = None  # STL only


@dataclass(frozen=True)
class ExportResult:
    files: tuple = field(default_factory=tuple)
    #: member -> solid.MemberSolid (STEP) or mesh.MemberMesh (STL), in the member frame
    members: dict = field(default_factory=dict)


def bore_diameters(spec) -> dict:
    """{member: bore diameter (mm)} from the spec (``bore_diameter_mm``; 0: no bore)."""
    return {m: float(getattr(getattr(spec, m), "bore_diameter_mm", 0.0) or 0.0) for m in MEMBERS}


def export(pair, options: ExportOptions = ExportOptions()) -> ExportResult:
    """Build the requested members and write them (see the module docstring).

    ``options.out_dir`` follows the one output rule (:mod:`beveloid.outputs`): an existing writable folder,
    or a new one created in its existing, writable parent; a missing parent (or any target that cannot be
    written) raises :class:`beveloid.outputs.OutputError` before anything is built."""
    require_cad(options.format)
    from . import assembly

    writer = WRITERS[options.format]
    bores = bore_diameters(pair.spec)
    out = Path(options.out_dir)
    check_output_dir(str(out), "out_dir")  # the one output rule: creates out_dir only, refuses a missing parent
    places = assembly.assembly_placements(pair) if options.assembled else None
    built = {m: writer.build(pair.geometry, m, bores[m], options) for m in options.members}
    shapes = {m: writer.place(built[m], None if places is None else places[m]) for m in options.members}
    if options.assembled:
        groups = [(f"{options.stem}_pair", options.members)]
    else:
        groups = [(f"{options.stem}_{m}", (m,)) for m in options.members]
    interrupts.check()  # a Ctrl-C swallowed during the build (beveloid/interrupts.py): nothing is written
    written = []
    try:
        for name, members in groups:
            path = out / f"{name}.{writer.extension}"
            partial = out / f".{name}.partial.{writer.extension}"  # whole or absent: renamed when complete
            try:
                volume, triangles = writer.write([shapes[m] for m in members], partial)
                os.replace(partial, path)
            except BaseException as exc:
                partial.unlink(missing_ok=True)
                if isinstance(exc, OSError) and exc.filename is None:  # a full disk: named by its file
                    raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
                raise
            written.append(WrittenFile(path, members, volume, tuple(built[m].teeth for m in members),
                                       max(built[m].max_error_um for m in members), triangles))
    except BaseException:  # nothing half-written: the files of this call go too (an empty new folder: the CLI)
        for f in written:
            f.path.unlink(missing_ok=True)
        raise
    return ExportResult(tuple(written), built)
