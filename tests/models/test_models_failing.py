"""A user's model file that fails is told as the user's error: exit 2, ``beveloid: error: FILE:LINE:
...``, and below it only the frames in their file (a syntax error: the line and its caret); sympy's
failure on their expression names the function of the model being derived and the kernel.

``derive --model`` runs in this process (it fails before generating anything costly: the models
here are small planes); the model that fails at first use from a spec runs in a fresh process
(the import hook's state is per process).
"""
from __future__ import annotations

import hashlib
import json
import re
import subprocess
import sys
import textwrap

import pytest

from beveloid.cli import main

# a plane with the involute's interface: enough for derive to call tooth_surface and sympy to work on it
PLANE = """
import sympy as sp

from beveloid.derivations.symbols import l, u


def plane(sigma):
    return sp.Matrix([l, u, 0]), sp.Matrix([0, 0, sigma]), l / 10
"""

MODELS = {
    "syntax": ('"""A syntax error."""\nimport sympy as sp\n\nbend = sp.sin(1\n\n\ndef tooth_surface(sigma):\n'
               "    return None\n"),
    "import": PLANE + textwrap.dedent("""
        def _table():
            raise RuntimeError("the lab's table is missing")


        TABLE = _table()


        def tooth_surface(sigma):
            return plane(sigma)
        """),
    "surface": PLANE + textwrap.dedent("""
        def _scaled(point, factor):
            if factor <= 0:
                raise ValueError(f"factor = {factor}: must be positive")
            return point * factor


        def tooth_surface(sigma):
            point, normal, roll = plane(sigma)
            return _scaled(point, sigma), normal, roll
        """),
    "sympy": PLANE + textwrap.dedent("""
        def tooth_surface(sigma):
            point, normal, roll = plane(sigma)
            return point + normal * sp.Abs(l - 1) / 1000, normal, roll
        """),
}


# what else sympy cannot make kernels of (one line each): an expression it cannot differentiate, a
# function without a numpy form
for _case, _term in (("floor", "sp.floor(l)"), ("erf", "sp.erf(l)")):
    MODELS[_case] = MODELS["sympy"].replace("sp.Abs(l - 1)", _term)
# a kernel that raises at the checked points: math.sqrt of a negative in the scalar twin (numpy: NaN)
MODELS["domain"] = MODELS["sympy"].replace("sp.Abs(l - 1)", "sp.sqrt(l - 100)")


def _derive(tmp_path, capsys, case):
    model = tmp_path / f"failing_{case}_model.py"
    model.write_text(MODELS[case])
    status = main(["derive", "--model", str(model), "--name", f"failing_{case}", "--out", str(tmp_path / "models")])
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if not ln.startswith("generating ")]  # derive's progress line
    assert not (tmp_path / "models").exists() or list((tmp_path / "models").iterdir()) == []  # nothing written
    return model, status, lines


def _line_of(case, fragment):
    return next(i for i, ln in enumerate(MODELS[case].splitlines(), 1) if fragment in ln)


def _only_their_frames(lines, model):
    """The lines below the error: "File" lines of the model only, each followed by its source line (and
    caret); returns the functions of the frames, outermost first."""
    frames = re.findall(r'^  File "([^"]+)", line \d+, in (\S+)$', "\n".join(lines), re.M)
    assert frames and {f for f, _ in frames} == {str(model)}, lines
    assert all(ln.startswith("  File ") or ln.startswith("    ") for ln in lines), lines
    return [fn for _, fn in frames]


def test_a_syntax_error_names_the_line_and_shows_it(tmp_path, capsys):
    model, status, lines = _derive(tmp_path, capsys, "syntax")
    assert status == 2
    assert re.match(rf"beveloid: error: {re.escape(str(model))}:4: SyntaxError: '\(' was never closed", lines[0])
    assert lines[1:] == ["    bend = sp.sin(1", "                 ^"], lines


def test_an_exception_at_import_shows_the_frames_in_the_file_only(tmp_path, capsys):
    model, status, lines = _derive(tmp_path, capsys, "import")
    assert status == 2
    assert lines[0] == (f"beveloid: error: {model}:{_line_of('import', 'raise')}: RuntimeError: the lab's table is missing"
                        " (while importing the model)"), lines
    assert _only_their_frames(lines[1:], model) == ["<module>", "_table"]
    assert 'raise RuntimeError("the lab' in "\n".join(lines[-3:])


def test_an_exception_inside_tooth_surface_shows_the_frames_in_the_file_only(tmp_path, capsys):
    model, status, lines = _derive(tmp_path, capsys, "surface")
    assert status == 2
    assert lines[0] == (f"beveloid: error: {model}:{_line_of('surface', 'raise')}: ValueError: factor = -1: must be"
                        " positive (while deriving tooth_surface)"), lines  # sigma = -1: the right flank
    assert _only_their_frames(lines[1:], model) == ["tooth_surface", "_scaled"]


def test_a_sympy_failure_names_the_function_being_derived(tmp_path, capsys):
    """Abs(l - 1) has a first derivative (sign) but its second is a DiracDelta: no code for it."""
    model, status, lines = _derive(tmp_path, capsys, "sympy")
    assert status == 2
    assert lines == [f"beveloid: error: {model.name}: tooth_surface cannot be derived: "
                     "surface_second_derivatives_left: DiracDelta(l - 1) has no numpy code"], lines


def test_a_model_that_fails_at_first_use_from_a_spec(tmp_path):
    """A model folder the catalog takes (hashes and stamp right) whose kernels no longer load (here: they
    name a numpy attribute that is not there, as kernels made elsewhere might): the spec's first use
    reports the kernel file's line and frames, exit 2."""
    from beveloid.derivations import crowned_flank, kernels
    from beveloid.models.discovery import FORMAT, INTERFACE, package_stamp
    from beveloid.spec import example_text

    folder = tmp_path / "models" / "brittle"
    folder.mkdir(parents=True)
    files = {"surface_brittle.py": '"""Kernels of the model "brittle"."""\nimport numpy\n\nREAL = numpy.float1024\n',
             "surface_brittle_scalar.py": "import math\n",
             "layout.py": "from beveloid.generated.layouts import CrownedSurfaceParams as BrittleSurfaceParams\n"}
    for name, text in files.items():
        (folder / name).write_text(text)
    face = dict(format=FORMAT, name="brittle", beveloid_version="0.1.0", package_stamp=package_stamp(),
                source=dict(path=str(tmp_path / "brittle_model.py"), sha256="0" * 64),
                glue=dict(base=kernels.glue_base(),
                          builtin=[kernels.model_entry(k, m) for k, m in kernels.SURFACE_MODELS.items()],
                          model=kernels.model_entry("brittle", crowned_flank)),
                files={n: hashlib.sha256(t.encode()).hexdigest() for n, t in files.items()})
    (folder / INTERFACE).write_text(json.dumps(face))
    spec = tmp_path / "brittle.toml"
    spec.write_text(example_text("case1").replace("[gear]", '[gear]\ntooth_surface = "brittle"', 1))
    import os

    env = dict(os.environ, BEVELOID_MODELS_DIR=str(tmp_path / "models"), BEVELOID_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.run([sys.executable, "-m", "beveloid.cli", "tca", str(spec), "--positions", "5"],
                          capture_output=True, text=True, env=env, timeout=300)
    lines = proc.stderr.splitlines()
    assert proc.returncode == 2, proc.stderr
    kernel = folder / "surface_brittle.py"
    assert lines[0].startswith(f"beveloid: error: {kernel}:4: AttributeError: module 'numpy' has no attribute"
                               " 'float1024'"), lines
    assert 'while loading the model "brittle" (user folder' in lines[0]
    assert "beveloid derive --model" in lines[0] and "--name brittle" in lines[0]  # how to regenerate it
    assert _only_their_frames(lines[1:], kernel) == ["<module>"] and lines[2] == "    REAL = numpy.float1024", lines


def test_other_expressions_without_kernels_are_named(tmp_path, capsys):
    said = {}
    for case in ("floor", "erf"):
        model, status, lines = _derive(tmp_path, capsys, case)
        assert status == 2 and len(lines) == 1, lines
        said[case] = lines[0]
    assert said["floor"].endswith(": tooth_surface cannot be derived: surface_jet_left: sympy cannot differentiate"
                                  " floor(l) (its derivative stays unevaluated)"), said
    assert said["erf"].endswith(": tooth_surface cannot be derived: surface_left: math.erf has no numpy form (the"
                                " module calls numpy only)"), said


def test_a_kernel_that_raises_at_the_checked_points_fails_a_check(tmp_path, capsys):
    model = tmp_path / "domain_model.py"
    model.write_text(MODELS["domain"])
    with pytest.warns(RuntimeWarning):  # the numpy kernels' NaN
        status = main(["derive", "--model", str(model), "--name", "domain", "--out", str(tmp_path / "models")])
    out = capsys.readouterr().out
    assert status == 1
    assert re.search(r"^  FAIL kernels evaluate: surface_domain_scalar\.surface_left_point raised ValueError: math"
                     r" domain error ", out, re.M), out
    assert 'model "domain" NOT written' in out and not (tmp_path / "models").exists()
