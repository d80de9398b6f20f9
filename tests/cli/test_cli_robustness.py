"""Hostile surroundings: a full or closed output (one line, exit 1, as Unix tools), a closed pipe
(quiet, 0), an ASCII terminal, a bogus matplotlib backend, a spec nested thousands deep. Each gives
one line and an exit status, or a clean fallback; never a traceback."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from beveloid import cli
from beveloid.spec import example_text


def _beveloid(args, tmp_path, **env):
    full_env = {**os.environ, **env}
    return subprocess.run([sys.executable, "-m", "beveloid.cli", *args], cwd=tmp_path, env=full_env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture
def case1(tmp_path):
    path = tmp_path / "my.toml"
    path.write_text(example_text("case1"))
    return str(path)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="/dev/full is a Linux device")
# one handler (cli._main) for every command: `pytest` runs it under a command that only prints and under
# one that solves; the design table and JSON (a second each in their own Python) in the slow tier
@pytest.mark.parametrize("args", [pytest.param(["design", "{case1}"], marks=pytest.mark.slow), ["example", "case1"],
                                  pytest.param(["design", "{case1}", "--json"], marks=pytest.mark.slow),
                                  ["tca", "{case1}", "--positions", "3"]])
def test_a_full_output_device_is_one_line_and_exit_1(tmp_path, case1, args):
    """As `cat file > /dev/full`: a write error is one line on stderr and exit 1."""
    args = " ".join(a.format(case1=case1) for a in args)
    proc = subprocess.run(["bash", "-c", f"{sys.executable} -m beveloid.cli {args} > /dev/full"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr == "beveloid: error: cannot write the output: No space left on device (errno 28)\n"


# the TCA's JSON in the slow tier; `pytest` runs the same handler on a closed stdout under `example`,
# and under `tca` on a full device (above) and a closed pipe (below)
@pytest.mark.parametrize("args", [["example", "case1"],
                                  pytest.param(["tca", "{case1}", "--positions", "3", "--json"], marks=pytest.mark.slow)])
def test_a_closed_stdout_is_a_write_error(tmp_path, case1, args):
    """`beveloid tca my.toml >&-`: the output is lost, so the command says so in one line and exits 1
    (as `cat file >&-` does), instead of exiting 0."""
    args = " ".join(a.format(case1=case1) for a in args)
    proc = subprocess.run(["bash", "-c", f"{sys.executable} -m beveloid.cli {args} >&-"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    assert proc.stderr == "beveloid: error: cannot write the output: Bad file descriptor (errno 9)\n"


def test_a_closed_pipe_ends_quietly(tmp_path, case1):
    """`beveloid tca my.toml --json | head -c 20`: head stops reading; beveloid ends with 0 and says nothing."""
    cmd = (f"{sys.executable} -m beveloid.cli tca {case1} --positions 40 --json | head -c 20;"
           " echo; echo status=${PIPESTATUS[0]}")
    proc = subprocess.run(["bash", "-c", cmd], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.stdout.startswith("{") and proc.stdout.rstrip().endswith("status=0"), proc.stdout
    assert proc.stderr == ""


def test_a_closed_stderr_still_gives_the_exit_status(tmp_path, case1):
    """Nothing can be said with stderr closed (`2>&-`), but the run completes (0) and bad input exits 2."""
    ok = subprocess.run(["bash", "-c", f"{sys.executable} -m beveloid.cli tca {case1} --positions 3 2>&-"],
                        cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert ok.returncode == 0 and "flank" in ok.stdout, ok.stdout
    bad = subprocess.run(["bash", "-c", f"{sys.executable} -m beveloid.cli tca missing.toml 2>&-"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and bad.stdout == ""


def test_an_ascii_terminal_gets_the_greek_symbols_by_name(tmp_path, case1):
    proc = _beveloid(["design", case1], tmp_path, PYTHONIOENCODING="ascii")
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    rows = {line.split("|")[0].strip(): line.split("|")[1].strip() for line in proc.stdout.splitlines() if "|" in line}
    assert rows["Normal pressure angle (deg)"] == "alphan"
    assert rows["Shaft angle (deg)"] == "delta"
    assert rows["Helix angle (deg)"] == "beta"
    proc.stdout.encode("ascii")  # nothing else escaped


def test_the_by_name_handler_keeps_what_it_cannot_name_readable():
    text = "αβ ξ Γ x₁ é"
    assert text.encode("ascii", "beveloid-names").decode("ascii") == "alphabeta xi Gamma x1 \\xe9"


def test_a_bogus_matplotlib_backend_falls_back_to_files(tmp_path, case1):
    png = tmp_path / "tca.png"
    proc = _beveloid(["tca", case1, "--positions", "3", "--flank", "right", "--plot", str(png)], tmp_path,
                     MPLBACKEND="bogus")
    assert proc.returncode == 0, proc.stderr
    assert png.read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("nested", ["[" * 5000 + "]" * 5000, "{a = " * 5000 + "1" + "}" * 5000])
def test_a_spec_nested_thousands_deep_is_one_line(tmp_path, capsys, nested):
    path = tmp_path / "deep.toml"
    path.write_text(example_text("case1") + f"\n[extra]\nkey = {nested}\n")
    assert cli.main(["design", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == (f"beveloid: error: {path}: arrays or tables nested too deeply: a spec holds sections of keys"
                   " with single values (`beveloid example case1` prints one)\n")


def test_a_value_nested_thousands_deep_in_a_mapping_is_a_spec_error():
    from beveloid.spec import SpecError, load_example, spec_from_dict, spec_to_dict

    data = spec_to_dict(load_example("case1"))
    value = 29
    for _ in range(5000):
        value = [value]
    data["pinion"]["teeth"] = value
    with pytest.raises(SpecError, match="nested too deeply"):
        spec_from_dict(data)
