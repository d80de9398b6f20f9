"""Surface p_max against Hertz at the LTCA's defaults over random designs (docs/validation.md section 7.2).

Random designs in the spec's ranges (module 1.5-10, teeth, shaft angle, helix and cone angles,
offset, faces), a random flank and torque; every loaded pair clear of the flank edges at 5
positions, against Hertz for that pair's load and curvatures (the JSON's pair_hertz_max_pressure_mpa).
The plate tooth (`--tooth-model plate`): the section is about the contact layer and the plate's face
coupling, and an FE tooth per random design would cost minutes of meshing each.

    python benchmarks/ltca_hertz_designs.py [SEEDS] [DESIGNS]    # defaults 1 16; SEEDS e.g. 1 or 1,2,3,4
    python benchmarks/ltca_hertz_designs.py shipped [fe|plate]    # case 1 and case 2 (default: fe)

Per seed: its pairs, the worst deviations and the mean |deviation|; then the pairs of all the seeds
binned by the loaded semi-axis along the contact over the tooth height.
"""
import sys
import tomllib
from pathlib import Path
import numpy as np
from beveloid import ltca
from beveloid.ltca.model.compliance import member_tooth
from beveloid.ltca.model.grid import centres
from beveloid.pair import Pair

base = tomllib.loads((Path(__file__).resolve().parents[1] / "examples" / "case1.toml").read_text())


def hertz_rows(pair, r):
    """(position, pair, load N, loaded a mm, a / h, p_max / Hertz - 1) of every loaded pair of the LTCA
    result ``r`` clear of the flank edges.  a = sqrt(5 <y^2>) is the loaded semi-axis along the contact
    from the pressure's second moment (exact for a Hertz ellipse), h = (h_a + h_f) m_n the tooth height."""
    h = member_tooth(pair.geometry, "pinion", 2.1e5, 0.3).plate_height_mm
    g, out = r.grid, []
    for j in range(r.pair_load_n.shape[0]):
        for k in range(r.pair_load_n.shape[1]):
            load = r.pair_load_n[j, k]
            if not load > 0 or np.isfinite(r.pair_edge_max_pressure_mpa[j, k]) or not np.isfinite(r.pair_hertz_max_pressure_mpa[j, k]):
                continue
            dev = r.pair_surface_max_pressure_mpa[j, k] / r.pair_hertz_max_pressure_mpa[j, k] - 1
            y = centres(g.along_half_mm[j, k], g.along_cells)
            pk = r.pressure_mpa[j, k].reshape(g.across_cells, g.along_cells).sum(axis=0)
            a_loaded = float(np.sqrt(5 * (pk * y ** 2).sum() / pk.sum()))
            out.append((j, k, load, a_loaded, a_loaded / h, dev))
    return out


def shipped(tooth_model):
    """The shipped cases, both flanks, 200 / 400 / 600 N m, 5 positions: the range of p_max / Hertz - 1
    and of a over the pairs clear of the edges."""
    print(f"shipped cases, {tooth_model} tooth | flank | T1 (N m) | pairs | p_max / Hertz - 1 | a (mm) | h (mm)")
    for case in ("case1", "case2"):
        pair = Pair.example(case)
        h = member_tooth(pair.geometry, "pinion", 2.1e5, 0.3).plate_height_mm
        for flank in ("left", "right"):
            for torque in (200.0, 400.0, 600.0):
                r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(flank=flank, positions=5, tooth_model=tooth_model))
                rows = hertz_rows(pair, r)
                dev = [100 * x[-1] for x in rows]
                a = [x[3] for x in rows]
                print(f"{case} | {flank} | {torque:g} | {len(rows)} | {min(dev):+.1f} to {max(dev):+.1f} % | "
                      f"{min(a):.1f}-{max(a):.1f} | {h:.1f}" if rows else f"{case} | {flank} | {torque:g} | 0 | - | - | {h:.1f}",
                      flush=True)


def seed_rows(seed, n):
    """The (module, flank, z1, z2, position, pair, load, a / h, p_max / Hertz - 1) of one seed's pairs."""
    rng = np.random.default_rng(seed)
    rows = []
    tried = 0
    designs = 0
    while designs < n and tried < 8 * n:
        tried += 1
        d = {k: dict(v) for k, v in base.items()}
        m = float(rng.choice([1.5, 2, 3, 4, 6, 8, 10]))
        d["pair"]["normal_module_mm"] = m
        z1 = int(rng.integers(18, 40)); z2 = int(rng.integers(z1 + 5, 80))
        d["pinion"]["teeth"] = z1; d["gear"]["teeth"] = z2
        d["pair"]["shaft_angle_deg"] = float(rng.uniform(5, 30))
        d["pinion"]["helix_angle_deg"] = float(rng.choice([-1, 1]) * rng.uniform(8, 28))
        d["pinion"]["cone_angle_deg"] = float(rng.uniform(1, 5)); d["gear"]["cone_angle_deg"] = float(rng.uniform(0.3, 3))
        d["pinion"]["profile_shift"] = float(rng.uniform(0, 0.4))
        d["pair"]["offset_mm"] = 0.5 * m * (z1 + z2) * float(rng.uniform(1.0, 1.25))
        fw = float(rng.uniform(6, 12)) * m
        d["pinion"]["face_width_mm"] = fw; d["gear"]["face_width_mm"] = fw * 1.2
        flank = str(rng.choice(["left", "right"]))
        try:
            pair = Pair.from_spec(d)
        except ValueError:  # a refused design (DesignError is a ValueError)
            continue
        torque = float(rng.uniform(0.3, 1.5)) * 100.0 * (m / 6) ** 2 * (z1 / 29)
        try:
            r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(flank=flank, positions=5, tooth_model="plate"))
        except Exception as exc:
            print("fail", exc); continue
        designs += 1
        rows += [(m, flank, z1, z2, *row) for row in hertz_rows(pair, r)]
        print(f"m {m} z {z1}/{z2} {flank} T {torque:.1f}: devs {[f'{x[-1]:+.3f}' for x in rows if x[:4]==(m, flank, z1, z2)]}", flush=True)
    return rows


def report(rows, label):
    devs = np.array([r[-1] for r in rows])
    print(f"{label}: points {len(devs)}  worst {devs.min():+.4f} / {devs.max():+.4f}  mean |dev| {np.abs(devs).mean():.4f}")


if len(sys.argv) > 1 and sys.argv[1] == "shipped":
    shipped(sys.argv[2] if len(sys.argv) > 2 else "fe")
    raise SystemExit
seeds = [int(v) for v in (sys.argv[1] if len(sys.argv) > 1 else "1").split(",")]
n = int(sys.argv[2]) if len(sys.argv) > 2 else 16
rows = []
for seed in seeds:
    mine = seed_rows(seed, n)
    report(mine, f"seed {seed}")
    rows += mine
if len(seeds) > 1:
    report(rows, f"seeds {','.join(map(str, seeds))}")
devs = np.array([r[-1] for r in rows])
ratio = np.array([r[-2] for r in rows])
print("loaded a / tooth height h | pairs | worst | mean |dev|")
for lo, hi in ((0, 0.5), (0.5, 1), (1, 1.5), (1.5, 2), (2, 3), (3, np.inf)):
    sel = (ratio >= lo) & (ratio < hi)
    if sel.any():
        print(f"{lo:g}-{hi:g} | {sel.sum()} | {devs[sel].min():+.4f} | {np.abs(devs[sel]).mean():.4f}")
