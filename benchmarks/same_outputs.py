"""Do two checkouts write the same outputs, and how long does each take?  In one run, alternating.

    git worktree add --detach /tmp/before REV
    python benchmarks/same_outputs.py /tmp/before [--rounds 2] [--only tca,sweep]

Runs each command below with each checkout on PYTHONPATH (its own beveloid, in a child process; the
numba cache warmed by one untimed run of each first), alternating old and new for ``--rounds`` rounds,
and prints per command whether the outputs are the same bytes (the JSON with its timing keys left
out; explore's CSV; optimize's front: the candidates' values and objectives in pareto.json order),
which top-level keys differ when they are not, and the least child CPU seconds of each checkout with
their ratio.  The shipped cases: case 1 and case 2 (the TCA), case 1 (the sweep, the loaded TCA with
the plate tooth at two torques, the rating, a 4 x 4 exploration, an optimisation of 8 candidates).
Not a test.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
C1, C2 = str(HERE / "examples" / "case1.toml"), str(HERE / "examples" / "case2.toml")
#: JSON keys that hold times (they differ run to run)
TIMING = ("seconds", "seconds_total", "us_per_point", "us_per_point_total", "solver_startup_s", "calculix_wall_s",
          "calculix_cpu_s", "mesh_s", "executor")

COMMANDS = {
    "tca": ["tca", C1, "--json"],
    "tca_errors": ["tca", C2, "--horizontal", "0.03", "--dx", "0.02", "--json"],
    "sweep": ["sweep", C1, "--samples", "2000", "--positions", "20", "--json"],
    "ltca": ["ltca", C1, "--torque-nm", "100,200", "--tooth-model", "plate", "--json"],
    "rating": ["rating", C1, "--torque-nm", "200", "--tooth-model", "plate", "--json"],
    "explore": ["explore", C1, "--vary", "pinion.cone_angle_deg=1:3:4", "--vary", "pinion.helix_angle_deg=15:25:4",
                "--workers", "1", "--out", "{out}"],
    "optimize": ["optimize", C1, "--vary", "pinion.lead_crowning_um=0:20", "--torque-nm", "200", "--budget", "8",
                 "--population", "4", "--tooth-model", "plate", "--grid", "5x5", "--positions", "3", "--workers", "1",
                 "--out", "{out}"],
}


def _strip(value):
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k not in TIMING}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _output(name: str, stdout: str, out: Path):
    """What is compared: the JSON without its timings, explore's CSV, optimize's front."""
    if name == "explore":
        return (out / "explore.csv").read_text()
    if name == "optimize":
        summary = json.loads((out / "pareto.json").read_text()) if (out / "pareto.json").exists() else {}
        return _strip(summary.get("front", summary))
    return _strip(json.loads(stdout))


def run(tree: str, name: str, scratch: Path):
    """(the output, child CPU seconds) of one command with ``tree``'s beveloid."""
    out = scratch / f"{name}_{abs(hash(tree))}"
    args = [a.replace("{out}", str(out)) for a in COMMANDS[name]]
    if out.exists():
        subprocess.run(["rm", "-rf", str(out)], check=True)
    env = dict(os.environ, PYTHONPATH=tree)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([sys.executable, "-m", "beveloid.cli", *args], cwd=scratch, env=env, capture_output=True,
                          text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode not in (0, 3, 4):  # rating's verdict exits 3/4 (fails, conditional)
        raise SystemExit(f"{tree}: beveloid {' '.join(args)} exited {proc.returncode}:\n{proc.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return _output(name, proc.stdout, out), cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("other", help="the other checkout (its root: beveloid/ inside)")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--only", default=",".join(COMMANDS))
    a = ap.parse_args()
    trees = {"old": str(Path(a.other).resolve()), "new": str(HERE)}
    names = a.only.split(",")
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp)
        for name in names:  # warm numba's caches and the FE data: untimed
            for tree in trees.values():
                run(tree, name, scratch)
        print(f"{'command':<11} {'same':<5} {'old CPU s':>10} {'new CPU s':>10} {'new/old':>8}  differing keys")
        for name in names:
            best, outs = {}, {}
            for r in range(a.rounds):
                for label in (("old", "new") if r % 2 == 0 else ("new", "old")):
                    outs[label], cpu = run(trees[label], name, scratch)
                    best[label] = min(best.get(label, cpu), cpu)
            same = json.dumps(outs["old"], sort_keys=True) == json.dumps(outs["new"], sort_keys=True)
            keys = ""
            if not same and isinstance(outs["old"], dict) and isinstance(outs["new"], dict):
                keys = ", ".join(sorted(k for k in set(outs["old"]) | set(outs["new"])
                                        if outs["old"].get(k) != outs["new"].get(k)))[:200]
            print(f"{name:<11} {str(same):<5} {best['old']:>10.2f} {best['new']:>10.2f} "
                  f"{best['new'] / best['old']:>8.2f}  {keys}", flush=True)


if __name__ == "__main__":
    main()
