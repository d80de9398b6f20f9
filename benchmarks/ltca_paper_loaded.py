"""docs/validation.md 7.5: the loaded study of `beveloid paper` (Figs 24-25) alone, as its table rows.

    python benchmarks/ltca_paper_loaded.py [fe|plate]      # default: the LTCA's default tooth (fe)

Runs :func:`beveloid.studies.loaded.case_task` for case 1 and case 2 (right flank, 8 positions, pinion
torques 5, 200, 400, 600 N m, the default grid), its figures into a temporary folder, and prints per
case and torque: the pattern areas, the surface peak and the loaded TE mean / p-p, as the page's table
shows them (`python docs/readme_numbers.py --record ltca_tables` records them).  Not a test.
"""
import sys
import tempfile

from beveloid.studies import loaded


def rows(model=None) -> list[str]:
    out = []
    with tempfile.TemporaryDirectory() as folder:
        for case in ("case1", "case2"):
            case_rows, _, _, seconds = loaded.case_task(case, folder, model)
            for c, fpd_deg, t1, _t2, pinion, gear, peak, te_mean, te_ptp, _share, converged in case_rows:
                label = f"{c[-1]} (ξ_R = {fpd_deg:.2f}°)" if t1 == loaded.TORQUES_NM[0] else c[-1]
                out.append(f"| {label} | {t1:g} | {100 * pinion:.0f}% | {100 * gear:.0f}% | {peak:.0f} | "
                           f"{te_mean:.2f} / {te_ptp:.2f} |" + ("" if converged == loaded.POSITIONS else
                                                                f" ({converged}/{loaded.POSITIONS} converged)"))
            print(f"({case}: {seconds:.1f} s)", file=sys.stderr)
    return out


if __name__ == "__main__":
    print("\n".join(rows(sys.argv[1] if len(sys.argv) > 1 else None)))
