"""The finite-element tooth (issue 31): a member sector meshed by gmsh (:mod:`.mesh`)."""
from __future__ import annotations

from .mesh import SectorMesh, sector_mesh

__all__ = ["SectorMesh", "sector_mesh"]
