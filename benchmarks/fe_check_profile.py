"""The FE contact pressure along one tooth pair's contact, from a kept fe-check folder.

    python benchmarks/fe_check_profile.py DIR [--set GEAR_FLANK_RIGHT_0] [--bins 40]

DIR holds ``fe_check.inp`` and ``fe_check.frd`` (``beveloid fe-check ... --out DIR``).  On the named
slave node set (the gear flank of the middle tooth pair by default): the nodes with CPRESS > 0,
their principal direction (the contact's long axis), the loaded length, and per bin along it the
largest pressure p(y).  The loaded semi-axis a = sqrt(5 <y^2>) with weights p(y)^2 (the line load
of a Hertz section is proportional to the square of its peak at a given curvature; the LTCA's
a is sqrt(5 <y^2>) of its pressure, the same for a Hertz ellipse), and the fullness mean p(y) /
max p(y) over the loaded length (pi / 4 = 0.785 for a Hertz ellipse, 1 for a uniform line load).
"""
import argparse
import json
import math
from pathlib import Path

import numpy as np

from beveloid.fecheck.results import contact_pressure, read_frd


def read_inp(path, set_name):
    """(node coordinates {id: xyz}, the node ids of ``set_name``) from a CalculiX deck."""
    coords, members, mode = {}, [], None
    with open(path) as fh:
        for line in fh:
            if line.startswith("*"):
                head = line.upper()
                mode = "node" if head.startswith("*NODE,") or head.startswith("*NODE\n") else None
                if head.startswith("*NSET") and f"NSET={set_name.upper()}" in head.replace(" ", ""):
                    mode = "set"
                continue
            if mode == "node":
                parts = line.split(",")
                coords[int(parts[0])] = np.array([float(v) for v in parts[1:4]])
            elif mode == "set":
                members += [int(v) for v in line.split(",") if v.strip()]
    return coords, np.array(members, dtype=int)


def profile(folder, set_name="GEAR_FLANK_RIGHT_0", bins=40) -> dict:
    folder = Path(folder)
    coords, ids = read_inp(folder / "fe_check.inp", set_name)
    block = contact_pressure(read_frd(folder / "fe_check.frd"))
    p = dict(zip(block.node_ids.tolist(), block.values[:, 0].tolist()))
    loaded = np.array([i for i in ids if p.get(int(i), 0.0) > 0.0])
    xyz = np.array([coords[int(i)] for i in loaded])
    pr = np.array([p[int(i)] for i in loaded])
    c = xyz.mean(axis=0)
    _, _, vt = np.linalg.svd(xyz - c, full_matrices=False)
    y = (xyz - c) @ vt[0]
    x = (xyz - c) @ vt[1]
    edges = np.linspace(y.min(), y.max(), bins + 1)
    which = np.clip(np.digitize(y, edges) - 1, 0, bins - 1)
    mids, peaks, widths = [], [], []
    for k in range(bins):
        on = which == k
        if on.any():
            mids.append(0.5 * (edges[k] + edges[k + 1]))
            peaks.append(float(pr[on].max()))
            widths.append(float(x[on].max() - x[on].min()))
    mids, peaks = np.array(mids), np.array(peaks)
    w = peaks ** 2 / np.sum(peaks ** 2)
    ybar = float(w @ mids)
    return {"set": set_name, "loaded_nodes": int(loaded.size), "peak_mpa": float(pr.max()),
            "loaded_length_mm": float(y.max() - y.min()),
            "semi_axis_along_mm": math.sqrt(5.0 * float(w @ (mids - ybar) ** 2)),
            "largest_loaded_width_mm": float(max(widths)),
            "fullness": float(peaks.mean() / peaks.max()),
            "profile_mpa": [round(v, 1) for v in peaks.tolist()]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("--set", default="GEAR_FLANK_RIGHT_0")
    ap.add_argument("--bins", type=int, default=40)
    a = ap.parse_args()
    print(json.dumps(profile(a.folder, a.set, a.bins), indent=1))


if __name__ == "__main__":
    main()
