"""docs/models.md's tutorial, end to end: the thinned-flank model of its code block derived into a
temporary model folder, then the two-flank backlash of case 1 with the gear thinned by 20 um
against the involute gear (numpy backend), with the times.

    python benchmarks/user_model_tutorial.py

The numbers the tutorial quotes come from this script.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

BACKLASH = r"""
import time, tomllib
from beveloid import tca
from beveloid.pair import Pair
from beveloid.solver import Solver
from beveloid.spec import example_text
t = time.perf_counter()
spec = tomllib.loads(example_text("case1"))
base = Pair.from_spec(spec).geometry
spec["gear"].update(tooth_surface="thinned", thinning_um=20.0)
thin = Pair.from_spec(spec).geometry
for name, g in (("involute gear", base), ("gear thinned by 20 um", thin)):
    r = tca.analyze(g, tca.Options(positions=20, approach_mm=None), solver=Solver("numpy"))
    print(f"{name}: backlash_um {r.backlash_um:.4g} ({r.backlash.status})")
print(f"both TCAs: {time.perf_counter() - t:.1f} s")
"""


def main() -> int:
    code = re.search(r"```python\n(.*?)```", (ROOT / "docs" / "models.md").read_text(), re.S).group(1)
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "thinned_flank.py").write_text(code)
        env = dict(os.environ, BEVELOID_MODELS_DIR=str(Path(tmp) / "models"))
        t = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "beveloid.cli", "derive", "--model", "thinned_flank.py",
                               "--name", "thinned"], cwd=tmp, env=env, capture_output=True, text=True)
        print(proc.stdout, end="")
        print(f"derive --model: exit {proc.returncode}, {time.perf_counter() - t:.1f} s wall")
        if proc.returncode:
            print(proc.stderr, end="")
            return 1
        proc = subprocess.run([sys.executable, "-c", BACKLASH], cwd=tmp, env=env, capture_output=True, text=True)
        print(proc.stdout, end="")
        return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
