"""A whole member as an OpenCASCADE solid: B-spline faces fitted through the generated surfaces.

One tooth and the gap after it are six faces (:data:`sampling.FACES`): both flanks, both root
fillets, the tip land (tip cone) and the root land (root cone).  Each is a bicubic B-spline surface
interpolating the face's points on an (s, z) grid (:mod:`beveloid.tooth.sampling`); the grid is
refined until the surface lies within :data:`FIT_TOL_UM` of the generated surface at the centres of
the grid cells (points not used for the fit).  The tooth is turned N times about the axis, the faces
are sewn, the toe and heel are capped by planar faces and the bore is cut.

A pointed tooth is built as it really ends: the face is cut where its tip land begins or ends (and where
a flank's undercut does: ``ToothSampler.face_pieces``) and each piece is fitted on its own; a pointed piece has no tip land (five
faces: its flanks end where they cross, ``ToothSampler.top_radius_mm``, and are sewn to each other), and
the land of a neighbouring piece narrows to zero width where the point begins (a degenerate edge).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import occ
from ..tooth.sampling import FACES, STEP_FIT_TOL_UM, ExportGeometryError, ToothSampler

#: the fitted faces lie within this distance of the generated surfaces between the fit points
#: (the export promises 1 um; the fit aims at a quarter of it)
FIT_TOL_UM = STEP_FIT_TOL_UM
#: the first grid (profile samples, axial samples) and how often it may be refined
FIRST_GRID = (24, 13)
MAX_REFINEMENTS = 3
#: the faces of a pointed range of the face: no tip land, the flanks meet where they cross
POINTED_FACES = tuple(f for f in FACES if f != "tip")


@dataclass(frozen=True)
class FaceFit:
    """How one face of the tooth was fitted."""

    face: str
    samples: tuple  # (profile, axial) grid points used for the fit
    max_error_um: float  # at the grid cells' centres (not used for the fit)
    surface: object  # the Geom_BSplineSurface, member frame


@dataclass(frozen=True)
class MemberSolid:
    """One member as a closed, valid OpenCASCADE solid in its own frame S_i (mm)."""

    member: str
    teeth: int
    bore_diameter_mm: float
    z_range_mm: tuple  # toe, heel
    shape: object  # TopoDS_Solid
    fits: tuple  # FaceFit per face of :data:`FACES` (per face of each piece of a pointed tooth)

    @property
    def max_fit_error_um(self) -> float:
        return max(f.max_error_um for f in self.fits)

    @property
    def max_error_um(self) -> float:
        """The writer registry's name for it (formats.Writer)."""
        return self.max_fit_error_um


def fit_face(sampler: ToothSampler, face: str, n_s: int, z) -> FaceFit:
    """The face's B-spline surface through n_s x len(z) points, and its error at the cell centres."""
    s = np.linspace(0.0, 1.0, n_s)
    surface = occ.fit_surface(sampler.face_points(face, s, z))
    mid = sampler.face_points(face, (s[1:] + s[:-1]) / 2, (z[1:] + z[:-1]) / 2)
    error_um = 1e3 * float(np.max(occ.distances_to_surface(surface, mid)))
    return FaceFit(face, (n_s, len(z)), error_um, surface)


def fit_tooth(sampler: ToothSampler, z_range, first=FIRST_GRID, tol_um=FIT_TOL_UM, faces=FACES) -> tuple:
    """Every face of ``faces`` (:data:`FACES`), refined until each is within tol_um off its fit points.

    All faces share one axial grid (their boundary rows then match point for point and parameter
    for parameter, which the sewing needs); a face that misses the tolerance gets twice the profile
    samples, and the axial grid is refined with it.
    """
    n_s = dict.fromkeys(faces, first[0])
    n_z = first[1]
    for _ in range(MAX_REFINEMENTS + 1):
        z = np.linspace(*z_range, n_z)
        fits = tuple(fit_face(sampler, face, n_s[face], z) for face in faces)
        missed = [f.face for f in fits if not f.max_error_um <= tol_um]
        if not missed:
            return fits
        for face in missed:
            n_s[face] = 2 * n_s[face] - 1
        n_z = 2 * n_z - 1
    worst = max(fits, key=lambda f: f.max_error_um)
    raise ExportGeometryError(
        f"{sampler.member} {worst.face}: from z = {z_range[0]:.3f} to {z_range[1]:.3f} mm the fitted surface stays"
        f" {worst.max_error_um:.3f} um from the generated surface with {worst.samples[0]} x {worst.samples[1]} points"
        f" (more than {tol_um} um): the face is not smooth enough there for a STEP B-spline face; --format stl"
        " builds it from the generated points")


def build_member(geometry, member: str, bore_diameter_mm: float = 0.0, first=FIRST_GRID) -> MemberSolid:
    """The member's whole gear as a valid OpenCASCADE solid in its frame S_i."""
    sampler = ToothSampler(geometry, member)
    sampler.check_bore(bore_diameter_mm)
    toe, heel = sampler.z_range_mm
    z_range = (min(toe, heel), max(toe, heel))
    sampler.check_buildable(np.linspace(*z_range, 21))
    sampler.check_step_buildable(np.linspace(*z_range, 21))
    fits = ()
    for z_from, z_to, landed in sampler.face_pieces(z_range):  # a pointed piece has no tip land
        fits += fit_tooth(sampler, (z_from, z_to), first, faces=FACES if landed else POINTED_FACES)
    tooth = [occ.face(f.surface) for f in fits]
    faces = [occ.transformed(f, occ.rotation_z(k * sampler.pitch_angle_rad)) if k else f
             for k in range(sampler.teeth) for f in tooth]
    shape = occ.closed_solid(faces)
    if bore_diameter_mm > 0:
        shape = occ.cut_bore(shape, bore_diameter_mm, z_range)
    if not occ.is_valid(shape):
        raise ExportGeometryError(f"{member}: OpenCASCADE finds the STEP solid built from its fitted faces invalid"
                                  " (BRepCheck_Analyzer); --format stl builds it from the generated points")
    return MemberSolid(member, sampler.teeth, float(bore_diameter_mm), (toe, heel), shape, fits)
