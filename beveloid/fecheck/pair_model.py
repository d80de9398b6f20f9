"""The pair's contact model at one mesh position, from the FE tooth's sector meshes.

Both sectors (``beveloid.fe.mesh.sector_mesh``: ``SECTOR_TEETH`` teeth, tooth 0 in the middle,
every tooth of a modelled tooth pair meshed at the loaded tooth's sizes) are placed as the TCA places the members (the generated placement, Eqs 30-35, with the assembly
errors): the pinion at the position's pinion angle, the gear at the angle of the rigid envelope
there (the first pair to touch), the same angles the LTCA holds.  The model frame is the
pinion's frame at that angle: the pinion's axis is z through the origin.

Contact pairs: per tooth pair, the gear's flank (slave) against the pinion's flank (master) of
the loaded flank side.  The gear's rim (bore or rim cylinder) is fixed; the pinion's rim is a
rigid body turned by the torque about z.  The pinion starts turned into the gear by
``PRELOAD_FRACTION`` of the LTCA's loaded rotation: it is free about z under the moment, so a
rigid pre-rotation does not change the equilibrium (it is added back to the reported rotation),
and the contact iterations start on patches rather than on single touching nodes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .deck import Body, ContactDeck, RigidLoad

__all__ = ["PRELOAD_FRACTION", "SECTOR_TEETH", "ModelRequest", "PairModel", "TCA_TO_CCX_TET10", "ccx_order", "jacobian_dets", "pair_model",
           "sector_teeth", "straighten_inverted"]

PRELOAD_FRACTION = 0.5
#: the sectors' teeth, the radial cuts free: the LTCA's pairs -1, 0, 1 on teeth -1, 0, 1, two more teeth
#: beside each outer one (docs/validation.md 11.0, ``benchmarks/fe_check_sector_bcs.py``: against a
#: 9-tooth sector an outer loaded tooth is 41-47 % too compliant in a free 3-tooth sector, 17-20 % too
#: stiff with the cuts clamped, 3-4 % too compliant in a free 5-tooth sector, within 0.1 % in a 7-tooth
#: one, for 2 % more elements than 5 teeth: the added teeth are meshed at the far size)
SECTOR_TEETH = 7
SECTOR_INDICES = tuple(range(-(SECTOR_TEETH // 2), SECTOR_TEETH // 2 + 1))
#: a tet10 in gmsh's order (mid-edge nodes 01, 12, 20, 03, 23, 13) to CalculiX's (.., 03, 13, 23)
TCA_TO_CCX_TET10 = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])


def ccx_order(nodes, tets):
    """The tets in CalculiX's C3D10 order: gmsh's order is recognised by its mid-edge node 8 lying
    nearer the middle of corners 2-3 than of 1-3 (over all elements), and permuted."""
    tets = np.asarray(tets)
    p = np.asarray(nodes)
    d23 = np.linalg.norm(p[tets[:, 8]] - 0.5 * (p[tets[:, 2]] + p[tets[:, 3]]), axis=1).sum()
    d13 = np.linalg.norm(p[tets[:, 8]] - 0.5 * (p[tets[:, 1]] + p[tets[:, 3]]), axis=1).sum()
    return tets[:, TCA_TO_CCX_TET10] if d23 < d13 else tets


_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # CalculiX's mid-edge nodes 5-10
_DL = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
#: where the Jacobian is checked: the corners and the 4 integration points (barycentric)
_G = (0.5854101966249685, 0.1381966011250105)
_SAMPLES = np.vstack([np.eye(4), np.full((4, 4), _G[1]) + np.eye(4) * (_G[0] - _G[1])])


def jacobian_dets(nodes, tets) -> np.ndarray:
    """(m, 8) the Jacobian determinant of each C3D10 (CalculiX order) at its corners and its four
    integration points (the quadratic tet's isoparametric map)."""
    x = np.asarray(nodes)[np.asarray(tets)]  # (m, 10, 3)
    out = []
    for lam in _SAMPLES:
        g = np.zeros((10, 4))
        for i in range(4):
            g[i, i] = 4.0 * lam[i] - 1.0
        for e, (i, j) in enumerate(_EDGES):
            g[4 + e, i], g[4 + e, j] = 4.0 * lam[j], 4.0 * lam[i]
        jac = np.einsum("mai,ak->mik", x, g @ _DL)
        out.append(np.linalg.det(jac))
    return np.stack(out, axis=1)


def straighten_inverted(nodes, tets, passes: int = 3):
    """Nodes with the mid-edge nodes of every element whose curved map folds (a Jacobian <= 0 at a
    corner or integration point) put back at the middle of their edge; returns (nodes, count)."""
    nodes = np.array(nodes, dtype=float)
    tets = np.asarray(tets)
    count = 0
    for _ in range(passes):
        bad = np.flatnonzero((jacobian_dets(nodes, tets) <= 0.0).any(axis=1))
        if bad.size == 0:
            break
        count += bad.size
        for e, (i, j) in enumerate(_EDGES):
            t = tets[bad]
            nodes[t[:, 4 + e]] = 0.5 * (nodes[t[:, i]] + nodes[t[:, j]])
    return nodes, count


@dataclass(frozen=True)
class PairModel:
    """The deck's data and what is needed to read its results.

    ``pairs``: per LTCA tooth pair k (in the LTCA's order) the contact pair's (slave, master) names
    or None when that pair is outside the sectors; ``moment_sign`` the sign of the moment about +z
    that loads the flank; ``phi_sign`` +1 when the pinion angle turns the pinion about +z;
    ``preload_rad`` the pre-rotation about +z; ``fillet_sets`` {member: [node set names]}."""

    deck: ContactDeck
    pairs: tuple
    tooth_pairs: tuple
    moment_sign: float
    phi_sign: float
    preload_rad: float
    pinion_angle_rad: float
    gear_angle_rad: float
    fillet_sets: dict
    elements: int
    dof: int


def _rotation_sign(placement_fn, angle, *extra):
    d = 1e-6
    r0 = placement_fn(angle, *extra).rotation
    r1 = placement_fn(angle + d, *extra).rotation
    return 1.0 if (r0.T @ r1)[1, 0] > 0 else -1.0


def _rz(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _facet_normals(nodes, tri):
    a = nodes[tri[:, 0]]
    n = np.cross(nodes[tri[:, 1]] - a, nodes[tri[:, 2]] - a)
    return n / np.linalg.norm(n, axis=1)[:, None], (a + nodes[tri[:, 1]] + nodes[tri[:, 2]]) / 3.0


@dataclass(frozen=True)
class ModelRequest:
    """What :func:`pair_model` builds: the pair, the flank, the position's angles and its LTCA
    numbers (the expected peak pressure and pinion rotation, for the penalty and the preload)."""

    pair: object
    flank: str
    torque_nm: float
    pinion_angle_rad: float
    gear_angle_rad: float
    expected_pressure_mpa: float
    expected_rotation_rad: float
    tooth_pairs: tuple


#: fe-check's ``--refinement N`` meshes each sector at the FE tooth's sizes (``beveloid.fe.mesh``)
#: x LEVEL_1_COARSEN / N: refinement 1 is the coarse check (the loads, the TE: case 1's seven-tooth
#: sectors at 181 000 DOF, the size of the three-tooth sectors' at x 2; docs/fe_check.md, Limits),
#: refinement 3 the FE tooth's own sizes.  With ``fine_fillets`` (fe-check's ``--fine-fillets``) the
#: fillets of the teeth in tooth pairs are not coarsened: at refinement N they are the FE tooth's at its
#: refinement N (``sector_mesh``'s ``fillet_coarsen``), so both models read the root on the same fillet
#: elements (case 1 at 1500 N m: 212 047 elements against 42 404, docs/fe_check.md, Limits).
LEVEL_1_COARSEN = 3.0


def sector_meshes(pair, refinement: int, coarsen: float = 1.0, strips=None, teeth=None,
                  fine_fillets: bool = False) -> dict:
    """{member: SectorMesh} of fe-check's ``refinement`` (see :data:`LEVEL_1_COARSEN`), every size
    also x ``coarsen``, :data:`SECTOR_TEETH` teeth; ``strips``: {member: ContactStrips or None} (the
    local refinement); ``teeth``: per tooth pair (pinion tooth, gear tooth) or None
    (:func:`sector_teeth`): those teeth are meshed at the loaded tooth's sizes (None: tooth 0 only), with
    ``fine_fillets`` their fillets at the FE tooth's (x ``coarsen`` / ``refinement``, without
    :data:`LEVEL_1_COARSEN`)."""
    from ..fe.mesh import sector_mesh

    strips = strips or {}
    fine = {m: tuple(sorted({0} | {t[i] for t in (teeth or ()) if t is not None}))
            for i, m in enumerate(("pinion", "gear"))}
    return {m: sector_mesh(pair, m, refinement, teeth=SECTOR_TEETH, coarsen=LEVEL_1_COARSEN * coarsen,
                           strips=strips.get(m), fine_teeth=fine[m],
                           fillet_coarsen=coarsen if fine_fillets else None)
            for m in ("pinion", "gear")}


def sector_teeth(pair, pinion_angle_rad, gear_angle_rad, tooth_pairs, indices=SECTOR_INDICES):
    """(s1, [per LTCA pair k: (pinion tooth, gear tooth) of the sectors, or None outside ``indices``]).

    LTCA pair k: pinion tooth 0 at phi1 - k p1, i.e. the sector's pinion tooth -s1 k, with the gear's
    tooth s2 k (gear tooth 0 at phi2 + k p2); s1, s2 the signs of the placements' turns about +z."""
    from ..generated import placement

    errors = np.asarray(pair.errors, dtype=float)
    layout = pair.geometry.placement()
    s1 = _rotation_sign(placement.pinion_placement, pinion_angle_rad, layout)
    s2 = _rotation_sign(placement.gear_placement, gear_angle_rad, errors, layout)
    out = []
    for k in tooth_pairs:
        mp, mg = int(round(-s1 * k)), int(round(s2 * k))
        out.append((mp, mg) if mp in indices and mg in indices else None)
    return s1, out


def pair_model(req: ModelRequest, meshes: dict) -> PairModel:
    """The contact model of ``req`` on ``meshes`` ({member: SectorMesh}, :func:`sector_meshes`)."""
    from ..generated import placement

    pair = req.pair
    geom = pair.geometry
    errors = np.asarray(pair.errors, dtype=float)
    layout = geom.placement()
    pp = placement.pinion_placement(req.pinion_angle_rad, layout)
    gp = placement.gear_placement(req.gear_angle_rad, errors, layout)
    pin, gear = meshes["pinion"], meshes["gear"]
    # the model frame: the pinion's frame at the position (pinion nodes as meshed)
    rg = pp.rotation.T @ gp.rotation
    tg = pp.rotation.T @ (np.asarray(gp.translation) - np.asarray(pp.translation))
    gear_nodes = gear.nodes @ rg.T + tg
    side = f"flank_{req.flank}"
    # the moment's sign: the pinion turned about +z pushes its loaded flank outwards, into the gear
    tri = pin.facets[f"{side}_0"]
    n, c = _facet_normals(pin.nodes, tri)
    push = np.einsum("ij,ij->i", np.cross([0.0, 0.0, 1.0], c), n)
    moment_sign = 1.0 if push.mean() > 0 else -1.0
    preload = moment_sign * PRELOAD_FRACTION * abs(req.expected_rotation_rad)
    pin_nodes = pin.nodes @ _rz(preload).T
    if set(pin.tooth_indices) != set(gear.tooth_indices):
        raise ValueError("the two sectors must have the same teeth")
    s1, teeth = sector_teeth(pair, req.pinion_angle_rad, req.gear_angle_rad, req.tooth_pairs, pin.tooth_indices)
    pairs = [None if t is None else (f"GEAR.{side}_{t[1]}", f"PINION.{side}_{t[0]}") for t in teeth]
    mat = _material(pair)
    bodies = (_body("PINION", pin_nodes, pin, (mat.pinion_e_mpa, mat.pinion_nu)),
              _body("GEAR", gear_nodes, gear, (mat.gear_e_mpa, mat.gear_nu)))
    deck = ContactDeck(bodies=bodies, young_mpa=mat.gear_e_mpa, poisson=mat.gear_nu,
                       contact_pairs=tuple(p for p in pairs if p is not None), fixed=("GEAR.rim",),
                       rigid=RigidLoad("PINION", "rim", moment_nmm=moment_sign * req.torque_nm * 1e3),
                       expected_pressure_mpa=req.expected_pressure_mpa)
    # the root stress is read on the fillets of the teeth in contact pairs (meshed at the loaded tooth's sizes)
    fillets = {m: [f"fillet_{side}_{t[i]}" for t in sorted({t for t in teeth if t is not None})
                   for side in ("left", "right")] for i, m in enumerate(("pinion", "gear"))}
    n_nodes = len(pin.nodes) + len(gear.nodes)
    return PairModel(deck, tuple(pairs), tuple(int(k) for k in req.tooth_pairs), moment_sign, s1, preload,
                     req.pinion_angle_rad, req.gear_angle_rad, fillets, len(pin.tets) + len(gear.tets),
                     3 * n_nodes + 6)


def _material(pair):
    from ..ltca import Material

    spec = getattr(pair, "spec", None)
    return Material.from_spec(spec) if spec is not None else Material()


def _body(name, nodes, mesh, elastic) -> Body:
    facets = {k: v[:, :3] for k, v in mesh.facets.items()}
    tets = ccx_order(nodes, mesh.tets)
    nodes, _ = straighten_inverted(nodes, tets)
    return Body(name, nodes, tets, facets, dict(mesh.node_sets), *elastic)
