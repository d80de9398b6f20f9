"""The element-size fields of a sector mesh (gmsh background fields), and the optional local
refinement over contact strips (``beveloid fe-check``).

The face-wide sizes (:func:`size_field`): the flanks and fillets of the loaded tooth at their own
size, grown linearly to the far size (``beveloid.fe.mesh``'s module docstring).  These alone are the
FE tooth's mesh (``beveloid.fe.tooth``): its cached data does not depend on anything below.

A **contact strip** (:class:`ContactStrip`) is where a loaded contact lies on one member: its
centre line as points on the flank (member frame, mm), a half-width (the tube about the line
that is refined: the patch's short semi-axis b plus a margin) and a target size (b / 3 by
default, from the caller).  The field is a gmsh ``Distance`` from the line's points and a
``Threshold``: the target size within the half-width, grown linearly (over
``STRIP_GROWTH`` times the size difference) to the far size.  The size is bounded below by
``STRIP_SIZE_MIN_MM`` and above by what keeps the estimated elements of all strips of one sector
under ``ContactStrips.max_elements`` at the mesh's refinement 1, coarsen 1 (fe-check's refinement 3;
every strip's size is scaled up by the same factor until the estimate fits); a sector refined or coarsened by a factor divides or
multiplies those sizes by it, as every other size (:func:`strip_sizes`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["FAR_GROWTH", "FILLET_GROWTH", "ContactStrip", "ContactStrips", "STRIP_SIZE_MIN_MM", "STRIP_GROWTH", "MAX_STRIP_ELEMENTS",
           "TETS_PER_H3", "SAMPLES_PER_ELEMENT", "DISTANCE_SAMPLING_MIN", "distance_sampling", "estimated_elements", "strip_sizes", "size_field"]

#: distance (in multiples of the size difference) over which the size grows from a fine face's size
#: to the far size: from the flanks, and (steeper, so the fine fillet band adds little volume) from
#: the fillets
FAR_GROWTH = 1.5
FILLET_GROWTH = 0.5
#: samples of a fine face's ``Distance`` field per element size along the face (:func:`distance_sampling`):
#: with two, every point of the face lies within about a third of an element of a sample, inside the
#: ``Threshold``'s ``DistMin`` (half an element), and is given the face's size
SAMPLES_PER_ELEMENT = 2.0
#: the fewest samples per bounding-box diagonal (gmsh's default order; a short face)
DISTANCE_SAMPLING_MIN = 60
#: the smallest strip element (mm): below it a 2-core machine cannot solve the model
STRIP_SIZE_MIN_MM = 0.01
#: distance over which the strip's size grows to the far size, in multiples of the size difference
STRIP_GROWTH = FAR_GROWTH
#: the default cap on the estimated elements in (and graded about) the strips of one sector at the FE
#: tooth's sizes (fe-check's refinement 3; refinement 1 triples every size); measured on the earlier
#: three-tooth sectors at those sizes: case 1's main pair at 1.3 b, its peak pressure within 8 % of the
#: 60 000 cap's (docs/validation.md 11.2)
MAX_STRIP_ELEMENTS = 20_000
#: tetrahedra per unit volume at size h: 1 / (h^3 / (6 sqrt 2)), the regular tetrahedron's volume
TETS_PER_H3 = 6.0 * math.sqrt(2.0)


@dataclass(frozen=True)
class ContactStrip:
    """One loaded contact on one member: ``points_mm`` (k, 3) its centre line on the flank (member
    frame), ``half_width_mm`` the refined tube's radius about it, ``size_mm`` the target element size
    there (before the sector's refinement / coarsen divide it)."""

    points_mm: np.ndarray
    half_width_mm: float
    size_mm: float

    def __post_init__(self):
        p = np.asarray(self.points_mm, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 1 or not np.isfinite(p).all():
            raise ValueError(f"points_mm of shape {p.shape}: must be (k >= 1, 3) finite")
        for key in ("half_width_mm", "size_mm"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{key} = {v!r}: must be a positive number (mm)")

    def length_mm(self) -> float:
        p = np.asarray(self.points_mm, dtype=float)
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


@dataclass(frozen=True)
class ContactStrips:
    """The strips of one sector and the cap on their estimated elements (:data:`MAX_STRIP_ELEMENTS`)."""

    strips: tuple
    max_elements: int = MAX_STRIP_ELEMENTS

    def __post_init__(self):
        if not (isinstance(self.max_elements, int) and self.max_elements >= 1000):
            raise ValueError(f"max_elements = {self.max_elements!r}: must be an integer >= 1000")


def _strip_elements(strip: ContactStrip, size: float, far: float) -> float:
    """Elements estimated in and about one strip: the half tube inside the solid (radius w, the
    line's length + 2 w) at the target size, and the graded shell about it, h = size + (d - w) /
    STRIP_GROWTH, integrated over d (a half cylinder, the line's length), as element counts."""
    w, L = strip.half_width_mm, strip.length_mm()
    tube = 0.5 * math.pi * w * w * (L + 2 * w) * TETS_PER_H3 / size ** 3
    d_max = w + STRIP_GROWTH * max(far - size, 0.0)
    d = np.linspace(w, d_max, 400)
    h = size + (d - w) / STRIP_GROWTH
    g = math.pi * d * (L + 2 * d) / h ** 3
    shell = float(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(d))) * TETS_PER_H3
    return tube + shell


def estimated_elements(strips: ContactStrips, scale: float, far_mm: float) -> float:
    """Elements estimated for every strip at its size x ``scale`` (bounded below)."""
    return sum(_strip_elements(s, max(s.size_mm * scale, STRIP_SIZE_MIN_MM), far_mm) for s in strips.strips)


def strip_sizes(strips: ContactStrips, divide: float, far_mm: float) -> tuple:
    """The size of each strip (mm): sized at ``divide`` = 1 (the mesh's refinement 1, coarsen 1;
    fe-check's refinement 3), its target bounded below by :data:`STRIP_SIZE_MIN_MM`, all scaled up
    together until the estimate is within the cap; then divided by ``divide`` (the sector's
    refinement / coarsen) like every other size of the sector, so that a sector refined or
    coarsened by a factor has every size, the strips' included, divided or multiplied by it (the
    cap holds at ``divide`` = 1 only).  ``far_mm``: the sector's far size (at ``divide``)."""
    far_at_one = far_mm * divide
    scale = 1.0
    for _ in range(100):
        if estimated_elements(strips, scale, far_at_one) <= strips.max_elements:
            break
        scale *= 1.05
    return tuple(max(s.size_mm * scale / divide, STRIP_SIZE_MIN_MM) for s in strips.strips)


def _threshold(f, distance, size_min, size_max, dist_min, growth):
    t = f.add("Threshold")
    f.setNumber(t, "InField", distance)
    f.setNumber(t, "SizeMin", size_min)
    f.setNumber(t, "SizeMax", size_max)
    f.setNumber(t, "DistMin", dist_min)
    f.setNumber(t, "DistMax", dist_min + growth * (size_max - size_min))
    return t


def distance_sampling(surfaces, size_mm: float) -> int:
    """gmsh's ``Sampling`` of a ``Distance`` field from ``surfaces`` that puts its samples at most
    ``size_mm`` / :data:`SAMPLES_PER_ELEMENT` apart on them.

    gmsh replaces a surface (not yet meshed) by a cloud of points about (its bounding box's diagonal /
    Sampling) apart, spread over the surface's triangulation, so the spacing is set by the diagonal,
    not by the surface's own extents.  Between two samples a point of the surface reads a distance of
    up to half their spacing, and the ``Threshold`` grows the size from there (by 1 / growth per mm
    beyond ``DistMin``); with a fixed Sampling (60 before) a 50 mm fillet's samples were 0.85 mm apart
    against its 0.24 mm elements, and its facets were meshed up to 3-4.5 times its size
    (``benchmarks/fe_fillet_sizes.py``, docs/validation.md 10.2)."""
    import gmsh

    diagonal = 0.0
    for tag in surfaces:
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(2, tag)
        diagonal = max(diagonal, math.dist((x0, y0, z0), (x1, y1, z1)))
    return max(DISTANCE_SAMPLING_MIN, math.ceil(SAMPLES_PER_ELEMENT * diagonal / size_mm) + 1)


def size_field(face_of, sizes, strips: ContactStrips | None = None, divide: float = 1.0) -> tuple:
    """Set gmsh's background field of the current model; returns the strips' sizes (mm, () without).

    ``face_of`` {face name: gmsh tag}; ``sizes`` the sector's :class:`beveloid.fe.mesh.MeshSizes`;
    ``strips`` refine the contact strips, their target sizes divided by ``divide``."""
    import gmsh

    f = gmsh.model.mesh.field
    fields = []
    for kind, h, growth in (("flank", sizes.flank_mm, FAR_GROWTH), ("fillet", sizes.fillet_mm, FILLET_GROWTH)):
        surfaces = [face_of[f"{kind}_{side}_0"] for side in ("left", "right")]
        d = f.add("Distance")
        f.setNumbers(d, "SurfacesList", surfaces)
        f.setNumber(d, "Sampling", distance_sampling(surfaces, h))
        fields.append(_threshold(f, d, h, sizes.far_mm, 0.5 * h, growth))
    out = ()
    if strips is not None and strips.strips:
        out = strip_sizes(strips, divide, sizes.far_mm)
        for strip, h in zip(strips.strips, out):
            tags = [gmsh.model.occ.addPoint(*p) for p in _dense(strip, 0.5 * strip.half_width_mm)]
            gmsh.model.occ.synchronize()
            d = f.add("Distance")
            f.setNumbers(d, "PointsList", tags)
            fields.append(_threshold(f, d, min(h, sizes.far_mm), sizes.far_mm, strip.half_width_mm, STRIP_GROWTH))
    m = f.add("Min")
    f.setNumbers(m, "FieldsList", fields)
    f.setAsBackgroundMesh(m)
    return out


def _dense(strip: ContactStrip, spacing: float) -> np.ndarray:
    """The centre line's points with at most ``spacing`` between neighbours (linear in between)."""
    p = np.asarray(strip.points_mm, dtype=float)
    out = [p[:1]]
    for a, b in zip(p[:-1], p[1:]):
        n = max(1, int(math.ceil(np.linalg.norm(b - a) / spacing)))
        out.append(a + (b - a) * (np.arange(1, n + 1) / n)[:, None])
    return np.concatenate(out)
