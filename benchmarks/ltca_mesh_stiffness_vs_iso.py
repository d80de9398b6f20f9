"""The LTCA's mesh stiffness against ISO 6336-1 method B's c' and c_gamma_alpha, near-cylindrical and near-parallel.

    python benchmarks/ltca_mesh_stiffness_vs_iso.py [--torques-nm 500,1000,2000] [--positions 20]
                                                    [--tooth-models plate,fe] [--shaft-angle-deg 1]
                                                    [--offset-mm 221.853] [--json]
    python benchmarks/ltca_mesh_stiffness_vs_iso.py --iso-only case1,case2   # ISO's c', c_gamma_alpha of examples

Not a test.  The pair is benchmarks/rating_fe_vs_iso.py's (case 1 with cone angles 0.05 deg, a spur
pinion, tip rounds 0.3 m_n) with a shaft angle of 1 deg (its 3 deg crosses the flanks enough to
load the middle of the face 1.6-2 times the mean: K_Hbeta below) at an offset of 221.853 mm, where
the gear's middle section has a profile shift of 0 (the pinion's is 0.15): ISO's formula's own
ground.  b is the common face width (the pinion's 50 mm; the gear is 60 mm).

* ISO (beveloid/rating/iso6336.py): c' = c'_th C_M C_R C_B cos beta and c_gamma_alpha =
  c' (0.75 eps_alpha + 0.25) of the middle virtual pair the rating uses (pinion middle section and
  its mate, rating/analysis.py), solid discs (C_R = 1).  ISO states them for F_t K_A / b >= 100 N/mm:
  every torque here loads more (F_t of the virtual pinion, K_A = 1).
* LTCA, per tooth model: its ``mesh_stiffness_mean_n_per_um`` (normal load over normal approach,
  the mean over the converged positions) per unit face width in the transverse plane,
  k cos^2 beta_b1 / b (``rating.analysis.mesh_stiffness_per_face_width``, as K_v method B takes it),
  against c_gamma_alpha; and the largest k over the positions where one tooth pair carries the load,
  the same conversion, against c' (ISO's largest stiffness of one pair).

The FE tooth's data is built once per member (about a minute each) and cached (BEVELOID_CACHE_DIR).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's beveloid, not an installed one
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

from beveloid import ltca  # noqa: E402
from beveloid.ltca.results.batch import summary  # noqa: E402
from beveloid.rating import iso6336  # noqa: E402
from beveloid.rating.analysis import mesh_stiffness_per_face_width  # noqa: E402
from beveloid.rating.face_load import face_load  # noqa: E402
from beveloid.rating.virtual import mate_gear, section_gear  # noqa: E402
from beveloid.solver import Solver  # noqa: E402
from rating_fe_vs_iso import near_parallel_pair  # noqa: E402

SHAFT_ANGLE_DEG = 1.0
OFFSET_MM = 221.853  # the gear's middle-section profile shift 0 at 1 deg (3 deg: 222.954)


def iso_pair(pair, flank="right"):
    """The middle virtual pair (pinion section and its parallel-axis mate) and b."""
    geom = pair.geometry
    b = min(geom.pinion.face_width_mm, geom.gear.face_width_mm)
    p_sec = section_gear(geom, "pinion", 0.0, flank)
    return iso6336.CylindricalPair(p_sec.gear, mate_gear(geom, p_sec, flank), b)


def ltca_stiffness(pair, pair_v, torque_nm, positions, tooth_model) -> dict:
    """The LTCA's c_gamma_alpha and single-pair c' in N/(mm um), the pairs carrying at each position, and
    the pinion's K_Hbeta and loaded face length at its peak line load (how much of the face carries)."""
    r = ltca.analyze(pair, ltca.LoadCase(torque_nm), ltca.Options(positions=positions, tooth_model=tooth_model), solver=Solver())
    b = pair_v.face_width_mm
    mean = summary(r)["mesh_stiffness_mean_n_per_um"]
    k = np.asarray(r.mesh_stiffness_n_per_um, float)
    carrying = (np.nan_to_num(r.pair_load_n) > 1e-6 * torque_nm).sum(axis=1)
    single = k[(carrying == 1) & np.isfinite(k)]
    face = face_load(r, pair.geometry, "pinion", b)
    return {"c_gamma_alpha": mesh_stiffness_per_face_width(mean, pair_v.gear, b),
            "single_pair": (mesh_stiffness_per_face_width(float(single.max()), pair_v.gear, b) if single.size
                            else float("nan")),
            "pairs_carrying": [int(c) for c in carrying], "K_H_beta": face.K_H_beta,
            "loaded_length_mm": face.loaded_length_mm}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--torques-nm", default="500,1000,2000")
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--tooth-models", default="plate,fe")
    ap.add_argument("--shaft-angle-deg", type=float, default=SHAFT_ANGLE_DEG)
    ap.add_argument("--offset-mm", type=float, default=OFFSET_MM)
    ap.add_argument("--iso-only", metavar="EXAMPLES", help="only ISO's c' and c_gamma_alpha of these examples' "
                    "middle virtual pairs (comma list)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.iso_only:
        from beveloid.pair import Pair

        for name in a.iso_only.split(","):
            pv = iso_pair(Pair.example(name))
            print(f"{name}: x {pv.gear.profile_shift:.3f} / {pv.mate.profile_shift:.3f}, z_n {iso6336.virtual_teeth(pv.gear):.2f}"
                  f" / {iso6336.virtual_teeth(pv.mate):.2f}, eps_alpha {pv.transverse_contact_ratio:.3f}, b"
                  f" {pv.face_width_mm:g} mm: ISO c' {iso6336.single_stiffness_n_per_mm_um(pv):.2f}, c_gamma_alpha"
                  f" {iso6336.mesh_stiffness_n_per_mm_um(pv):.2f} N/(mm um)")
        return
    pair = near_parallel_pair(offset_mm=a.offset_mm, shaft_angle_deg=a.shaft_angle_deg)
    pair_v = iso_pair(pair)
    g, m = pair_v.gear, pair_v.mate
    c_prime = iso6336.single_stiffness_n_per_mm_um(pair_v)
    c_gamma = iso6336.mesh_stiffness_n_per_mm_um(pair_v)
    out = {"shaft_angle_deg": a.shaft_angle_deg, "offset_mm": a.offset_mm, "face_width_mm": pair_v.face_width_mm, "x1": g.profile_shift, "x2": m.profile_shift,
           "z_n1": iso6336.virtual_teeth(g), "z_n2": iso6336.virtual_teeth(m), "eps_alpha": pair_v.transverse_contact_ratio,
           "iso_c_prime": c_prime, "iso_c_gamma_alpha": c_gamma, "rows": []}
    for t in (float(v) for v in a.torques_nm.split(",")):
        line_load = 2000.0 * t / g.reference_diameter_mm / pair_v.face_width_mm
        for model in a.tooth_models.split(","):
            row = ltca_stiffness(pair, pair_v, t, a.positions, model)
            out["rows"].append({"torque_nm": t, "line_load_n_per_mm": line_load, "tooth_model": model, **row,
                                "c_gamma_alpha_over_iso": row["c_gamma_alpha"] / c_gamma,
                                "single_pair_over_iso_c_prime": row["single_pair"] / c_prime})
    if a.json:
        print(json.dumps(out))
        return
    print(f"near-parallel pair, shaft angle {a.shaft_angle_deg:g} deg, offset {a.offset_mm:g} mm: x1 {g.profile_shift:.3f}, x2 {m.profile_shift:.3f}, "
          f"z_n {out['z_n1']:.2f} / {out['z_n2']:.2f}, eps_alpha {out['eps_alpha']:.3f}, b {pair_v.face_width_mm:g} mm; "
          f"ISO c' {c_prime:.2f}, c_gamma_alpha {c_gamma:.2f} N/(mm um)")
    print(f"{'T (N m)':>8} {'F_t/b':>7} {'tooth':>6} {'c_gamma LTCA':>13} {'/ ISO':>6} {'single pair LTCA':>17}"
          f" {'/ c_ISO':>8} {'K_Hbeta':>8} {'loaded face mm':>15}")
    for r in out["rows"]:
        print(f"{r['torque_nm']:>8g} {r['line_load_n_per_mm']:>7.0f} {r['tooth_model']:>6} {r['c_gamma_alpha']:>13.2f}"
              f" {r['c_gamma_alpha_over_iso']:>6.3f} {r['single_pair']:>17.2f} {r['single_pair_over_iso_c_prime']:>8.3f}"
              f" {r['K_H_beta']:>8.3f} {r['loaded_length_mm']:>15.1f}")


if __name__ == "__main__":
    main()
