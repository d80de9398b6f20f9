"""Solid models of a designed pair: STEP (OpenCASCADE) and STL (trimesh), issue 22.

``export(pair, options)`` builds each requested member as a closed OpenCASCADE solid whose flanks,
root fillets, tip and root lands are B-spline surfaces fitted through the generated surfaces
(:mod:`beveloid.export.solid`), and writes it:

* ``ExportOptions(format="step")``: a STEP file (AP214, mm) written by OpenCASCADE;
* ``ExportOptions(format="stl")``: the solid meshed by OpenCASCADE within ``chord_um`` and written
  as a binary STL by trimesh (watertight: checked before writing).

Each member is written in its own frame S_i (``<stem>_pinion.step``, ``<stem>_gear.step``); with
``assembled=True`` the requested members go into one file ``<stem>_pair.<ext>``, placed in the
fixed frame S_f as designed (generated/placement.py, Eqs 30-35, with the spec's [misalignment]).

Needs the ``cad`` extra (``pip install "beveloid[cad]"``): :func:`require_cad` says so in one line.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

FORMATS = ("step", "stl")
MEMBERS = ("pinion", "gear")
INSTALL_HINT = 'beveloid export needs OpenCASCADE and trimesh: pip install "beveloid[cad]"'
#: the STL's chord error (um): the mesh lies within this of the fitted faces, which lie within 1 um
#: of the generated surfaces (5 um promised in all)
CHORD_UM = 2.0


class CadMissing(ImportError):
    """The ``cad`` extra is not installed (its message is one line: what to install)."""


def require_cad() -> None:
    """Raise :class:`CadMissing` unless OCP (cadquery-ocp) and trimesh import."""
    try:
        import OCP.BRepBuilderAPI  # noqa: F401
        import trimesh  # noqa: F401
    except ImportError:
        raise CadMissing(INSTALL_HINT) from None


@dataclass(frozen=True)
class ExportOptions:
    """What to export; validated on construction (ValueError naming the option)."""

    format: str = "step"
    members: tuple = MEMBERS
    assembled: bool = False
    out_dir: str | os.PathLike = "."
    stem: str = "beveloid"
    chord_um: float = CHORD_UM

    def __post_init__(self):
        if self.format not in FORMATS:
            raise ValueError(f"format = {self.format!r}: must be one of {', '.join(FORMATS)}")
        if not self.members or any(m not in MEMBERS for m in self.members) or len(set(self.members)) != len(self.members):
            raise ValueError(f"members = {self.members!r}: must be pinion, gear or both, each once")
        if not (0.1 <= self.chord_um <= 3.0):
            raise ValueError(f"chord_um = {self.chord_um!r}: must be from 0.1 to 3 (um)")


@dataclass(frozen=True)
class WrittenFile:
    """One file the export wrote."""

    path: Path
    members: tuple
    volume_mm3: float  # of the solid(s) (STEP) or of the mesh (STL)
    teeth: tuple  # per member
    max_fit_error_um: float  # the fitted faces against the generated surfaces, off the fit points
    triangles: int | None = None  # STL only


@dataclass(frozen=True)
class ExportResult:
    files: tuple = field(default_factory=tuple)
    solids: dict = field(default_factory=dict)  # member -> solid.MemberSolid (member frame)


def bore_diameters(spec) -> dict:
    """{member: bore diameter (mm)} from the spec (``bore_diameter_mm``; 0: no bore)."""
    return {m: float(getattr(getattr(spec, m), "bore_diameter_mm", 0.0) or 0.0) for m in MEMBERS}


def export(pair, options: ExportOptions = ExportOptions()) -> ExportResult:
    """Build the requested members and write them (see the module docstring)."""
    require_cad()
    from . import occ, solid, stl

    bores = bore_diameters(pair.spec)
    solids = {m: solid.build_member(pair.geometry, m, bores[m]) for m in options.members}
    out = Path(options.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if options.assembled:
        places = solid.assembly_placements(pair)
        groups = [(out / f"{options.stem}_pair.{options.format}", options.members,
                   occ.compound([occ.transformed(solids[m].shape, places[m]) for m in options.members]))]
    else:
        groups = [(out / f"{options.stem}_{m}.{options.format}", (m,), solids[m].shape) for m in options.members]
    written = []
    for path, members, shape in groups:
        teeth = tuple(solids[m].teeth for m in members)
        fit = max(solids[m].max_fit_error_um for m in members)
        if options.format == "step":
            occ.write_step(shape, path)
            volume = sum(occ.volume_mm3(s) for s in occ.solids_of(shape))
            written.append(WrittenFile(path, members, volume, teeth, fit))
        else:
            mesh = stl.mesh_of(shape, options.chord_um * 1e-3)
            stl.write(mesh, path)
            written.append(WrittenFile(path, members, float(mesh.volume), teeth, fit, len(mesh.faces)))
    return ExportResult(tuple(written), solids)
