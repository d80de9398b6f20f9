"""Finding user models and telling stale or unknown ones (no derivation, no compilation: cheap).

A model folder here is written by hand (model.json and a file it names); the catalog only reads
model.json, hashes files and compares stamps, so that is what these tests exercise.  The
end-to-end path (derive, then every analysis) is tests/models/test_models_installed.py.
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from beveloid.models import catalog as current_catalog
from beveloid.models.discovery import FORMAT, INTERFACE, MODELS_ENV, discover, file_sha256, package_stamp
from beveloid.spec import SpecError, spec_from_dict
from beveloid.spec.schema import key_docs_markdown

BUILTIN = ("involute", "crowned", "micro_geometry")


def _model(root: Path, name: str, source: Path, stamp: str | None = None) -> Path:
    folder = root / name
    folder.mkdir(parents=True)
    (folder / f"surface_{name}.py").write_text("# kernels\n")
    face = dict(format=FORMAT, name=name, beveloid_version="0.1.0", package_stamp=stamp or package_stamp(),
                source=dict(path=str(source), sha256=file_sha256(source)),
                files={f"surface_{name}.py": file_sha256(folder / f"surface_{name}.py")},
                glue=dict(base={}, builtin=[], model=dict(name=name, module=f"surface_{name}", layout="X",
                                                          nparams=16, input_keys=[], selected_by=[], choice_keys=[])))
    (folder / INTERFACE).write_text(json.dumps(face))
    return folder


def test_usable_stale_and_unknown_models(tmp_path, monkeypatch):
    src = tmp_path / "lab" / "my_flank.py"
    src.parent.mkdir()
    src.write_text("# a derivation module (never run by the catalog)\n")
    root = tmp_path / "models"
    _model(root, "good", src)
    _model(root, "old", src, stamp="0" * 16)  # made for another build of the package
    edited = _model(root, "edited", src)
    (edited / "surface_edited.py").write_text("# kernels, edited by hand\n")
    _model(root, "involute", src)  # a built-in name: the built-in model wins
    bad = _model(root, "bare", src)  # a model.json without the glue entry
    (bad / INTERFACE).write_text(json.dumps(dict(json.loads((bad / INTERFACE).read_text()), glue={})))
    (root / "notes").mkdir()  # not a model folder: ignored
    monkeypatch.setenv(MODELS_ENV, str(root))
    cat = discover(BUILTIN)
    assert [m.name for m in cat.user] == ["good"] and cat.user[0].origin == "user folder"
    assert sorted(cat.stale) == ["bare", "edited", "old"] and "incomplete" in cat.problem("bare")
    assert cat.problem("good") is None and cat.problem("crowned") is None
    old = cat.problem("old")
    assert "stale" in old and "another build" in old and f"beveloid derive --model {src} --name old" in old
    assert "surface_edited.py" in cat.problem("edited")
    unknown = cat.problem("nosuch")
    assert "no such tooth-surface model" in unknown and '"good"' in unknown and "--name nosuch" in unknown
    # the derivation module changed since the model was generated
    src.write_text("# changed\n")
    cat = discover(BUILTIN)
    assert [m.name for m in cat.user] == [] and "changed since it was generated" in cat.problem("good")
    # a folder that does not exist: no user models
    monkeypatch.setenv(MODELS_ENV, str(tmp_path / "elsewhere"))
    cat = discover(BUILTIN)
    assert cat.user == () and cat.stale == {}


def test_a_spec_naming_an_unknown_model_gets_one_line():
    assert current_catalog().user == ()  # the suite runs with an empty user model folder (tests/conftest.py)
    data = _toml_dict()
    data["gear"]["tooth_surface"] = "crowend"
    with pytest.raises(SpecError) as exc:
        spec_from_dict(data)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith('gear.tooth_surface = "crowend": no such tooth-surface model')
    assert "beveloid derive --model FILE --name crowend" in msg and "did you mean crowned?" in msg


def _toml_dict():
    import tomllib

    from beveloid.spec import example_text

    return tomllib.loads(example_text("case1"))


def test_readme_key_table_holds_the_built_in_models_only():
    table = key_docs_markdown()
    assert '"involute", "crowned", "micro_geometry" |' in table.replace("one of ", "")


def _cli(args, env=None, cwd=None):
    import os

    return subprocess.run([sys.executable, "-m", "beveloid.cli", *args], capture_output=True, text=True,
                          env=dict(os.environ, **(env or {})), cwd=cwd, timeout=300)


@pytest.mark.slow
def test_derive_refuses_bad_requests_in_one_line(tmp_path):
    import site

    bad = tmp_path / "no_surface.py"
    bad.write_text('"""States no tooth_surface."""\nPARAMETERS = ()\n')
    cases = [(["derive", "--model", str(bad)], "--name NAME is missing"),
             (["derive", "--name", "x"], "--model FILE is missing"),
             (["derive", "--model", str(bad), "--name", "x", "--check"], "--check with --model"),
             (["derive", "--model", str(bad), "--name", "x", "--out", site.getsitepackages()[0]], "inside"),
             (["derive", "--model", str(bad), "--name", "Bad-Name"], "--name Bad-Name: must be lower-case"),
             (["derive", "--model", str(bad), "--name", "involute_scalar"], "scalar twin"),
             (["derive", "--model", str(bad), "--name", "crowned"], "a built-in model has this name"),
             (["derive", "--model", str(bad), "--name", "fine"], "defines no tooth_surface"),
             (["example", "--schema", "--model", "nosuch"], "--model nosuch: no such tooth-surface model")]
    for args, text in cases:
        proc = _cli(args, env={MODELS_ENV: str(tmp_path / "models")})
        assert proc.returncode == 2, (args, proc.stderr)
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and text in lines[0], (args, proc.stderr)
    assert not (tmp_path / "models").exists()  # nothing written


def test_derive_check_only_compares(monkeypatch, capsys):
    """`derive --check` prints no "generating ..." lines (it generates nothing): the CLI passes no progress."""
    from beveloid.cli import main
    from beveloid.derivations import derive as derive_module

    seen = []

    def compare(check=False, progress=None, docs_page=True):
        seen.append((check, progress))
        return "", 0.1

    monkeypatch.setattr(derive_module, "derive", compare)
    assert main(["derive", "--check", "--no-docs"]) == 0
    assert seen == [(True, None)]
    assert "generating" not in capsys.readouterr().err


def test_models_lists_every_model_with_its_keys(tmp_path):
    proc = _cli(["models", "--json"], env={MODELS_ENV: str(tmp_path)})
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert [m["name"] for m in out["models"]] == list(BUILTIN) and out["user_folder"] == str(tmp_path)
    crowned = {k["key"]: k for k in out["models"][1]["keys"]}
    assert crowned["lead_crowning_um"]["unit"] == "um" and crowned["lead_crowning_um"]["highest"] == 200.0


def test_models_of_an_installed_package_are_found_by_entry_point(tmp_path, monkeypatch):
    """A package declaring `beveloid.models = lab = "lab_models"` ships model folders in lab_models/."""
    site = tmp_path / "site"
    (site / "lab_models").mkdir(parents=True)
    (site / "lab_models" / "__init__.py").write_text("raise RuntimeError('the catalog must not import this')\n")
    src = tmp_path / "lab_flank.py"
    src.write_text("# the lab's derivation module\n")
    _model(site / "lab_models", "labflank", src)
    info = site / "lab_models-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: lab-models\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[beveloid.models]\nlab = lab_models\n")
    monkeypatch.syspath_prepend(str(site))
    monkeypatch.setenv(MODELS_ENV, str(tmp_path / "empty"))
    cat = discover(BUILTIN)
    assert [(m.name, m.origin) for m in cat.user] == [("labflank", "package lab")]
    assert cat.user[0].folder == site / "lab_models" / "labflank"
    # a user-folder model of the same name comes first
    _model(tmp_path / "mine", "labflank", src)
    monkeypatch.setenv(MODELS_ENV, str(tmp_path / "mine"))
    assert [(m.name, m.origin) for m in discover(BUILTIN).user] == [("labflank", "user folder")]


@pytest.mark.slow
def test_derive_refuses_a_model_that_fails_a_check(tmp_path):
    """A normal that is not the surface's: exit 1, the failed check named, nothing written."""
    model = tmp_path / "wrong_normal_model.py"
    model.write_text((Path(__file__).resolve().parents[1] / "data" / "wrong_normal_model.py").read_text())
    proc = _cli(["derive", "--model", str(model), "--name", "wrong", "--out", str(tmp_path / "models")])
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert re.search(r"^  FAIL normal orthogonal to the surface: .* = \d\.\de-0[1-4] ", proc.stdout, re.M), proc.stdout
    assert re.search(r"^  ok   unit normal:", proc.stdout, re.M)  # the normal is still a unit vector
    assert 'model "wrong" NOT written' in proc.stdout
    # nothing written, not even its staging folder: the folder the run made is removed again
    assert not (tmp_path / "models").exists() or list((tmp_path / "models").iterdir()) == []
