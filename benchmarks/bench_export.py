"""Export of a pointed tooth: seconds, triangles, volume, STEP against STL.

    python benchmarks/bench_export.py [--against CHECKOUT]

The pinion of tests/export/test_export_pointed.py (13 teeth, module 2, cone angle 8 deg, profile shift
0.45, face 21 mm: a tip land from the toe to z = 8.35 mm, pointed from there to the heel), exported as
STEP and as STL in a fresh process per format and checkout (``--against``: another checkout first, e.g.
``git archive REV | tar -x -C /tmp/before``), each timed around ``beveloid.export.export`` (wall and CPU
seconds; OpenCASCADE's import not included).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

_RUN = r'''
import json, os, sys, tempfile, time, tomllib
sys.path.insert(0, os.getcwd())
from beveloid.errors import UserError
from beveloid.export import ExportOptions, export, require_cad
from beveloid.pair import Pair
from beveloid.spec import example_text
d = tomllib.loads(example_text("case1"))
d["pair"].update(offset_mm=146.0 / 3, normal_module_mm=2.0)
d["pinion"].update(teeth=13, cone_angle_deg=8.0, profile_shift=0.45, face_width_mm=21.0)
d["gear"].update(face_width_mm=10.0)
pair = Pair.from_spec(d)
fmt = sys.argv[1]
require_cad(fmt)
import OCP.BRepBuilderAPI, trimesh  # noqa: F401 (imported before the clock starts)
with tempfile.TemporaryDirectory() as out:
    t, c = time.perf_counter(), time.process_time()
    try:
        (f,) = export(pair, ExportOptions(format=fmt, members=("pinion",), out_dir=out, stem="p")).files
        r = {"seconds": time.perf_counter() - t, "cpu_seconds": time.process_time() - c, "volume_mm3": f.volume_mm3,
             "triangles": f.triangles, "max_error_um": f.max_error_um}
    except UserError as exc:
        r = {"refused": str(exc)}
print(json.dumps(r))
'''


def run(where: str, fmt: str) -> dict:
    out = subprocess.run([sys.executable, "-c", _RUN, fmt], cwd=where, check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--against", metavar="CHECKOUT", help="another checkout, run first (before)")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    for label, where in ([("before", a.against)] if a.against else []) + [("this", here)]:
        res = {fmt: run(where, fmt) for fmt in ("step", "stl")}
        for fmt, r in res.items():
            if "refused" in r:
                print(f"{label:6} {fmt}: refused: {r['refused']}")
                continue
            tri = f", {r['triangles']} triangles" if r["triangles"] is not None else ""
            print(f"{label:6} {fmt}: {r['seconds']:.1f} s wall, {r['cpu_seconds']:.1f} s CPU, volume"
                  f" {r['volume_mm3']:.3f} mm3, within {r['max_error_um']:.3f} um{tri}")
        if all("volume_mm3" in r for r in res.values()):
            v = res["step"]["volume_mm3"], res["stl"]["volume_mm3"]
            print(f"{label:6} STL / STEP volume - 1: {v[1] / v[0] - 1:.2e}")
    print(f"load average after: {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
