"""The script's quick start and exit (fewer young collections, ``gc.freeze`` after the command:
beveloid/cli/__init__.py) change nothing a user sees, and in-process callers keep their collector
as it was."""
from __future__ import annotations

import gc
import json
import subprocess
import sys
from pathlib import Path

from beveloid import cli

ROOT = Path(__file__).resolve().parents[2]


def test_script_output_is_the_in_process_output(capsys, tmp_path):
    argv = ["tca", str(ROOT / "examples" / "case1.toml"), "--positions", "3", "--json"]
    frozen, threshold = gc.get_freeze_count(), gc.get_threshold()
    assert cli.main(argv) == 0
    assert gc.get_freeze_count() <= frozen  # argv given: nothing frozen in the caller's process (frees may leave it)
    assert gc.get_threshold() == threshold  # nor its collector's thresholds changed
    here = json.loads(capsys.readouterr().out)
    p = subprocess.run([sys.executable, "-m", "beveloid.cli", *argv], capture_output=True, text=True, timeout=600,
                       cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout) == here
    assert p.stderr == ""


def test_the_script_collects_young_objects_less_often(tmp_path):
    code = ("import gc, sys; from beveloid import cli; before = gc.get_threshold(); sys.argv = ['beveloid', 'example', "
            "'case1']; status = cli.main(); print(status, *before, *gc.get_threshold(), file=sys.stderr)")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    status, *thresholds = (int(v) for v in p.stderr.split())
    before, after = thresholds[:3], thresholds[3:]
    assert status == 0 and after[0] == cli.GC_YOUNG_THRESHOLD > before[0]
    assert after[1:] == before[1:]  # the older generations' as they were


def test_script_error_exit_is_unchanged(tmp_path):
    p = subprocess.run([sys.executable, "-m", "beveloid.cli", "tca", str(tmp_path / "missing.toml")],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr


def test_started_pythons_import_the_beveloid_under_test():
    """A Python the tests start in pytest's own folder (the checkout: `python -m beveloid.cli ...`,
    `python -c ...`) imports the beveloid these tests import, also on a non-editable install, not the
    checkout's copy (tests/conftest.py sets PYTHONSAFEPATH: the working folder stays off sys.path)."""
    import beveloid

    code = "import os, sys, beveloid; print(beveloid.__file__); print(os.getcwd() in sys.path or '' in sys.path)"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == [beveloid.__file__, "False"]
