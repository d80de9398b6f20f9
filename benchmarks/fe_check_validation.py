"""FE (CalculiX) against the LTCA, the runs of docs/validation.md 11 (full-contact FE check).

Each run is ``beveloid.fecheck.analyze`` (what ``beveloid fe-check`` runs) on one design,
flank, torque and refinement; the table gives per quantity FE / LTCA.  Results are appended as
JSON lines to OUT (default fe_check_runs.jsonl) so that a long series can be resumed.

    python benchmarks/fe_check_validation.py [--designs case1:right,case2:right] [--torques 100,400]
        [--refinements 1,2] [--coarsen 1.0] [--tooth-model fe|plate] [--no-local-refinement]
        [--contact-size-um UM] [--max-strip-elements N] [--out fe_check_runs.jsonl] [--keep DIR] [--table-only]

DESIGN is an example's name (case1, case2) or a spec file (*.toml).  Runs are local-refined over
the LTCA's patches (beveloid.fecheck.strips) unless --no-local-refinement.  The page's tables are
``table`` and ``hertz_table`` of the runs docs/readme_numbers.py records (``--record fe_check
--fe-check-runs OUT``).
"""
import argparse
import json
import sys
import time
from pathlib import Path

from beveloid.fe.sizes import MAX_STRIP_ELEMENTS
from beveloid import fecheck, ltca
from beveloid.pair import Pair


def _pair(design):
    """An example's name (case1, case2) or a spec file."""
    if design.endswith(".toml"):
        from beveloid.spec import load_spec

        return Pair.from_spec(load_spec(design))
    return Pair.example(design)


def _keep_dir(a, design, flank, torque, refinement):
    """The folder to keep the run's deck and results in (--keep DIR), None: a temporary one."""
    if a.keep is None:
        return None
    strips = "none" if a.no_local_refinement else f"cap{a.max_strip_elements}"
    name = f"{Path(design).stem}_{flank}_{torque:g}nm_r{refinement}_x{a.coarsen:g}_{strips}"
    return str(Path(a.keep) / name)


def run(design, flank, torque, refinement, a):
    t0 = time.perf_counter()
    out = fecheck.analyze(_pair(design), ltca.LoadCase(torque), fecheck.Options(
        ltca=ltca.Options(flank=flank, tooth_model=a.tooth_model), refinement=refinement, coarsen=a.coarsen,
        local_refinement=not a.no_local_refinement, contact_size_um=a.contact_size_um,
        max_strip_elements=a.max_strip_elements, out_dir=_keep_dir(a, design, flank, torque, refinement)),
        progress=lambda done, total, s: print(s, file=sys.stderr, flush=True) if not s.startswith("ccx") else None).to_json()
    out.update(design=design, total_s=time.perf_counter() - t0, coarsen=a.coarsen, tooth_height_mm=tooth_height_mm(design),
               max_strip_elements=a.max_strip_elements, contact_size_um=a.contact_size_um)
    return out


def tooth_height_mm(design):
    """The pinion's whole depth (tip height + the cutter's addendum), mm: 13.5 for case 1."""
    member = _pair(design).geometry.pinion
    return member.tip_height_mm + member.cutter_addendum_mm


def hertz_table(rows):
    """Per run, the pair the LTCA loads most: a/h (the LTCA's patch), its peak pressure in the FE and
    the LTCA, and Hertz for that pair's curvatures at the LTCA's load and at the FE's (x (F_FE / F_LTCA)^(1/3))."""
    lines = ["| design, flank | T (N m) | N | elements | main pair | a/h (LTCA) | load FE / LTCA (N) | peak p FE / LTCA (MPa)"
             " | Hertz at LTCA / FE load (MPa) | FE, LTCA against Hertz at own load |", "|" + "---|" * 10]
    for r in rows:
        c, lt = r["calculix"], r["ltca"]
        loads = [v or 0.0 for v in lt["pair_normal_load_n"]]
        k = loads.index(max(loads))
        h = r.get("tooth_height_mm") or tooth_height_mm(r["design"])
        a_mm = r["ltca_patch_semi_axes_mm"][k][1]
        f_fe, f_lt = c["pair_normal_load_n"][k], lt["pair_normal_load_n"][k]
        hz = r["ltca_hertz_max_pressure_mpa"][k]
        hz_fe = None if hz is None or not f_fe else hz * (f_fe / f_lt) ** (1 / 3)
        p_fe, p_lt = c["pair_max_pressure_mpa"][k], lt["pair_max_pressure_mpa"][k]
        dev = lambda p, q: "-" if p is None or q is None else f"{100 * (p / q - 1):+.1f} %"  # noqa: E731
        lines.append(
            f"| {r['design']} {r['flank']} (pos. {r['position']}) | {r['torque_nm']:g} | {r['refinement']}"
            f"{'' if r.get('coarsen', 1.0) == 1.0 else ' (x' + format(r['coarsen'], 'g') + ')'} | {r['elements']}"
            f" | {r['tooth_pairs'][k]} | {fmt(None if a_mm is None else a_mm / h, '.2f')} ({fmt(a_mm, '.1f')} / {h:.1f})"
            f" | {fmt(f_fe, '.0f')} / {fmt(f_lt, '.0f')} | {fmt(p_fe, '.0f')} / {fmt(p_lt, '.0f')}"
            f" | {fmt(hz, '.0f')} / {fmt(hz_fe, '.0f')} | {dev(p_fe, hz_fe)}, {dev(p_lt, hz)} |")
    return "\n".join(lines)


def _key(r):
    local = r.get("local_refinement") is not None
    return (r["design"], r["flank"], r["torque_nm"], r["refinement"], r.get("coarsen", 1.0), local,
            r.get("max_strip_elements") if local else None, r.get("contact_size_um"))


def fmt(v, f):
    return "-" if v is None else format(v, f)


def _strips(r):
    """The refined pairs' element sizes (mm, pinion / gear) or "none" (runs before the strips)."""
    if r.get("local_refinement") is None:
        return "none"
    return "; ".join(f"{e['pinion_element_mm']:.3f} / {e['gear_element_mm']:.3f}" for e in r["local_refinement"])


def table(rows):
    lines = ["| design, flank | T (N m) | N | strip h (mm) | elements / DOF | ccx wall / CPU (s) | pair loads FE / LTCA (N)"
             " | peak p FE / LTCA / Hertz(LTCA) (MPa) | area FE / LTCA (mm²) | loaded TE FE / LTCA (µrad), unloaded"
             " | root σ1 pinion / gear FE; LTCA (MPa) | total s (mesh, ccx wall) |", "|" + "---|" * 12]
    for r in rows:
        c, lt = r["calculix"], r["ltca"]
        hz = r.get("ltca_hertz_max_pressure_mpa") or [None] * len(c["pair_normal_load_n"])
        pairs = lambda key, f: "; ".join(f"{fmt(a, f)} / {fmt(b, f)}" for a, b in zip(c[key], lt[key])  # noqa: E731
                                         if (a or 0) > 0 or (b or 0) > 0)
        peaks = "; ".join(f"{fmt(a, '.0f')} / {fmt(b, '.0f')} / {fmt(h, '.0f')}"
                          for a, b, h in zip(c["pair_max_pressure_mpa"], lt["pair_max_pressure_mpa"], hz)
                          if (a or 0) > 0 or (b or 0) > 0)
        lines.append(
            f"| {r['design']} {r['flank']} (pos. {r['position']}, {r.get('ltca_tooth_model', 'plate')}) | {r['torque_nm']:g} | {r['refinement']}"
            f"{'' if r.get('coarsen', 1.0) == 1.0 else ' (x' + format(r['coarsen'], 'g') + ')'} | {_strips(r)}"
            f" | {r['elements']} / {r['dof']} | {r['calculix_wall_s']:.0f} / {r['calculix_cpu_s']:.0f}"
            f" | {pairs('pair_normal_load_n', '.0f')} | {peaks}"
            f" | {pairs('contact_area_mm2', '.2f')} | {fmt(c['loaded_transmission_error_urad'], '.1f')} / "
            f"{fmt(lt['loaded_transmission_error_urad'], '.1f')}, {r['unloaded_transmission_error_urad']:.1f}"
            f" | {fmt(c['root_stress_max_mpa']['pinion'], '.1f')} / {fmt(c['root_stress_max_mpa']['gear'], '.1f')};"
            f" {fmt(lt['root_stress_max_mpa']['pinion'], '.1f')} / {fmt(lt['root_stress_max_mpa']['gear'], '.1f')}"
            f" | {r['total_s']:.0f} ({r['mesh_s']:.0f}, {r['calculix_wall_s']:.0f}) |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", default="case1:right,case2:right")
    ap.add_argument("--torques", default="100,400")
    ap.add_argument("--refinements", default="1,2")
    ap.add_argument("--coarsen", type=float, default=1.0)
    ap.add_argument("--out", default="fe_check_runs.jsonl")
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--keep", default=None, help="keep each run's deck and results under this folder (for fe_check_profile.py)")
    ap.add_argument("--tooth-model", default=None, help="the LTCA's tooth model (fe, plate; default: its default)")
    ap.add_argument("--no-local-refinement", action="store_true", help="the face-wide sizes only (runs before issue 33's strips)")
    ap.add_argument("--contact-size-um", type=float, default=None, help="the strips' element size (default b / 3)")
    ap.add_argument("--max-strip-elements", type=int, default=MAX_STRIP_ELEMENTS)
    a = ap.parse_args()
    if a.keep is not None:
        Path(a.keep).mkdir(parents=True, exist_ok=True)  # fe_check creates only each run's own folder in it
    path = Path(a.out)
    done = [json.loads(s) for s in path.read_text().splitlines()] if path.exists() else []
    if not a.table_only:
        for item in a.designs.split(","):
            design, flank = item.split(":")
            for t in map(float, a.torques.split(",")):
                for n in map(int, a.refinements.split(",")):
                    local = not a.no_local_refinement
                    key = (design, flank, t, n, a.coarsen, local, a.max_strip_elements if local else None,
                           a.contact_size_um)
                    if any(_key(r) == key for r in done):
                        continue
                    r = run(design, flank, t, n, a)
                    done.append(r)
                    with path.open("a") as fh:
                        fh.write(json.dumps(r, allow_nan=False) + "\n")
                    print(table([r]), flush=True)
    print(table(done))
    print(hertz_table(done))


if __name__ == "__main__":
    main()
