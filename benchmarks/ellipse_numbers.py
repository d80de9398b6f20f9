"""Numbers of docs/validation.md, section "Contact ellipses and bearing pattern": run with
`python benchmarks/ellipse_numbers.py` from the checkout (numpy backend, 60 positions)."""
import math
from pathlib import Path

import numpy as np

from beveloid import contact_ellipse, tca
from beveloid.pair import Pair
from beveloid.solver import Solver

ROOT = Path(__file__).resolve().parents[1]
errs = {"aligned": (0,0,0,0,0), "dx=0.1mm": (0.1,0,0,0,0), "dy=0.1mm": (0,0.1,0,0,0), "dz=0.1mm": (0,0,0.1,0,0),
        "vertical=0.05deg": (0,0,0,math.radians(0.05),0), "horizontal=0.05deg": (0,0,0,0,math.radians(0.05))}
for case in ("case1","case2"):
    g = Pair.from_spec(ROOT / "examples" / f"{case}.toml").geometry
    for lab, e in errs.items():
        r = tca.analyze(g, tca.Options(positions=60, approach_mm=contact_ellipse.DEFAULT_APPROACH_MM, errors=e),
                        solver=Solver("numpy"))
        for fl in (("left","right") if lab=="aligned" else ("right",)):
            fr = r.flanks[fl]; ce = fr.contact_ellipse
            act = fr.active & (np.array(ce.status)=="ellipse")
            ref = tca.reference_contact(g, fl)
            if not act.any(): print(case, lab, fl, "no active ellipse"); continue
            a = ce.semi_axes_mm[act]; t = ce.truncated_length_mm[act]
            area = np.pi*a[:,0]*a[:,1]
            tarea = np.pi/2*t/2*a[:,1]*2  # truncated: chord x minor
            P1 = fr.pinion_contact[act]
            print(f"{case} {lab:18s} {fl:5s} a {a[:,0].mean():7.3f} b {a[:,1].mean():.4f} 2a {2*a[:,0].mean():7.3f} chord {t.min():6.2f}-{t.max():6.2f} mean {t.mean():6.2f} axis {np.nanmean(ce.major_axis_deg[act]):+6.2f} deg  area {area.mean():7.2f} pinion z {P1[:,2].min():+6.2f}..{P1[:,2].max():+6.2f}")
