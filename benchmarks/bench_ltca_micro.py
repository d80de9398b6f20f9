"""LTCA cost per position: case 1 unmodified vs W4's pair (crowned + tip + end relief), in one run (issue 20).

    python benchmarks/bench_ltca_micro.py

Not a test: 3 repeats of 8 positions at 400 N m each, median seconds per position, and the ratio.
"""
import time, warnings, sys
import numpy as np
warnings.simplefilter("ignore")
sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
from beveloid.pair import Pair
from beveloid import ltca
from bench_tca import micro_case1
g0 = Pair.example("case1").geometry
g1 = micro_case1()
for g in (g0, g1):
    ltca.analyze(g, ltca.LoadCase(400.0), ltca.Options(flank="right", positions=3, tooth_model="plate"))  # warm-up
res = {"unmodified": [], "modified": []}
for rep in range(3):
    for name, g in (("unmodified", g0), ("modified", g1)):
        t = time.perf_counter()
        r = ltca.analyze(g, ltca.LoadCase(400.0), ltca.Options(flank="right", positions=8, tooth_model="plate"))
        res[name].append((time.perf_counter() - t) / 8)
for k, v in res.items():
    print(k, "s/position median %.3f" % np.median(v), [round(x, 3) for x in v])
print("ratio modified/unmodified %.2f" % (np.median(res["modified"]) / np.median(res["unmodified"])))
