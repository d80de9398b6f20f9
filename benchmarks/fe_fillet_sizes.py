"""Does the FE tooth's mesh have, on its fillets, the element size its rule asks for?  (issue 57.5)

The fillet band's size field (``beveloid.fe.sizes.size_field``) is a gmsh ``Threshold`` on a ``Distance``
from the loaded tooth's fillet surfaces, and gmsh's ``Distance`` replaces a surface by Sampling x Sampling
points of its parameter square (today's Sampling: 60).  Along the face the samples are then the fillet's
length / 59 apart: 0.85 mm on case 1's pinion (face 50 mm) against its fillet elements of 0.24 mm, so a
point of the fillet between two sample lines reads a distance up to half that spacing, and the size there
grows by 1 / FILLET_GROWTH per mm of it.  This script meshes each member's sector as the FE tooth does
(``fe.mesh.sector_mesh`` of its body) at each ``--refinements`` level, once with each ``--sampling`` (gmsh's
option set for the fillet's and flank's distance fields while the mesh is made: ``auto`` is the Sampling
that puts the samples at most half the level's fillet element apart along the face), and prints the
corner edges of the loaded tooth's fillet facets against the rule's size: median, 90th percentile and
largest, each over the rule's ``fillet_mm``, with the sector's tets and the meshing time.  No FE solve:
seconds a member.

    python benchmarks/fe_fillet_sizes.py [--designs case1,R1] [--members pinion,gear] [--refinements 1,2]
        [--sampling 60,auto]

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

#: the Sampling that fe.sizes.size_field sets today
TODAY = 60


def fillet_edges(pair, member: str, refinement: int, sampling) -> dict:
    """Mesh ``member``'s FE-tooth sector at ``refinement`` with the distance fields sampled ``sampling`` times
    per parameter direction (an int, or "auto"); its fillet facets' corner edge lengths (mm) and the rule's size."""
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
        sampling = max(TODAY, math.ceil(2.0 * face_mm / rule.fillet_mm) + 1)
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
    a.add_argument("--sampling", default=f"{TODAY},rule",
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
