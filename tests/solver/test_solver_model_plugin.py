"""A new tooth-surface model is a derivation module, a registry entry and `beveloid derive`:
nothing in beveloid/ changes.

In a scratch copy of the checkout, tests/data/shifted_flank_model.py (the involute flank moved
along the member axis by ``axial_shift_mm``) is registered under the name "shifted" and the
kernels are regenerated with the real `beveloid derive` (``--no-docs``: docs/derivations.md
and the 50-digit verification behind it are not what this test is about, and it must stay as it
was).  The gear then uses that model from its TOML section, and the TCA and the loaded TCA (runtime unchanged, numpy backend) must give
exactly the surface contact and the loaded TE of the involute pair with the gear moved by dz =
axial_shift_mm (edge contacts differ: the model moves the flank and not the blank) (Eq 34's dz_q moves
the gear along its own axis, which commutes with the rotation phi'_2).
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = r"""
import json, sys
import numpy as np
from beveloid import tca
from beveloid.pair import Pair
from beveloid.generated import surface_models
plug = Pair.from_spec(sys.argv[1]).geometry
base = Pair.from_spec(sys.argv[2]).geometry
shift = dict(plug.gear.surface_options)["axial_shift_mm"]
a = tca.analyze(plug, flanks=("right",), positions=40, backend="numpy").flanks["right"]
b = tca.analyze(base, (0.0, 0.0, shift, 0.0, 0.0), flanks=("right",), positions=40, backend="numpy").flanks["right"]
# surface contacts only: the shifted model moves the flank, not its blank, so edge contacts differ
both = (np.array(a.status) == "ok") & (np.array(b.status) == "ok")
from beveloid import ltca  # the loaded TCA reaches the surfaces only through geometry.surface/surface_jet
la = ltca.analyze(plug, 100.0, "right", positions=3, pairs=3, backend="numpy")
lb = ltca.analyze(base, 100.0, "right", errors=(0.0, 0.0, shift, 0.0, 0.0), positions=3, pairs=3, backend="numpy")
# the TE references differ (the shifted surface moves the pitch point); the load-induced part does not
elastic = lambda r: (r.loaded_te - r.unloaded_te) * 1e6  # noqa: E731
print(json.dumps({"ltca_converged": bool(la.converged.all() and lb.converged.all()),
                  "ltca_te_diff_urad": float(np.abs(elastic(la) - elastic(lb)).max()),
                  "ltca_te_urad": float(np.abs(elastic(la)).max()),
                  "ltca_load_diff": float(np.abs(la.pair_load_n - lb.pair_load_n).max() / np.abs(lb.pair_load_n).max()),
                  "models": list(surface_models.MODELS), "gear_model": plug.gear.tooth_surface,
                  "pinion_model": plug.pinion.tooth_surface, "shift": shift, "compared": int(both.sum()),
                  "max_diff_rad": float(np.abs(a.gear_angle[both] - b.gear_angle[both]).max()),
                  "import": tca.__file__}))
"""


def _run(args, cwd, env):
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=240)


def _snapshot(folder, pattern):
    """{path: bytes} of the files below folder that match pattern."""
    return {p.relative_to(folder): p.read_bytes() for p in folder.rglob(pattern) if p.is_file()}


@pytest.mark.long_running
def test_a_new_surface_model_needs_no_runtime_edit(tmp_path):
    work = tmp_path / "checkout"
    ignore = shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc")
    for d in ("beveloid", "derivations", "generated", "docs"):
        shutil.copytree(ROOT / d, work / d, ignore=ignore)
    shutil.copy(ROOT / "pyproject.toml", work / "pyproject.toml")
    runtime_before, docs_before = _snapshot(work / "beveloid", "*.py"), _snapshot(work / "docs", "*")
    # 1. the derivation module and 2. its registry entry
    shutil.copy(ROOT / "tests" / "data" / "shifted_flank_model.py", work / "derivations" / "shifted_flank_model.py")
    with open(work / "derivations" / "kernels.py", "a") as fh:
        fh.write("\nfrom . import shifted_flank_model  # noqa: E402\n\nSURFACE_MODELS['shifted'] = shifted_flank_model\n")
    env = dict(os.environ, PYTHONPATH=str(work))
    # 3. beveloid derive
    proc = _run([sys.executable, "-m", "beveloid.cli", "derive", "--no-docs"], work, env)
    assert proc.returncode == 0, proc.stderr
    assert (work / "generated" / "surface_shifted.py").is_file()
    assert _snapshot(work / "beveloid", "*.py") == runtime_before
    assert _snapshot(work / "docs", "*") == docs_before
    # the pair: case 1, the gear on the new model with its own TOML key
    text = (ROOT / "examples" / "case1.toml").read_text()
    (tmp_path / "base.toml").write_text(text)
    plug = re.sub(r"^\[gear\][^\n]*\n", lambda m: m.group(0) + 'tooth_surface = "shifted"\naxial_shift_mm = 0.2\n', text,
                  count=1, flags=re.M)
    assert plug != text
    (tmp_path / "plug.toml").write_text(plug)
    proc = _run([sys.executable, "-c", SCRIPT, str(tmp_path / "plug.toml"), str(tmp_path / "base.toml")], tmp_path,
                env)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert Path(out["import"]).is_relative_to(work)  # the scratch checkout's runtime ran
    from beveloid.generated import surface_models

    assert out["models"] == [*surface_models.MODELS, "shifted"]
    assert (out["pinion_model"], out["gear_model"], out["shift"]) == ("involute", "shifted", 0.2)
    assert out["compared"] >= 10
    assert out["max_diff_rad"] < 1e-9
    # the loaded TCA on the new model: the same loaded rotation and pair loads as the involute pair with
    # the gear moved
    assert out["ltca_converged"] and out["ltca_te_urad"] > 1.0
    # (the grid extent is sized by iteration on floats that differ at round-off: 0.1% on the loads)
    assert out["ltca_te_diff_urad"] < 1e-2 and out["ltca_load_diff"] < 1e-3
