"""The TCA on micro-geometry flanks: a contact path across a linear tip relief's kink, the two
backends on a modified pair, and the CLI commands on a modified TOML (nothing in the runtime
knows about the modification)."""
from __future__ import annotations

import dataclasses
import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from beveloid import tca
from beveloid.solver import Solver
from beveloid.solver.core import on_patch

ROOT = Path(__file__).resolve().parents[2]
OFF = dict(profile_crowning_um=0.0, lead_crowning_um=0.0, tip_relief_um=0.0, tip_relief_height_mm=1.0,
           tip_relief_shape="parabolic", end_relief_um=0.0, end_relief_length_mm=1.0, end_relief_shape="parabolic",
           lead_slope_um=0.0)


def relieved(geom, **opts):
    """Both members on the micro-geometry model with the same options."""
    o = tuple(sorted(dict(OFF, **opts).items()))
    return dataclasses.replace(
        geom, pinion=dataclasses.replace(geom.pinion, tooth_surface="micro_geometry", surface_options=o),
        gear=dataclasses.replace(geom.gear, tooth_surface="micro_geometry", surface_options=o))


def tip_ramp(member, point):
    """The tip ramp's argument rho - (rho_a - h_a) (mm) at contact points (..., 3)."""
    h = dict(member.surface_options)["tip_relief_height_mm"]
    return np.hypot(point[..., 0], point[..., 1]) - (member.tip_radius(point[..., 2]) - h)


def test_contact_across_a_linear_tip_relief_kink(geom1):
    """Newton on a C0 surface: the kernels give the derivatives of the side the iterate is on.
    Contacts below the relief on both members are the involute pair's to 1e-12 rad; contacts
    inside the relieved band converge too; a position whose contact would sit on the kink line
    itself has no smooth solution (the normal jumps there by ~C_a/h_a) and is reported with its
    status and no number."""
    mod = relieved(geom1, tip_relief_um=20.0, tip_relief_height_mm=2.0, tip_relief_shape="linear")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # diverging iterates at the kink overflow in numpy
        a = tca.mesh_flank(mod, "left", positions=40, solver=Solver("numpy"))
    b = tca.mesh_flank(geom1, "left", positions=40, solver=Solver("numpy"))
    st_a, st_b = np.asarray(a.status), np.asarray(b.status)
    ok = st_a == "ok"
    t1 = tip_ramp(mod.pinion, a.pinion_contact)
    t2 = tip_ramp(mod.gear, a.gear_contact)
    below = ok & (st_b == "ok") & (t1 < -1e-3) & (t2 < -1e-3)
    inside = ok & ((t1 > 1e-3) | (t2 > 1e-3))
    assert below.sum() >= 10 and inside.sum() >= 5  # the path crosses the kink
    assert np.abs(a.gear_angle[below] - b.gear_angle[below]).max() <= 1e-12
    # inside the band the relief moves the contact: the gear lags by the removal over the base radius
    assert np.abs(a.gear_angle[inside] - b.gear_angle[inside]).max() > 1e-6
    failed = st_a == "failed"
    assert np.isnan(a.gear_angle[failed]).all()


@pytest.mark.long_running
def test_backends_agree_on_a_modified_pair(geom1):
    """numpy and compiled backends on case 1 with crowning, a parabolic tip relief, an end relief
    and a lead slope, under an assembly error: contact points and gear angles where both are on
    the patch away from the boundary rule's threshold."""
    mod = relieved(geom1, profile_crowning_um=20.0, lead_crowning_um=20.0, tip_relief_um=20.0,
                   tip_relief_height_mm=2.0, end_relief_um=15.0, end_relief_length_mm=8.0, lead_slope_um=-6.0)
    errors = (0.0, 0.0, 0.5, 0.0, 0.0)
    res = {}
    for backend in ("numpy", "compiled"):
        solver = Solver(backend)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res[backend] = tca.mesh_flank(mod, "right", errors, positions=30, solver=solver)
    a, b = res["numpy"], res["compiled"]
    margin_a, margin_b = np.asarray(a.boundary_margin_mm), np.asarray(b.boundary_margin_mm)
    tol = Solver("numpy").options.patch_tol_mm
    clear = (np.abs(margin_a + tol) > 1e-6) & (np.abs(margin_b + tol) > 1e-6)  # away from on_patch's threshold
    sa, sb = np.asarray(a.status), np.asarray(b.status)
    assert (sa[clear] == sb[clear]).all()
    both = clear & (sa == "ok") & (sb == "ok")
    assert both.sum() >= 10
    assert np.abs(a.gear_angle[both] - b.gear_angle[both]).max() <= 1e-12
    assert np.abs(a.pinion_contact[both] - b.pinion_contact[both]).max() <= 1e-9
    assert on_patch(-tol + 1e-6, tol) and not on_patch(-tol - 1e-6, tol)  # the rule the comparison stays away from


def _modified_toml(tmp_path):
    text = (ROOT / "examples" / "case1.toml").read_text()
    add = ('tip_relief_um = 20.0\ntip_relief_height_mm = 2.0\ntip_relief_shape = "linear"\nend_relief_um = 15.0\n'
           'end_relief_length_mm = 8.0\nlead_crowning_um = 10.0\n')
    for sec in ("pinion", "gear"):
        text = re.sub(rf"^\[{sec}\][^\n]*\n", lambda m: m.group(0) + add, text, count=1, flags=re.M)
    path = tmp_path / "modified.toml"
    path.write_text(text)
    return path


@pytest.mark.slow
@pytest.mark.long_running
def test_cli_commands_run_on_a_modified_pair(tmp_path):
    path = _modified_toml(tmp_path)
    run = lambda *a: subprocess.run([sys.executable, "-m", "beveloid.cli", *a], capture_output=True, text=True,  # noqa: E731
                                    timeout=600, cwd=tmp_path)
    p = run("tca", str(path), "--positions", "20", "--flank", "right", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert "right" in json.dumps(out)
    p = run("sweep", str(path), "--samples", "4", "--positions", "10")
    assert p.returncode == 0, p.stderr
    p = run("ltca", str(path), "--torque-nm", "200", "--positions", "3", "--tooth-model", "plate")
    assert p.returncode == 0, p.stderr
    bad = path.read_text().replace('tip_relief_shape = "linear"', 'tip_relief_shape = "cubic"', 1)
    path.write_text(bad)
    p = run("tca", str(path))
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "pinion.tip_relief_shape" in p.stderr and '"linear"' in p.stderr and "cubic" in p.stderr
