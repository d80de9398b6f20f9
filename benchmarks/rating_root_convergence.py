"""Is the FE tooth's root stress, the one that decides the rating's local S_F, converged?  (issue 57.5)

For each design and member: the largest root stress over the mesh cycle of the LTCA at the rating's
torque (K_A = K_v = 1 here) and default positions (the FE tooth's smoothed fillet stresses, what the LTCA,
the rating's S_F and optimize read), with the FE tooth at --fe-coarsen 2 (every element twice as large),
at its default (refinement 1) and at --fe-refinement 2 (every element half as large), each level under its
own LTCA; the default's distance from the refined value and from the Richardson extrapolation of the three
(order from the three levels, h = 2, 1, 1/2); and the refined tooth reading the default's LTCA loads, which
splits the default's distance from refinement 2 into the read-out's part (the same loads, two meshes) and
the load distribution's (the refined tooth under its own LTCA against under the default's loads).  Prints a
markdown table, and a second one: where the default reads its maximum (face z from the toe and the heel,
height above the root cone), the fillet's smallest radius against its element size, and the rating's coarse
check (beveloid/rating/root_convergence.py: the default's loads read with the coarsened tooth and with the
default's mesh through the coarsened tooth's read-out window, their change and its two-mesh GCI 3 |same window
/ coarse - 1|, beside the window's effect, default / same window - 1) and the rating's ``converged`` (the
parameters outside the validated range in brackets).

    python benchmarks/rating_root_convergence.py [--designs case1,case2,A,B,C,R1,R2,R3] [--levels 0,1,2] [--notch]
    python benchmarks/rating_root_convergence.py --designs path/to/design.toml   # any design (named by its stem)
    python benchmarks/rating_root_convergence.py --designs R5701-3   # rating_invariance.py --random 5701:3's third
    python benchmarks/rating_root_convergence.py --designs U11 --torque-nm 500 --refined 1.5   # an unseen design
    python benchmarks/rating_root_convergence.py --designs case2 --levels 1 --fillet-rule 2,0.0125   # a trial rule

    python benchmarks/rating_root_convergence.py --designs case1,R1 --fillet-sweep 2,4 --growths 0.5,1   # 2D only

``--fillet-sweep K,...``: no FE tooth and no LTCA: per member the 2D section at mid-face (``--notch``'s) meshed
at the default's sizes, then at its flank and far sizes with the fillet's elements at rho_F / K for each K
(``--fillet-sweep ""``: the default's sizes only), over its converged value (the notch stress of a load at
the flank's tip / at the middle of its radii), for each fillet band's growth of ``--growths`` (the size's
rise away from the fillet, ``fe.sizes.FILLET_GROWTH``, set for the 2D mesh while it is made): how the
fillet's discretisation alone reads at each rule, a few seconds a member.
``--jitter 1.02,1.04``: a third table, the default's LTCA loads read by the FE tooth with every element size
a few percent larger (the nodes move, the rule does not): the read-out's own scatter.
``--peak-2d``: no FE tooth and no LTCA: per member the converged 2D section at mid-face (``--notch``'s) under a
load at the flank's tip, its fillet's (and root land's) largest principal stress along the profile: where it
peaks, how wide the peak is (the arc within 3 % and 10 % of it, mm and fillet elements), the largest of the
read-out's fit (``fe.contact.readout_matrix``, the 2D samples as its nodes, read every 0.01 fillet element over
+-1 element of the peak) over the peak (its bias), and the largest of samples half an element apart (a P2
mesh's node rows) over the peak, the smallest over their placements.
``--fillet-rule K,F[,G]``: every level's FE tooth meshed with another fillet rule, ``fe.mesh.FILLET_RADIUS_ELEMENTS`` K
and ``fe.mesh.FILLET_SIZE_NOTCH_PER_MODULE`` F (the fillet's elements at rho_F / K where the floor would leave fewer
than K of them, not below F m_n) and the fillet band's growth G (``fe.sizes.FILLET_GROWTH``); each enters the FE
cache's key.
``--levels 0,1``: coarsen 2 and the default only (refinement 2 takes up to 5 GB and minutes a member).
``--notch``: a last column, the 2D section (fe.plane_strain) meshed at each level's sizes over its converged
value, at the maximum's section.  The FE data of each level is built once per design and cached; run one
design per invocation, so that each refinement-2 tooth's memory is returned.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_fe_tooth import fe_options  # noqa: E402
from rating_invariance import DESIGNS, _torques  # noqa: E402

LEVELS = (("coarsen 2", 1, 2.0), ("default", 1, 1.0), ("refinement 2", 2, 1.0))
SHORT = {"A": 0, "B": 1, "C": 2}
#: three designs drawn at random (the generator of the issue 57 audits, seed 5701, its first three: m_n
#: 2-5, alpha_n 20-25 deg, shaft angle 4-30 deg, random crowning, reliefs and misalignment; sharp racks),
#: at their higher torque (benchmarks/rating_invariance.py's rule); not looked at when the smoothed
#: read-out's window was chosen
RANDOM = {
    "R1": """
[pair]
normal_module_mm = 3.0
normal_pressure_angle_deg = 22.5
shaft_angle_deg = 25.1
offset_mm = 129.7
[pinion]
teeth = 30
cone_angle_deg = 0.6
helix_angle_deg = 20.9
profile_shift = 0.41
face_width_mm = 38.0
lead_crowning_um = 17.0
[gear]
teeth = 54
cone_angle_deg = 1.4
face_width_mm = 40.0
end_relief_um = 11.0
[misalignment]
horizontal_deg = -0.009
vertical_deg = -0.014
""",
    "R2": """
[pair]
normal_module_mm = 2.0
normal_pressure_angle_deg = 22.5
shaft_angle_deg = 25.1
offset_mm = 72.8
[pinion]
teeth = 22
cone_angle_deg = 2.5
helix_angle_deg = 18.2
profile_shift = 0.46
face_width_mm = 27.0
lead_crowning_um = 10.0
tip_relief_um = 17.0
[gear]
teeth = 49
cone_angle_deg = 2.1
face_width_mm = 26.0
""",
    "R3": """
[pair]
normal_module_mm = 3.0
normal_pressure_angle_deg = 22.5
shaft_angle_deg = 21.5
offset_mm = 81.6
[pinion]
teeth = 20
cone_angle_deg = 2.3
helix_angle_deg = 29.1
profile_shift = -0.0
face_width_mm = 41.0
lead_crowning_um = 12.0
profile_crowning_um = 5.0
tip_relief_um = 20.0
[gear]
teeth = 33
cone_angle_deg = 2.4
face_width_mm = 49.0
tip_relief_um = 9.0
""",
    # session 11's untuned check design (m_n 3.5, 17/36, 12 deg, 6 um lead crowning, 5 um pinion tip relief,
    # 0.02 deg vertical), read at 500 N m (--torque-nm 500) where no read-out rule was chosen on it
    "U11": """
[pair]
normal_module_mm = 3.5
normal_pressure_angle_deg = 20.0
shaft_angle_deg = 12.0
offset_mm = 95.0

[pinion]
teeth = 17
cone_angle_deg = 1.5
helix_angle_deg = 20.0
profile_shift = 0.35
face_width_mm = 30.0
lead_crowning_um = 6.0
tip_relief_um = 5.0

[gear]
teeth = 36
cone_angle_deg = 1.0
face_width_mm = 32.0
lead_crowning_um = 6.0

[misalignment]
vertical_deg = 0.02
""",
}


def _pair(name):
    """The design ``name``: case1 / case2, one of :data:`RANDOM`, A / B / C (rating_invariance's), R{seed}-{k}
    (the k-th design ``rating_invariance.py --random SEED:N`` draws) or a TOML design file's path (ending in
    .toml)."""
    import re

    from rating_invariance import random_designs

    from beveloid.pair import Pair
    from beveloid.spec import load_spec, spec_from_toml_bytes

    if name.endswith(".toml"):
        return Pair.from_spec(load_spec(name))
    drawn = re.fullmatch(r"R(\d+)-(\d+)", name)
    if drawn:
        seed, k = int(drawn[1]), int(drawn[2])
        return Pair.from_spec(spec_from_toml_bytes(random_designs(seed, k)[k - 1].encode()))
    if name in ("case1", "case2"):
        return Pair.example(name)
    if name in RANDOM:
        return Pair.from_spec(spec_from_toml_bytes(RANDOM[name].encode()))
    return Pair.from_spec(spec_from_toml_bytes(list(DESIGNS.values())[SHORT[name]].encode()))


def richardson(coarse, mid, fine, ratio=2.0):
    """(extrapolated value, order) of three values at element sizes 2 h, h, h / ``ratio`` (f(h) = f_0 + C h^p);
    None where they do not converge monotonically or the order is outside 0.1-10."""
    from scipy.optimize import brentq

    d1, d2 = mid - coarse, fine - mid
    if d1 == 0 or d2 == 0 or d1 * d2 < 0:
        return None, None
    h = (2.0, 1.0, 1.0 / ratio)

    def gap(p):  # d1 / d2 of the model, less the measured
        return (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p) - d1 / d2

    if gap(0.1) * gap(10.0) > 0:
        return None, None
    p = brentq(gap, 0.1, 10.0)
    c = -d2 / (h[1] ** p - h[2] ** p)
    return fine - c * h[2] ** p, p


def _notch_ratios(pair, member, z_mm, flank, sizes, moduli) -> list:
    """The 2D section's notch stress (``fe.plane_strain``) meshed at the FE tooth's element sizes ``sizes``
    over its converged value (refinement 1, within 0.2 % of refinement 8: docs/validation.md 12.1), in the
    transverse section ``z_mm`` of ``member``'s body, under a load at the flank's tip and under one at the
    middle of its radii."""
    import numpy as np

    from beveloid.fe import plane_strain as ps
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    body = body_pair(pair, member)
    geometry = getattr(body, "geometry", body)
    z = np.array([z_mm])
    radii = [float(np.hypot(*ToothSampler(geometry, member).face_points(f"flank_{flank}", np.array([s]), z)[0, 0, :2]))
             for s in (0.0, 1.0)]
    loads = (ps.SectionLoad(flank, ps.TIP), ps.SectionLoad(flank, 0.5 * sum(radii)))
    conv = ps.notch_stress(body, member, loads, ps.NotchOptions(), z_mm=z_mm, material=moduli)
    fe = ps.notch_stress(body, member, loads, ps.NotchOptions(fe_sizes=sizes), z_mm=z_mm, material=moduli)
    return [f.tension_mpa_per_n_mm / c.tension_mpa_per_n_mm for f, c in zip(fe, conv)]


def _notch_ratio(pair, member, z_mm, flank, sizes, moduli) -> float:
    """The mean of :func:`_notch_ratios` (the tip's and the middle's)."""
    import numpy as np

    return float(np.mean(_notch_ratios(pair, member, z_mm, flank, sizes, moduli)))


def main(argv=None) -> int:
    import numpy as np

    from beveloid import ltca
    from beveloid.ltca.model.teeth import fe_tooth, root_stresses
    from beveloid.names import MEMBERS
    from beveloid.rating.analysis import POSITIONS
    from beveloid.rating.root_convergence import _sizes, root_stress_convergence

    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--designs", default="case1,case2,A,B,C,R1,R2,R3")
    a.add_argument("--torque-nm", type=float, default=None,
                   help="the torque (N m) of every design; default 1500 for case1 / case2, else rating_invariance's higher")
    a.add_argument("--levels", default="0,1,2", help="of coarsen 2, default, the refined level (0-based)")
    a.add_argument("--refined", default="2", choices=("2", "1.5"),
                   help="the refined level: refinement 2 (every size halved), or every size / 1.5 (--fe-coarsen 2/3: "
                        "about 2.4 times fewer tets than refinement 2, for the designs whose refinement 2 does not "
                        "fit the machine); the Richardson extrapolation takes its ratio")
    a.add_argument("--notch", action="store_true",
                   help="add the 2D section at each level's mesh sizes over its converged value (fe.plane_strain)")
    a.add_argument("--jitter", default=None, metavar="C,...",
                   help="also read the default's LTCA loads with the FE tooth at each --fe-coarsen C (1.02, 1.04: every "
                        "size a few percent larger): how far the read-out moves when the nodes move and the rule does "
                        "not (a third table)")
    a.add_argument("--fillet-sweep", default=None, metavar="K,...",
                   help="the 2D section only, with the fillet's elements at rho_F / K for each K (no FE tooth)")
    a.add_argument("--peak-2d", action="store_true",
                   help="the 2D section only: the notch peak's width and the read-out's bias on it (no FE tooth)")
    a.add_argument("--growths", default=None, metavar="G,...",
                   help="with --fillet-sweep: the fillet band's growths (fe.sizes.FILLET_GROWTH; default today's)")
    a.add_argument("--fillet-rule", default=None, metavar="K,F[,G]",
                   help="mesh with fe.mesh.FILLET_RADIUS_ELEMENTS K, FILLET_SIZE_NOTCH_PER_MODULE F and the fillet band's "
                        "growth G (fe.sizes.FILLET_GROWTH; default today's): a trial rule")
    args = a.parse_args(argv)
    if args.fillet_rule is not None:
        from beveloid.fe import mesh, sizes

        rule = [float(v) for v in args.fillet_rule.split(",")]
        mesh.FILLET_RADIUS_ELEMENTS, mesh.FILLET_SIZE_NOTCH_PER_MODULE = rule[:2]
        if len(rule) > 2:
            mesh.FILLET_GROWTH = sizes.FILLET_GROWTH = rule[2]
    if args.peak_2d:
        return peak_2d(args.designs.split(","))
    if args.fillet_sweep is not None:
        from beveloid.fe.sizes import FILLET_GROWTH

        growths = [FILLET_GROWTH] if args.growths is None else [float(g) for g in args.growths.split(",")]
        return fillet_sweep(args.designs.split(","), [float(k) for k in args.fillet_sweep.split(",") if k], growths)
    global LEVELS
    ratio = float(args.refined)
    if args.refined == "1.5":
        LEVELS = LEVELS[:2] + (("refinement 1.5", 1, 2.0 / 3.0),)
    refined = LEVELS[2][0]
    levels = [LEVELS[int(i)] for i in args.levels.split(",")]
    where_rows, jitter_rows = [], []
    print(f"| design | T (N m) | member | fillet radius / element (mm) | root stress max (MPa): coarsen 2 / default / "
          f"{refined} | default / {refined} − 1 | Richardson (order) | default / Richardson − 1 | {refined} "
          f"reading the default's loads (MPa) | default / that − 1 (read-out) | that / {refined} − 1 (loads) |"
          + (f" 2D section at the mesh's sizes / converged: coarsen 2 / default / {refined} |" if args.notch else ""))
    print("|---|---|---|---|---|---|---|---|---|---|---|" + ("---|" if args.notch else ""))
    for spec in args.designs.split(","):
        pair, name = _pair(spec), Path(spec).stem
        material = ltca.Material.from_spec(pair.spec)
        moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
        torque = args.torque_nm or (1500.0 if name in ("case1", "case2") else _torques(pair)[1])
        nan = {"pinion": math.nan, "gear": math.nan}
        values = {label: dict(nan) for label, _, _ in LEVELS}
        notch = {label: dict(nan) for label, _, _ in LEVELS}
        kept, default_result = dict(nan), None
        for label, refinement, coarsen in levels:
            t0 = time.perf_counter()
            options = fe_options(refinement / coarsen if coarsen < 1.0 else refinement, positions=POSITIONS,
                                 tooth_model="fe", **({"fe_coarsen": coarsen} if coarsen >= 1.0 else {}))
            r = ltca.analyze(pair, ltca.LoadCase(torque), options)
            values[label] = r.root_stress_max_mpa()
            if args.notch:
                at = r.root_stress_location()
                for m in MEMBERS:
                    notch[label][m] = _notch_ratio(pair, m, float(at[m]["z_mm"]), options.flank,
                                                   _sizes(pair, m, refinement, coarsen), moduli[m])
            if label == "default":
                default_result = r
                where_rows += _where(name, torque, pair, r, root_stress_convergence(pair, r, material))
                if args.jitter:
                    jitter_rows += _jitter(name, pair, r, moduli, options, [float(c) for c in args.jitter.split(",")])
            elif label == refined and default_result is not None:
                # the refined tooth under the default's LTCA loads: separates the read-out's change from the
                # load distribution's (each level runs its own LTCA)
                teeth = tuple(fe_tooth(pair, m, moduli[m], options) for m in MEMBERS)
                read = root_stresses(teeth, default_result, default_result.converged)["tension"]
                kept = {m: float(np.nanmax(read[m])) for m in MEMBERS}
            del r
            print(f"  {name} {label}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
        for m in ("pinion", "gear"):
            c, d, f = (values[label][m] for label, _, _ in LEVELS)
            ext, p = richardson(c, d, f, ratio) if math.isfinite(f) else (None, None)
            rich = "not monotonic" if ext is None else f"{ext:.1f} ({p:.2f})"
            off = "" if ext is None else f"{d / ext - 1:+.1%}"
            sizes = _sizes(pair, m, 1, 1.0)
            row = (f"| {name} | {torque:g} | {m} | {sizes.fillet_radius_mm:.3f} / {sizes.fillet_mm:.3f} | {c:.1f} / "
                   f"{d:.1f} / {f:.1f} | {d / f - 1:+.1%} | {rich} | {off} | {kept[m]:.1f} | {d / kept[m] - 1:+.1%} | "
                   f"{kept[m] / f - 1:+.1%} |")
            if args.notch:
                row += " " + " / ".join(f"{notch[label][m]:.3f}" for label, _, _ in LEVELS) + " |"
            print(row, flush=True)
    print("\n| design | member | max at face z from toe / heel (mm), height above root (mm) | fillet radius min / "
          "fillet element (mm) | the default's loads read by the coarsened mesh / by the default's through that window "
          "/ the default (MPa) | mesh change at a fixed window | window effect | two-mesh GCI | converged (outside) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for row in where_rows:
        print(row)
    if jitter_rows:
        print(f"\n| design | member | default reading (MPa) | read with every size x {args.jitter.replace(',', ' / ')} "
              "(MPa) | largest / smallest − 1 |")
        print("|---|---|---|---|---|")
        for row in jitter_rows:
            print(row)
    return 0


def _jitter(name, pair, result, moduli, options, coarsens) -> list:
    """``--jitter``'s rows: the default's LTCA loads read by the FE tooth at each coarsen (module docstring)."""
    import dataclasses

    import numpy as np

    from beveloid.ltca.model.teeth import fe_tooth, root_stresses
    from beveloid.names import MEMBERS

    default = result.root_stress_max_mpa()
    reads = []
    for c in coarsens:
        moved = dataclasses.replace(options, fe_coarsen=c)
        teeth = tuple(fe_tooth(pair, m, moduli[m], moved) for m in MEMBERS)
        read = root_stresses(teeth, result, result.converged)["tension"]
        reads.append({m: float(np.nanmax(read[m])) for m in MEMBERS})
    rows = []
    for m in MEMBERS:
        values = [default[m]] + [r[m] for r in reads]
        rows.append(f"| {name} | {m} | {default[m]:.1f} | {' / '.join(f'{r[m]:.1f}' for r in reads)} | "
                    f"{max(values) / min(values) - 1:+.1%} |")
    return rows


def fillet_sweep(designs, ks, growths) -> int:
    """``--fillet-sweep``'s table (module docstring)."""
    from beveloid import ltca
    from beveloid.fe import mesh
    from beveloid.fe.mesh import MeshSizes
    from beveloid.rating.root_convergence import _sizes
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    heads = [f"growth {g:g}, {label}: tip / mid" for g in growths
             for label in ["the default's elements"] + [f"ρ_F / {k:g}" for k in ks]]
    print("| design | member | fillet radius (mm, m_n) / default's element (mm) | " + " | ".join(heads) + " |")
    print("|---|---|---|" + "---|" * len(heads))
    kept = mesh.FILLET_GROWTH
    for spec in designs:
        pair, name = _pair(spec), Path(spec).stem
        material = ltca.Material.from_spec(pair.spec)
        moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
        for m in ("pinion", "gear"):
            body = body_pair(pair, m)
            geometry = getattr(body, "geometry", body)
            z = 0.5 * sum(ToothSampler(geometry, m).z_range_mm)
            base = _sizes(pair, m, 1, 1.0)
            rho = base.fillet_radius_mm
            cells = []
            for g in growths:
                mesh.FILLET_GROWTH = g  # the 2D section's fe_sizes grow from the fillet by fe.mesh.FILLET_GROWTH
                try:
                    cells += [" / ".join(f"{v:.3f}" for v in _notch_ratios(pair, m, z, "right", sizes, moduli[m]))
                              for sizes in [base] + [MeshSizes(base.flank_mm, rho / k, base.far_mm, rho) for k in ks]]
                finally:
                    mesh.FILLET_GROWTH = kept
            print(f"| {name} | {m} | {rho:.3f}, {rho / geometry.normal_module_mm:.3f} / {base.fillet_mm:.3f} | "
                  + " | ".join(cells) + " |", flush=True)
    return 0


def _profile_stress(body, member, z_mm, material):
    """(arc mm, largest principal stress MPa per N/mm) along the right fillet and the root land beside it of the
    converged 2D section ``z_mm`` (``fe.plane_strain`` at its defaults: within 0.2 % of refinement 8) under a
    load at the flank's tip, the arc from the land's far end."""
    import numpy as np

    from beveloid.fe import plane_strain as ps

    geometry = getattr(body, "geometry", body)
    load = (ps.SectionLoad("right", ps.TIP),)
    profile = ps.section_profile(geometry, member, z_mm, load, ps.NotchOptions(), 0.0)
    sm = ps._mesh_section(profile, ps._sizes(profile, geometry.normal_module_mm, 1.0, None))
    u = ps.solve_point_loads(sm.mesh, np.concatenate([sm.facets[k] for k in ps.CLAMPED]), sm.load_vertices,
                             -profile.load_normals, material)
    r = ps.edge_stresses(sm.mesh, ps._fillet_facets(sm.facets, "right"), u, material)
    x, s = r.points_mm.reshape(2, -1), r.max_principal_mpa[0].ravel()
    order = np.argsort(np.arctan2(x[1], x[0]))
    x, s = x[:, order], s[order]
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(x, axis=1)))])
    arc, first = np.unique(np.round(arc, 7), return_index=True)
    return arc, s[first]


def peak_2d(designs) -> int:
    """``--peak-2d``'s table (module docstring)."""
    import numpy as np

    from beveloid import ltca
    from beveloid.fe.contact import READ_FACE_PER_MODULE, READ_PROFILE_PER_FILLET_SIZE, readout_matrix
    from beveloid.rating.root_convergence import _sizes
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    print("| design | member | fillet radius / element (mm) | peak's arc within 3 % / 10 % (mm; elements) | read-out's "
          "largest / peak | largest of rows half an element apart / peak, smallest over their placements |")
    print("|---|---|---|---|---|---|")
    for spec in designs:
        pair, name = _pair(spec), Path(spec).stem
        material = ltca.Material.from_spec(pair.spec)
        for m in ("pinion", "gear"):
            e_mpa, nu = (material.pinion_e_mpa, material.pinion_nu) if m == "pinion" else (material.gear_e_mpa, material.gear_nu)
            body = body_pair(pair, m)
            geometry = getattr(body, "geometry", body)
            z = 0.5 * sum(ToothSampler(geometry, m).z_range_mm)
            sizes = _sizes(pair, m, 1, 1.0)
            fe = sizes.fillet_mm
            arc, s = _profile_stress(body, m, z, (e_mpa, nu))
            k = int(np.argmax(s))
            widths = [np.ptp(arc[s >= f * s[k]]) for f in (0.97, 0.9)]
            at = arc[k] + np.arange(-1.0, 1.0 + 1e-9, 0.01) * fe
            nodes = np.stack([np.zeros_like(arc), arc, np.zeros_like(arc)], axis=1)
            reads = np.stack([np.zeros_like(at), at, np.zeros_like(at)], axis=1)
            t, b = np.tile([0.0, 1.0, 0.0], (len(at), 1)), np.tile([0.0, 0.0, 1.0], (len(at), 1))
            w = readout_matrix(reads, t, b, nodes, READ_FACE_PER_MODULE * geometry.normal_module_mm,
                               READ_PROFILE_PER_FILLET_SIZE * fe)
            rows = min(np.max(np.interp(np.arange(arc[k] - fe + o, arc[k] + fe, 0.5 * fe), arc, s))
                       for o in np.linspace(0.0, 0.5 * fe, 11))
            print(f"| {name} | {m} | {sizes.fillet_radius_mm:.3f} / {fe:.3f} | {widths[0]:.3f} / {widths[1]:.3f}; "
                  f"{widths[0] / fe:.2f} / {widths[1] / fe:.2f} | {np.max(w @ s) / s[k]:.4f} | {rows / s[k]:.4f} |",
                  flush=True)
    return 0


def _where(name, torque, pair, result, estimate) -> list:
    """The second table's rows of one design (module docstring)."""
    rows = []
    at = result.root_stress_location()
    for m in ("pinion", "gear"):
        e, w = estimate[m], at[m]
        toe, heel = sorted(pair.geometry.member(m).face_limits)
        rows.append(f"| {name} | {m} | {w['z_mm'] - toe:.2f} / {heel - w['z_mm']:.2f}, {w['height_mm']:.3f} | "
                    f"{e['fillet_radius_mm']:.3f} / {e['fillet_element_mm']:.3f} | {e['coarse_mpa']:.1f} / "
                    f"{e['same_window_mpa']:.1f} / {e['default_mpa']:.1f} | {e['change']:+.1%} | {e['window_effect']:+.1%} "
                    f"| {e['coarse_gci']:.1%} | {e['converged']}"
                    + (f" ({', '.join(o['parameter'] for o in e['outside_range'])})" if e["outside_range"] else "") + " |")
    return rows


if __name__ == "__main__":
    raise SystemExit(main())
