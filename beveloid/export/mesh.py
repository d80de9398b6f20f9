"""STL: a closed triangle mesh whose vertices are points of the generated surfaces (trimesh writes it).

Independent of the STEP path: no B-spline fit, no OpenCASCADE.  In every section z of a common axial
grid the tooth's faces (:mod:`beveloid.export.sampling`) are walked in order round the gear

    fillet_left (root -> form limit), flank_left (-> tip), tip, flank_right (tip -> form limit),
    fillet_right (-> root), root (-> the next tooth's fillet_left)

so that each shared point is one vertex; consecutive sections are joined by two triangles per cell,
the toe and heel by a fan from the axis (no bore) or by a strip to the bore circle.  The grids are
refined until the generated surface at every cell's centre (points not used for the mesh) lies within
the chord tolerance of the cell's two triangles.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from trimesh.triangles import closest_point

from .sampling import ExportGeometryError, ToothSampler, rotate_z

#: the faces in the order the section walks them, and the direction of s along the walk
RING = (("fillet_left", 1), ("flank_left", 1), ("tip", 1), ("flank_right", -1), ("fillet_right", -1), ("root", 1))
FIRST_GRID = (12, 9)
#: a face that misses the chord tolerance gets GROWTH times the samples (and the axial grid with it)
GROWTH = 1.4
MAX_REFINEMENTS = 10


@dataclass(frozen=True)
class MemberMesh:
    """One member's closed mesh in its frame S_i (mm), and how closely it follows the surfaces."""

    member: str
    teeth: int
    mesh: trimesh.Trimesh
    samples: dict  # face -> (profile, axial) grid points
    max_chord_error_um: float  # at the cells' centres


def _tooth_ring(sampler, n_s, z):
    """Section points of one tooth (n_ring, n_z, 3), each shared point once, and per face the
    (first ring index, its s grid, walk direction)."""
    parts, cells, start = [], {}, 0
    for face, direction in RING:
        s = np.linspace(0.0, 1.0, n_s[face])
        pts = sampler.face_points(face, s[::direction], z)[:-1]  # the last is the next face's first
        cells[face] = (start, s, direction)
        parts.append(pts)
        start += len(pts)
    return np.concatenate(parts), cells


def _chord_errors(sampler, ring, cells, z):
    """{face: largest distance (mm) of the generated cell centres to their cells' two triangles}."""
    ring = np.concatenate([ring, rotate_z(ring[:1], sampler.pitch_angle_rad)])  # + the next tooth's first point
    out = {}
    for face, (start, s, direction) in cells.items():
        mid = sampler.face_points(face, ((s[1:] + s[:-1]) / 2)[::direction], (z[1:] + z[:-1]) / 2)
        i = (start + np.arange(len(s) - 1))[:, None]
        j = np.arange(len(z) - 1)[None, :]
        a, b, c, d = ring[i, j], ring[i + 1, j], ring[i + 1, j + 1], ring[i, j + 1]
        dist = []
        for tri in ((a, b, c), (a, c, d)):
            t = np.stack(np.broadcast_arrays(*tri), axis=-2).reshape(-1, 3, 3)
            q = mid.reshape(-1, 3)
            dist.append(np.linalg.norm(closest_point(t, q) - q, axis=-1))
        out[face] = float(np.max(np.minimum(*dist)))
    return out


def _refined_ring(sampler, z_range, chord_mm, first=FIRST_GRID):
    n_s = {face: first[0] for face, _ in RING}
    n_z = first[1]
    for _ in range(MAX_REFINEMENTS + 1):
        z = np.linspace(*z_range, n_z)
        ring, cells = _tooth_ring(sampler, n_s, z)
        errors = _chord_errors(sampler, ring, cells, z)
        missed = [f for f, e in errors.items() if not e <= chord_mm]
        if not missed:
            return ring, z, {f: (n, n_z) for f, n in n_s.items()}, max(errors.values())
        for face in missed:
            n_s[face] = int(np.ceil(GROWTH * n_s[face]))
        n_z = int(np.ceil(GROWTH * n_z))
    raise RuntimeError(f"{sampler.member}: the mesh stays {1e3 * max(errors.values()):.2f} um from the generated"
                       f" surfaces (more than {1e3 * chord_mm:.2f} um)")


def _cap(outline, bore_mm, z, first_index, centre_index, bore_index, member):
    """Triangles closing one end: outline ring indices -> axis (fan) or -> bore ring (strip)."""
    ang = np.arctan2(outline[:, 1], outline[:, 0])
    step = np.angle(np.exp(1j * (np.roll(ang, -1) - ang)))  # outline point k -> k + 1, round the gear
    if np.any(step < -1e-12) or abs(step.sum() - 2 * np.pi) > 1e-6:
        raise ExportGeometryError(f"{member}: the transverse section at z = {z:.3f} mm is not star-shaped about the"
                                  " axis (its outline turns back): the STL end faces cannot be closed")
    n = len(outline)
    i = first_index + np.arange(n)
    k = first_index + (np.arange(n) + 1) % n
    if bore_mm <= 0:
        return np.column_stack([np.full(n, centre_index), k, i])
    bi, bk = bore_index + np.arange(n), bore_index + (np.arange(n) + 1) % n
    return np.concatenate([np.column_stack([bi, k, i]), np.column_stack([bi, bk, k])])


def build_mesh(geometry, member: str, bore_diameter_mm: float = 0.0, chord_um: float = 3.0,
               first=FIRST_GRID) -> MemberMesh:
    """The member's closed mesh in S_i, vertices on the generated surfaces, within chord_um of them."""
    sampler = ToothSampler(geometry, member)
    toe, heel = sampler.z_range_mm
    z_range = (min(toe, heel), max(toe, heel))
    sampler.check_buildable(np.linspace(*z_range, 21))
    ring, z, samples, error = _refined_ring(sampler, z_range, chord_um * 1e-3, first)
    n_t, n_z = sampler.teeth, len(z)
    rings = np.concatenate([rotate_z(ring, k * sampler.pitch_angle_rad) for k in range(n_t)])  # (n, n_z, 3)
    n = len(rings)
    index = np.arange(n * n_z).reshape(n, n_z)
    i0, i1 = index, np.roll(index, -1, axis=0)
    a, b, c, d = i0[:, :-1], i1[:, :-1], i1[:, 1:], i0[:, 1:]
    tris = [np.column_stack([a.ravel(), b.ravel(), c.ravel()]), np.column_stack([a.ravel(), c.ravel(), d.ravel()])]
    vertices = [rings.reshape(-1, 3)]  # vertex i * n_z + j: ring point i in section j
    extra = n * n_z
    for j, orient in ((0, 1), (n_z - 1, -1)):
        zz = z[j]
        if bore_diameter_mm > 0:
            ang = np.arctan2(rings[:, j, 1], rings[:, j, 0])
            r = bore_diameter_mm / 2
            vertices.append(np.column_stack([r * np.cos(ang), r * np.sin(ang), np.full(n, zz)]))
            cap = _cap(rings[:, j], bore_diameter_mm, zz, 0, -1, extra, member)
            cap = np.where(cap < n, cap * n_z + j, cap)  # outline ring index -> vertex index
            tris.append(cap[:, ::orient])
            extra += n
        else:
            vertices.append(np.array([[0.0, 0.0, zz]]))
            cap = _cap(rings[:, j], 0.0, zz, 0, extra, -1, member)
            cap = np.where(cap < n, cap * n_z + j, cap)
            tris.append(cap[:, ::orient])
            extra += 1
    if bore_diameter_mm > 0:  # the bore wall between the toe's and the heel's bore rings
        lo, hi = n * n_z + np.arange(n), n * n_z + n + np.arange(n)
        lo1, hi1 = np.roll(lo, -1), np.roll(hi, -1)
        tris += [np.column_stack([lo, hi, hi1]), np.column_stack([lo, hi1, lo1])]
    mesh = trimesh.Trimesh(vertices=np.concatenate(vertices), faces=np.concatenate(tris), process=False)
    if mesh.volume < 0:
        mesh.invert()
    if not (mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0):
        raise RuntimeError(f"{member}: the STL mesh is not closed (watertight {mesh.is_watertight}, consistently"
                           f" wound {mesh.is_winding_consistent})")
    return MemberMesh(member, n_t, mesh, samples, 1e3 * error)


def placed(mesh: trimesh.Trimesh, rotation, translation) -> trimesh.Trimesh:
    """A copy of the mesh moved by p -> rotation @ p + translation."""
    out = mesh.copy()
    out.vertices = out.vertices @ np.asarray(rotation, dtype=float).T + np.asarray(translation, dtype=float)
    return out


def write(mesh: trimesh.Trimesh, path) -> None:
    mesh.export(str(path), file_type="stl")
