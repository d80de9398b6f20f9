"""docs/validation.md 1: Eqs 1-7, 12-27 and 30-35 are consistent: the pitch-point guess of the aligned
pair solves Eq 38 before any Newton step.

    python benchmarks/pitch_point_guess.py

The guess: each flank's point at radius r_w in the pitch point's transverse section, turned to the
pitch-point angle (`tca.reference.point_at_radius`, as `reference_contact` starts its Newton).  Printed
per case and flank: the largest position residual of Eq 38 (mm), the largest normal residual, and the
pinion point's radius less r_w1 (mm).  Not a test.
"""
import math

import numpy as np

from beveloid.pair import Pair
from beveloid.tca.contact import evaluate
from beveloid.tca.reference import point_at_radius


def guess(geom, flank):
    """(Eq 38 unknowns at the guess, the pinion angle)."""
    sides = [point_at_radius(geom, m, flank, geom.member(m).working_pitch_radius_mm,
                             geom.member(m).reference_section_offset_mm) for m in ("pinion", "gear")]
    (l1, u1, psi1), (l2, u2, psi2) = sides
    return np.array([l1, u1, l2, u2, geom.gear.pitch_point_angle - psi2]), geom.pinion.pitch_point_angle - psi1


for case in ("case1", "case2"):
    geom = Pair.example(case).geometry
    for flank in ("left", "right"):
        x, phi1 = guess(geom, flank)
        s = evaluate(geom, flank, x, phi1, np.zeros(5))
        p1 = s.pinion_point
        print(f"{case} {flank}: position residual {np.abs(s.residual[:3]).max():.1e} mm, normal residual "
              f"{np.abs(s.residual[3:]).max():.1e}, pinion point radius - r_w1 "
              f"{math.hypot(p1[0], p1[1]) - geom.pinion.working_pitch_radius_mm:.1e} mm")
