"""A tooth-surface model of one's own, in an installed package: `beveloid derive --model`, then every
analysis by name, on both backends, with nothing written into the package.

The package is installed non-editable (`pip install --no-deps --no-build-isolation` of a copy of
the checkout) into a fresh virtual environment; its dependencies come from the test environment's
site-packages through a .pth file (no download, no second numba).  Its site-packages is then
made read-only, and its files are compared before and after.  tests/data/shifted_flank_model.py
(the involute flank moved along the member's own axis by ``axial_shift_mm``), copied outside the
checkout, is derived into the default user model folder (XDG_DATA_HOME points into the test's
folder).  The gear then uses it from its TOML section, and the TCA and the loaded TCA must give
exactly the surface contact and the loaded TE of the involute pair with the gear moved by dz =
axial_shift_mm (Eq 34's dz_q moves the gear along its own axis, which commutes with phi'_2; edge
contacts differ: the model moves the flank and not the blank), and the compiled backend the
numpy backend's numbers; export writes the gear's solid (with a 0.2 um shift).

Cost: the compiled backend compiles its point Newton (the step every contact path and normal gap
takes) over the composed glue (~11 s of CPU, its cache in the test's folder; the whole paths and gaps
would be ~55 s: they are the same code for every model, compiled and checked by the rest of the
suite); deriving the model ~5 s, the install ~5 s.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = r"""
import gc, json, sys
gc.set_threshold(50_000, 50, 100)  # as the test processes (tests/conftest.py): its numba compilation ~20 % faster
import numpy as np
from beveloid import ltca, tca
from beveloid.generated import surface_models
from beveloid.pair import Pair
from beveloid.solver import Solver, backends
from beveloid.solver.records import settings
from beveloid.generated.tca_kernels import UNKNOWNS
GEAR_ANGLE = UNKNOWNS.index("gear_angle_rad")
plug = Pair.from_spec(sys.argv[1]).geometry
base = Pair.from_spec(sys.argv[2]).geometry
shift = dict(plug.gear.surface_options)["axial_shift_mm"]
out = {"models": list(surface_models.MODELS), "gear_model": plug.gear.tooth_surface,
       "pinion_model": plug.pinion.tooth_surface, "shift": shift, "import": tca.__file__}
numpy = Solver("numpy")
b = tca.analyze(base, tca.Options(flanks=("right",), positions=40, approach_mm=None, errors=(0.0, 0.0, shift, 0.0, 0.0)),
                solver=numpy).flanks["right"]
lb = ltca.analyze(base, ltca.LoadCase(100.0, errors=(0.0, 0.0, shift, 0.0, 0.0)),
                  ltca.Options(flank="right", positions=3, pairs=3, tooth_model="plate"), solver=numpy)
elastic = lambda r: (r.loaded_te - r.unloaded_te) * 1e6  # noqa: E731
a = tca.analyze(plug, tca.Options(flanks=("right",), positions=40, approach_mm=None), solver=numpy).flanks["right"]
la = ltca.analyze(plug, ltca.LoadCase(100.0), ltca.Options(flank="right", positions=3, pairs=3, tooth_model="plate"),
                  solver=numpy)
# surface contacts only: the shifted model moves the flank, not its blank, so edge contacts differ
both = (np.array(a.status) == "ok") & (np.array(b.status) == "ok")
out["numpy"] = {"compared": int(both.sum()),
                "max_diff_rad": float(np.abs(a.gear_angle[both] - b.gear_angle[both]).max()),
                "ltca_converged": bool(la.converged.all() and lb.converged.all()),
                "ltca_te_diff_urad": float(np.abs(elastic(la) - elastic(lb)).max()),
                "ltca_te_urad": float(np.abs(elastic(la)).max()),
                "ltca_load_diff": float(np.abs(la.pair_load_n - lb.pair_load_n).max() / np.abs(lb.pair_load_n).max())}
# the default loaded analysis, the FE tooth (coarsened for the suite), on the model: the tooth bends as its
# body, the unmodified rack's, loaded at the shifted flank's points (issues 46 and 48); before, a flank
# that does not meet the rack's root fillet was refused ("... um apart at the form limit")
fe = ltca.analyze(Pair.from_spec(sys.argv[1]), ltca.LoadCase(200.0),
                  ltca.Options(positions=3, grid=(5, 5), tooth_model="fe", fe_coarsen=8.0), solver=numpy)
out["fe"] = {"tooth_model": fe.tooth_model, "root_stress_max_mpa": fe.root_stress_max_mpa()}
# the compiled core composed with the model: its point Newton (the step every path and gap calls) from the
# aligned reference contact, at every surface contact of the numpy paths, against the numpy backend's
problem = plug.problem("right")
ref = tca.reference_contact(plug, "right")
opts = settings(scale_mm=plug.gear.working_pitch_radius_mm, tol_mm=tca.newton_tolerance(plug), max_iter=50)
rows = []
for i in np.flatnonzero(np.array(a.status) == "ok"):
    sol = {k: backends.namespace(k).solve_point(problem, ref.x.copy(), float(a.pinion_angle[i]), np.zeros(5), opts)
           for k in ("numpy", "compiled")}
    rows.append((bool(sol["numpy"][1]) and bool(sol["compiled"][1]),
                 float(np.abs(sol["numpy"][0] - sol["compiled"][0]).max()),
                 float(abs(sol["compiled"][0][GEAR_ANGLE] - a.gear_angle[i]))))
out["compiled"] = {"points": len(rows), "converged": all(r[0] for r in rows),
                   "max_diff_backends": max(r[1] for r in rows), "max_diff_paths_gear_angle": max(r[2] for r in rows)}
from beveloid import generated  # the scalar modules the compiled backend compiles with the core
out["compiled_kernels"] = [m for m in generated.SCALAR_MODULES if "shifted" in m]
print(json.dumps(out))
"""


def _run(args, cwd, env, timeout=600):
    return subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def _snapshot(folder):
    """{path: bytes} of every file below folder."""
    return {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def _venv(tmp: Path) -> tuple[Path, Path]:
    """A fresh virtual environment with beveloid installed non-editable; (its python, its site-packages)."""
    src = tmp / "src"
    ignore = shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc", "*.egg-info", "build")
    for d in ("beveloid", "derivations", "generated"):
        shutil.copytree(ROOT / d, src / d, ignore=ignore)
    for f in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / f, src / f)
    venv = tmp / "venv"
    proc = _run([sys.executable, "-m", "venv", "--without-pip", venv], tmp, dict(os.environ))
    assert proc.returncode == 0, proc.stderr
    python = venv / "bin" / "python"
    site = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], tmp,
                     dict(os.environ)).stdout.strip())
    # the test environment's packages (numpy, numba, sympy, ...) after the venv's own
    paths = dict.fromkeys([sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])
    (site / "zz_test_environment.pth").write_text("".join(f"{p}\n" for p in paths))
    proc = _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-build-isolation",
                 "--no-index", "--quiet", src], tmp, dict(os.environ, PIP_DISABLE_PIP_VERSION_CHECK="1"))
    assert proc.returncode == 0, proc.stderr
    return python, site


@pytest.mark.slow
@pytest.mark.long_running
def test_a_model_of_ones_own_in_an_installed_package(tmp_path):
    python, site = _venv(tmp_path)
    for p in [site, *site.rglob("*")]:
        p.chmod(p.stat().st_mode & ~0o222)  # read-only site-packages
    before = _snapshot(site)
    lab = tmp_path / "lab"  # outside the checkout, as a user's own folder
    lab.mkdir()
    shutil.copy(ROOT / "tests" / "data" / "shifted_flank_model.py", lab / "shifted_flank_model.py")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("BEVELOID_", "NUMBA_", "PYTHON", "XDG_"))}
    env.update(XDG_DATA_HOME=str(tmp_path / "data"), BEVELOID_CACHE_DIR=str(tmp_path / "cache"),
               PYTHONDONTWRITEBYTECODE="1")
    # derive, into the default user model folder
    proc = _run([python, "-m", "beveloid.cli", "derive", "--model", "shifted_flank_model.py", "--name", "shifted"],
                lab, env)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    folder = tmp_path / "data" / "beveloid" / "models" / "shifted"
    assert f"wrote model \"shifted\" to {folder}" in proc.stdout
    for check in ("unit normal", "first derivatives", "second derivatives", "scalar twins", "meshing, right flank"):
        assert re.search(rf"^  ok +{check}:", proc.stdout, re.M), (check, proc.stdout)
    assert sorted(p.name for p in folder.iterdir()) == ["layout.py", "model.json", "surface_shifted.py",
                                                          "surface_shifted_scalar.py"]
    # listed with its key, unit and range; in the key schema when selected
    proc = _run([python, "-m", "beveloid.cli", "models", "--json"], lab, env)
    listed = {m["name"]: m for m in json.loads(proc.stdout)["models"]}
    assert listed["shifted"]["origin"] == "user folder" and listed["shifted"]["keys"] == [dict(
        key="axial_shift_mm", unit="mm", default=0.0, lowest=-5.0, highest=5.0,
        description="shift of the whole flank along the member axis")]
    line = "axial_shift_mm: optional (default 0), a number from -5 to 5 (mm)"
    assert line in _run([python, "-m", "beveloid.cli", "example", "--schema", "--model", "shifted"], lab, env).stdout
    assert line not in _run([python, "-m", "beveloid.cli", "example", "--schema"], lab, env).stdout
    # the pair: case 1, the gear on the new model with its own TOML key
    text = (ROOT / "examples" / "case1.toml").read_text()
    (lab / "base.toml").write_text(text)
    plug = re.sub(r"^\[gear\][^\n]*\n", lambda m: m.group(0) + 'tooth_surface = "shifted"\naxial_shift_mm = 0.2\n', text,
                  count=1, flags=re.M)
    assert plug != text
    (lab / "plug.toml").write_text(plug)
    proc = _run([python, "-c", SCRIPT, "plug.toml", "base.toml"], lab, env)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert Path(out["import"]).is_relative_to(site)  # the installed package ran
    from beveloid.generated import surface_models

    assert out["models"] == [*surface_models.MODELS, "shifted"]
    assert (out["pinion_model"], out["gear_model"], out["shift"]) == ("involute", "shifted", 0.2)
    assert out["compiled_kernels"] == ["surface_shifted_scalar"]  # compiled with the core
    run = out["numpy"]
    assert run["compared"] >= 10 and run["max_diff_rad"] < 1e-9, run
    # the loaded TCA on the new model: the loaded rotation and pair loads of the involute pair with the
    # gear moved (the grid extent is sized by iteration on floats that differ at round-off: 0.1 % on the loads)
    assert run["ltca_converged"] and run["ltca_te_urad"] > 1.0, run
    assert run["ltca_te_diff_urad"] < 1e-2 and run["ltca_load_diff"] < 1e-3, run
    # the FE tooth on the model (SCRIPT): it runs, and both members' roots carry stress
    assert out["fe"]["tooth_model"] == "fe" and all(v > 0 for v in out["fe"]["root_stress_max_mpa"].values()), out
    # the compiled core on the new model: the numpy backend's Newton to round-off, and the paths' contacts
    run = out["compiled"]
    assert run["points"] >= 10 and run["converged"], run
    assert run["max_diff_backends"] < 1e-9 and run["max_diff_paths_gear_angle"] < 1e-9, run
    # export: the gear's solid (STL: its vertices lie on the generated surfaces), and the involute gear's.
    # A 0.2 um shift: the flank then meets the rack's root fillet within export's join tolerance (a larger
    # step is blended into the fillet, tooth/sampling.py BLEND_FRACTION: docs/models.md, Limits)
    (lab / "small.toml").write_text(plug.replace("axial_shift_mm = 0.2", "axial_shift_mm = 0.0002"))
    for name in ("small", "base"):
        proc = _run([python, "-m", "beveloid.cli", "export", f"{name}.toml", "--format", "stl", "--member", "gear",
                     "--out", name], lab, env)
        assert proc.returncode == 0, proc.stderr
    plug_stl, base_stl = (lab / "small" / "small_gear.stl").read_bytes(), (lab / "base" / "base_gear.stl").read_bytes()
    assert len(plug_stl) > 10000 and plug_stl != base_stl
    # its key is validated like a built-in key
    (lab / "far.toml").write_text(plug.replace("axial_shift_mm = 0.2", "axial_shift_mm = 9"))
    proc = _run([python, "-m", "beveloid.cli", "tca", "far.toml"], lab, env)
    assert proc.returncode == 2 and proc.stderr.strip().splitlines() == [
        "beveloid: error: far.toml: gear.axial_shift_mm = 9: must be a number from -5 to 5 (mm)"], proc.stderr
    # a stale model says so in one line: the derivation module changed since
    with open(lab / "shifted_flank_model.py", "a") as fh:
        fh.write("# edited\n")
    proc = _run([python, "-m", "beveloid.cli", "tca", "plug.toml"], lab, env)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert "is stale" in proc.stderr and "beveloid derive --model" in proc.stderr and "--name shifted" in proc.stderr
    # nothing was written into the installed package
    assert _snapshot(site) == before
