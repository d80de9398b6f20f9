"""docs/validation.md 6: the backlash of the designed pairs, of case 1 under errors, and of case 1 crowned.

    python benchmarks/backlash_numbers.py      # about a minute with the solver compiled

`tca.backlash` (the smallest two-flank play over one pinion pitch, at r_w2, um).  Crowned: case 1 with
profile and lead crowning of 10 um on both members (`beveloid tca` prints the same three numbers).
Not a test.
"""
import math
import tomllib

from beveloid import tca
from beveloid.pair import Pair
from beveloid.spec.parse import example_text

DEG = math.pi / 180


def errors(dx=0.0, dy=0.0, dz=0.0, vertical_deg=0.0, horizontal_deg=0.0):
    return (dx, dy, dz, vertical_deg * DEG, horizontal_deg * DEG)


def crowned_case1(c_um=10.0):
    spec = tomllib.loads(example_text("case1"))
    for member in ("pinion", "gear"):
        spec[member].update(profile_crowning_um=c_um, lead_crowning_um=c_um)
    return Pair.from_spec(spec)


def show(label, b):
    if b.um is None:
        print(f"{label}: not measured, status {b.status}")
    else:
        print(f"{label}: {b.um:.3g} um (at the reference {b.at_reference_um:.3g}, largest {b.max_um:.3g})")


def main():
    for case in ("case1", "case2"):
        show(f"{case} aligned", tca.backlash(Pair.example(case)))
    case1 = Pair.example("case1")
    for label, e in (("dx = +0.5 mm", errors(dx=0.5)), ("dy = +0.5 mm", errors(dy=0.5)), ("dz = +0.5 mm", errors(dz=0.5)),
                     ("dq = -0.5 mm", errors(-0.5, -0.5, -0.5)), ("horizontal = +0.03 deg", errors(horizontal_deg=0.03)),
                     ("horizontal = -0.03 deg", errors(horizontal_deg=-0.03)), ("vertical = +0.2 deg", errors(vertical_deg=0.2)),
                     ("vertical = -0.2 deg", errors(vertical_deg=-0.2))):
        show(f"case1 {label}", tca.backlash(case1, e))
    crowned = crowned_case1()
    show("case1 crowned 10 um, aligned", tca.backlash(crowned))
    show("case1 crowned 10 um, horizontal = +0.03 deg", tca.backlash(crowned, errors(horizontal_deg=0.03)))


if __name__ == "__main__":
    main()
