"""Which part of the FE tooth's mesh moves its root stress?  (issue 57.5, docs/validation.md 10.2)

The LTCA runs once with the default FE tooth (the rating's positions, the design's torque); its loads
(every converged, loaded position and pair) are then read again with FE teeth whose mesh differs in
one part only, the load distribution kept: the fillet's elements (``fillet``: their size per fillet
radius, and ``fillet_min``: the floor per module), the flanks' (``flank``, per module), everything else
(``far``, per module: the tooth's interior, the root land, the rim), how fast the fillet's size grows
into it (``growth``), or every size (``coarsen``).  Per variant and member: the largest root stress, where
(height above the root cone), the mesh's nodes and fillet nodes.

    python benchmarks/fe_root_mesh_parts.py --design A [--torque-nm 290] \\
        [--variants "coarsen=2;far=0.5;fillet=0.25,fillet_min=0.02;flank=0.15"] [--cutter-tip-radius 0.38]

``--design``: case1, case2, A, B, C (benchmarks/rating_invariance.py) or a spec file;
``--cutter-tip-radius``: both members' rack tip radius per module (0: the default sharp rack).  Each
variant's FE data is computed in a temporary cache folder (BEVELOID_CACHE_DIR when set).  Memory: the
sector's factorisation grows fast with its nodes (design A with ``far=0.25``, 175 000 nodes, took 18 GB).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: variant key -> the beveloid.fe.mesh constant it sets
KEYS = {"fillet": "FILLET_SIZE_PER_RADIUS", "fillet_min": "FILLET_SIZE_MIN_PER_MODULE", "flank": "FLANK_SIZE_PER_MODULE",
        "far": "FAR_SIZE_PER_MODULE", "growth": "FILLET_GROWTH"}


def _pair(design, tip_radius):
    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes
    from rating_root_convergence import SHORT
    from rating_invariance import DESIGNS

    if design in ("case1", "case2"):
        text = (Path(__file__).resolve().parents[1] / "examples" / f"{design}.toml").read_text()
    elif design in SHORT:
        text = list(DESIGNS.values())[SHORT[design]]
    else:
        text = Path(design).read_text()
    if tip_radius:
        text = text.replace("[gear]", f"cutter_tip_radius_coefficient = {tip_radius:g}\n[gear]", 1)
        text += f"\ncutter_tip_radius_coefficient = {tip_radius:g}\n"
    return Pair.from_spec(spec_from_toml_bytes(text.encode()))


def _variant(text) -> dict:
    out = {}
    for item in filter(None, text.split(",")):
        k, v = item.split("=")
        if k not in KEYS and k != "coarsen":
            raise SystemExit(f"variant key {k!r}: must be one of {', '.join([*KEYS, 'coarsen'])}")
        out[k] = float(v)
    return out


def main(argv=None) -> int:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--design", default="A")
    a.add_argument("--torque-nm", type=float, default=None, help="default: 1500 on case 1 / 2, else 10.1's higher torque")
    a.add_argument("--variants", default="coarsen=2;far=0.5;fillet=0.25,fillet_min=0.02;flank=0.15")
    a.add_argument("--cutter-tip-radius", type=float, default=0.0)
    args = a.parse_args(argv)
    os.environ.setdefault("BEVELOID_CACHE_DIR", tempfile.mkdtemp(prefix="fe_root_mesh_parts_"))

    import numpy as np

    from beveloid import ltca
    from beveloid.fe import contact, mesh, sizes
    from beveloid.fe.cache import cached_tooth_data
    from beveloid.ltca.model import teeth
    from beveloid.rating.analysis import POSITIONS
    from rating_invariance import _torques

    pair = _pair(args.design, args.cutter_tip_radius)
    torque = args.torque_nm or (1500.0 if args.design in ("case1", "case2") else _torques(pair)[1])
    options = ltca.Options(positions=POSITIONS, tooth_model="fe")
    result = ltca.analyze(pair, ltca.LoadCase(torque), options)
    material = ltca.Material.from_spec(pair.spec)
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    saved = {k: getattr(mesh, name) for k, name in KEYS.items()}
    print(f"{args.design} (rack tip radius {args.cutter_tip_radius:g} m_n), {torque:g} N m: largest root stress (MPa) "
          f"of the default LTCA's loads, height above the root (mm), nodes / fillet nodes")
    print("| variant | pinion | gear |\n|---|---|---|")
    for text in ["default", *args.variants.split(";")]:
        v = {} if text == "default" else _variant(text)
        for k, name in KEYS.items():
            setattr(mesh, name, v.get(k, saved[k]))
        sizes.FILLET_GROWTH = mesh.FILLET_GROWTH
        t0 = time.perf_counter()
        cells = []
        try:
            data = {m: cached_tooth_data(pair, m, *moduli[m], 1, coarsen=v.get("coarsen", 1.0))[0]
                    for m in ("pinion", "gear")}
            r = teeth.root_stresses(tuple(contact.FeTooth(data[m], options.flank) for m in ("pinion", "gear")),
                                    result, result.converged)
            for m in ("pinion", "gear"):
                a = r["tension"][m]
                j, k = np.unravel_index(int(np.nanargmax(a)), a.shape)
                cells.append(f"{a[j, k]:.1f} at {r['where'][m][j, k, 1]:.3f} ({int(data[m].stat('nodes'))} / "
                             f"{data[m].fillet_points_mm.shape[1]})")
        finally:
            for k, name in KEYS.items():
                setattr(mesh, name, saved[k])
            sizes.FILLET_GROWTH = mesh.FILLET_GROWTH
        print(f"| {text} | {cells[0]} | {cells[1]} |", flush=True)
        print(f"  {text}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
