"""The pair model's numbers from CalculiX's .frd / .dat (per tooth pair, the rotation, root stress)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .deck import ccx_name
from .results import contact_pressure, max_principal, read_dat, read_frd, write_vtu

__all__ = ["PairResults", "read_pair_results"]


@dataclass(frozen=True)
class PairResults:
    """Per LTCA tooth pair (nan where the pair is not modelled or carries nothing): normal load (N),
    peak contact pressure (MPa), contact area (mm^2); the pinion's rotation about +z including the
    preload (rad); the largest principal fillet stress per member (MPa); the moment of the contact
    forces on the pinion about its axis, positive against the applied moment (N mm)."""

    pair_load_n: np.ndarray
    pair_max_pressure_mpa: np.ndarray
    pair_area_mm2: np.ndarray
    rotation_rad: float
    root_stress_mpa: dict
    moment_nmm: float


def read_pair_results(run, model, info, vtu_path=None) -> PairResults:
    frd = read_frd(run.file("frd"))
    dat = read_dat(run.file("dat"))
    deck = model.deck
    bodies = {b.name: b for b in deck.bodies}
    offset = info["node_offset"]
    n = info["nodes"]
    pressure = contact_pressure(frd)
    p_all = pressure.on(n)[:, 0] if pressure is not None else np.zeros(n)
    forces = {cf.slave.upper(): cf for cf in dat.contact}
    P = len(model.pairs)
    load, peak, area = np.full(P, np.nan), np.full(P, np.nan), np.full(P, np.nan)
    moment = 0.0
    for k, names in enumerate(model.pairs):
        if names is None:
            continue
        cf = forces.get("S" + ccx_name(names[0]))
        body, fset = names[0].split(".", 1)
        b = bodies[body]
        nodes = np.unique(b.facet_sets[fset]) + offset[body]
        peak[k] = float(p_all[nodes].max())
        if cf is not None:
            load[k] = float(np.linalg.norm(cf.force_n))
            area[k] = cf.area_mm2 if cf.area_mm2 is not None else np.nan
            moment += float(cf.moment_nmm[2])
    rot_node = info["rot_node"]
    rotation = model.preload_rad + float(dat.displacements.get(rot_node, np.full(3, np.nan))[2])
    stress = frd["STRESS"].on(n)[:, :6] if "STRESS" in frd else None
    root = {}
    for member in ("pinion", "gear"):
        body = member.upper()
        b = bodies[body]
        sets = [b.node_sets[s] for s in model.fillet_sets[member]]
        nodes = np.unique(np.concatenate(sets)) + offset[body] if sets else np.array([], dtype=int)
        root[member] = float(max_principal(stress[nodes]).max()) if stress is not None and nodes.size else np.nan
    if vtu_path is not None:
        nodes_all = np.concatenate([b.nodes_mm for b in deck.bodies])
        tets = np.concatenate([np.asarray(b.tets) + offset[b.name] for b in deck.bodies])
        write_vtu(vtu_path, nodes_all, tets, frd)
    # the contact forces act on the gear's (slave) flanks; on the pinion they are opposite
    return PairResults(load, peak, area, rotation, root, model.moment_sign * moment)
