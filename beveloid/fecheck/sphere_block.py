"""The closed-form check of the contact pipeline: a spherical cap pressed on a block (Hertz).

A cap of a sphere of radius R (height ``cap_mm``, flat face up) touches a block at the origin; the
block's bottom is fixed, the cap's flat face is a rigid body pushed down by a force P (its other
motions held).  Hertz (Johnson 1985, 4.2; :mod:`beveloid.ltca.mechanics.hertz`): a = (3 P R / (4 E*))^(1/3),
p0 = 3 P / (2 pi a^2).  Meshed by gmsh as second-order tetrahedra, graded towards the contact point.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .deck import Body, ContactDeck, RigidLoad

__all__ = ["SphereBlock", "GMSH_TO_CCX_TET10", "gmsh_body", "sphere_block_deck"]

#: gmsh's tet10 node order (mid-edge 4: 0-1, 5: 1-2, 6: 2-0, 7: 3-0, 8: 3-2, 9: 3-1) to CalculiX's C3D10
GMSH_TO_CCX_TET10 = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])


@dataclass(frozen=True)
class SphereBlock:
    """The case: sphere radius, cap height, block half-width and depth (mm), load (N), contact mesh size
    (mm, at the contact point; the far mesh is ``far_over_fine`` times coarser), material, and the
    cap's initial overlap as a fraction of the Hertz approach: the cap is free along z under the
    force, so a rigid overlap does not change the equilibrium, and it starts the contact iterations
    on a patch rather than on the one touching node."""

    radius_mm: float = 10.0
    cap_mm: float = 2.5
    block_half_mm: float = 5.0
    block_depth_mm: float = 5.0
    load_n: float = 2000.0
    fine_mm: float = 0.1
    far_over_fine: float = 12.0
    young_mpa: float = 210000.0
    poisson: float = 0.3
    preload_fraction: float = 0.5

    def hertz(self):
        """:class:`beveloid.ltca.mechanics.hertz.HertzPointContact` of the case (sphere on a flat, one material)."""
        from ..ltca.mechanics.hertz import hertz_point_contact

        e_star = self.young_mpa / (2.0 * (1.0 - self.poisson ** 2))
        a = 1.0 / (2.0 * self.radius_mm)
        return hertz_point_contact(a, a, self.load_n, e_star)


def gmsh_body(name, volume_tag, surfaces: dict, node_sets: dict):
    """A :class:`Body` of one gmsh volume (second order, already meshed): its tet10s, facet sets of the
    named surface entities {set: [surface tags]} and node sets {set: [surface tags]} (all their nodes)."""
    import gmsh

    etypes, _, enodes = gmsh.model.mesh.getElements(3, volume_tag)
    tets = np.asarray(enodes[list(etypes).index(11)], dtype=np.int64).reshape(-1, 10)
    tags = np.unique(tets)
    index = {int(t): i for i, t in enumerate(tags)}
    all_tags, all_xyz, _ = gmsh.model.mesh.getNodes()
    order = np.argsort(all_tags)
    coords = np.asarray(all_xyz).reshape(-1, 3)[order[np.searchsorted(np.asarray(all_tags)[order], tags)]]
    local = np.vectorize(index.__getitem__)
    facets, nsets = {}, {}
    for key, ents in surfaces.items():
        tri = [np.asarray(gmsh.model.mesh.getElementsByType(9, s)[1]).reshape(-1, 6)[:, :3] for s in ents]
        facets[key] = local(np.concatenate(tri))
    for key, ents in node_sets.items():
        nodes = [np.asarray(gmsh.model.mesh.getNodes(2, s, includeBoundary=True)[0]) for s in ents]
        nsets[key] = local(np.unique(np.concatenate(nodes)))
    return Body(name, coords, local(tets)[:, GMSH_TO_CCX_TET10], facets, nsets)


def _meshed(case: SphereBlock):
    import gmsh

    occ = gmsh.model.occ
    r, h, w, d = case.radius_mm, case.cap_mm, case.block_half_mm, case.block_depth_mm
    z0 = -case.preload_fraction * case.hertz().approach_mm
    sphere = occ.addSphere(0, 0, r + z0, r)
    cut = occ.addBox(0, 0, z0, r, r, h)
    cap = occ.intersect([(3, sphere)], [(3, cut)])[0][0][1]
    block = occ.addBox(0, 0, -d, w, w, d)
    occ.synchronize()
    point = occ.addPoint(0, 0, 0)
    occ.synchronize()
    fld = gmsh.model.mesh.field
    dist = fld.add("Distance")
    fld.setNumbers(dist, "PointsList", [point])
    thr = fld.add("Threshold")
    fld.setNumber(thr, "InField", dist)
    fld.setNumber(thr, "SizeMin", case.fine_mm)
    fld.setNumber(thr, "SizeMax", case.fine_mm * case.far_over_fine)
    fld.setNumber(thr, "DistMin", 0.6 * (3 * case.load_n * r / (4 * case.young_mpa / 1.82)) ** (1 / 3))
    fld.setNumber(thr, "DistMax", 6.0 * h)
    fld.setAsBackgroundMesh(thr)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{opt}", 0)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)

    def faces(vol):
        return [t for _, t in gmsh.model.getBoundary([(3, vol)], oriented=False)]

    def at(vol, axis, value):
        out = []
        for s in faces(vol):
            box = gmsh.model.getBoundingBox(2, s)
            if abs(box[axis] - value) < 1e-6 and abs(box[axis + 3] - value) < 1e-6:
                out.append(s)
        return out

    cap_top = at(cap, 2, h + z0)
    cap_x, cap_y = at(cap, 0, 0.0), at(cap, 1, 0.0)
    cap_sphere = [s for s in faces(cap) if s not in cap_top + cap_x + cap_y]
    block_top, block_bottom = at(block, 2, 0.0), at(block, 2, -d)
    body = gmsh_body("CAP", cap, {"CONTACT": cap_sphere}, {"TOP": cap_top, "XSYM": cap_x, "YSYM": cap_y})
    top = body.node_sets["TOP"]  # held by the rigid body: not also by the symmetry planes
    for key in ("XSYM", "YSYM"):
        body.node_sets[key] = np.setdiff1d(body.node_sets[key], top)
    return (body,
            gmsh_body("BLOCK", block, {"CONTACT": block_top},
                      {"BOTTOM": block_bottom, "XSYM": at(block, 0, 0.0), "YSYM": at(block, 1, 0.0)}))


def sphere_block_deck(case: SphereBlock = SphereBlock()) -> ContactDeck:
    """The deck of a quarter of the case (symmetry planes x = 0 and y = 0): cap (slave) on block
    (master), block bottom fixed, the cap's top pushed by P / 4."""
    import gmsh

    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("sphere_block")
        cap, block = _meshed(case)
    finally:
        gmsh.finalize()
    return ContactDeck(bodies=(cap, block), young_mpa=case.young_mpa, poisson=case.poisson,
                       contact_pairs=(("CAP.CONTACT", "BLOCK.CONTACT"),), fixed=("BLOCK.BOTTOM",),
                       constraints=(("CAP.XSYM", 1, 1), ("CAP.YSYM", 2, 2), ("BLOCK.XSYM", 1, 1),
                                    ("BLOCK.YSYM", 2, 2)),
                       rigid=RigidLoad("CAP", "TOP", centre_mm=(0.0, 0.0, case.cap_mm - case.preload_fraction * case.hertz().approach_mm), rotation_rad=0.0,
                                       axial_force_n=-case.load_n / 4.0),
                       expected_pressure_mpa=case.hertz().max_pressure_mpa)
