"""Measurements of written exports, for the export tests.

They read the files back (OpenCASCADE for STEP, trimesh for STL) and hold them against points of
the generated surfaces that were not used to build them: random (s, z) on every face of the tooth
(beveloid.tooth.sampling), turned onto random teeth.
"""
from __future__ import annotations

import math

import numpy as np

from beveloid.tooth.sampling import FACES, ToothSampler, rotate_z


def off_fit_points(geometry, member, seed=0, per_face=4):
    """{face: points (k, 3)} of the generated surfaces at random (s, z), on random teeth (member frame)."""
    rng = np.random.default_rng(seed)
    sampler = ToothSampler(geometry, member)
    lo, hi = sorted(sampler.z_range_mm)
    out = {}
    for face in FACES:
        s = rng.uniform(0.02, 0.98, per_face)
        z = rng.uniform(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo), per_face)
        pts = sampler.face_points(face, s, z).reshape(-1, 3)
        teeth = rng.integers(0, sampler.teeth, len(pts))
        out[face] = np.stack([rotate_z(p, k * sampler.pitch_angle_rad) for p, k in zip(pts, teeth)])
    return out


def distances_to_step_faces(shape, points, pad_mm=0.05):
    """Distance (mm) of each point to the nearest B-spline face of a shape read from STEP."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBndLib import BRepBndLib
    from OCP.GeomAbs import GeomAbs_BSplineSurface

    from beveloid.export import occ

    faces = []
    for f in occ.faces_of(shape):
        if BRepAdaptor_Surface(f).GetType() != GeomAbs_BSplineSurface:
            continue
        box = Bnd_Box()
        occ.static(BRepBndLib, "Add")(f, box)
        box.Enlarge(pad_mm)
        faces.append((box, occ.surface_of(f)))
    from OCP.gp import gp_Pnt

    out = []
    for p in np.asarray(points, dtype=float).reshape(-1, 3):
        q = gp_Pnt(*map(float, p))
        near = [s for box, s in faces if not box.IsOut(q)]
        out.append(min((float(occ.distances_to_surface(s, p[None])[0]) for s in near), default=math.inf))
    return np.array(out)


def distances_to_mesh(mesh, points, candidates=32, signed=False):
    """Distance (mm) of each point to a triangle mesh (exact point-triangle distances to the triangles
    whose centroids are nearest); signed: negative inside (along the nearest triangle's outward normal)."""
    from scipy.spatial import cKDTree
    from trimesh.triangles import closest_point

    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    tris = mesh.triangles
    _, idx = cKDTree(tris.mean(axis=1)).query(pts, k=candidates)
    q = np.repeat(pts, candidates, axis=0)
    c = closest_point(tris[idx.ravel()], q)
    d = np.linalg.norm(c - q, axis=-1).reshape(len(pts), candidates)
    best = np.argmin(d, axis=1)
    dist = d[np.arange(len(pts)), best]
    if not signed:
        return dist
    # the side: of the nearest triangles (several when the nearest point is a shared vertex or edge), the
    # one the point lies farthest off the plane of (the others' planes pass nearly through the point)
    c = c.reshape(len(pts), candidates, 3)
    side = np.einsum("ikj,ikj->ik", pts[:, None, :] - c, mesh.face_normals[idx])
    tied = d <= dist[:, None] + 1e-9
    pick = np.argmax(np.where(tied, np.abs(side), -1.0), axis=1)
    return np.where(side[np.arange(len(pts)), pick] < 0, -dist, dist)


def section_crossings(mesh, z_mm, radius_mm):
    """How often the mesh's transverse section at z crosses the circle of the radius."""
    from trimesh.intersections import mesh_plane

    seg = mesh_plane(mesh, plane_normal=[0, 0, 1], plane_origin=[0, 0, z_mm])
    r = np.hypot(seg[..., 0], seg[..., 1])
    return int(np.count_nonzero((r[:, 0] - radius_mm) * (r[:, 1] - radius_mm) < 0))


def tooth_probe(geometry, member):
    """(z, radius, angle of tooth 0's middle): half-way up the tooth at mid-face, on the tip land's middle."""
    sampler = ToothSampler(geometry, member)
    z = float(np.mean(sampler.z_range_mm))
    mid = sampler.tip_points(np.array([0.5]), np.array([z]))[0, 0]
    radius = float(sampler.root_radius_mm(z) + sampler.tip_radius_mm(z)) / 2
    return z, radius, math.atan2(mid[1], mid[0])
