"""The generated kernels: `beveloid derive --check` / `--no-docs` and the sympy-free runtime (helpers: generated_support.py, fixtures: conftest.py)."""
from __future__ import annotations

import ast
import functools
import importlib
import inspect
import os
import re
import shutil
import subprocess
import sys
import tokenize
import types
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import codegen, kernels
from generated_support import *  # noqa: F401,F403  (the shared samplers and comparisons)


# One xdist worker runs these modules: their sympy models and renderings (~15 s) are built once per process.
pytestmark = pytest.mark.xdist_group("generated")

# ---------------------------------------------------------------------------------------
# 10. `beveloid derive --check` / `--no-docs` and the sympy-free runtime
# ---------------------------------------------------------------------------------------


@pytest.fixture
def cheap_derive(monkeypatch, specs, rendered):
    """`beveloid derive` without the 18 s equation verification, the 5 s model build and the
    8 s rendering: the docs page renders as committed, the models are the ones built for this
    session and their files are this session's rendering (``rendered``: what the generator
    renders is checked above, against the committed files and against a second rendering).
    The tests below are about the command: its comparison, diff, exit status and writing nothing."""
    from beveloid.derivations import docs, registry

    committed_docs = (ROOT / "docs" / "derivations.md").read_text()
    session_specs = list(specs.values())
    real_generate = codegen.generate

    def generate(out_dir, specs_, cse=True, progress=None, extra=None):
        if out_dir is None and cse and list(specs_) == session_specs and extra == kernels.glue_files():
            return dict(rendered)
        return real_generate(out_dir, specs_, cse=cse, progress=progress, extra=extra)

    monkeypatch.setattr(registry, "verify", lambda *a, **k: None)
    monkeypatch.setattr(docs, "render_derivations_md", lambda results=None: committed_docs)
    monkeypatch.setattr(kernels, "module_specs", lambda models=None: session_specs)
    monkeypatch.setattr(codegen, "generate", generate)


def test_derive_check_passes_on_a_clean_checkout(cheap_derive, capsys):
    from beveloid.cli import main

    before = {p.name: p.read_bytes() for p in GENERATED.glob("*.py")}
    assert main(["derive", "--check"]) == 0
    out, err = capsys.readouterr()
    assert out == ""
    assert "up to date" in err
    assert {p.name: p.read_bytes() for p in GENERATED.glob("*.py")} == before


def test_derive_check_reports_a_stale_copy(cheap_derive, capsys, monkeypatch, tmp_path):
    from beveloid.cli import main
    from beveloid.derivations import derive

    shutil.copytree(GENERATED, tmp_path / "generated", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "docs", tmp_path / "docs")
    (tmp_path / "pyproject.toml").write_text("")
    stale = tmp_path / "generated" / "contact_system.py"
    ops = OPS.search(stale.read_text())[1]
    stale.write_text(OPS.sub("    # ops: 0", stale.read_text(), count=1))
    (tmp_path / "generated" / "orphan.py").write_text("x = 1\n")
    monkeypatch.setattr(derive, "source_root", lambda: tmp_path)

    assert main(["derive", "--check"]) == 1
    out, err = capsys.readouterr()
    assert "--- generated/contact_system.py (committed)\n+++ generated/contact_system.py (regenerated)\n" in out
    assert f"\n-    # ops: 0\n+    # ops: {ops}\n" in out
    assert "generated/orphan.py" in out
    for other in ["docs/derivations.md"] + [f"generated/{n}" for n in FILES if n != "contact_system.py"]:
        assert f"--- {other} " not in out, other
    assert HINT in err
    # --check writes nothing
    assert "# ops: 0\n" in stale.read_text() and (tmp_path / "generated" / "orphan.py").exists()


def test_derive_no_docs_leaves_the_docs_page_and_its_verification_out(cheap_derive, capsys, monkeypatch, tmp_path):
    from beveloid.cli import main
    from beveloid.derivations import derive, registry

    shutil.copytree(GENERATED, tmp_path / "generated", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "docs", tmp_path / "docs")
    (tmp_path / "pyproject.toml").write_text("")
    page = tmp_path / "docs" / "derivations.md"
    page.write_text("stale\n")
    monkeypatch.setattr(derive, "source_root", lambda: tmp_path)

    assert main(["derive", "--check"]) == 1
    assert "--- docs/derivations.md (committed)\n" in capsys.readouterr().out

    def no_verification(*args, **kwargs):
        raise AssertionError("--no-docs verified the equations")

    monkeypatch.setattr(registry, "verify", no_verification)
    assert main(["derive", "--check", "--no-docs"]) == 0
    out, err = capsys.readouterr()
    assert out == "" and "generated/ is up to date" in err
    (tmp_path / "generated" / "orphan.py").write_text("x = 1\n")
    assert main(["derive", "--no-docs"]) == 0
    assert "(files changed)" in capsys.readouterr().err
    assert not (tmp_path / "generated" / "orphan.py").exists() and page.read_text() == "stale\n"


def test_runtime_kernels_import_without_sympy(tmp_path):
    modules = ", ".join(f"beveloid.generated.{m}" for m in MODULES + SCALAR_MODULES + SUPPORT_MODULES)
    code = (f"import sys, beveloid.generated, {modules}\n"
            "bad = sorted(m for m in ('sympy', 'jinja2', 'mpmath', 'beveloid.derivations') if m in sys.modules)\n"
            "assert not bad, bad\n"
            "print(beveloid.generated.__file__)\n")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    # editable install: the checkout's generated/; regular install: an identical copy
    imported = Path(proc.stdout.strip()).parent
    assert {"design_equations.py", f"surface_{MODEL}.py", "contact_system.py"} <= set(FILES)
    for name in FILES:
        assert (imported / name).read_bytes() == (GENERATED / name).read_bytes(), name
