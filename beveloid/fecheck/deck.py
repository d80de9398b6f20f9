"""A CalculiX input deck (``.inp``) of elastic solids in frictionless contact.

The model: second-order tetrahedra (C3D10) of one linear-elastic material; surfaces from facet
sets (element faces); one *CONTACT PAIR per (slave, master) surface pair, surface-to-surface,
frictionless, penalty contact with a linear pressure-overclosure law; node sets fixed in the
three translations; one node set tied to a reference node by *RIGID BODY, whose rotation node
carries a *CLOAD moment (or a prescribed rotation) about the global z axis; the reference node's
translations and its rotations about x and y are held.  One *STATIC step, NLGEOM off.

Node numbering: the bodies' nodes in order, 1-based (body b's node i is ``offset[b] + i + 1``),
then the reference node and the rotation node.  Connectivity in CalculiX's C3D10 order (corners
1-4, then the mid-edge nodes of 1-2, 2-3, 3-1, 1-4, 2-4, 3-4).

The penalty choice (CalculiX manual, *SURFACE BEHAVIOR): the slope K is
``PENALTY_OVER_E`` x E per mm (CalculiX advises 5 to 50 x E); the tension at large clearance is
``TENSION_OVER_PRESSURE`` (0.25 %, the manual's advice) of the expected peak pressure: it gives
the first iteration stiffness across the gaps, so a body held only by contact is not singular.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Body", "ContactDeck", "ccx_name", "PENALTY_OVER_E", "RigidLoad", "TENSION_OVER_PRESSURE", "face_elements",
           "write_deck"]

PENALTY_OVER_E = 50.0  #: penalty slope K = 50 E per mm (CalculiX's advice: 5-50 E)
TENSION_OVER_PRESSURE = 0.0025  #: tension at large clearance / expected peak pressure (CalculiX: 0.25 %)

#: C3D10 faces by local corner indices (CalculiX S1..S4)
_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))


@dataclass(frozen=True)
class Body:
    """One solid: nodes (n, 3) mm, C3D10 connectivity (m, 10) 0-based in CalculiX order, facet sets
    {name: (k, 3) corner node indices of boundary triangles}, node sets {name: node indices}."""

    name: str
    nodes_mm: np.ndarray
    tets: np.ndarray
    facet_sets: dict = field(default_factory=dict)
    node_sets: dict = field(default_factory=dict)
    young_mpa: float | None = None  #: the body's own material, else the deck's
    poisson: float | None = None


@dataclass(frozen=True)
class RigidLoad:
    """A node set of one body turned as a rigid body about the z axis through ``centre_mm``: a moment
    ``moment_nmm`` about +z, or (when ``rotation_rad`` is given) a prescribed rotation instead;
    ``axial_force_n`` along +z on the reference node, whose z translation is held when it is None.
    The reference node's x, y translations are held, and with ``hold_rotation`` the rotations about
    x and y."""

    body: str
    node_set: str
    centre_mm: tuple = (0.0, 0.0, 0.0)
    moment_nmm: float = 0.0
    rotation_rad: float | None = None
    hold_rotation: bool = True
    axial_force_n: float | None = None


@dataclass(frozen=True)
class ContactDeck:
    """What :func:`write_deck` writes: bodies, material, contact pairs ((slave, master) facet sets,
    each "BODY.SET"), fixed node sets ("BODY.SET"), the rigid load, the expected peak pressure (MPa,
    for the penalty's tension) and the output node sets to print."""

    bodies: tuple
    young_mpa: float
    poisson: float
    contact_pairs: tuple
    fixed: tuple
    rigid: RigidLoad
    expected_pressure_mpa: float = 1000.0
    penalty_over_e: float = PENALTY_OVER_E
    constraints: tuple = ()  #: ("BODY.SET", first dof, last dof) held at 0 (symmetry planes)


def face_elements(tets: np.ndarray, facets: np.ndarray):
    """(element indices, face numbers 1-4) of the triangles ``facets`` (k, 3) corner nodes among the
    faces of ``tets``; raises ValueError naming how many facets are no element's face."""
    tets = np.asarray(tets)
    keys = {}
    for f, (a, b, c) in enumerate(_FACES):
        tri = np.sort(tets[:, [a, b, c]], axis=1)
        for e, t in enumerate(map(tuple, tri)):
            keys[t] = (e, f + 1)
    found = [keys.get(tuple(t)) for t in np.sort(np.asarray(facets), axis=1)]
    missing = sum(1 for v in found if v is None)
    if missing:
        raise ValueError(f"{missing} of {len(found)} facets are not faces of the body's tetrahedra")
    return np.array([v[0] for v in found], dtype=int), np.array([v[1] for v in found], dtype=int)


def ccx_name(name: str) -> str:
    """A CalculiX name of "BODY.SET" (or "BODY_SET"): the dot an underscore, a minus sign "M", upper case
    (CalculiX folds names to upper case)."""
    return name.replace(".", "_", 1).replace("-", "M").upper()


def _lines(prefix, ids, per_line=8):
    ids = [str(int(i)) for i in ids]
    return [prefix + ", ".join(ids[i:i + per_line]) for i in range(0, len(ids), per_line)]


def write_deck(deck: ContactDeck, path) -> dict:
    """Write the deck to ``path``; returns {"nodes", "elements", "ref_node", "rot_node",
    "node_offset": {body: offset}, "element_offset": {body: offset}}."""
    out = ["*HEADING", "beveloid fe-check: frictionless contact of elastic solids (C3D10)"]
    node_off, elem_off, n_nodes, n_elems = {}, {}, 0, 0
    bodies = {b.name: b for b in deck.bodies}
    for b in deck.bodies:
        node_off[b.name], elem_off[b.name] = n_nodes, n_elems
        out.append(f"*NODE, NSET=N{b.name}")
        ids = np.arange(len(b.nodes_mm)) + n_nodes + 1
        out += [f"{i}, {x:.9g}, {y:.9g}, {z:.9g}" for i, (x, y, z) in zip(ids, b.nodes_mm)]
        out.append(f"*ELEMENT, TYPE=C3D10, ELSET=E{b.name}")
        eids = np.arange(len(b.tets)) + n_elems + 1
        conn = np.asarray(b.tets) + n_nodes + 1
        out += [f"{e}, " + ", ".join(str(int(v)) for v in row) for e, row in zip(eids, conn)]
        for name, nodes in b.node_sets.items():
            out.append(f"*NSET, NSET={ccx_name(b.name + '_' + name)}")
            out += _lines("", np.unique(np.asarray(nodes)) + n_nodes + 1)
        n_nodes += len(b.nodes_mm)
        n_elems += len(b.tets)
    ref, rot = n_nodes + 1, n_nodes + 2
    r = deck.rigid
    out += ["*NODE, NSET=NREF", f"{ref}, {r.centre_mm[0]:.9g}, {r.centre_mm[1]:.9g}, {r.centre_mm[2]:.9g}",
            "*NODE, NSET=NROT", f"{rot}, {r.centre_mm[0]:.9g}, {r.centre_mm[1]:.9g}, {r.centre_mm[2]:.9g}"]
    surfaces = set()
    for slave, master in deck.contact_pairs:
        surfaces.update((slave, master))
    for s in sorted(surfaces):
        bname, fname = s.split(".", 1)
        b = bodies[bname]
        els, faces = face_elements(b.tets, b.facet_sets[fname])
        out.append(f"*SURFACE, NAME=S{ccx_name(s)}, TYPE=ELEMENT")
        out += [f"{e + elem_off[bname] + 1}, S{f}" for e, f in zip(els, faces)]
    for b in deck.bodies:
        e = deck.young_mpa if b.young_mpa is None else b.young_mpa
        nu = deck.poisson if b.poisson is None else b.poisson
        out += [f"*MATERIAL, NAME=M{b.name}", "*ELASTIC", f"{e:.9g}, {nu:.9g}",
                f"*SOLID SECTION, ELSET=E{b.name}, MATERIAL=M{b.name}"]
    k = deck.penalty_over_e * deck.young_mpa
    tension = TENSION_OVER_PRESSURE * deck.expected_pressure_mpa
    out += ["*SURFACE INTERACTION, NAME=FRICTIONLESS", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{k:.9g}, {tension:.9g}"]
    for slave, master in deck.contact_pairs:
        out += ["*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE",
                f"S{ccx_name(slave)}, S{ccx_name(master)}"]
    out += [f"*RIGID BODY, NSET={ccx_name(r.body + '_' + r.node_set)}, REF NODE={ref}, ROT NODE={rot}", "*BOUNDARY"]
    for s in deck.fixed:
        out.append(f"{ccx_name(s)}, 1, 3")
    for s, first, last in deck.constraints:
        out.append(f"{ccx_name(s)}, {first}, {last}")
    out += [f"{ref}, 1, 2", f"{rot}, 1, 2"] if r.hold_rotation else [f"{ref}, 1, 2"]
    if r.axial_force_n is None:
        out.append(f"{ref}, 3, 3")
    out += ["*STEP", "*STATIC", "1.0, 1.0, 1e-4, 1.0"]
    if r.rotation_rad is not None:
        out += ["*BOUNDARY", f"{rot}, 3, 3, {r.rotation_rad:.9g}"]
    loads = ([] if r.rotation_rad is not None else [f"{rot}, 3, {r.moment_nmm:.9g}"]) + \
        ([] if r.axial_force_n is None else [f"{ref}, 3, {r.axial_force_n:.9g}"])
    if loads:
        out += ["*CLOAD"] + loads
    out += ["*NODE FILE", "U", "*EL FILE", "S", "*CONTACT FILE", "CDIS, CSTR",
            "*NODE PRINT, NSET=NROT", "U", "*NODE PRINT, NSET=NREF, TOTALS=ONLY", "RF",
            "*CONTACT PRINT", "CELS"]
    for slave, master in deck.contact_pairs:
        out += [f"*CONTACT PRINT, SLAVE=S{ccx_name(slave)}, MASTER=S{ccx_name(master)}", "CF"]
    out.append("*END STEP")
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")
    return {"nodes": n_nodes + 2, "elements": n_elems, "ref_node": ref, "rot_node": rot,
            "node_offset": node_off, "element_offset": elem_off}
