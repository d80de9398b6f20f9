"""A box of 10-node tets: the closed-form checks of the FE solver (tests, benchmarks)."""
from __future__ import annotations

import math

from .mesh import MeshSizes, SectorMesh, SectorShape, record_from_gmsh

__all__ = ["box_mesh"]


def box_mesh(size_mm, element_mm: float) -> SectorMesh:
    """A box [0, a] x [0, b] x [0, c] as 10-node tets (the closed-form checks of the FE solver):
    named faces ``x0``, ``x1``, ``y0``, ``y1``, ``z0``, ``z1``."""
    import gmsh

    a, b, c = (float(v) for v in size_mm)
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box")
        vol = gmsh.model.occ.addBox(0, 0, 0, a, b, c)
        gmsh.model.occ.synchronize()
        face_of = {}
        for _, tag in gmsh.model.getBoundary([(3, vol)], oriented=False):
            x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(2, tag)
            for axis, lo, hi, length in (("x", x0, x1, a), ("y", y0, y1, b), ("z", z0, z1, c)):
                if hi - lo < 1e-6:
                    face_of[f"{axis}{0 if lo < 0.5 * length else 1}"] = tag
        gmsh.option.setNumber("Mesh.MeshSizeMax", element_mm)
        gmsh.option.setNumber("Mesh.MeshSizeMin", element_mm)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.model.mesh.generate(3)
        sizes = MeshSizes(element_mm, element_mm, element_mm, math.inf)
        return record_from_gmsh(gmsh, "box", face_of, SectorShape(tooth_indices=(0,), pitch_angle_rad=0.0,
                                                                  rim_radius_mm=0.0, sizes=sizes, refinement=1,
                                                                  z_range_mm=(0.0, c)))
    finally:
        gmsh.finalize()
