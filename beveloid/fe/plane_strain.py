"""The notch benchmark of the FE tooth: a 2D plane-strain model of one transverse section.

``notch_stress(pair, member, loads, options)`` meshes one transverse section of a member (the
same sector as the FE tooth's, :mod:`beveloid.fe.mesh`: the loaded tooth 0 and one neighbour each
side, cut radially in the middle of the outer root lands, down to the same rim; the rim and both
cuts clamped), as 6-node triangles by gmsh, solves plane-strain linear elasticity on isoparametric
P2 triangles (scikit-fem) under a normal line load on the flank of tooth 0, and reads the stress
along both root fillets of tooth 0 and the root lands beside them.  The section is the generated one: the flanks and root fillets
that :class:`beveloid.tooth.sampling.ToothSampler` samples (the trochoid of a sharp rack, the
envelope of a rounded rack's tip round, undercut where the rack cuts it), closed into one profile
exactly as the FE tooth's sector (``fe.mesh._section_segments``), with more points a segment
(:attr:`NotchOptions.points`).  Each load is a point of the loaded flank at a radius (or its tip),
made a vertex of the profile, the force along the flank's inward normal in the section.

What it gives (:class:`NotchStress`, per load, per unit line load of 1 N/mm): the largest maximum
principal stress on the loaded side's fillet and land (tension; in plane strain the out-of-plane stress is
nu (s_xx + s_yy), below the in-plane one on a free surface), where it is (radius, height above the
root circle, the angle of the fillet's tangent to the tooth's centre line there), and the most
compressive minimum principal stress on the other fillet.  The stress is the P2 field's, evaluated
on the fillet's boundary edges at :data:`EDGE_POINTS` points each (no smoothing, no extrapolation).

Element sizes (mm, ``refinement`` N divides every size): on both fillets of tooth 0
h_fillet = min(FILLET_SIZE_PER_MODULE m_n, FILLET_SIZE_PER_RADIUS rho_F) / N (rho_F the fillet's
smallest radius of curvature, :func:`beveloid.fe.mesh.fillet_radius_mm`); on the flanks of tooth 0
FLANK_SIZE_PER_MODULE m_n / N, at the load points LOAD_SIZE_PER_MODULE m_n / N; elsewhere
FAR_SIZE_PER_MODULE m_n / N, grown linearly from the fine curves.  A plane-strain section of a few
thousand triangles solves in well under a second: the benchmark refines it until the notch stress
moves by less than 1 % (``benchmarks/notch_benchmark.py``, docs/validation.md 12).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import Basis, CellBasis, ElementTriP2, ElementVector, MeshTri2, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

from ..names import FLANKS
from ..tooth.sampling import ToothSampler
from . import mesh as sector
from .solve import CLAMPED

__all__ = ["EDGE_POINTS", "FAR_SIZE_PER_MODULE", "FILLET_SIZE_PER_MODULE", "FILLET_SIZE_PER_RADIUS",
           "FLANK_SIZE_PER_MODULE", "LEVEL_BIN_PER_RADIUS", "LOAD_SIZE_PER_MODULE", "TIP", "EdgeStress",
           "LineLoadReading", "NotchOptions", "NotchStress", "SectionLoad", "SectionProfile", "edge_stresses",
           "fe_tooth_line_load", "fillet_level", "notch_stress", "section_profile", "solve_point_loads", "tri6_mesh"]

FILLET_SIZE_PER_MODULE = 0.02
FILLET_SIZE_PER_RADIUS = 0.1
FLANK_SIZE_PER_MODULE = 0.1
LOAD_SIZE_PER_MODULE = 0.02
FAR_SIZE_PER_MODULE = 0.5
#: points a fillet edge is read at (its ends included)
EDGE_POINTS = 5
#: the displacement element: vector P2 triangles, isoparametric on the MeshTri2 (curved boundary edges)
_ELEMENT = ElementVector(ElementTriP2())
#: a load at the tip of the flank (where it meets the tip circle, or where a pointed tooth's flanks cross)
TIP = math.inf


@dataclass(frozen=True)
class NotchOptions:
    """The 2D model's knobs: ``refinement`` divides every element size; ``points`` per profile segment
    of the section (the FE tooth's lofted sections take ``fe.mesh.SEGMENT_POINTS`` = 9); ``teeth`` of
    the sector (odd, >= 3: the FE tooth's 3); ``fe_sizes``: a :class:`beveloid.fe.mesh.MeshSizes` to mesh
    the section as the FE tooth meshes its sector instead (its fillet, flank and far sizes, the load
    points at the flank's size, grown from the fillets as the FE tooth grows them; ``refinement`` then
    unused): the same notch at the FE tooth's own elements (``benchmarks/rating_root_convergence.py``)."""

    refinement: float = 1.0
    points: int = 41
    teeth: int = 3
    fe_sizes: object = None

    def __post_init__(self):
        if not (isinstance(self.refinement, (int, float)) and 0.1 <= self.refinement <= 64):
            raise ValueError(f"refinement = {self.refinement!r}: must be a number from 0.1 to 64")
        if not (isinstance(self.points, int) and 5 <= self.points <= 2001):
            raise ValueError(f"points = {self.points!r}: must be an integer from 5 to 2001")
        if not (isinstance(self.teeth, int) and self.teeth >= 3 and self.teeth % 2 == 1):
            raise ValueError(f"teeth = {self.teeth!r}: must be an odd integer >= 3")


@dataclass(frozen=True)
class SectionLoad:
    """A normal line load on tooth 0's ``flank`` at ``radius_mm`` (:data:`TIP`: at the flank's tip)."""

    flank: str
    radius_mm: float

    def __post_init__(self):
        if self.flank not in FLANKS:
            raise ValueError(f"flank = {self.flank!r}: must be one of {', '.join(FLANKS)}")
        if not (self.radius_mm > 0):
            raise ValueError(f"radius_mm = {self.radius_mm!r}: must be a positive radius (mm) or TIP")


@dataclass(frozen=True)
class NotchStress:
    """The section's fillet stresses under one load, per unit normal line load (MPa per N/mm)."""

    load: SectionLoad
    load_point_mm: np.ndarray  # (2,) where the load acts (section plane x, y)
    tension_mpa_per_n_mm: float  # the largest max-principal stress on the loaded side's fillet
    radius_mm: float  # where it is
    height_above_root_mm: float
    tangent_angle_deg: float  # the fillet's tangent there against the tooth's centre line (ISO: 30 deg)
    compression_mpa_per_n_mm: float  # the most compressive min-principal stress on the other fillet
    nodes: int
    triangles: int


@dataclass(frozen=True)
class SectionProfile:
    """The closed profile of one section: ``segments`` [(name, points (n, 2))] in profile order
    (the FE tooth's sector names; the loaded flank of tooth 0 split at the load points), then the
    radial cut, the rim arc and the other cut; ``loads`` the load points' vertices."""

    segments: tuple
    rim_radius_mm: float
    root_radius_mm: float
    load_points_mm: np.ndarray  # (k, 2)
    load_normals: np.ndarray  # (k, 2) outward unit normals in the section
    centre_angle_rad: float  # the polar angle of tooth 0's centre line
    fillet_radius_mm: float  # the fillet's smallest radius of curvature (mesh sizes)


def _flank_l(sampler, flank, z, radius):
    """Rack parameter l of the flank point at ``radius`` in the section z (TIP: the flank's tip)."""
    from ..tooth.profile import flank_at_radius

    zz = np.array([z])
    if math.isinf(radius):
        return float(sampler.flank_tip(flank, zz)[0][0])
    return float(flank_at_radius(sampler.geometry, sampler.member, flank, z, radius)[1])


def section_profile(geometry, member: str, z_mm: float, loads, options: NotchOptions = NotchOptions(),
                    bore_diameter_mm: float = 0.0) -> SectionProfile:
    """The section z_mm (member frame S_i) of ``member`` closed as the FE tooth's sector, with the
    load points of ``loads`` (:class:`SectionLoad`) as vertices of tooth 0's flanks."""
    sampler = ToothSampler(geometry, member)
    z = np.array([float(z_mm)])
    idx = tuple(range(-(options.teeth // 2), options.teeth // 2 + 1))
    segments = [(name, pts[:, 0, :2]) for name, pts in sector._section_segments(sampler, z, idx, options.points)]
    l0 = {f: float(sampler.form_limits(f, z)[0][0]) for f in FLANKS}
    l_tip = {f: _flank_l(sampler, f, z[0], math.inf) for f in FLANKS}
    at = [min(max((_flank_l(sampler, ld.flank, z[0], ld.radius_mm) - l0[ld.flank]) / (l_tip[ld.flank] - l0[ld.flank]),
                  0.0), 1.0) for ld in loads]
    for flank in FLANKS:
        knots = sorted({0.0, 1.0, *(s for s, ld in zip(at, loads) if ld.flank == flank)})
        if len(knots) == 2:
            continue
        pieces = [sampler.flank_points(flank, np.linspace(a, b, max(5, int(math.ceil(options.points * (b - a))))),
                                       z)[:, 0, :2] for a, b in zip(knots[:-1], knots[1:])]
        if flank == "right":  # the profile runs along increasing polar angle: the right flank's tip first
            pieces = [p[::-1] for p in pieces[::-1]]
        name = f"flank_{flank}_0"
        k = [seg[0] for seg in segments].index(name)
        segments[k:k + 1] = [(name if i == 0 else f"{name}_{i}", p) for i, p in enumerate(pieces)]
    points, normals = [], []
    for s, ld in zip(at, loads):
        l = np.array([l0[ld.flank] + s * (l_tip[ld.flank] - l0[ld.flank])])
        surf = geometry.surface(member, ld.flank, l, sampler.flank_u(ld.flank, l, z))
        points.append(np.asarray(surf.point)[0, :2])
        nrm = np.asarray(surf.normal)[0, :2]
        normals.append(nrm / np.linalg.norm(nrm))
    tip = sampler.face_points("tip", np.array([0.5]), z)[0, 0]
    return SectionProfile(tuple(segments), sector.rim_radius(sampler, bore_diameter_mm),
                          float(sampler.root_radius_mm(z)[0]), np.array(points).reshape(-1, 2),
                          np.array(normals).reshape(-1, 2), math.atan2(tip[1], tip[0]),
                          sector.fillet_radius_mm(sampler))


@dataclass(frozen=True)
class _SectionMesh:
    mesh: object  # skfem.MeshTri2
    facets: dict  # curve name -> skfem facet indices
    load_vertices: np.ndarray  # (k,) skfem vertex index of each load point


#: growth of the element size away from a fine curve: the size rises by 1/GROWTH per mm
GROWTH = 2.0


def _sizes(profile: SectionProfile, normal_module_mm: float, refinement: float, fe_sizes=None) -> dict:
    if fe_sizes is not None:
        return {"fillet": fe_sizes.fillet_mm, "flank": fe_sizes.flank_mm, "load": fe_sizes.flank_mm, "far": fe_sizes.far_mm,
                "growth": sector.FILLET_GROWTH}
    m = normal_module_mm
    return {"fillet": min(FILLET_SIZE_PER_MODULE * m, FILLET_SIZE_PER_RADIUS * profile.fillet_radius_mm) / refinement,
            "flank": FLANK_SIZE_PER_MODULE * m / refinement, "load": LOAD_SIZE_PER_MODULE * m / refinement,
            "far": FAR_SIZE_PER_MODULE * m / refinement}


def _threshold(field, distance, fine, far, growth=None):
    t = field.add("Threshold")
    field.setNumber(t, "InField", distance)
    field.setNumber(t, "SizeMin", fine)
    field.setNumber(t, "SizeMax", far)
    field.setNumber(t, "DistMin", 0.5 * fine)
    field.setNumber(t, "DistMax", 0.5 * fine + (GROWTH if growth is None else growth) * (far - fine))
    return t


def _mesh_section(profile: SectionProfile, sizes: dict) -> _SectionMesh:
    """gmsh: the profile as splines, closed by the cuts and the rim arc; 6-node triangles whose
    boundary mid-nodes lie on the curves (gmsh's second order on the geometry)."""
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("section")
        occ = gmsh.model.occ
        curves, first, prev = {}, None, None
        for name, pts in profile.segments:
            tags = [prev if prev is not None else occ.addPoint(pts[0, 0], pts[0, 1], 0.0)]
            tags += [occ.addPoint(x, y, 0.0) for x, y in pts[1:]]
            first = tags[0] if first is None else first
            curves[name] = occ.addSpline(tags)
            prev = tags[-1]
        r = profile.rim_radius_mm
        end, start = profile.segments[-1][1][-1], profile.segments[0][1][0]
        a_end, a_start = math.atan2(end[1], end[0]), math.atan2(start[1], start[0])
        p_end = occ.addPoint(r * math.cos(a_end), r * math.sin(a_end), 0.0)
        p_start = occ.addPoint(r * math.cos(a_start), r * math.sin(a_start), 0.0)
        centre = occ.addPoint(0.0, 0.0, 0.0)
        curves["side_hi"] = occ.addLine(prev, p_end)
        curves["rim"] = occ.addCircleArc(p_end, centre, p_start)
        curves["side_lo"] = occ.addLine(p_start, first)
        loop = occ.addCurveLoop(list(curves.values()))
        occ.addPlaneSurface([loop])
        occ.synchronize()
        field = gmsh.model.mesh.field
        fine = []
        for kind in ("fillet", "flank"):
            d = field.add("Distance")
            field.setNumbers(d, "CurvesList", [t for n, t in curves.items() if n.startswith((f"{kind}_left_0",
                                                                                           f"{kind}_right_0"))])
            field.setNumber(d, "Sampling", 400)
            fine.append(_threshold(field, d, sizes[kind], sizes["far"], sizes.get("growth")))
        if len(profile.load_points_mm):
            pts = [occ.addPoint(x, y, 0.0) for x, y in profile.load_points_mm]
            occ.synchronize()
            d = field.add("Distance")
            field.setNumbers(d, "PointsList", pts)
            fine.append(_threshold(field, d, sizes["load"], sizes["far"], sizes.get("growth")))
        mn = field.add("Min")
        field.setNumbers(mn, "FieldsList", fine)
        field.setAsBackgroundMesh(mn)
        for key in ("MeshSizeFromCurvature", "MeshSizeExtendFromBoundary", "MeshSizeFromPoints"):
            gmsh.option.setNumber(f"Mesh.{key}", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        mesh, facets = tri6_mesh(gmsh, curves)
    finally:
        gmsh.finalize()
    verts = mesh.doflocs[:, :mesh.t.max() + 1].T
    load_vertices = np.array([int(np.argmin(np.sum((verts - p) ** 2, axis=1))) for p in profile.load_points_mm],
                             dtype=np.int64)
    gap = [float(np.linalg.norm(verts[v] - p)) for v, p in zip(load_vertices, profile.load_points_mm)]
    if gap and max(gap) > 1e-6:
        raise RuntimeError(f"a load point is {max(gap):.3g} mm from the nearest mesh vertex: not a vertex of the mesh")
    return _SectionMesh(mesh, facets, load_vertices)


def tri6_mesh(gmsh, curves: dict) -> tuple:
    """(MeshTri2, {name: facet indices}) of gmsh's current 2D second-order mesh: its 6-node triangles
    (turned counter-clockwise) and the facets of each named curve (``curves`` {name: curve tag})."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags] = np.arange(tags.size)
    xy = coords.reshape(-1, 3)[:, :2]
    tri6 = gmsh.model.mesh.getElementType("Triangle", 2)
    line3 = gmsh.model.mesh.getElementType("Line", 2)
    et, _, en = gmsh.model.mesh.getElements(2)
    tri = index[np.asarray(en[list(et).index(tri6)], dtype=np.int64).reshape(-1, 6)]
    lines = {}
    for name, tag in curves.items():
        et, _, en = gmsh.model.mesh.getElements(1, tag)
        lines[name] = index[np.asarray(en[list(et).index(line3)], dtype=np.int64).reshape(-1, 3)]
    a, b, c = xy[tri[:, 0]], xy[tri[:, 1]], xy[tri[:, 2]]
    flip = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    tri[flip] = tri[flip][:, [0, 2, 1, 5, 4, 3]]
    mesh = MeshTri2(np.ascontiguousarray(xy.T), np.ascontiguousarray(tri.T))
    corners = np.unique(tri[:, :3])  # MeshTri2 numbers the corner nodes in this order
    vertex = np.full(xy.shape[0], -1, dtype=np.int64)
    vertex[corners] = np.arange(corners.size)
    facet_of = {(int(i), int(j)): k for k, (i, j) in enumerate(np.sort(mesh.facets, axis=0).T)}
    return mesh, {name: np.array([facet_of[tuple(sorted((int(vertex[p]), int(vertex[q]))))] for p, q in ln[:, :2]])
                  for name, ln in lines.items()}


def _fillet_facets(facets: dict, flank: str) -> np.ndarray:
    """The facets of tooth 0's ``flank`` fillet and of the root land beside it (a sharp rack's
    trochoid meets the land tangentially at the fillet's deepest point, where its stress peaks)."""
    return np.concatenate([facets[f"fillet_{flank}_0"], facets[sector.FILLET_LANDS[flank]]])


#: the reference triangle's edges (corner a, corner b) and the point at parameter t along each
_EDGES = (((0, 1), lambda t: np.stack([t, 0 * t])), ((1, 2), lambda t: np.stack([1 - t, t])),
          ((2, 0), lambda t: np.stack([0 * t, 1 - t])))


def _edge_bases(mesh, facets) -> list:
    """CellBases that evaluate the field on the given boundary facets, :data:`EDGE_POINTS` points each
    (ends included), in the reference coordinates of the triangle that owns each facet (no inverse
    map of the curved elements): one basis per local edge index."""
    tri = mesh.f2t[0, facets]
    t = np.linspace(0.0, 1.0, EDGE_POINTS)
    ends = np.sort(mesh.facets[:, facets], axis=0)
    out = []
    for (a, b), along in _EDGES:
        mine = np.sort(mesh.t[[a, b]][:, tri], axis=0)
        hit = np.all(mine == ends, axis=0)
        if hit.any():
            out.append(CellBasis(mesh, _ELEMENT, elements=tri[hit], quadrature=(along(t), np.full(t.size, 1.0 / t.size))))
    return out


def solve_point_loads(mesh, clamped_facets, vertices, forces, material) -> np.ndarray:
    """Plane-strain displacements (dofs, k) (mm) of a MeshTri2 under k point loads: load j the force
    ``forces[j]`` (2,) (N per mm of thickness) at mesh vertex ``vertices[j]``; every dof of the facets
    ``clamped_facets`` held; E, nu = ``material`` (MPa, -).  One factorisation, all loads."""
    import scipy.sparse.linalg

    lam, mu = lame_parameters(*material)
    basis = Basis(mesh, _ELEMENT, intorder=4)
    K = asm(linear_elasticity(lam, mu), basis)
    clamped = basis.get_dofs(facets=np.asarray(clamped_facets)).all()
    F = np.zeros((basis.N, len(vertices)))
    for j, (v, f) in enumerate(zip(vertices, forces)):
        F[basis.nodal_dofs[:, v], j] = f
    free = np.setdiff1d(np.arange(basis.N), clamped)
    U = np.zeros_like(F)
    U[free] = scipy.sparse.linalg.splu(K[free][:, free].tocsc()).solve(np.ascontiguousarray(F[free]))
    return U


@dataclass(frozen=True)
class EdgeStress:
    """The stress on boundary facets, :data:`EDGE_POINTS` points a facet (its ends included)."""

    max_principal_mpa: np.ndarray  # (k loads, facets, points)
    min_principal_mpa: np.ndarray
    points_mm: np.ndarray  # (2, facets, points)


def edge_stresses(mesh, facets, displacements, material) -> EdgeStress:
    """The plane-strain principal stresses (the out-of-plane nu (s_xx + s_yy) among them) of the
    displacements (dofs, k) on the boundary ``facets``, each facet read in the triangle that owns it."""
    e_mpa, nu = material
    lam, mu = lame_parameters(e_mpa, nu)
    s1, s3, xs = [], [], []
    for cb in _edge_bases(mesh, facets):
        grad = np.stack([cb.interpolate(u).grad for u in np.asarray(displacements).T])  # (k, 2, 2, el, pts)
        eps = 0.5 * (grad + np.swapaxes(grad, 1, 2))
        tr = eps[:, 0, 0] + eps[:, 1, 1]
        sxx, syy, sxy = lam * tr + 2 * mu * eps[:, 0, 0], lam * tr + 2 * mu * eps[:, 1, 1], 2 * mu * eps[:, 0, 1]
        mid, rad = 0.5 * (sxx + syy), np.hypot(0.5 * (sxx - syy), sxy)
        szz = nu * (sxx + syy)
        s1.append(np.maximum(mid + rad, szz))
        s3.append(np.minimum(mid - rad, szz))
        xs.append(np.asarray(cb.global_coordinates()))
    return EdgeStress(np.concatenate(s1, axis=1), np.concatenate(s3, axis=1), np.concatenate(xs, axis=1))


def notch_stress(pair, member: str, loads, options: NotchOptions = NotchOptions(), z_mm: float | None = None,
                 material=(210_000.0, 0.3)) -> tuple:
    """(:class:`NotchStress` per load of ``loads``): the plane-strain section z_mm (member frame; None:
    mid-face) of ``member`` under each load alone, E, nu = ``material`` (MPa, -).  ``pair``: a
    :class:`beveloid.pair.Pair` (its spec gives the bore, as the FE tooth's) or a ``PairGeometry``."""
    geometry = getattr(pair, "geometry", pair)
    spec = getattr(pair, "spec", None)
    bore = float(getattr(getattr(spec, member, None), "bore_diameter_mm", 0.0) or 0.0) if spec else 0.0
    loads = tuple(loads)
    if z_mm is None:
        z_mm = 0.5 * sum(ToothSampler(geometry, member).z_range_mm)
    profile = section_profile(geometry, member, z_mm, loads, options, bore)
    sm = _mesh_section(profile, _sizes(profile, geometry.normal_module_mm, options.refinement, options.fe_sizes))
    U = solve_point_loads(sm.mesh, np.concatenate([sm.facets[k] for k in CLAMPED]), sm.load_vertices,
                          -profile.load_normals, material)  # 1 N/mm along each inward normal
    reads = {side: edge_stresses(sm.mesh, _fillet_facets(sm.facets, side), U, material) for side in FLANKS}
    centre = np.array([math.cos(profile.centre_angle_rad), math.sin(profile.centre_angle_rad)])
    out = []
    for j, ld in enumerate(loads):
        loaded, other = reads[ld.flank], reads[FLANKS[1 - FLANKS.index(ld.flank)]]
        f, q = np.unravel_index(int(np.argmax(loaded.max_principal_mpa[j])), loaded.max_principal_mpa[j].shape)
        x = loaded.points_mm
        tangent = x[:, f, -1] - x[:, f, 0]
        angle = math.degrees(math.acos(min(1.0, abs(float(tangent @ centre)) / float(np.linalg.norm(tangent)))))
        radius = float(np.hypot(*x[:, f, q]))
        out.append(NotchStress(ld, profile.load_points_mm[j], float(loaded.max_principal_mpa[j, f, q]), radius,
                               radius - profile.root_radius_mm, angle, float(np.min(other.min_principal_mpa[j])),
                               int(sm.mesh.doflocs.shape[1]), int(sm.mesh.t.shape[1])))
    return tuple(out)


#: the height bands of :func:`fillet_level`, in fillet radii (:func:`beveloid.fe.mesh.fillet_radius_mm`):
#: measured, the level moves by less than 1 % from 0.05 to 0.025 radii on a 2.05 mm and a 0.47 mm fillet
#: (a sharp rack's trochoid peaks within a tenth of a millimetre of the root)
LEVEL_BIN_PER_RADIUS = 0.05


def fillet_level(height_mm, z_mm, stress_mpa, z_range_mm, bin_mm: float) -> float:
    """The mid-face level of a 3D fillet's nodal stress under a load uniform along the face: of the
    nodes in the middle half of the face, the mean stress of those in each band of height above
    the root (``bin_mm`` wide), the largest of these means.  Along a uniformly loaded face the field
    does not change, so the nodes of one band sample one value: their mean removes the node-to-node
    scatter of a tet mesh's nodal stresses that a largest value picks up."""
    lo, hi = sorted(z_range_mm)
    middle = np.abs(np.asarray(z_mm) - 0.5 * (lo + hi)) <= 0.25 * (hi - lo)
    band = np.floor(np.asarray(height_mm)[middle] / bin_mm).astype(int)
    values = np.asarray(stress_mpa)[middle]
    return float(max(values[band == k].mean() for k in np.unique(band)))


@dataclass(frozen=True)
class LineLoadReading:
    """The FE tooth (:mod:`beveloid.fe.tooth`) under the 2D model's load made a uniform line load along
    the whole face, per unit line load (MPa per N/mm)."""

    max_mpa_per_n_mm: float  # FeTooth.root_stress: the largest over the loaded fillet (what the LTCA reads)
    mid_face_mpa_per_n_mm: float  # the median over the middle half of the face of FeTooth.along_face's slices
    level_mpa_per_n_mm: float  # fillet_level of the loaded fillet's counted nodes
    height_above_root_mm: float  # where the largest is
    face_z_mm: float


def fe_tooth_line_load(data, geometry, member: str, load: SectionLoad, points: int = 41) -> LineLoadReading:
    """The FE tooth ``data`` of ``member`` under ``load`` (:class:`SectionLoad`) on every section of the
    face: ``points`` flank points from toe to heel at its radius, forces by the trapezoidal rule (the
    FE tooth's load grid takes them as it takes the LTCA's), 1 N/mm in all."""
    from ..tooth.profile import flank_at_radius
    from .contact import FeTooth
    from .solve import principal_stresses

    sampler = ToothSampler(geometry, member)
    lo, hi = sorted(sampler.z_range_mm)
    z = np.linspace(lo, hi, points)
    if math.isinf(load.radius_mm):
        at = sampler.flank_points(load.flank, np.array([1.0]), z)[0]
    else:
        at = flank_at_radius(geometry, member, load.flank, z, np.full(z.shape, float(load.radius_mm)))[0]
    forces = np.full(points, (hi - lo) / (points - 1))
    forces[[0, -1]] *= 0.5
    tooth = FeTooth(data, load.flank)
    top = tooth.root_stress(at, forces)
    centres, along = tooth.along_face(at, forces)
    middle = np.abs(centres - 0.5 * (lo + hi)) <= 0.25 * (hi - lo)
    side = FLANKS.index(load.flank)
    g = tooth.weights(at).T @ forces
    nodal = principal_stresses(tooth.stress[side] @ g)[:, 2]
    counted = tooth.counted(g)[0]
    level = fillet_level(data.fillet_height_mm[side][counted], data.fillet_points_mm[side][counted, 2],
                         nodal[counted], (lo, hi), LEVEL_BIN_PER_RADIUS * sector.fillet_radius_mm(sampler))
    return LineLoadReading(top.tension_mpa, float(np.nanmedian(along[middle])), level, top.height_mm, top.z_mm)
