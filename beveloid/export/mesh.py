"""STL: a closed triangle mesh whose vertices are points of the generated surfaces (trimesh writes it).

Independent of the STEP path: no B-spline fit, no OpenCASCADE.  In every section z of a common axial
grid the tooth's faces (:mod:`beveloid.tooth.sampling`) are walked in order round the gear

    fillet_left (root -> form limit), flank_left (-> tip), tip, flank_right (tip -> form limit),
    fillet_right (-> root), root (-> the next tooth's fillet_left)

so that each shared point is one vertex; consecutive sections are joined by two triangles per cell,
the toe and heel each by one polygon per tooth (the section's tooth outline from the left fillet's root
point to the right one's, closed by their chord: a ladder of rungs across the tooth, so an undercut
outline that turns back in angle is closed as well) and the star-shaped rest, the root lands and those chords, by a fan from
the axis (no bore) or by a strip to the bore circle.  The grids are refined until the generated
surface at every cell's centre (points not used for the mesh) lies within the chord tolerance of the
cell's two triangles.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh
from trimesh.triangles import closest_point

from ..tooth.sampling import ExportGeometryError, ToothSampler, rotate_z

#: the faces in the order the section walks them, and the direction of s along the walk
RING = (("fillet_left", 1), ("flank_left", 1), ("tip", 1), ("flank_right", -1), ("fillet_right", -1), ("root", 1))
FIRST_GRID = (12, 9)
#: a face that misses the chord tolerance gets GROWTH times the samples (and the axial grid with it)
GROWTH = 1.4
MAX_REFINEMENTS = 10
#: a tip land narrower than this (mm) is a pointed section's: its points are one point of the mesh
POINT_MM = 1e-4


@dataclass(frozen=True)
class MemberMesh:
    """One member's closed mesh in its frame S_i (mm), and how closely it follows the surfaces."""

    member: str
    teeth: int
    mesh: trimesh.Trimesh
    samples: dict  # face -> (profile, axial) grid points
    max_chord_error_um: float  # at the cells' centres

    @property
    def max_error_um(self) -> float:
        """The writer registry's name for it (formats.Writer)."""
        return self.max_chord_error_um


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
    ring = np.concatenate(parts)
    # a pointed section's tip land has no width: its points (the flanks' ends, where they cross, and the
    # tip face's) are made one point, which build_mesh then makes one vertex (an STL file stores float32
    # coordinates: points ~1e-6 mm apart would be merged or not by its reader's rounding)
    top = slice(cells["tip"][0], cells["flank_right"][0] + 1)
    pointed = np.linalg.norm(ring[top.start, :] - ring[top.stop - 1, :], axis=-1) <= POINT_MM
    ring[top, pointed] = ring[top, pointed].mean(axis=0)
    return ring, cells


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


def axial_grid(breaks, n_z):
    """About n_z sections from breaks[0] to breaks[-1] with every break a section: each piece between two
    breaks gets its share of the sections by length (at least one cell).  The breaks are where a face changes
    how it ends (ToothSampler.face_pieces: a pointed tooth's tip land, a flank's undercut): its edge turns
    there, which a cell between two sections would cut across (a chord error only a fine grid closes)."""
    breaks = np.asarray(breaks, dtype=float)
    span = breaks[-1] - breaks[0]
    parts = [np.linspace(lo, hi, max(2, int(np.ceil((n_z - 1) * (hi - lo) / span)) + 1))[:-1]
             for lo, hi in zip(breaks[:-1], breaks[1:])]
    return np.concatenate(parts + [breaks[-1:]])


def _refined_ring(sampler, z_range, chord_mm, first=FIRST_GRID):
    n_s = {face: first[0] for face, _ in RING}
    n_z = first[1]
    breaks = [lo for lo, _, _ in sampler.face_pieces(z_range)] + [z_range[1]]
    for _ in range(MAX_REFINEMENTS + 1):
        z = axial_grid(breaks, n_z)
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


def _angles_round(outline, z, member):
    """Polar angles of a section's outline, unwrapped from its first point (n + 1: the last closes)."""
    ang = np.arctan2(outline[:, 1], outline[:, 0])
    step = np.angle(np.exp(1j * (np.roll(ang, -1) - ang)))  # outline point k -> k + 1, round the gear
    if np.any(step < -1e-9) or abs(step.sum() - 2 * np.pi) > 1e-6:  # a pointed tip's two ends: ~1e-10 apart
        raise ExportGeometryError(f"{member}: the transverse section at z = {z:.3f} mm is not star-shaped about the"
                                  " axis (its outline turns back): the STL end faces cannot be closed")
    return ang[0] + np.concatenate([[0.0], np.cumsum(step)])


def _tooth_cap(ring_xy, top, root_start):
    """Triangles (k, 3) of one tooth's outline in a section (ring points 0 .. root_start, closed by the chord
    from the right fillet's root point back to the left one's), +z normals: a ladder between its left
    side (0 up to the tip land's right end ``top``, radius growing) and its right side (root_start up to
    the point below ``top``), rungs in order of radius.  An undercut outline turns back in angle but not in radius, so
    every rung lies across the tooth; a pointed tip's land of zero width gives triangles of no area."""
    radius = np.hypot(ring_xy[:, 0], ring_xy[:, 1])
    left = np.arange(0, top + 1)
    right = np.arange(root_start, top, -1)  # up to the point below the top: the edge (top, top + 1) closes it
    a, b = np.maximum.accumulate(radius[left]), np.maximum.accumulate(radius[right])
    a[a > b[-1]] = b[-1]  # the tip land's points: reached before the right side's last rung
    out, i, k = [], 0, 0
    while i < len(left) - 1 or k < len(right) - 1:
        if k == len(right) - 1 or (i < len(left) - 1 and a[i + 1] <= b[k + 1]):
            out.append((left[i], left[i + 1], right[k]))
            i += 1
        else:
            out.append((left[i], right[k + 1], right[k]))
            k += 1
    tris = np.array(out)
    p = ring_xy[tris]
    area2 = np.sum((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    return tris if area2 > 0 else tris[:, ::-1]


def _stitch(outer_angles, inner_angles):
    """Triangles (outer/inner ring positions, +z normals) between two closed rings round the axis, both
    with non-decreasing unwrapped angles over one turn (n + 1 and m + 1 values: the last closes the
    ring); the inner ring starts at or after the outer one.  Returns (k, 3) of (ring, position) codes:
    outer position p as p, inner position q as -1 - q."""
    n, m = len(outer_angles) - 1, len(inner_angles) - 1
    out, i, k = [], 0, 0
    while i < n or k < m:
        if k == m or (i < n and outer_angles[i + 1] <= inner_angles[k + 1]):
            out.append((i, (i + 1) % n, -1 - (k % m)))
            i += 1
        else:
            out.append((i % n, -1 - ((k + 1) % m), -1 - (k % m)))
            k += 1
    return np.array(out)


def _bore_ring(radius_mm, chord_mm):
    """Uniform angles (over one turn from 0) of a polygon within chord_mm of the bore circle."""
    m = max(64, int(np.ceil(2 * np.pi / np.sqrt(8 * chord_mm / radius_mm))))
    return 2 * np.pi * np.arange(m) / m


def build_mesh(geometry, member: str, bore_diameter_mm: float = 0.0, chord_um: float = 3.0,
               first=FIRST_GRID) -> MemberMesh:
    """The member's closed mesh in S_i, vertices on the generated surfaces, within chord_um of them."""
    sampler = ToothSampler(geometry, member)
    sampler.check_bore(bore_diameter_mm)
    toe, heel = sampler.z_range_mm
    z_range = (min(toe, heel), max(toe, heel))
    sampler.check_buildable(np.linspace(*z_range, 21))
    ring, z, samples, error = _refined_ring(sampler, z_range, chord_um * 1e-3, first)
    n_t, n_z = sampler.teeth, len(z)
    rings = np.concatenate([rotate_z(ring, k * sampler.pitch_angle_rad) for k in range(n_t)])  # (n, n_z, 3)
    n, per_tooth = len(rings), len(ring)
    root_start = sum(samples[face][0] - 1 for face, _ in RING[:-1])  # the right fillet's root point
    top = sum(samples[face][0] - 1 for face, _ in RING[:3])  # the right flank's top: the tip land's right end
    # the end faces: per tooth its outline (ring 0 .. root_start) closed by a chord, and the rest inside
    # the root circle (each tooth's two root points and its root land), star-shaped about the axis
    base = np.concatenate([[0], np.arange(root_start, per_tooth)])
    sel = np.concatenate([k * per_tooth + base for k in range(n_t)])
    n_sel = len(sel)
    index = np.arange(n * n_z).reshape(n, n_z)  # vertex i * n_z + j: ring point i in section j
    i0, i1 = index, np.roll(index, -1, axis=0)
    a, b, c, d = i0[:, :-1], i1[:, :-1], i1[:, 1:], i0[:, 1:]  # angle, then z increasing: outward normals
    tris = [np.column_stack([a.ravel(), b.ravel(), c.ravel()]), np.column_stack([a.ravel(), c.ravel(), d.ravel()])]
    vertices = [rings.reshape(-1, 3)]
    count = n * n_z
    bore = _bore_ring(bore_diameter_mm / 2, chord_um * 1e-3) if bore_diameter_mm > 0 else None
    bore_rings = []
    for j, flip in ((0, True), (n_z - 1, False)):  # the toe's normal is -z, the heel's +z
        outer = _angles_round(rings[sel, j], z[j], member)
        tooth = _tooth_cap(ring[:root_start + 1, j, :2], top, root_start)
        tooth_caps = np.concatenate([index[k * per_tooth + tooth, j] for k in range(n_t)])
        tris.append(tooth_caps[:, ::-1] if flip else tooth_caps)
        if bore is None:
            codes = np.column_stack([np.arange(n_sel), np.roll(np.arange(n_sel), -1), np.full(n_sel, -1)])
            inner_index = np.array([count])
            vertices.append(np.array([[0.0, 0.0, z[j]]]))
        else:
            start = int(np.searchsorted(np.mod(bore - outer[0], 2 * np.pi), 0.0))  # first at or after the outline's
            order = np.roll(np.arange(len(bore)), -start)
            rel = np.mod(bore[order] - outer[0], 2 * np.pi)
            codes = _stitch(outer - outer[0], np.concatenate([rel, [rel[0] + 2 * np.pi]]))
            inner_index = count + order
            r = bore_diameter_mm / 2
            vertices.append(np.column_stack([r * np.cos(bore), r * np.sin(bore), np.full(len(bore), z[j])]))
            bore_rings.append(count + np.arange(len(bore)))
        cap = np.where(codes >= 0, index[sel[np.clip(codes, 0, n_sel - 1)], j], inner_index[np.clip(-1 - codes, 0, None)])
        tris.append(cap[:, ::-1] if flip else cap)
        count += len(inner_index) if bore is not None else 1
    if bore is not None:  # the bore wall, normals toward the axis
        lo, hi = bore_rings
        lo1, hi1 = np.roll(lo, -1), np.roll(hi, -1)
        tris += [np.column_stack([lo, hi1, lo1]), np.column_stack([lo, hi, hi1])]
    faces = np.concatenate(tris)
    tip_start = sum(samples[face][0] - 1 for face, _ in RING[:2])  # the tip land's left end
    pointed = np.all(ring[tip_start:top + 1] == ring[top], axis=(0, -1))  # per section (_tooth_ring)
    if pointed.any():
        # a pointed section's tip land is one point: its ring points become one vertex (that of the
        # right flank's top) and the land's cells, now edges, are dropped.  Only these: other points
        # that coincide (the fillet cut by a tip round of zero radius) stay apart, their cells of no
        # area closing the surface as every other cell does
        remap = np.arange(count)
        for k in range(n_t):
            land = index[k * per_tooth + tip_start:k * per_tooth + top + 1][:, pointed]
            remap[land] = land[-1]
        faces = remap[faces]
        faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])]
    mesh = trimesh.Trimesh(vertices=np.concatenate(vertices), faces=faces, process=False)
    if pointed.any():
        mesh.remove_unreferenced_vertices()
    problem = open_edges(mesh.faces, len(mesh.vertices))
    if problem or not enclosed_volume_mm3(mesh) > 0:
        raise RuntimeError(f"{member}: the STL mesh is not closed ({problem or 'no positive volume'})")
    return MemberMesh(member, n_t, mesh, samples, 1e3 * error)


def open_edges(faces, n_vertices) -> str | None:
    """None when the triangles close a consistently oriented surface (each directed edge once, and
    its reverse once: every edge between two triangles that run it in opposite directions), else
    what is wrong.  trimesh's is_watertight and is_winding_consistent say the same; on a long face's
    tens of millions of triangles they took ~20 s and several GB (they build its whole edge graph)."""
    faces = np.asarray(faces, dtype=np.int64)
    a, b = faces, np.roll(faces, -1, axis=1)  # the directed edges a -> b of every triangle
    forward = np.sort((a * n_vertices + b).ravel())
    if forward.size and np.any(forward[1:] == forward[:-1]):
        return "an edge run twice in the same direction: not consistently oriented, or not a 2-manifold"
    if not np.array_equal(forward, np.sort((b * n_vertices + a).ravel())):
        return "an edge with no triangle on its other side: not watertight"
    return None


def enclosed_volume_mm3(mesh, block=1 << 20) -> float:
    """The volume (mm^3) a closed, outward-oriented mesh encloses: the sum of the signed tetrahedra
    from the origin, sum of v0 . (v1 x v2) / 6, in blocks of triangles (trimesh's ``volume`` computes
    every mass property with a dozen arrays the size of the mesh: ~25 s and ~10 GB on 32 million
    triangles)."""
    v, f = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    total = 0.0
    for start in range(0, len(f), block):
        (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = (v[f[start:start + block, k]].T for k in range(3))
        total += float(np.sum(x0 * (y1 * z2 - z1 * y2) - y0 * (x1 * z2 - z1 * x2) + z0 * (x1 * y2 - y1 * x2)))
    return total / 6.0


def placed(mesh: trimesh.Trimesh, rotation, translation) -> trimesh.Trimesh:
    """A copy of the mesh moved by p -> rotation @ p + translation."""
    out = mesh.copy()
    out.vertices = out.vertices @ np.asarray(rotation, dtype=float).T + np.asarray(translation, dtype=float)
    return out


def joined(meshes) -> trimesh.Trimesh:
    """One mesh of several closed meshes (each stays a closed shell)."""
    return meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(list(meshes))


def write(mesh: trimesh.Trimesh, path) -> None:
    mesh.export(str(path), file_type="stl")
