"""Output folders, one rule for every output (issue 29, items 5 and 6): the named folder is created
when its parent exists and is writable, and refused in one line (exit 2) otherwise, before any work;
a run interrupted by Ctrl-C lists only the files it wrote and removes a folder it made and left empty.
The interruptions are real SIGINTs sent to a `python -m beveloid.cli` process."""
from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from beveloid import cli, pair  # noqa: F401 (imported before any test patches what it imports)
from beveloid.cli import paths

REPO = Path(__file__).resolve().parents[2]
C1 = str(REPO / "examples" / "case1.toml")


def _one_line_exit_2(capsys, argv, *fragments):
    rc = cli.main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("beveloid: error: "), err
    for f in fragments:
        assert f in err, (f, err)


@pytest.fixture
def no_work(monkeypatch):
    """Any design, paper study, export or exploration fails the test: the target must be refused first."""
    def boom(*a, **k):
        raise AssertionError("computed before checking the output target")
    for target in ("beveloid.design.design", "beveloid.studies.paper.run", "beveloid.pair.Pair.from_spec",
                   "beveloid.explore.run.prepare"):
        monkeypatch.setattr(target, boom)


@pytest.mark.parametrize("argv", [["paper", "--out"], ["export", C1, "--out"],
                                  ["explore", C1, "--vary", "pinion.cone_angle_deg=1:2:2", "--out"]])
def test_a_missing_parent_is_refused_and_nothing_is_created(capsys, tmp_path, no_work, argv):
    target = tmp_path / "missing" / "deep" / "dir"
    _one_line_exit_2(capsys, [*argv, str(target)], "--out = ", "does not exist")
    assert not (tmp_path / "missing").exists()


@pytest.mark.parametrize("argv", [["paper", "--out"], ["export", C1, "--out"],
                                  ["explore", C1, "--vary", "pinion.cone_angle_deg=1:2:2", "--out"]])
def test_a_place_that_cannot_hold_a_folder_is_one_line(capsys, no_work, argv):
    """/proc accepts no new folder (for root too): one line, not a traceback."""
    _one_line_exit_2(capsys, [*argv, "/proc/beveloid-out"], "--out = /proc/beveloid-out")


@pytest.mark.parametrize("argv", [["design", C1], ["tca", C1, "--positions", "3"],
                                  ["ltca", C1, "--torque-nm", "10", "--positions", "3"]])
def test_a_plot_into_proc_is_refused_before_any_work(capsys, no_work, argv):
    """/proc passes the permission test (for root) and takes no new file (issue 60: `--plot /proc/d.png`
    crashed with a traceback after the computation): one line, before any work."""
    _one_line_exit_2(capsys, [*argv, "--plot", "/proc/d.png"], "--plot = /proc/d.png: cannot create a file in /proc")


@pytest.mark.parametrize("argv", [["design", C1], ["tca", C1, "--positions", "3"],
                                  ["ltca", C1, "--torque-nm", "10", "--positions", "3"]])
def test_a_plot_into_a_missing_tree_is_refused(capsys, tmp_path, no_work, argv):
    _one_line_exit_2(capsys, [*argv, "--plot", str(tmp_path / "a" / "b" / "x.png")], "--plot = ", "does not exist")
    assert not (tmp_path / "a").exists()


def test_the_named_folder_is_created_one_level(tmp_path, capsys):
    """`--plot newdir/x.png` makes newdir (its parent exists), as `--out newdir` does."""
    png = tmp_path / "newdir" / "x.png"
    assert cli.main(["design", C1, "--plot", str(png)]) == 0, capsys.readouterr().err
    assert png.read_bytes().startswith(b"\x89PNG")
    paths.check_output_dir(str(tmp_path / "out"), "--out")
    assert (tmp_path / "out").is_dir() and paths.created_here(tmp_path / "out")
    assert paths.remove_empty_created() == [(tmp_path / "out").absolute()]
    assert not (tmp_path / "out").exists()


def test_a_folder_it_made_holding_only_a_probe_a_ctrl_c_stopped_is_removed(tmp_path):
    """The folder check writes and removes an empty probe file; a Ctrl-C between the two (right after the
    folder is made: what test_ctrl_c_removes_the_folder_it_made_and_left_empty[export] sends) left the probe,
    and the folder was kept for it."""
    from beveloid import outputs

    out = tmp_path / "out"
    paths.check_output_dir(str(out), "--out")
    (out / (outputs.PROBE_PREFIX + "abc123")).write_bytes(b"")  # the probe the interrupt left
    assert paths.remove_empty_created() == [out.absolute()]
    assert not out.exists()
    kept = tmp_path / "kept"
    paths.check_output_dir(str(kept), "--out")
    (kept / "result.csv").write_text("x")  # a real output keeps its folder
    assert paths.remove_empty_created() == [] and (kept / "result.csv").exists()


def test_a_failed_run_leaves_no_folder_it_made(tmp_path, capsys):
    """A plot folder made for a run that then stops on bad input is removed again."""
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(C1).read_text().replace("teeth = 29", "teeth = 5", 1))
    rc = cli.main(["design", str(bad), "--plot", str(tmp_path / "plots" / "x.png")])
    assert rc == 2, capsys.readouterr()
    assert not (tmp_path / "plots").exists()


def _interrupt(argv, tmp_path, ready, wait_s=1.0):
    """Start `beveloid ARGV`, send SIGINT once ``ready()`` holds (and ``wait_s`` more), return the process."""
    # the installed beveloid, as every started Python of the suite (tests/conftest.py); it loads the
    # solver the suite compiled (``compiled_solver``): a Ctrl-C inside numba's first compilation
    # waits for it (~30 s: numba swallows the interrupt, beveloid.interrupts re-raises it after)
    proc = subprocess.Popen([sys.executable, "-m", "beveloid.cli", *argv], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 240
    while not ready() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(wait_s)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=240)
    return proc.returncode, out, err


# SIGINT this long after the output folder appears: before the run's first file (the export's first
# STL is written ~0.5 s after its folder is made: 0.3 s was too late once the mesh's checks got faster)
# paper: 3 s after its folder appears, its worker processes are up and at work (a Ctrl-C while they are
# still being spawned is tests/studies/test_studies_tasks.py's, without this test's race against the load)
@pytest.mark.parametrize("argv, wait_s", [
    pytest.param(["paper", "--positions", "10", "--out", "{out}"], 3.0, marks=pytest.mark.slow),  # waits 3 s by design
    (["export", C1, "--format", "stl", "--out", "{out}"], 0.0)], ids=["paper", "export"])
def test_ctrl_c_removes_the_folder_it_made_and_left_empty(tmp_path, argv, wait_s, compiled_solver):
    out = tmp_path / "run_out"
    rc, _, err = _interrupt([a.format(out=out) for a in argv], tmp_path, out.exists, wait_s=wait_s)
    # 130, or ended by the signal itself after the clean-up (a shell shows 130 for both; seen under
    # load on a loaded 2-core machine, the cause not found): the clean-up below is what must hold
    assert rc in (130, -signal.SIGINT), err
    assert "Traceback" not in err and err.strip().endswith("interrupted"), err
    assert not out.exists(), sorted(p.name for p in out.iterdir())
    if argv[0] == "paper":  # its files are moved in only at the end: it says that nothing was written
        assert f"beveloid paper: --out = {out}: nothing written (the folder, made by this run, is removed)" in err, err


def test_ctrl_c_in_explore_lists_only_the_files_written(tmp_path, compiled_solver):
    out = tmp_path / "explore_out"
    # ~2000 designs with a 200-set Monte Carlo each: tens of seconds even on a quiet machine, so the
    # SIGINT (1 s after the chunk folder appears) always lands in the middle of the run
    argv = ["explore", C1, "--vary", "pinion.cone_angle_deg=1:3:2000", "--mc", "200", "--chunk", "4",
            "--workers", "1", "--out", str(out)]
    rc, stdout, err = _interrupt(argv, tmp_path, lambda: (out / "chunks").is_dir(), wait_s=1.0)
    # 130, or ended by the signal itself after the clean-up (a shell shows 130 for both): the worker
    # pool's exit handlers may see the interrupt again
    assert rc in (130, -signal.SIGINT), err
    assert "Traceback" not in err
    if not out.exists():  # stopped before a design finished: nothing left behind
        assert "nothing written" in err
        return
    listed = next(line for line in stdout.splitlines() if line.startswith(("Files in", "No result files")))
    if listed.startswith("Files in"):
        for name in listed.split(": ", 1)[1].split(", "):
            assert (out / name).is_file(), (name, listed)


def test_derive_model_out_follows_the_folder_rule(tmp_path, capsys):
    """`derive --model ... --out DIR` is refused before any work when DIR's parent does not exist
    (it used to create the whole missing tree)."""
    model = Path(__file__).resolve().parents[1] / "data" / "shifted_flank_model.py"
    deep = tmp_path / "no" / "such" / "dir"
    _one_line_exit_2(capsys, ["derive", "--model", str(model), "--name", "shifted", "--out", str(deep)],
                     "--out = ", "does not exist")
    assert not (tmp_path / "no").exists()


def test_fe_check_out_follows_the_folder_rule(tmp_path, capsys):
    """`fe-check --out DIR` is refused before any work (CalculiX or not) when DIR's parent is missing."""
    deep = tmp_path / "no" / "such" / "dir"
    _one_line_exit_2(capsys, ["fe-check", C1, "--torque-nm", "100", "--out", str(deep)], "--out = ", "does not exist")
    assert not (tmp_path / "no").exists()
