"""Solid models of a designed pair: STEP (OpenCASCADE) and STL (trimesh), issue 22.

``export(pair, options)`` builds each requested member as a closed OpenCASCADE solid whose flanks,
root fillets, tip and root lands are B-spline surfaces fitted through the generated surfaces
(:mod:`beveloid.export.solid`), and writes it:

* ``ExportOptions(format="step")``: a STEP file (AP214, mm) written by OpenCASCADE;
* ``ExportOptions(format="stl")``: a closed triangle mesh whose vertices are generated surface
  points, within ``chord_um`` of the surfaces (:mod:`beveloid.export.mesh`), written as a binary
  STL by trimesh (watertight: checked before writing).  No OpenCASCADE on this path: the two
  formats are built independently, and their volumes agree (tests/export).

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
#: the STL's chord error aimed at (um) at the cells' centres; 5 um is promised anywhere
CHORD_UM = 3.0


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
        if not (0.5 <= self.chord_um <= 4.0):
            raise ValueError(f"chord_um = {self.chord_um!r}: must be from 0.5 to 4 (um)")


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
    """Build the requested members and write them (see the module docstring)."""
    require_cad()
    from . import assembly, mesh

    bores = bore_diameters(pair.spec)
    out = Path(options.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    places = assembly.assembly_placements(pair) if options.assembled else None
    if options.format == "step":
        from . import occ, solid

        built = {m: solid.build_member(pair.geometry, m, bores[m]) for m in options.members}
        shapes = {m: built[m].shape if places is None else occ.transformed(built[m].shape, places[m].trsf)
                  for m in options.members}
        fits = {m: built[m].max_fit_error_um for m in options.members}
    else:
        built = {m: mesh.build_mesh(pair.geometry, m, bores[m], options.chord_um) for m in options.members}
        shapes = {m: built[m].mesh if places is None else mesh.placed(built[m].mesh, *places[m].matrix)
                  for m in options.members}
        fits = {m: built[m].max_chord_error_um for m in options.members}
    if options.assembled:
        groups = [(f"{options.stem}_pair", options.members)]
    else:
        groups = [(f"{options.stem}_{m}", (m,)) for m in options.members]
    written = []
    for name, members in groups:
        path = out / f"{name}.{options.format}"
        teeth = tuple(built[m].teeth for m in members)
        error = max(fits[m] for m in members)
        if options.format == "step":
            shape = occ.compound([shapes[m] for m in members]) if len(members) > 1 else shapes[members[0]]
            occ.write_step(shape, path)
            volume = sum(occ.volume_mm3(s) for s in occ.solids_of(shape))
            written.append(WrittenFile(path, members, volume, teeth, error))
        else:
            joined = mesh.joined([shapes[m] for m in members])
            mesh.write(joined, path)
            written.append(WrittenFile(path, members, float(joined.volume), teeth, error, len(joined.faces)))
    return ExportResult(tuple(written), built)
