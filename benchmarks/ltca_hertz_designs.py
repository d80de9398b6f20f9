"""Surface p_max against Hertz at the LTCA's defaults over random designs (docs/validation.md section 7.2).

Random designs in the spec's ranges (module 1.5-10, teeth, shaft angle, helix and cone angles,
offset, faces), a random flank and torque; every loaded pair clear of the flank edges at 5
positions, against Hertz for that pair's load and curvatures (the JSON's pair_hertz_max_pressure_mpa).

    python benchmarks/ltca_hertz_designs.py [SEED] [DESIGNS]     # defaults 1 16
"""
import sys
import tomllib
from pathlib import Path
import numpy as np
from beveloid import ltca
from beveloid.ltca.compliance import member_tooth
from beveloid.ltca.grid import centres
from beveloid.pair import Pair

base = tomllib.loads((Path(__file__).resolve().parents[1] / "examples" / "case1.toml").read_text())
rng = np.random.default_rng(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
n = int(sys.argv[2]) if len(sys.argv) > 2 else 12
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
        r = ltca.analyze(pair, ltca.Options(torque_nm=torque, flank=flank, positions=5))
    except Exception as exc:
        print("fail", exc); continue
    designs += 1
    for j in range(5):
        for k in range(r.pair_load_n.shape[1]):
            load = r.pair_load_n[j, k]
            if not load > 0 or np.isfinite(r.pair_edge_max_pressure_mpa[j, k]) or not np.isfinite(r.pair_hertz_max_pressure_mpa[j, k]):
                continue
            dev = r.pair_surface_max_pressure_mpa[j, k] / r.pair_hertz_max_pressure_mpa[j, k] - 1
            # the loaded semi-axis along the contact from the pressure's second moment, a = sqrt(5 <y^2>)
            # (exact for a Hertz ellipse), over the tooth height h = (h_a + h_f) m_n
            g = r.grid
            y = centres(g.along_half_mm[j, k], g.along_cells)
            pk = r.pressure_mpa[j, k].reshape(g.across_cells, g.along_cells).sum(axis=0)
            a_loaded = float(np.sqrt(5 * (pk * y ** 2).sum() / pk.sum()))
            h = member_tooth(pair.geometry, "pinion", 2.1e5, 0.3).plate_height_mm
            rows.append((m, flank, z1, z2, j, k, load, a_loaded / h, dev))
    print(f"m {m} z {z1}/{z2} {flank} T {torque:.1f}: devs {[f'{x[-1]:+.3f}' for x in rows if x[:4]==(m, flank, z1, z2)]}", flush=True)
devs = np.array([r[-1] for r in rows])
ratio = np.array([r[-2] for r in rows])
print(f"points {len(devs)}  worst {devs.min():+.4f} / {devs.max():+.4f}  mean |dev| {np.abs(devs).mean():.4f}")
print("loaded a / tooth height h | pairs | worst | mean |dev|")
for lo, hi in ((0, 0.5), (0.5, 1), (1, 1.5), (1.5, 2), (2, 3), (3, np.inf)):
    sel = (ratio >= lo) & (ratio < hi)
    if sel.any():
        print(f"{lo:g}-{hi:g} | {sel.sum()} | {devs[sel].min():+.4f} | {np.abs(devs[sel]).mean():.4f}")
