"""Which sector fe-check should model: the compliance of the loaded teeth against the sector's
teeth and the boundary conditions of its radial cuts (docs/validation.md 11.0, "The sectors").

Per member of a design, the sector meshed by ``beveloid.fe.mesh.sector_mesh`` (the FE tooth's sizes
x COARSEN, every loaded tooth -1, 0, 1 at the loaded tooth's sizes) and solved by
``beveloid.fe.solve`` (P2 tets, one factorisation): a unit normal force at each point of a 3 x 3
grid on the right flank (profile 0.2 / 0.5 / 0.85 of form limit to tip, face 0.1 / 0.5 / 0.9) of
teeth -1, 0 and 1, all nine at once (a load spread over the flank: a point force's own field is
not resolved at these sizes), the displacement along the normal read at the FE tooth's depth at
each of the nine points (``beveloid.fe.tooth.flank_compliance``, the raw reading: bending, shear,
rim and the local flattening at that depth).  Sectors:

* ``3 free``: 3 teeth, rim clamped, radial cuts free (fe-check's gear rim fixed / pinion rim rigid);
* ``3 clamped``: 3 teeth, rim and radial cuts clamped (the FE tooth's boundary conditions);
* ``5 free``, ``7 free``: 5 or 7 teeth, rim clamped, cuts free;
* ``9 free``: the reference (a tooth four pitches from a free cut: the whole gear to < 1 %, below).

Printed: per tooth the mean and range over the nine points of the reading / the reference's.

    python benchmarks/fe_check_sector_bcs.py [--design case1] [--coarsen 2.0] [--members pinion,gear]
"""
import argparse
import time

import numpy as np

from beveloid.fe import solve
from beveloid.fe.mesh import sector_mesh
from beveloid.fe.tooth import DEPTH_PER_MODULE, flank_compliance
from beveloid.ltca import Material
from beveloid.pair import Pair
from beveloid.tooth.sampling import ToothSampler

SECTORS = (("3 free", 3, ("rim",)), ("3 clamped", 3, solve.CLAMPED), ("5 free", 5, ("rim",)),
           ("7 free", 7, ("rim",)), ("9 free", 9, ("rim",)))
TEETH = (-1, 0, 1)


def grid_points(pair, member):
    """(points (9, 3), outward normals (9, 3)) on tooth 0's right flank."""
    sampler = ToothSampler(pair.geometry, member)
    toe, heel = sampler.z_range_mm
    z = np.array([toe + f * (heel - toe) for f in (0.1, 0.5, 0.9)])
    l_tip, u_tip = sampler.flank_tip("right", z)
    l0 = sampler.form_limits("right", z)[0]
    s = np.array([0.2, 0.5, 0.85])[:, None]
    l = l0[None, :] + s * (l_tip - l0)[None, :]
    u = sampler.flank_u("right", l, z[None, :], u0=u_tip[None, :])
    surf = pair.geometry.surface(member, "right", l, u)
    return np.asarray(surf.point).reshape(-1, 3), np.asarray(surf.normal).reshape(-1, 3)


def turned(p, angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2]], axis=1)


def compliances(pair, member, coarsen):
    """{sector name: (3 teeth, 9 points) compliance (mm/N)}, and the meshes' sizes."""
    mat = Material.from_spec(pair.spec)
    e, nu = (mat.pinion_e_mpa, mat.pinion_nu) if member == "pinion" else (mat.gear_e_mpa, mat.gear_nu)
    p0, n0 = grid_points(pair, member)
    depth = np.full(len(p0), DEPTH_PER_MODULE * pair.geometry.normal_module_mm)
    out, about = {}, {}
    meshes = {}
    for name, teeth, clamped in SECTORS:
        t0 = time.perf_counter()
        if teeth not in meshes:
            meshes[teeth] = sector_mesh(pair, member, coarsen=coarsen, teeth=teeth, fine_teeth=TEETH)
        mesh = meshes[teeth]
        el = solve.factorise(mesh, e, nu, clamped=clamped)
        rows = []
        for k in TEETH:
            a = k * mesh.pitch_angle_rad
            raw, _, _ = flank_compliance(el, turned(p0, a), turned(n0, a), depth)
            rows.append(raw.sum(axis=1))
        out[name] = np.array(rows)
        about[name] = (len(mesh.tets), time.perf_counter() - t0)
    return out, about


def measure(design="case1", coarsen=2.0, members=("pinion", "gear")) -> dict:
    """{"design", "coarsen", member: {sector: {"elements", "ratio": (3 teeth, 9 points) / the reference's}}}."""
    pair = Pair.example(design)
    out = {"design": design, "coarsen": coarsen}
    for member in members:
        c, about = compliances(pair, member, coarsen)
        ref = c[SECTORS[-1][0]]
        out[member] = {name: {"elements": about[name][0], "ratio": (c[name] / ref).tolist()} for name, _, _ in SECTORS}
    return out


def table(data) -> list:
    """The table's lines (header, rule, rows) of :func:`measure`'s data."""
    lines = ["| member | sector | elements | tooth -1 | tooth 0 | tooth 1 |", "|---|---|---|---|---|---|"]
    for member in ("pinion", "gear"):
        for name, _, _ in SECTORS:
            if member not in data:
                continue
            e = data[member][name]
            r = np.asarray(e["ratio"])
            cells = " | ".join(f"{r[i].mean():.3f} ({r[i].min():.3f}-{r[i].max():.3f})" for i in range(len(TEETH)))
            lines.append(f"| {member} | {name} | {e['elements']} | {cells} |")
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--design", default="case1")
    ap.add_argument("--coarsen", type=float, default=2.0, help="x the FE tooth's sizes (2: fe-check's refinement 1)")
    ap.add_argument("--members", default="pinion,gear")
    a = ap.parse_args()
    data = measure(a.design, a.coarsen, tuple(a.members.split(",")))
    print(f"{a.design}, FE tooth sizes x {a.coarsen:g}; reading / the 9-tooth free sector's, mean (min-max) over "
          "the 3 x 3 flank grid")
    print("\n".join(table(data)))


if __name__ == "__main__":
    main()
