"""Does the FE tooth's mesh have, on its fillets, the element size its rule asks for?  (issue 57.5)

The fillet band's size field (``beveloid.fe.sizes.size_field``) is a gmsh ``Threshold`` on a ``Distance``
from the loaded tooth's fillet surfaces, and gmsh's ``Distance`` reads the distance from samples of the
surfaces about (their bounding box's diagonal / Sampling) apart.  With a fixed Sampling of 60 (before
``fe.mesh.MESH_RULES_VERSION`` 6) the samples of a 50 mm fillet were 0.85 mm apart against its 0.24 mm
elements, so a point of the fillet between two samples read a distance up to half that spacing, and the
size there grew by 1 / FILLET_GROWTH per mm of it.  Today ``fe.sizes.distance_sampling`` sets the Sampling
so that the samples are at most half the face's element apart.  This script meshes each member's sector as
the FE tooth does (``fe.mesh.sector_mesh`` of its body) at each ``--refinements`` level, once with each
``--sampling``: ``rule`` (the FE tooth's own: the flank's / the fillet's Sampling), an integer (gmsh's
option for both fields, 60 the old one), or ``auto`` (the fillet's size along the face's length), and
prints the corner edges of the loaded tooth's fillet facets against the rule's size: median, 90th
percentile and largest, each over the rule's ``fillet_mm``, with the sector's tets and the meshing time.
No FE solve: seconds a member.

    python benchmarks/fe_fillet_sizes.py [--designs case1,R1] [--members pinion,gear] [--refinements 1,2]
        [--sampling 60,rule]

Designs are named as in benchmarks/rating_root_convergence.py (case1, case2, R1-R3, R{seed}-{k}, a TOML path).
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from rating_root_convergence import _pair  # noqa: E402

#: the Sampling that fe.sizes.size_field set before MESH_RULES_VERSION 6 (the least it sets today)
OLD_SAMPLING = 60


def fillet_edges(pair, member: str, refinement: int, sampling) -> dict:
    """Mesh ``member``'s FE-tooth sector at ``refinement`` with the distance fields' Sampling ``sampling`` (an
    int, "auto" or "rule"); its fillet facets' corner edge lengths (mm) and the rule's size."""
    import gmsh
    import numpy as np

    from beveloid.fe.mesh import mesh_sizes, sector_mesh
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    body = body_pair(pair, member)
    geometry = getattr(body, "geometry", body)
    sampler = ToothSampler(geometry, member)
    rule = mesh_sizes(sampler, geometry.normal_module_mm, refinement)
    if sampling == "auto":
        face_mm = abs(sampler.z_range_mm[1] - sampler.z_range_mm[0])
        sampling = max(OLD_SAMPLING, math.ceil(2.0 * face_mm / rule.fillet_mm) + 1)
    set_number = gmsh.model.mesh.field.setNumber
    used = []

    def sampled(tag, option, value):
        if option == "Sampling":
            value = value if sampling == "rule" else sampling
            used.append(int(value))
        return set_number(tag, option, value)

    gmsh.model.mesh.field.setNumber = sampled
    try:
        t = time.perf_counter()
        sector = sector_mesh(body, member, refinement=refinement)
        seconds = time.perf_counter() - t
    finally:
        gmsh.model.mesh.field.setNumber = set_number
    edges = []
    for face in ("fillet_left_0", "fillet_right_0"):
        p = sector.nodes[sector.facets[face][:, :3]]
        edges += [np.linalg.norm(p[:, i] - p[:, (i + 1) % 3], axis=1) for i in range(3)]
    edges = np.concatenate(edges)
    return {"sampling": "/".join(map(str, used)), "fillet_mm": sector.sizes.fillet_mm, "rho_mm": sector.sizes.fillet_radius_mm,
            "median": float(np.median(edges)), "p90": float(np.percentile(edges, 90)), "max": float(edges.max()),
            "tets": len(sector.tets), "seconds": seconds}


def main(argv=None) -> int:
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("--designs", default="case1,R1")
    a.add_argument("--members", default="pinion,gear")
    a.add_argument("--refinements", default="1,2")
    a.add_argument("--sampling", default=f"{OLD_SAMPLING},rule",
                   help="gmsh Distance Sampling values (both fields), auto (the fillet's size along the face), "
                        "or rule (the FE tooth's own, fe.sizes.distance_sampling: flank / fillet)")
    args = a.parse_args(argv)
    samplings = [s if s in ("auto", "rule") else int(s) for s in args.sampling.split(",")]
    print("| design | member | refinement | ρ_F / rule's fillet element (mm) | Sampling | fillet edges / rule: "
          "median / p90 / max | tets | meshing (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.designs.split(","):
        pair = _pair(name)
        for member in args.members.split(","):
            for refinement in (int(r) for r in args.refinements.split(",")):
                for sampling in samplings:
                    r = fillet_edges(pair, member, refinement, sampling)
                    h = r["fillet_mm"]
                    print(f"| {Path(name).stem} | {member} | {refinement} | {r['rho_mm']:.3f} / {h:.3f} | "
                          f"{r['sampling']} | {r['median'] / h:.2f} / {r['p90'] / h:.2f} / {r['max'] / h:.2f} | "
                          f"{r['tets']} | {r['seconds']:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
