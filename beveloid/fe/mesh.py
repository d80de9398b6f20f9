"""A sector of one member meshed by gmsh as second-order (10-node) tetrahedra.

``sector_mesh(pair, member, refinement=1, teeth=3)`` builds the sector from OUR geometry: the
transverse sections of the tooth faces that the export samples (``tooth.sampling.ToothSampler``:
the generated flanks, the generated root fillets, tip and root cones) are closed into one planar
profile per section z, and gmsh's OpenCASCADE kernel lofts a solid through the sections
(``addThruSections``).  Every segment of the profile becomes one lateral face of the solid, so each
face of the mesh is known by name without searching.  A fillet far thinner than its elements (a
sharp rack's trochoid can be micrometres high) takes a strip of the root land beside it into its face
(:func:`fillet_strips`): the fillet face is then the fillet and that strip, and its stress reading
covers both (as the plane-strain section's reading covers the land beside a fillet).

The sector (member frame S_i, mm): ``teeth`` whole teeth (odd, the loaded tooth 0 in the middle,
tooth k turned by k pitches from the sampled tooth), the root lands either side cut in their middle
by a radial surface (``side_lo``, ``side_hi``), down to the inner surface ``rim``: a cylinder of radius
r_root,min - RIM_DEPTH_PER_HEIGHT * h (h the tooth depth; ISO 6336-3 takes a rim of 1.2 h or more as
not weakening the tooth), or the bore where the member has one outside that cylinder.

Element size (mm, ``refinement`` N divides every size): on the flanks of the loaded tooth
h_flank = FLANK_SIZE_PER_MODULE m_n / N; in the fillets of the loaded tooth
h_fillet = min(max(FILLET_SIZE_PER_RADIUS rho_F, FILLET_SIZE_MIN_PER_MODULE m_n),
max(rho_F / FILLET_RADIUS_ELEMENTS, FILLET_SIZE_NOTCH_PER_MODULE m_n), h_flank) (rho_F the smallest radius
of curvature of the fillet section at mid-face) / N: the second term binds only where the floor would leave
the radius fewer than FILLET_RADIUS_ELEMENTS elements (rho_F < 0.07 m_n), down to the notch floor 0.0125 m_n
(rho_F below 0.021875 m_n, a sharp rack's notch, has fewer than 1.75 elements across its radius); elsewhere
h_far = FAR_SIZE_PER_MODULE m_n / N, grown linearly from the fine faces (over FAR_GROWTH times the size difference from the flanks, over FILLET_GROWTH
times it from the fillets: the fine fillet band stays thin).  The distance from a fine face is read from
samples of it at most half its element size apart (``fe.sizes.distance_sampling``), so that the face
itself is meshed at its size between the samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..tooth.sampling import ToothSampler
from .sizes import FAR_GROWTH, FILLET_GROWTH, ContactStrips, size_field

__all__ = ["FACE_KINDS", "SectorMesh", "MeshSizes", "mesh_sizes", "sector_mesh", "fillet_radius_mm",
           "FLANK_SIZE_PER_MODULE", "FAR_SIZE_PER_MODULE", "MESH_RULES_VERSION", "FAR_GROWTH", "FILLET_GROWTH",
           "FILLET_LANDS", "FILLET_SIZE_PER_RADIUS", "FILLET_RADIUS_ELEMENTS", "FILLET_SIZE_NOTCH_PER_MODULE", "RIM_DEPTH_PER_HEIGHT", "SectorShape", "record_from_gmsh"]

#: raise when the meshing rules change (it is part of the FE cache's key)
MESH_RULES_VERSION = 8  # 4: a fillet far thinner than its elements takes a strip of land; 5: FILLET_RADIUS_ELEMENTS;
# 6: the fine faces' distance fields sampled at half their element size (fe.sizes.distance_sampling); 7: the notch
# floor FILLET_SIZE_NOTCH_PER_MODULE 0.025 -> 0.0125 (R5701-4's gear, rho_F 0.028 m_n, had been held at 0.88 rho_F);
# 8: FILLET_RADIUS_ELEMENTS 1.5 -> 1.75 (case 2's gear, rho_F 0.045 m_n, read 3.1 % below the mean of its refined
# draws at rho_F / 1.5)
FLANK_SIZE_PER_MODULE = 0.3
FAR_SIZE_PER_MODULE = 1.0
FILLET_SIZE_PER_RADIUS = 0.5
RIM_DEPTH_PER_HEIGHT = 1.2
#: the fillet's size is kept above this fraction of the module (a sharp rack's trochoid has a radius
#: of curvature of a few hundredths of a module at its deepest point, where it is not loaded); the
#: fillet band is meshed at 0.5 rho_F, not below this (case 1 at refinement 1: 0.24 mm on both members,
#: whose 0.5 rho_F is 0.21 / 0.14 mm; `python -m benchmarks.bench_fe_tooth sizes 1`): with
#: the curved P2 tets of fe/solve.py the root stress then moves by +5.7 % (pinion) and +2.9 % (gear)
#: from refinement 1 to 2 (docs/loaded_contact.md 9.6, `python -m benchmarks.bench_fe_tooth convergence
#: 1 2`); 0.8 rho_F had left the pinion's 11 % short of refinement 2 (measured when this rule was
#: chosen, commit c09e4f1's docs/loaded_contact.md 9.6)
FILLET_SIZE_MIN_PER_MODULE = 0.04
#: ... but the floor gives way where it would leave the fillet's smallest radius fewer than this many
#: elements: a radius near the floor's size is a notch whose peak the floor's elements do not resolve.
#: Measured on docs/validation.md 10.2's designs before this rule (the smoothed root stress, default
#: against refinement 2): every member with rho_F >= 1.76 floor elements read within +3.3 %, while
#: case 1's and case 2's gears (rho_F 1.16 and 1.12 elements) read 2.9 % and 5.0 % low; 1.5 refined those.
#: 1.75 since MESH_RULES_VERSION 8: at rho_F / 1.5 case 2's gear still read 3.1 % below the mean of its refined
#: draws, at rho_F / 1.75 0.1-0.4 %; the eight members of 10.2's first table it changes (rho_F < 0.07 m_n) read
#: -2.7 ... +2.2 % from their refined values at 1.22-1.32 times their tets, and it leaves the members at 1.76
#: floor elements and above (case 1's and case 2's pinions) as they were
FILLET_RADIUS_ELEMENTS = 1.75
#: and not below this fraction of the module: a trochoid's bottom sharper than 1.75 times it (a sharp rack
#: on many teeth: design B's gear, 0.009 mm on a 4 mm module) is a notch no affordable mesh resolves, which
#: the rating reports (rating.root_convergence).  0.025 had held R5701-4's gear (rho_F 0.028 m_n) at 0.88 rho_F,
#: 8-9 % below its converged root stress; at 0.0125 its radius sets its elements (rho_F / 1.75 since
#: MESH_RULES_VERSION 8: -2.7 % from the rho_F / 1.5 rule's every size / 1.5, docs/validation.md 10.2); no member of
#: 10.2's first table has rho_F below 0.021875 m_n
FILLET_SIZE_NOTCH_PER_MODULE = 0.0125
#: transverse sections the solid is lofted through, and points per face segment in a section
SECTIONS = 9
SEGMENT_POINTS = 9
#: the faces of one tooth in the order a section's profile runs (increasing polar angle)
TOOTH_FACES = ("fillet_left", "flank_left", "tip", "flank_right", "fillet_right", "root")
FACE_KINDS = TOOTH_FACES + ("side_lo", "side_hi", "rim", "toe", "heel")
#: the root land beside each fillet of tooth 0 (the names of :class:`SectorMesh`'s node sets and facets): a
#: sharp rack's trochoid meets it tangentially near where the fillet's stress peaks
FILLET_LANDS = {"left": "root_-1", "right": "root_0"}


@dataclass(frozen=True)
class MeshSizes:
    flank_mm: float
    fillet_mm: float
    far_mm: float
    fillet_radius_mm: float


@dataclass(frozen=True)
class SectorMesh:
    """A member sector as 10-node tetrahedra (gmsh / CalculiX C3D10 node order), member frame S_i.

    * ``nodes``: (n, 3) float, mm, member frame S_i (z along the axis, toe to heel as the spec);
    * ``tets``: (m, 10) int, 0-based node indices, gmsh order (4 corners, then the mid-edge nodes of
      edges 01, 12, 20, 03, 23, 13); CalculiX C3D10 takes the last two swapped (``ccx_tets``);
    * ``facets``: {name: (k, 6) int} the boundary's 6-node triangles of each named surface, outward
      normals (corners 0, 1, 2 counter-clockwise seen from outside, then mid-nodes of 01, 12, 20).
      Names: ``"<face>_<k>"`` for face in :data:`TOOTH_FACES` and tooth k in ``tooth_indices``
      (``flank_left_0`` the loaded tooth's left flank; ``root_k`` the land after tooth k, the last
      one cut in half, ``root_start`` the half land before the first tooth), and ``side_lo``,
      ``side_hi`` (the radial cuts), ``rim`` (bore or rim cylinder), ``toe``, ``heel`` (end planes);
    * ``node_sets``: {name: sorted unique node indices} of the same surfaces;
    * ``tooth_indices``: the sector's teeth, e.g. (-1, 0, 1): tooth k is the sampled tooth turned
      by k * 2 pi / N about the z axis (the TCA's tooth pairs are counted the same way);
    * ``pitch_angle_rad`` (2 pi / N), ``sizes`` (:class:`MeshSizes`), ``refinement``, ``member``,
      ``strip_sizes_mm`` (the contact strips' sizes, ``beveloid.fe.sizes``).
    """

    member: str
    nodes: np.ndarray
    tets: np.ndarray
    facets: dict
    node_sets: dict
    tooth_indices: tuple
    pitch_angle_rad: float
    rim_radius_mm: float
    sizes: MeshSizes
    refinement: int
    z_range_mm: tuple = field(default=(0.0, 0.0))
    strip_sizes_mm: tuple = ()  #: each contact strip's element size (mm), () without strips

    @property
    def corner_tets(self) -> np.ndarray:
        return self.tets[:, :4]

    @property
    def ccx_tets(self) -> np.ndarray:
        """The tets in CalculiX C3D10 order (mid-nodes 01, 12, 20, 03, 13, 23), 0-based."""
        return self.tets[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]

    def volume_mm3(self) -> float:
        """Volume of the straight-sided corner tetrahedra (mm^3)."""
        p = self.nodes[self.tets[:, :4]]
        return float(np.sum(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]),
                                      p[:, 3] - p[:, 0])) / 6.0)


def fillet_radius_mm(sampler: ToothSampler, flank: str = "left") -> float:
    """The smallest radius of curvature of the fillet in the mid-face section (mm), from 81 samples."""
    z = np.array([0.5 * sum(sampler.z_range_mm)])
    p = sampler.face_points(f"fillet_{flank}", np.linspace(0.0, 1.0, 81), z)[:, 0, :2]
    d1 = np.gradient(p, axis=0)
    d2 = np.gradient(d1, axis=0)
    speed = np.hypot(d1[:, 0], d1[:, 1])
    curv = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(speed, 1e-300) ** 3
    return float(1.0 / np.max(curv[2:-2]))


def mesh_sizes(sampler: ToothSampler, normal_module_mm: float, refinement: float,
               fillet_refinement: float | None = None) -> MeshSizes:
    """The element sizes of the module docstring; ``fillet_refinement`` (None: ``refinement``) divides the
    fillet's size instead (fe-check's sectors: their fillets at the FE tooth's sizes, the rest coarser)."""
    rho = fillet_radius_mm(sampler)
    flank = FLANK_SIZE_PER_MODULE * normal_module_mm
    fillet = min(max(FILLET_SIZE_PER_RADIUS * rho, FILLET_SIZE_MIN_PER_MODULE * normal_module_mm),
                 max(rho / FILLET_RADIUS_ELEMENTS, FILLET_SIZE_NOTCH_PER_MODULE * normal_module_mm), flank)
    fillet /= refinement if fillet_refinement is None else fillet_refinement
    return MeshSizes(flank / refinement, fillet, FAR_SIZE_PER_MODULE * normal_module_mm / refinement, rho)


def _rotate(points, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * points[..., 0] - s * points[..., 1], s * points[..., 0] + c * points[..., 1],
                     points[..., 2]], axis=-1)


def _section_segments(sampler: ToothSampler, z, teeth: tuple, n: int, strip_mm: float = 0.0):
    """Per face segment of the profile: (name, points (n_points, len(z), 3)) in profile order.

    ``strip_mm`` (the fillet's element size): a fillet shorter than STRIP_BELOW_FRACTION of it in
    some section (a sharp rack's trochoid can be a few micrometres high) takes a strip of the root
    land beside it, ``strip_mm`` wide along the land, into its face (:func:`fillet_strips`): a face
    far thinner than its elements gave gmsh overlapping boundary facets."""
    s = np.linspace(0.0, 1.0, n)
    pitch = sampler.pitch_angle_rad
    strips = fillet_strips(sampler, z, strip_mm)
    base = {f: sampler.face_points(f, s, z) for f in TOOTH_FACES if f != "root"}
    if strips["left"] is not None:  # the land before the tooth, ending at its left fillet, then the fillet
        land = _land(sampler, z, 1.0 - strips["left"], 1.0, LAND_STRIP_POINTS + 1)[:-1]
        base["fillet_left"] = np.concatenate([_rotate(land, -pitch), base["fillet_left"]])
    base["flank_right"] = base["flank_right"][::-1]
    base["fillet_right"] = base["fillet_right"][::-1]
    if strips["right"] is not None:  # the fillet, then the land after it
        land = _land(sampler, z, np.zeros(len(z)), strips["right"], LAND_STRIP_POINTS + 1)[1:]
        base["fillet_right"] = np.concatenate([base["fillet_right"], land])
    lo = np.zeros(len(z)) if strips["right"] is None else strips["right"]
    hi = np.ones(len(z)) if strips["left"] is None else 1.0 - strips["left"]
    base["root"] = _land(sampler, z, lo, hi, n)
    segments = [("root_start", _rotate(_land(sampler, z, 0.5 * (lo + hi), hi, n), (teeth[0] - 1) * pitch))]
    for k in teeth:
        for f in TOOTH_FACES:
            pts = base[f]
            if f == "root" and k == teeth[-1]:
                pts = _land(sampler, z, lo, 0.5 * (lo + hi), n)
            segments.append((f"{f}_{k}", _rotate(pts, k * pitch)))
    return segments


#: profile points of one segment closer than this to the point kept before them are left out of its spline (mm):
#: OpenCASCADE refuses a spline through coincident points (its confusion tolerance is 1e-7 mm), and a rack tip
#: radius of ~1e-16 m_n (in its documented range) samples a fillet whose points lie 5e-11 mm apart
DISTINCT_POINT_MM = 1e-6


def _distinct_points(p: np.ndarray) -> np.ndarray:
    """The points (n, 3) of one segment in one section without those within :data:`DISTINCT_POINT_MM` of the
    point kept before them; its two ends stay (they join the neighbouring segments): where the last lies that close
    to an interior point kept, the interior one goes."""
    keep = [0]
    for i in range(1, len(p) - 1):
        if np.linalg.norm(p[i] - p[keep[-1]]) >= DISTINCT_POINT_MM:
            keep.append(i)
    if len(keep) > 1 and np.linalg.norm(p[-1] - p[keep[-1]]) < DISTINCT_POINT_MM:
        keep.pop()
    return p[keep + [len(p) - 1]]


#: points a fillet's land strip adds to its section's profile segment (besides the fillet's own)
LAND_STRIP_POINTS = 4
#: a strip takes at most this fraction of the land's length in each section
LAND_STRIP_MAX_FRACTION = 0.25
#: a fillet shorter than this fraction of its element size in some section takes a land strip (a
#: sharp rack's 12 um pinion fillet meshed at 0.32 mm without one; its gear's 7 nm fillet did not)
STRIP_BELOW_FRACTION = 0.25


def _land(sampler: ToothSampler, z, lo, hi, n: int):
    """The root land of the sampled tooth (root cone, ``root`` face) from s = lo to s = hi (per
    section, arrays of len(z)) at n points each: (n, len(z), 3)."""
    lo, hi = np.broadcast_to(lo, (len(z),)), np.broadcast_to(hi, (len(z),))
    if np.all(lo == lo[0]) and np.all(hi == hi[0]):  # no strip: the same s in every section
        return sampler.face_points("root", np.linspace(lo[0], hi[0], n), z)
    return np.concatenate([sampler.face_points("root", np.linspace(a, b, n), z[j:j + 1])
                           for j, (a, b) in enumerate(zip(lo, hi))], axis=1)


def fillet_strips(sampler: ToothSampler, z, strip_mm: float) -> dict:
    """{flank: None, or the fraction of the land (root face's s, per section) its fillet takes}: a
    fillet whose section (a polyline of 33 points) is shorter than STRIP_BELOW_FRACTION ``strip_mm``
    in some section z takes ``strip_mm`` of the land beside it in every section (at most
    LAND_STRIP_MAX_FRACTION of it).  The fillets of a rounded rack are far longer: none takes one."""
    out = {"left": None, "right": None}
    if strip_mm <= 0.0:
        return out
    fine = np.linspace(0.0, 1.0, 33)
    land = np.sum(np.linalg.norm(np.diff(sampler.face_points("root", fine, z), axis=0), axis=-1), axis=0)
    for flank in out:
        pts = sampler.face_points(f"fillet_{flank}", fine, z)
        length = np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=-1), axis=0)
        if np.min(length) < STRIP_BELOW_FRACTION * strip_mm:
            out[flank] = np.minimum(strip_mm / land, LAND_STRIP_MAX_FRACTION)
    return out


def _references(segments, z, r_rim):
    """A point of each lateral face in the mid section: the middle of its profile segment."""
    j = len(z) // 2
    refs = {name: pts[pts.shape[0] // 2, j] for name, pts in segments}
    ends = {"side_lo": segments[0][1][0, j], "side_hi": segments[-1][1][-1, j]}
    angle = {k: math.atan2(p[1], p[0]) for k, p in ends.items()}
    for k, p in ends.items():
        r = 0.5 * (math.hypot(p[0], p[1]) + r_rim)
        refs[k] = np.array([r * math.cos(angle[k]), r * math.sin(angle[k]), z[j]])
    mid = 0.5 * (angle["side_lo"] + angle["side_hi"])
    refs["rim"] = np.array([r_rim * math.cos(mid), r_rim * math.sin(mid), z[j]])
    return refs


def rim_radius(sampler: ToothSampler, bore_diameter_mm: float) -> float:
    """The sector's inner radius (mm): the rim of the module docstring, or the bore where it leaves a
    thinner rim (a bore further in does not weaken the tooth, ISO 6336-3's rim of 1.2 h; and a bore of
    1e-38 mm is no bore to mesh)."""
    z = np.array(sampler.z_range_mm)
    r_root = float(np.min(sampler.root_radius_mm(z)))
    depth = float(np.max(sampler.tip_radius_mm(z) - sampler.root_radius_mm(z)))
    return max(r_root - RIM_DEPTH_PER_HEIGHT * depth, 0.5 * bore_diameter_mm)


def sector_mesh(pair, member: str, refinement: int = 1, teeth: int = 3, coarsen: float = 1.0,
                strips: ContactStrips | None = None, fine_teeth: tuple = (0,),
                fillet_coarsen: float | None = None) -> SectorMesh:
    """The member's sector meshed by gmsh (see :class:`SectorMesh` for the record's fields).

    ``pair``: a :class:`beveloid.pair.Pair` (its spec gives the bore) or a ``PairGeometry``;
    ``refinement`` N divides every element size; ``teeth`` (odd, >= 3) the sector's teeth;
    ``coarsen`` multiplies every size (> 1: a cheaper mesh for tests and quick looks); ``strips``
    (:class:`beveloid.fe.sizes.ContactStrips`, member frame) refine about loaded contacts
    (fe-check only: the FE tooth passes none, its meshes do not depend on it); ``fine_teeth``: the
    teeth whose flanks and fillets are meshed at the loaded tooth's sizes (fe-check: every tooth that
    carries a load; the FE tooth loads tooth 0 only); ``fillet_coarsen`` (None: ``coarsen``) multiplies
    the fillets' size instead (fe-check: its sectors' fillets at the FE tooth's sizes, every other size
    coarser).
    """
    import gmsh

    if not (isinstance(refinement, int) and 1 <= refinement <= 4):
        raise ValueError(f"fe_refinement = {refinement!r}: must be an integer from 1 to 4")
    if not (isinstance(teeth, int) and teeth >= 3 and teeth % 2 == 1):
        raise ValueError(f"teeth = {teeth!r}: must be an odd integer >= 3")
    geometry = getattr(pair, "geometry", pair)
    spec = getattr(pair, "spec", None)
    bore = float(getattr(getattr(spec, member, None), "bore_diameter_mm", 0.0) or 0.0) if spec else 0.0
    sampler = ToothSampler(geometry, member)
    toe, heel = sampler.z_range_mm
    zlo, zhi = min(toe, heel), max(toe, heel)
    sampler.check_buildable(np.linspace(zlo, zhi, 11))
    sampler.check_bore(bore)
    idx = tuple(range(-(teeth // 2), teeth // 2 + 1))
    if not (0 in fine_teeth and set(fine_teeth) <= set(idx)):
        raise ValueError(f"fine_teeth = {fine_teeth!r}: must hold tooth 0 and only teeth of {idx}")
    if not (isinstance(coarsen, (int, float)) and 0.25 <= coarsen <= 8):
        raise ValueError(f"coarsen = {coarsen!r}: must be a number from 0.25 to 8")
    if fillet_coarsen is not None and not (isinstance(fillet_coarsen, (int, float)) and 0.125 <= fillet_coarsen <= 8):
        raise ValueError(f"fillet_coarsen = {fillet_coarsen!r}: must be None or a number from 0.125 to 8")
    sizes = mesh_sizes(sampler, geometry.normal_module_mm, refinement / coarsen,
                       None if fillet_coarsen is None else refinement / fillet_coarsen)
    r_rim = rim_radius(sampler, bore)
    z = np.linspace(zlo, zhi, SECTIONS)
    segments = _section_segments(sampler, z, idx, SEGMENT_POINTS, strip_mm=sizes.fillet_mm)

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(f"{member}_sector")
        occ = gmsh.model.occ
        wires = []
        for j, zj in enumerate(z):
            curves, first = [], None
            prev_tag = None
            for _, pts in segments:
                p = _distinct_points(pts[:, j])
                tags = [occ.addPoint(*p[0]) if prev_tag is None else prev_tag]
                tags += [occ.addPoint(*q) for q in p[1:]]
                first = tags[0] if first is None else first
                curves.append(occ.addSpline(tags))
                prev_tag = tags[-1]
            end = segments[-1][1][-1, j]
            start = segments[0][1][0, j]
            a_end, a_start = math.atan2(end[1], end[0]), math.atan2(start[1], start[0])
            p_end = occ.addPoint(r_rim * math.cos(a_end), r_rim * math.sin(a_end), zj)
            p_start = occ.addPoint(r_rim * math.cos(a_start), r_rim * math.sin(a_start), zj)
            centre = occ.addPoint(0.0, 0.0, zj)
            curves.append(occ.addLine(prev_tag, p_end))
            curves.append(occ.addCircleArc(p_end, centre, p_start))
            curves.append(occ.addLine(p_start, first))
            wires.append(occ.addCurveLoop(curves))
        out = occ.addThruSections(wires, makeSolid=True, makeRuled=False)
        occ.synchronize()
        volumes = [t for d, t in out if d == 3]
        if len(volumes) != 1:
            raise RuntimeError(f"{member}: gmsh lofted {len(volumes)} volumes through the sections, not one")
        faces = [t for d, t in gmsh.model.getBoundary([(3, volumes[0])], oriented=False)]
        face_of = _name_faces(faces, _references(segments, z, r_rim), z)
        for name, tag in face_of.items():
            gmsh.model.addPhysicalGroup(2, [tag], name=name)
        gmsh.model.addPhysicalGroup(3, volumes, name="sector")
        fine = size_field(face_of, sizes, strips, refinement / coarsen)
        _fine_teeth(face_of, sizes, fine_teeth)
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # frontal-Delaunay surfaces
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay (measured faster than HXT here)
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)  # mid-nodes placed by _curve_midnodes
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        _curve_midnodes(gmsh, face_of)
        return record_from_gmsh(gmsh, member, face_of, SectorShape(
            tooth_indices=idx, pitch_angle_rad=sampler.pitch_angle_rad, rim_radius_mm=r_rim, sizes=sizes,
            refinement=refinement, z_range_mm=(toe, heel), strip_sizes_mm=fine))
    finally:
        gmsh.finalize()


def _fine_teeth(face_of, sizes, fine_teeth):
    """Mesh the flanks and fillets of every tooth in ``fine_teeth`` as tooth 0's: the size field of
    each (:func:`beveloid.fe.sizes.size_field` on that tooth's faces) and the background field the
    smallest of them and of tooth 0's (the current one, strips included)."""
    import gmsh

    others = [k for k in fine_teeth if k != 0]
    if not others:
        return
    f = gmsh.model.mesh.field
    fields = [max(f.list())]  # the Min field size_field made the background
    for k in others:
        size_field({f"{kind}_{side}_0": face_of[f"{kind}_{side}_{k}"] for kind in ("flank", "fillet")
                    for side in ("left", "right")}, sizes)
        fields.append(max(f.list()))
    m = f.add("Min")
    f.setNumbers(m, "FieldsList", fields)
    f.setAsBackgroundMesh(m)


def _name_faces(faces, references, z):
    """{name: gmsh face tag}: the end planes by z, each lateral face by the reference point (a point
    of its profile segment in the mid section) nearest to its own parametric middle."""
    import gmsh
    from scipy.optimize import linear_sum_assignment

    out, lateral = {}, []
    for tag in faces:
        box = gmsh.model.getBoundingBox(2, tag)
        if abs(box[2] - box[5]) < 1e-3:
            out["toe" if abs(box[2] - z[0]) < abs(box[2] - z[-1]) else "heel"] = tag
        else:
            lateral.append(tag)
    names = list(references)
    if len(lateral) != len(names) or len(out) != 2:
        raise RuntimeError(f"the lofted sector has {len(lateral)} lateral faces and {len(out)} end faces, expected"
                           f" {len(names)} and 2")
    mids = []
    for tag in lateral:
        lo, hi = gmsh.model.getParametrizationBounds(2, tag)
        mids.append(gmsh.model.getValue(2, tag, 0.5 * (np.asarray(lo) + np.asarray(hi))))
    cost = np.linalg.norm(np.asarray(mids)[:, None, :] - np.array([references[n] for n in names])[None], axis=-1)
    rows, cols = linear_sum_assignment(cost)
    return {**out, **{names[c]: lateral[r] for r, c in zip(rows, cols)}}


def _curve_midnodes(gmsh, face_of):
    """Move the mid-edge nodes of the boundary triangles onto their face: the face evaluated at the
    mean of the edge's corner parameters (gmsh's own curved setOrder, a projection per node, took
    10 s for 20k nodes).  Corners on the face's boundary curves take the face parameters of their
    curve parameter (the curve's own trace on the face); the few left (the curves' end points) are
    parametrised on the face by projection (a projection of every boundary corner took 1 s a member)."""
    tri6 = gmsh.model.mesh.getElementType("Triangle", 2)
    for name, tag in face_of.items():
        if name in ("toe", "heel"):
            continue  # planes: the straight mid-point lies on them
        inner, _, par = gmsh.model.mesh.getNodes(2, tag, includeBoundary=False, returnParametricCoord=True)
        uv = dict(zip(inner.tolist(), np.asarray(par).reshape(-1, 2)))
        for _, curve in gmsh.model.getBoundary([(2, tag)], combined=False, oriented=False):
            on, _, t = gmsh.model.mesh.getNodes(1, abs(curve), includeBoundary=False, returnParametricCoord=True)
            if len(on):
                uv.update(zip(on.tolist(), np.asarray(
                    gmsh.model.reparametrizeOnSurface(1, abs(curve), t, tag)).reshape(-1, 2)))
        et, _, en = gmsh.model.mesh.getElements(2, tag)
        tri = np.asarray(en[list(et).index(tri6)], dtype=np.int64).reshape(-1, 6)
        edge_nodes = sorted(set(np.unique(tri[:, :3]).tolist()) - set(uv))
        if edge_nodes:
            xyz = np.array([gmsh.model.mesh.getNode(n)[0] for n in edge_nodes])
            par = np.asarray(gmsh.model.getParametrization(2, tag, xyz.ravel())).reshape(-1, 2)
            uv.update(zip(edge_nodes, par))
        mids, params = {}, []
        for a, b, m in ((0, 1, 3), (1, 2, 4), (2, 0, 5)):
            for row in tri.tolist():
                if row[m] not in mids:
                    mids[row[m]] = len(params)
                    params.append(0.5 * (uv[row[a]] + uv[row[b]]))
        xyz = np.asarray(gmsh.model.getValue(2, tag, np.ravel(params))).reshape(-1, 3)
        for node, k in mids.items():
            gmsh.model.mesh.setNode(node, xyz[k], [])


class SectorShape(NamedTuple):
    """What a sector is beside its mesh: the :class:`SectorMesh` fields of the same names."""

    tooth_indices: tuple
    pitch_angle_rad: float
    rim_radius_mm: float
    sizes: "MeshSizes"
    refinement: int
    z_range_mm: tuple
    strip_sizes_mm: tuple = ()


def record_from_gmsh(gmsh, member, face_of, shape: SectorShape) -> SectorMesh:
    """The :class:`SectorMesh` of gmsh's current mesh, faces named by ``face_of`` {name: face tag}."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(tags)
    tags = tags[order]
    nodes = coords.reshape(-1, 3)[order]
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags] = np.arange(tags.size)
    etypes, _, enodes = gmsh.model.mesh.getElements(3)
    tet10 = gmsh.model.mesh.getElementType("Tetrahedron", 2)
    k = list(etypes).index(tet10)
    tets = index[np.asarray(enodes[k], dtype=np.int64).reshape(-1, 10)]
    tri6 = gmsh.model.mesh.getElementType("Triangle", 2)
    facets, node_sets = {}, {}
    for name, tag in face_of.items():
        et, _, en = gmsh.model.mesh.getElements(2, tag)
        tri = index[np.asarray(en[list(et).index(tri6)], dtype=np.int64).reshape(-1, 6)]
        facets[name] = tri
        node_sets[name] = np.unique(tri)
    # only nodes used by the tets (gmsh keeps geometry points too)
    used = np.unique(tets)
    remap = np.full(nodes.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    nodes = nodes[used]
    tets = remap[tets]
    facets = {k: remap[v] for k, v in facets.items()}
    node_sets = {k: remap[v] for k, v in node_sets.items()}
    facets = _outward(nodes, tets, facets)
    return SectorMesh(member=member, nodes=nodes, tets=tets, facets=facets, node_sets=node_sets, **shape._asdict())


def _outward(nodes, tets, facets):
    """Facets turned so that their corner normals point out of the volume: away from the fourth
    corner of the tet they bound."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [1, 2, 3]], tets[:, [0, 2, 3]]])
    opposite = np.concatenate([tets[:, 3], tets[:, 2], tets[:, 0], tets[:, 1]])
    key = {tuple(f): o for f, o in zip(np.sort(faces, axis=1).tolist(), opposite.tolist())}
    return {name: _turned(nodes, tri, key) for name, tri in facets.items()}


def _turned(nodes, tri, key):
    if tri.size == 0:
        return tri
    fourth = np.array([key[tuple(f)] for f in np.sort(tri[:, :3], axis=1).tolist()])
    a = nodes[tri[:, 0]]
    n = np.cross(nodes[tri[:, 1]] - a, nodes[tri[:, 2]] - a)
    flip = np.einsum("ij,ij->i", n, nodes[fourth] - a) > 0
    out = tri.copy()
    out[flip] = tri[flip][:, [0, 2, 1, 5, 4, 3]]
    return out
