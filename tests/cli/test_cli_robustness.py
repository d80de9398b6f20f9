"""Hostile surroundings: a full output device, an ASCII terminal, a bogus matplotlib backend, a spec
nested thousands deep. Each gives one line and exit 2, or a clean fallback; never a traceback."""
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
@pytest.mark.parametrize("args", [["design", "{case1}"], ["example", "case1"], ["design", "{case1}", "--json"],
                                  ["tca", "{case1}", "--positions", "3"]])
def test_a_full_output_device_is_one_line_and_exit_2(tmp_path, case1, args):
    args = [a.format(case1=case1) for a in args]
    with open("/dev/full", "w") as full:
        proc = subprocess.run([sys.executable, "-m", "beveloid.cli", *args], cwd=tmp_path, stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=300)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == "beveloid: error: cannot write the output: No space left on device (errno 28)\n"


@pytest.mark.parametrize("closed", [">&-", "2>&-"])
def test_a_closed_output_stream_is_like_the_null_device(tmp_path, case1, closed):
    """`beveloid tca my.toml >&-`: the caller closed stdout (Python sees None); the run completes
    with exit 0 and no traceback, and with stderr closed an error still exits 2."""
    cmd = f"{sys.executable} -m beveloid.cli tca {case1} --positions 3 {closed}"
    proc = subprocess.run(["bash", "-c", cmd], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr and "Traceback" not in proc.stdout
    bad = subprocess.run(["bash", "-c", f"{sys.executable} -m beveloid.cli tca missing.toml {closed}"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr


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
