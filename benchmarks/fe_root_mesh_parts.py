"""Which part of the FE tooth's mesh moves its root stress?  (issue 57.5, docs/validation.md 10.2)

The LTCA runs once with the default FE tooth (the rating's positions, the design's torque); its loads
(every converged, loaded position and pair) are then read again with FE teeth whose mesh differs in
one part only, the load distribution kept: the fillet's elements (``fillet``: their size per fillet
radius, and ``fillet_min``: the floor per module; ``radius_elements``: the fewest elements across the radius
where the floor gives way, and ``notch``: that rule's floor per module), the flanks' (``flank``, per module),
everything else (``far``, per module: the tooth's interior, the root land, the rim), how fast the fillet's
size grows into it (``growth``), or every size (``coarsen``; ``coarsen=0.6667`` is every size / 1.5, the
refined level of rating_root_convergence.py ``--refined 1.5``); ``window``: the read-out's half-width along
the fillet's profile per fillet element at refinement 1 (``fe.contact.READ_PROFILE_PER_FILLET_SIZE``; a finer
fillet rule narrows the window with its elements, this keeps it).  Per variant and member: the largest root
stress, where (height above the root cone), the mesh's nodes and fillet nodes; with ``--cost`` also the
fillet's element (mm), the tets, the FE data's seconds (the tooth's ``stats``: mesh, assembly,
factorisation, solve; and the child's wall time, with its start and the read-out) and peak RSS, each
variant's FE data computed afresh in a child process of its own.

    python benchmarks/fe_root_mesh_parts.py --design A [--torque-nm 290] \\
        [--variants "coarsen=2;far=0.5;fillet=0.25,fillet_min=0.02;flank=0.15"] [--cutter-tip-radius 0.38]
    python benchmarks/fe_root_mesh_parts.py --design R1 --member gear --cost \\
        --variants "coarsen=0.6667;growth=1;growth=1,coarsen=0.6667"

``--design``: a name rating_root_convergence.py takes (case1, case2, R1-R3, R5701-k, U11, A, B, C) or a spec file;
``--member``: read one member only (the other's FE data is still the default LTCA's);
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
        "far": "FAR_SIZE_PER_MODULE", "growth": "FILLET_GROWTH", "radius_elements": "FILLET_RADIUS_ELEMENTS",
        "notch": "FILLET_SIZE_NOTCH_PER_MODULE", "window": "READ_PROFILE_PER_FILLET_SIZE"}


def _pair(design, tip_radius):
    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes
    from rating_root_convergence import _pair as named_pair

    if not tip_radius:
        return named_pair(design)
    if design in ("case1", "case2"):
        text = (Path(__file__).resolve().parents[1] / "examples" / f"{design}.toml").read_text()
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


def _module(key):
    from beveloid.fe import contact, mesh

    return contact if key == "window" else mesh


def _set(v: dict, saved: dict) -> None:
    from beveloid.fe import mesh, sizes

    for k, name in KEYS.items():
        setattr(_module(k), name, v.get(k, saved[k]))
    sizes.FILLET_GROWTH = mesh.FILLET_GROWTH


def _child(args) -> int:
    """Compute one variant's FE data of one member into the cache and print its stats (``--cost``)."""
    import json

    from beveloid import ltca
    from beveloid.fe.cache import cached_tooth_data

    pair = _pair(args.design, args.cutter_tip_radius)
    material = ltca.Material.from_spec(pair.spec)
    e_nu = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    v = _variant(args.child)
    _set(v, {k: getattr(_module(k), name) for k, name in KEYS.items()})
    # computed afresh in a folder of its own (its cost measured even where the entry exists), then copied
    # into the cache the parent reads
    import shutil

    target = Path(os.environ["BEVELOID_CACHE_DIR"]) / "fe"
    os.environ["BEVELOID_CACHE_DIR"] = tempfile.mkdtemp(prefix="fe_root_mesh_parts_child_")
    data, how = cached_tooth_data(pair, args.member, *e_nu[args.member], 1, coarsen=v.get("coarsen", 1.0))
    target.mkdir(parents=True, exist_ok=True)
    for f in (Path(os.environ["BEVELOID_CACHE_DIR"]) / "fe").iterdir():
        shutil.move(str(f), target / f.name)
    shutil.rmtree(os.environ["BEVELOID_CACHE_DIR"], ignore_errors=True)
    seconds = sum(data.stat(k) for k in ("mesh_s", "assemble_s", "factor_s", "solve_s"))
    print(json.dumps({"how": how, "tets": data.stat("tets"), "seconds": seconds}))
    return 0


def main(argv=None) -> int:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--design", default="A")
    a.add_argument("--torque-nm", type=float, default=None, help="default: 1500 on case 1 / 2, else 10.1's higher torque")
    a.add_argument("--variants", default="coarsen=2;far=0.5;fillet=0.25,fillet_min=0.02;flank=0.15")
    a.add_argument("--cutter-tip-radius", type=float, default=0.0)
    a.add_argument("--member", choices=("pinion", "gear", "both"), default="both")
    a.add_argument("--cost", action="store_true", help="each variant's FE data in a child process: tets, seconds, peak RSS")
    a.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = a.parse_args(argv)
    os.environ.setdefault("BEVELOID_CACHE_DIR", tempfile.mkdtemp(prefix="fe_root_mesh_parts_"))
    if args.child is not None:
        return _child(args)

    import json
    import subprocess

    import numpy as np

    from beveloid import ltca
    from beveloid.fe import contact, mesh
    from beveloid.fe.cache import cached_tooth_data
    from beveloid.ltca.model import teeth
    from beveloid.rating.analysis import POSITIONS
    from rating_invariance import _torques

    pair = _pair(args.design, args.cutter_tip_radius)
    torque = args.torque_nm or (1500.0 if args.design in ("case1", "case2") else _torques(pair)[1])
    options = ltca.Options(positions=POSITIONS, tooth_model="fe")
    t0 = time.perf_counter()
    result = ltca.analyze(pair, ltca.LoadCase(torque), options)
    print(f"  the default LTCA: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    material = ltca.Material.from_spec(pair.spec)
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    saved = {k: getattr(_module(k), name) for k, name in KEYS.items()}
    from beveloid.fe import cache

    kept = set(cache._KEPT)  # the default LTCA's FE data; each variant's is let go after its row
    members = ("pinion", "gear") if args.member == "both" else (args.member,)
    print(f"{args.design} (rack tip radius {args.cutter_tip_radius:g} m_n), {torque:g} N m: largest root stress (MPa) "
          f"of the default LTCA's loads, height above the root (mm), nodes / fillet nodes"
          + ("; fillet element (mm), tets, FE data (s), peak RSS (GB) of its child process" if args.cost else ""), flush=True)
    print(f"| variant | {' | '.join(members)} |\n|---|{'---|' * len(members)}")
    for text in ["default", *args.variants.split(";")]:
        v = {} if text == "default" else _variant(text)
        t0 = time.perf_counter()
        cost = {}
        if args.cost:
            for m in members:
                cmd = ["/usr/bin/time", "-f", "RSS_KB %M %e", sys.executable, __file__, "--design", args.design, "--member", m,
                       "--cutter-tip-radius", str(args.cutter_tip_radius), "--child", "" if text == "default" else text]
                out = subprocess.run(cmd, capture_output=True, text=True)
                if out.returncode:
                    raise SystemExit(f"variant {text!r} {m}: child failed:\n{out.stderr[-3000:]}")
                rss = [ln for ln in out.stderr.splitlines() if ln.startswith("RSS_KB ")]
                info = json.loads(out.stdout.strip().splitlines()[-1])
                cost[m] = (info, float(rss[-1].split()[1]) / 1024 ** 2 if rss else float("nan"),
                           float(rss[-1].split()[2]) if rss else float("nan"))
        _set(v, saved)
        cells = []
        try:
            data = {m: cached_tooth_data(pair, m, *moduli[m], 1, coarsen=v.get("coarsen", 1.0) if m in members else 1.0)[0]
                    for m in ("pinion", "gear")}
            fillet_h = {m: mesh.mesh_sizes(_sampler(pair, m), pair.geometry.normal_module_mm, 1.0 / v.get("coarsen", 1.0))
                        .fillet_mm for m in members} if args.cost else {}
            r = teeth.root_stresses(tuple(contact.FeTooth(data[m], options.flank) for m in ("pinion", "gear")),
                                    result, result.converged)
            for m in members:
                a = r["tension"][m]
                j, k = np.unravel_index(int(np.nanargmax(a)), a.shape)
                cell = (f"{a[j, k]:.1f} at {r['where'][m][j, k, 1]:.3f} ({int(data[m].stat('nodes'))} / "
                        f"{data[m].fillet_points_mm.shape[1]})")
                if args.cost:
                    info, rss, wall = cost[m]
                    cell += f"; {fillet_h[m]:.3f}, {int(info['tets'])}, {info['seconds']:.0f} s ({wall:.0f} s wall), {rss:.1f} GB"
                    if info["how"] == "hit":
                        cell += " (cached)"
                cells.append(cell)
        finally:
            _set({}, saved)
            data = None
            for key in [k for k in cache._KEPT if k not in kept]:
                cache._KEPT.pop(key)
        print(f"| {text} | {' | '.join(cells)} |", flush=True)
        print(f"  {text}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    return 0


def _sampler(pair, member):
    """The member's ToothSampler, as ``beveloid.fe.mesh.sector_mesh`` samples it."""
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    body = body_pair(pair, member)
    return ToothSampler(getattr(body, "geometry", body), member)


if __name__ == "__main__":
    raise SystemExit(main())
