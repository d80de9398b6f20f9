"""The few OpenCASCADE (OCP) calls the export makes, in one place.

``cadquery-ocp`` names some static methods with a ``_s`` suffix and, from OCCT 8 on, some without;
:func:`static` finds either.  Importing this module imports OCP: callers reach it through
:func:`beveloid.export.require_cad`, which says in one line what to install when it is missing.
"""
from __future__ import annotations

import contextlib
import math
import os
import sys

import numpy as np
from OCP.Approx import Approx_IsoParametric
from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeSolid, BRepBuilderAPI_Sewing,
                                BRepBuilderAPI_Transform)
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
from OCP.GeomAPI import GeomAPI_PointsToBSplineSurface, GeomAPI_ProjectPointOnSurf
from OCP.GProp import GProp_GProps
from OCP.gp import gp_Ax1, gp_Ax2, gp_Dir, gp_Pnt, gp_Trsf
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.ShapeAnalysis import ShapeAnalysis_FreeBounds
from OCP.ShapeFix import ShapeFix_Solid
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID, TopAbs_WIRE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Compound

try:
    from OCP.collections import Array2_gp_Pnt as _PointGrid  # cadquery-ocp 8
except ImportError:  # cadquery-ocp 7
    from OCP.TColgp import TColgp_Array2OfPnt as _PointGrid

#: sewing tolerance (mm): neighbouring fitted faces share their boundary points, so their edges
#: differ by the fit error (< 1e-6 mm); this only has to exceed that
SEWING_TOL_MM = 1e-4


def static(cls, name):
    """A static method of an OCP class, ``name_s`` or ``name``."""
    return getattr(cls, name + "_s", None) or getattr(cls, name)


def _downcast(kind, shape):
    return static(TopoDS, kind)(shape)


def fit_surface(points):
    """A bicubic B-spline surface interpolating a grid of points (n_s, n_z, 3) (mm), parameters uniform
    in the grid index (faces sampled on the same rows then have the same boundary curves)."""
    n_s, n_z, _ = points.shape
    grid = _PointGrid(1, n_s, 1, n_z)
    for i in range(n_s):
        for j in range(n_z):
            x, y, z = (float(c) for c in points[i, j])
            grid.SetValue(i + 1, j + 1, gp_Pnt(x, y, z))
    fit = GeomAPI_PointsToBSplineSurface()
    fit.Interpolate(grid, Approx_IsoParametric)
    if not fit.IsDone():
        raise RuntimeError("OpenCASCADE could not interpolate a B-spline surface through the sampled points")
    return fit.Surface()


def distances_to_surface(surface, points):
    """Distances (mm) from points (..., 3) to a surface (orthogonal projection).  One projector for all
    points (its sampling of the surface made once): ~6x faster than a new projector per point, the same
    distances (OpenCASCADE's tree search, Extrema_ExtAlgo_Tree, is ~10x faster again but returned a
    local minimum for a point of a pointed tooth's fillet: 0.027 um for 0.001)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.empty(len(pts))
    proj = GeomAPI_ProjectPointOnSurf()
    proj.Init(surface, *surface.Bounds())
    for k, (x, y, z) in enumerate(pts):
        proj.Perform(gp_Pnt(float(x), float(y), float(z)))
        out[k] = proj.LowerDistance() if proj.NbPoints() else math.inf
    return out.reshape(np.shape(points)[:-1])


def face(surface):
    return BRepBuilderAPI_MakeFace(surface, 1e-7).Face()


def rotation_z(angle):
    t = gp_Trsf()
    t.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), float(angle))
    return t


def placement(rotation, translation):
    """A rigid transform p -> rotation @ p + translation (3x3, 3,)."""
    t = gp_Trsf()
    r, d = np.asarray(rotation, dtype=float), np.asarray(translation, dtype=float)
    t.SetValues(*(float(v) for v in np.column_stack([r, d]).ravel()))
    return t


def transformed(shape, trsf):
    return BRepBuilderAPI_Transform(shape, trsf, True).Shape()


def closed_solid(faces):
    """A solid from faces that bound it except for planar ends: sewn, the ends capped by planar faces."""
    sew = BRepBuilderAPI_Sewing(SEWING_TOL_MM)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    open_shell = sew.SewedShape()
    bounds = ShapeAnalysis_FreeBounds(open_shell, SEWING_TOL_MM, False, False).GetClosedWires()
    sew = BRepBuilderAPI_Sewing(SEWING_TOL_MM)
    sew.Add(open_shell)
    for wire in _each(bounds, TopAbs_WIRE, "Wire"):
        cap = BRepBuilderAPI_MakeFace(wire, True)
        if not cap.IsDone():
            raise RuntimeError("OpenCASCADE could not cap an end of the gear with a planar face")
        sew.Add(cap.Face())
    sew.Perform()
    shells = list(_each(sew.SewedShape(), TopAbs_SHELL, "Shell"))
    if len(shells) != 1 or sew.NbFreeEdges():
        raise RuntimeError(f"the sewn gear is not one closed shell ({len(shells)} shells,"
                           f" {sew.NbFreeEdges()} free edges)")
    fix = ShapeFix_Solid(BRepBuilderAPI_MakeSolid(shells[0]).Solid())
    fix.Perform()
    return _downcast("Solid", fix.Solid())


def cut_bore(solid, diameter_mm, z_range_mm):
    """The solid less a coaxial cylinder of the diameter, through its whole length."""
    lo, hi = min(z_range_mm) - 1.0, max(z_range_mm) + 1.0
    tool = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, lo), gp_Dir(0, 0, 1)), diameter_mm / 2, hi - lo).Shape()
    cut = BRepAlgoAPI_Cut(solid, tool)
    if not cut.IsDone():
        raise RuntimeError("OpenCASCADE could not cut the bore")
    solids = list(_each(cut.Shape(), TopAbs_SOLID, "Solid"))
    if len(solids) != 1:
        raise RuntimeError(f"cutting the bore left {len(solids)} solids")
    return solids[0]


def is_valid(shape) -> bool:
    return bool(BRepCheck_Analyzer(shape).IsValid())


def volume_mm3(shape) -> float:
    """The volume of a solid (mm^3), OpenCASCADE's Gauss integration over its faces.  Its adaptive
    Gauss-Kronrod variant (volume only) at a face tolerance of 1e-5 took half the time on the paper's
    teeth but was 1.5e-6 off on the pointed pinion of benchmarks/bench_export.py (this one: 9e-9);
    at 1e-6 it was as accurate and as slow (docs/performance.md, "Test suite")."""
    props = GProp_GProps()
    static(BRepGProp, "VolumeProperties")(shape, props)
    return float(props.Mass())


def compound(shapes):
    builder, out = BRep_Builder(), TopoDS_Compound()
    builder.MakeCompound(out)
    for s in shapes:
        builder.Add(out, s)
    return out


def faces_of(shape):
    return list(_each(shape, TopAbs_FACE, "Face"))


def solids_of(shape):
    return list(_each(shape, TopAbs_SOLID, "Solid"))


def surface_of(face_shape):
    return static(BRep_Tool, "Surface")(face_shape)


@contextlib.contextmanager
def quiet():
    """OpenCASCADE's STEP translator prints its statistics on the process's stdout: send them to
    /dev/null (the command's own output stays clean, e.g. for a pipe)."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 1)
            try:
                yield
            finally:
                os.dup2(saved, 1)
    finally:
        os.close(saved)


def write_step(shape, path):
    with quiet():
        static(Interface_Static, "SetCVal")("write.step.unit", "MM")
        static(Interface_Static, "SetCVal")("write.step.schema", "AP214IS")
        writer = STEPControl_Writer()
        writer.Transfer(shape, STEPControl_AsIs)
        done = writer.Write(str(path)) == IFSelect_RetDone
    if not done:
        raise OSError(f"{path}: OpenCASCADE could not write the STEP file")


def read_step(path):
    with quiet():
        reader = STEPControl_Reader()
        done = reader.ReadFile(str(path)) == IFSelect_RetDone
        if done:
            reader.TransferRoots()
    if not done:
        raise OSError(f"{path}: OpenCASCADE could not read the STEP file")
    return reader.OneShape()


def _each(shape, kind, name):
    ex = TopExp_Explorer(shape, kind)
    while ex.More():
        yield _downcast(name, ex.Current())
        ex.Next()
