"""The FE tooth's root stress against a notch benchmark of its own, and ISO 6336-3 against both
(issue 41, 3; docs/validation.md 12).

    python benchmarks/notch_benchmark.py convergence      # the 2D model under refinement
    python benchmarks/notch_benchmark.py fe-tooth [--refinement 1 2] [--no-sectors]   # the FE tooth against the 2D model
    python benchmarks/notch_benchmark.py iso              # ISO method B against the 2D model (matrix)
    python benchmarks/notch_benchmark.py helical          # a near-cylindrical helical pair: LTCA + FE tooth
    python benchmarks/notch_benchmark.py shipped          # case 1 and case 2 under ISO's load case

The 2D model is ``beveloid.fe.plane_strain`` (P2 triangles, plane strain, the generated section:
the FE tooth's own sector).  Its designs are near-spur beveloid pinions (helix 0, cone angles 0.05 deg,
shaft angle 3 deg, module 6 mm) from a case-1 spec, their mate a 45-tooth gear whose offset is set
so that its profile shift is 0; the load of ISO's method B is the whole normal force at the outer
point of single pair contact of the virtual spur pair (d_en, at the same depth below the tip on
the real section, as ``beveloid.rating.fe_check``), the 2D model's at that radius of the mid-face
section.  Every stress is per unit normal line load (MPa per N/mm) or a ratio of two measured in
the same run.  FE data is cached (BEVELOID_CACHE_DIR).
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's beveloid, not an installed one

import numpy as np

from beveloid.fe import plane_strain as ps
from beveloid.ltca import Material
from beveloid.pair import Pair
from beveloid.rating import iso6336
from beveloid.rating.virtual import mate_gear, section_gear
from beveloid.spec import load_example, spec_from_dict, spec_to_dict

MODULE_MM = 6.0
MATE_TEETH = 45
FLANK = "right"


def near_spur_pair(teeth, profile_shift, tip_round, face_width_mm=50.0, helix_deg=0.0, shaft_deg=3.0,
                   mate_teeth=MATE_TEETH, mate_shift=0.0) -> Pair:
    """A near-cylindrical pinion (cone angles 0.05 deg) and its mate; the offset is found (secant) so that
    the mate's profile shift is ``mate_shift``; both cut by racks with tip round ``tip_round`` m_n."""
    d = spec_to_dict(load_example("case1"))
    d["pair"].update(shaft_angle_deg=shaft_deg, normal_module_mm=MODULE_MM)
    d["pinion"].update(teeth=teeth, profile_shift=profile_shift, cone_angle_deg=0.05, helix_angle_deg=helix_deg,
                       cutter_tip_radius_coefficient=tip_round, face_width_mm=face_width_mm)
    d["gear"].update(teeth=mate_teeth, cone_angle_deg=0.05, cutter_tip_radius_coefficient=tip_round,
                     face_width_mm=face_width_mm)

    def at(offset):
        d["pair"]["offset_mm"] = offset
        return Pair.from_spec(spec_from_dict(d))

    transverse = MODULE_MM / math.cos(math.radians(helix_deg))
    offsets = [transverse * (teeth + mate_teeth) / 2 + MODULE_MM * (profile_shift + mate_shift)]
    offsets.append(offsets[0] + 0.5 * MODULE_MM)
    miss = [at(o).design.gear.profile_shift - mate_shift for o in offsets]
    while abs(miss[-1]) > 1e-7 and len(miss) < 12:
        offsets.append(offsets[-1] - miss[-1] * (offsets[-1] - offsets[-2]) / (miss[-1] - miss[-2]))
        miss.append(at(offsets[-1]).design.gear.profile_shift - mate_shift)
    return at(offsets[-1])


def iso_case(pair, member="pinion", flank=FLANK) -> dict:
    """ISO method B on the member's mid-face virtual gear: sigma_F0 per unit normal line load (Y_beta
    included), the radius of the real section where d_en lies, and the 30 deg chord's height."""
    g = pair.geometry
    sg = section_gear(g, member, 0.0, flank)
    gear = sg.gear
    virtual = iso6336.CylindricalPair(gear, mate_gear(g, sg, flank), g.member(member).face_width_mm)
    bend = iso6336.bending_geometry(virtual)
    y_beta = iso6336.helix_factor_bending(virtual.overlap_ratio, gear.helix_angle)
    mn, rho = gear.normal_module_mm, gear.rack_tip_radius_mm
    d_n = mn * bend.virtual_teeth
    # F_t / b per unit normal line load F_n / b = 1 N/mm
    per_line_load = math.cos(gear.normal_pressure_angle) * math.cos(gear.base_helix_angle)
    G = rho / mn - gear.rack_dedendum_mm / mn + gear.profile_shift
    chord = mn / 2 * (bend.virtual_teeth * math.cos(math.pi / 3 - bend.theta) + G / math.cos(bend.theta) - rho / mn)
    return {"sigma_F0": per_line_load / mn * bend.Y_F * bend.Y_S * y_beta, "radius_mm": (bend.d_en_mm - d_n
            + gear.reference_diameter_mm) / 2, "bend": bend, "Y_beta": y_beta, "x_n": gear.profile_shift,
            "chord_height_mm": chord - (d_n / 2 + mn * gear.profile_shift - gear.rack_dedendum_mm),
            "q_s": bend.s_Fn_mm / (2 * bend.rho_F_mm)}


def loads_of(iso) -> tuple:
    return ps.SectionLoad(FLANK, ps.TIP), ps.SectionLoad(FLANK, iso["radius_mm"])


def material(pair, member="pinion"):
    """(E MPa, nu) of the member (the LTCA's Material)."""
    m = Material.from_spec(pair.spec)
    return getattr(m, f"{member}_e_mpa"), getattr(m, f"{member}_nu")


#: the near-spur pinions of the convergence and FE tooth comparisons: case 1's pinion made spur,
#: a rack with the tip round 0.3 m_n and the paper's sharp rack
BENCH = {"rounded 0.3": (29, 0.15, 0.3), "sharp": (29, 0.15, 0.0)}


def convergence(_args):
    print("2D plane strain, near-spur pinion z 29, x 0.15, m 6 (mid-face section); sigma (MPa per N/mm) at the tip "
          "load / at d_en, peak height above the root (mm); profile points per segment 41 unless said")
    print("| rack | refinement | points | nodes | tip load | HPSTC load | height (tip / HPSTC) | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for name, (z, x, rho) in BENCH.items():
        pair = near_spur_pair(z, x, rho)
        loads = loads_of(iso_case(pair))
        last = None
        for ref, pts in ((0.5, 41), (1, 41), (2, 41), (4, 41), (8, 41), (4, 161), (4, 9)):
            t = time.process_time()
            r = ps.notch_stress(pair, "pinion", loads, ps.NotchOptions(refinement=ref, points=pts),
                                material=material(pair))
            dt = time.process_time() - t
            print(f"| {name} | {ref} | {pts} | {r[0].nodes} | {r[0].tension_mpa_per_n_mm:.5f} | "
                  f"{r[1].tension_mpa_per_n_mm:.5f} | {r[0].height_above_root_mm:.3f} / "
                  f"{r[1].height_above_root_mm:.3f} | {dt:.1f} |")
            if pts == 41 and last is not None:
                step = [abs(a.tension_mpa_per_n_mm / b.tension_mpa_per_n_mm - 1) for a, b in zip(r, last)]
                print(f"|  | change from the previous refinement: {100 * max(step):.3f} % |")
            last = r if pts == 41 else last


def _sector_line_load(pair, member, radii_mm, refinement, ends="free", points=201):
    """The FE tooth's own sector mesh and solver (fe.mesh, fe.solve) under a smooth uniform line load
    (``points`` flank points, not the FE tooth's 9-point grid) at each of ``radii_mm`` (TIP: the flank's tip),
    the toe and heel ``ends`` "free" (the FE tooth) or held axially (u_z = 0: plane strain in the
    sector); the largest max-principal stress of the loaded fillet's nodes in the middle half of the
    face, MPa per N/mm."""
    from beveloid.tooth.sampling import ToothSampler
    from beveloid.fe import solve
    from beveloid.fe.mesh import fillet_radius_mm, sector_mesh
    from beveloid.tooth.profile import flank_at_radius

    g = pair.geometry
    mesh = sector_mesh(pair, member, refinement=refinement)
    e, nu = material(pair, member)
    K = solve.stiffness(mesh, e, nu)
    dofs = 3 * np.arange(mesh.nodes.shape[0])[:, None] + np.arange(3)
    fixed = [dofs[mesh.node_sets[n]].ravel() for n in solve.CLAMPED]
    if ends == "held":
        fixed += [dofs[mesh.node_sets[n], 2] for n in ("toe", "heel")]
    fixed = np.unique(np.concatenate(fixed))
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    solver = solve.sparse_solver()
    lu = solve.PardisoFactor(K[free][:, free]) if solver == "pardiso" else None
    if lu is None:
        import scipy.sparse.linalg
        lu = scipy.sparse.linalg.splu(K[free][:, free].tocsc())
    elastic = solve.Elastic(mesh, dofs, free, K.shape[0], e, nu, lu, {})
    sampler = ToothSampler(g, member)
    lo, hi = sorted(sampler.z_range_mm)
    z = np.linspace(lo, hi, points)
    w = np.full(points, (hi - lo) / (points - 1))
    w[[0, -1]] *= 0.5
    rhs = []
    for radius in radii_mm:
        if math.isinf(radius):
            l, u = sampler.flank_tip(FLANK, z)
        else:
            _, l, u = flank_at_radius(g, member, FLANK, z, np.full(z.shape, radius))
        surf = g.surface(member, FLANK, l, u)
        at = solve.displacement_operator(elastic, solve.locate(mesh, np.asarray(surf.point)), -np.asarray(surf.normal))
        rhs.append(at.T @ w)
    field = elastic.solve(np.stack(rhs, axis=1))
    nodes = mesh.node_sets[f"fillet_{FLANK}_0"]
    stress = (solve.stress_operator(elastic, nodes) @ field).reshape(-1, 6, len(rhs))
    sig = solve.principal_stresses(np.moveaxis(stress, 2, 0))[..., 2]  # (loads, nodes)
    height = np.hypot(mesh.nodes[nodes, 0], mesh.nodes[nodes, 1]) - sampler.root_radius_mm(mesh.nodes[nodes, 2])
    middle = np.abs(mesh.nodes[nodes, 2] - 0.5 * (lo + hi)) <= 0.25 * (hi - lo)
    band = ps.LEVEL_BIN_PER_RADIUS * fillet_radius_mm(sampler)
    return [(ps.fillet_level(height, mesh.nodes[nodes, 2], s, (lo, hi), band), float(np.max(s[middle]))) for s in sig]


def fe_tooth(args):
    from beveloid.fe.cache import cached_tooth_data

    print("FE tooth (fe.tooth, fe.contact.FeTooth) against the 2D model (refinement 4), near-spur pinion z 29, "
          "x 0.15, m 6, face 50 mm: a uniform line load along the face; sigma in MPa per N/mm and its ratio to the "
          "2D; max: the largest over the fillet of the nodal means (tooth_data(smooth=False)); level: "
          "plane_strain.fillet_level of the nodal means (the mean over the middle half of the face in bands of height, "
          "the largest band), then the largest there; read max: the largest of the fillet stresses read on the "
          "member's read grid (fe.contact.readout_matrix: the FE tooth's data, what the LTCA and the rating read)")
    print("| rack | load | 2D | refinement | FE tooth max | FE tooth level | read max | FE tooth's sector, smooth "
          "load: ends free | ends held (u_z = 0) | 6 mm slice, ends held |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, (z, x, rho) in BENCH.items():
        pair = near_spur_pair(z, x, rho)
        thin = near_spur_pair(z, x, rho, face_width_mm=6.0)
        loads = loads_of(iso_case(pair))
        two = ps.notch_stress(pair, "pinion", loads, ps.NotchOptions(refinement=4), material=material(pair))
        for ref in args.refinement:
            data, _ = cached_tooth_data(pair, "pinion", *material(pair), ref, smooth=False)
            smooth, _ = cached_tooth_data(pair, "pinion", *material(pair), ref)
            radii = [ld.radius_mm for ld in loads]
            sectors = [] if args.no_sectors else [_sector_line_load(p, "pinion", radii, ref, ends) for p, ends in
                                                  ((pair, "free"), (pair, "held"), (thin, "held"))]
            for k, (load, flat) in enumerate(zip(loads, two)):
                fe = ps.fe_tooth_line_load(data, pair.geometry, "pinion", load)
                sm = ps.fe_tooth_line_load(smooth, pair.geometry, "pinion", load)
                base = flat.tension_mpa_per_n_mm
                what = "tip" if math.isinf(load.radius_mm) else f"d_en (r {load.radius_mm:.2f} mm)"
                cells = [f"{fe.max_mpa_per_n_mm:.4f} = {fe.max_mpa_per_n_mm / base:.3f}",
                         f"{fe.level_mpa_per_n_mm:.4f} = {fe.level_mpa_per_n_mm / base:.3f}",
                         f"{sm.max_mpa_per_n_mm:.4f} = {sm.max_mpa_per_n_mm / base:.3f}"]
                cells += [f"{s[k][0] / base:.3f} ({s[k][1] / base:.3f})" for s in sectors] or ["not run"] * 3
                print(f"| {name} | {what} | {base:.4f} | {ref} | " + " | ".join(cells) + " |")


#: the ISO matrix: teeth, profile shift, rack tip round / m_n
MATRIX = {"teeth": (15, 20, 30, 45, 60), "x": (-0.3, 0.0, 0.3, 0.6), "rho": (0.0, 0.2, 0.38)}


def iso(args):
    print("ISO 6336-3:2019 method B sigma_F0 against the 2D model (refinement 2), near-spur pinions, m 6, "
          "load at d_en; FE/ISO, the 2D peak height above the root and ISO's 30 deg chord height (mm)")
    print("| z | x | rho_fP/m_n | q_s | Y_F | Y_S | 2D (MPa per N/mm) | ISO sigma_F0 | 2D / ISO | 2D peak height | "
          "ISO chord height | 2D tangent angle (deg) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for z in args.teeth or MATRIX["teeth"]:
        for x in MATRIX["x"]:
            for rho in MATRIX["rho"]:
                try:
                    pair = near_spur_pair(z, x, rho)
                    c = iso_case(pair)
                    r = ps.notch_stress(pair, "pinion", [ps.SectionLoad(FLANK, c["radius_mm"])],
                                        ps.NotchOptions(refinement=2), material=material(pair))[0]
                except Exception as exc:  # a design or section this matrix point does not have: say which
                    print(f"| {z} | {x:g} | {rho:g} | {type(exc).__name__}: {str(exc)[:120]} |")
                    continue
                b = c["bend"]
                print(f"| {z} | {x:g} | {rho:g} | {c['q_s']:.2f} | {b.Y_F:.3f} | {b.Y_S:.3f} | "
                      f"{r.tension_mpa_per_n_mm:.4f} | {c['sigma_F0']:.4f} | {r.tension_mpa_per_n_mm / c['sigma_F0']:.3f}"
                      f" | {r.height_above_root_mm:.2f} | {c['chord_height_mm']:.2f} | {r.tangent_angle_deg:.0f} |")


def _lower_fillet_peaks(pair, lt, member):
    """[(stress MPa, face z mm, height mm)] of the largest max-principal stress over the LTCA's cycle in the
    lower half of the loaded fillet (height below half the fillet's), on the whole face and more than one
    module from its ends: the tooth's bending peak, without the near field of a contact that the FE
    tooth's grid lumps onto its form-limit row at the top of the fillet (a point force there reads over 2 mm
    into the fillet; the bending peak and ISO's 30 deg tangent lie in the lower half: 12.1, 12.3), and
    without the face ends."""
    from beveloid.fe.cache import cached_tooth_data
    from beveloid.fe.contact import FeTooth
    from beveloid.fe.solve import principal_stresses
    from beveloid.tooth import sections

    data, _ = cached_tooth_data(pair, member, *material(pair, member), 1)
    tooth = FeTooth(data, FLANK)
    side = tooth.index
    height = data.fillet_height_mm[side]
    lower_half = height < 0.5 * height.max()
    z = data.fillet_points_mm[side][:, 2]
    inside = np.abs(z - data.z_mm.mean()) < 0.5 * np.ptp(data.z_mm) - pair.geometry.normal_module_mm
    points = lt.gap.pinion_point if member == "pinion" else lt.gap.gear_point
    area = lt.cell_area_mm2
    best = [(-math.inf, math.nan, math.nan)] * 2
    for j in np.flatnonzero(lt.converged):
        for k in range(points.shape[1]):
            f = np.where(lt.gap.in_flank[j, k], lt.pressure_mpa[j, k] * area[j, k], 0.0)
            if f.sum() <= 0:
                continue
            g = tooth.weights(points[j, k]).T @ f
            s1 = principal_stresses(tooth.stress[side] @ g)[:, 2]
            lower = tooth.counted(g)[0] & lower_half
            for n, mask in enumerate((lower, lower & inside)):
                i = int(np.argmax(np.where(mask, s1, -np.inf)))
                if s1[i] > best[n][0]:
                    best[n] = (float(s1[i]), float(sections.face_z(pair.geometry, member, z[i])), float(height[i]))
    return best


def helical(args):
    from beveloid import ltca, rating
    from beveloid.rating.fe_check import iso_load_case_detail
    from beveloid.solver import Solver

    print(f"Near-cylindrical pairs (cone angles 0.05 deg, shaft angle {args.shaft_deg:g} deg, z 29 / 45, x 0.15 / 0, "
          f"m 6, faces 50 mm), pinion torque {args.torque_nm:g} N m, {args.positions} positions, FE tooth refinement 1:"
          " the LTCA's root stress (FE tooth: its largest over the cycle, as the rating reads it, and the largest in "
          "the lower half of the fillet) against ISO sigma_F0 of the middle section as the rating computes it "
          "(Y_beta, f_eps in Y_F; K_A = K_v = 1), and the same FE tooth under ISO's own load case (the whole force on"
          " a straight line at d_en: max / median over the face)")
    print("| pinion helix | rack | member | beta (deg) | Y_beta | f_eps | eps_beta | ISO sigma_F0 (MPa) | K_Fbeta | "
          "LTCA + FE max / sigma_F0 (face z, height mm) | lower fillet half / sigma_F0 (face z, height mm) | "
          "the same, > 1 m_n from the face ends | ISO load case FE / sigma_F0: max, median | median x Y_beta f_eps |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for beta in args.helix_deg:
        for name, rho in (("rounded 0.3", 0.3), ("sharp", 0.0)):
            pair = near_spur_pair(29, 0.15, rho, helix_deg=beta, shaft_deg=args.shaft_deg)
            options = rating.Options(ltca.Options(positions=args.positions, tooth_model="fe"))
            lt = ltca.analyze(pair, ltca.LoadCase(args.torque_nm), options.ltca, solver=Solver())
            r = rating.analyze(pair, ltca.LoadCase(args.torque_nm), options, ltca_result=lt)
            for member, m in r.members.items():
                s = m.sections["middle"]
                d = iso_load_case_detail(pair, member)
                w = m.root_stress_location or {}
                sg = section_gear(pair.geometry, member, 0.0, FLANK)
                eps_beta = iso6336.CylindricalPair(sg.gear, mate_gear(pair.geometry, sg, FLANK),
                                                   pair.geometry.member(member).face_width_mm).overlap_ratio
                peaks = _lower_fillet_peaks(pair, lt, member)
                median = d.fe_face_median_mpa / d.sigma_F0_mpa
                print(f"| {beta:g} | {name} | {member} | {s.helix_angle_deg:.1f} | {s.Y_beta:.3f} | {s.bending.f_eps:.3f} |"
                      f" {eps_beta:.2f} | {s.sigma_F0_mpa:.1f} | {s.K_F_beta:.3f} | "
                      f"{m.root_stress_max_mpa / s.sigma_F0_mpa:.3f} ({w.get('face_z_mm', math.nan):.1f}, "
                      f"{w.get('height_above_root_mm', math.nan):.2f}) | "
                      + " | ".join(f"{v / s.sigma_F0_mpa:.3f} ({fz:.1f}, {h:.2f})" for v, fz, h in peaks)
                      + f" | {d.fe_max_mpa / d.sigma_F0_mpa:.3f}, {median:.3f} | "
                      f"{median * s.Y_beta * s.bending.f_eps:.3f} |")


def shipped(_args):
    from beveloid.rating.fe_check import iso_load_case_detail

    print("The shipped designs under ISO's load case (rating.fe_check.iso_load_case_detail: the whole normal force at"
          " d_en on a straight line uniform along the face, FE refinement 1) beside what the benchmark separates: "
          "ISO's helix factors, and ISO's notch on a near-spur pinion of the virtual gear's z_n (rounded), x_n and "
          "rack (the 2D model at refinement 2, load at its d_en)")
    print("| case | member | beta (deg) | eps_beta | Y_beta | f_eps | FE max / sigma_F0 | FE median / sigma_F0 | median x"
          " Y_beta f_eps | virtual spur z_n, x_n: 2D / ISO | what is left |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for case in ("case1", "case2"):
        pair = Pair.example(case)
        for member in ("pinion", "gear"):
            d = iso_load_case_detail(pair, member)
            c = iso_case(pair, member)
            sg = section_gear(pair.geometry, member, 0.0, FLANK)
            eps_beta = iso6336.CylindricalPair(sg.gear, mate_gear(pair.geometry, sg, FLANK),
                                               pair.geometry.member(member).face_width_mm).overlap_ratio
            helix = c["Y_beta"] * c["bend"].f_eps
            zn, xn = c["bend"].virtual_teeth, c["x_n"]
            spur = near_spur_pair(round(zn), xn, sg.gear.rack_tip_radius_mm / sg.gear.normal_module_mm)
            sc = iso_case(spur)
            flat = ps.notch_stress(spur, "pinion", [ps.SectionLoad(FLANK, sc["radius_mm"])],
                                   ps.NotchOptions(refinement=2), material=material(spur))[0]
            notch = flat.tension_mpa_per_n_mm / sc["sigma_F0"]
            median = d.fe_face_median_mpa / d.sigma_F0_mpa
            print(f"| {case} | {member} | {math.degrees(sg.gear.helix_angle):.1f} | {eps_beta:.2f} | {c['Y_beta']:.3f} | "
                  f"{c['bend'].f_eps:.3f} | {d.fe_max_mpa / d.sigma_F0_mpa:.3f} | {median:.3f} | {median * helix:.3f} | "
                  f"{round(zn)}, {xn:.2f}: {notch:.3f} | {median * helix / notch:.3f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    sub.add_parser("convergence")
    p = sub.add_parser("fe-tooth")
    p.add_argument("--refinement", type=int, nargs="+", default=[1])
    p.add_argument("--no-sectors", action="store_true",
                   help="leave out the sector columns (three more meshes a refinement: the heavy part)")
    p = sub.add_parser("iso")
    p.add_argument("--teeth", type=int, nargs="*")
    p = sub.add_parser("helical")
    p.add_argument("--helix-deg", type=float, nargs="+", default=[0.0, 15.0, 25.0])
    p.add_argument("--shaft-deg", type=float, default=1.0)
    p.add_argument("--torque-nm", type=float, default=1000.0)
    p.add_argument("--positions", type=int, default=20)
    sub.add_parser("shipped")
    args = ap.parse_args()
    {"convergence": convergence, "fe-tooth": fe_tooth, "iso": iso, "helical": helical, "shipped": shipped}[
        args.command](args)


if __name__ == "__main__":
    main()
