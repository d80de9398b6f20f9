"""Rules of the runtime's shape, read from the source with ``ast`` (docs/architecture.md):

* no function or method of beveloid/ takes more than MAX_PARAMETERS parameters (self and cls not
  counted; generated code excluded): a longer list is a record to pass (beveloid/solver/records.py);
* every package of beveloid/ declares its public surface in ``__all__``, and every name there exists.

Functions and packages that other work items still have to bring under the rules are listed
by name below (PENDING_*): each entry must still exist and still break the rule, so a fix
fails this test until its entry is removed, and nothing new can join the lists unseen.
"""
from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "beveloid"
MAX_PARAMETERS = 8

#: (file relative to the checkout, function) still over MAX_PARAMETERS, owned by other work items
PENDING_PARAMETERS: set = set()
#: packages (folders relative to the checkout) that do not declare __all__ yet
PENDING_ALL: set = set()


def _sources():
    for path in sorted(PACKAGE.rglob("*.py")):
        if "generated" in path.relative_to(ROOT).parts:
            continue
        yield path.relative_to(ROOT).as_posix(), ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def parameter_names(node: ast.FunctionDef | ast.AsyncFunctionDef) -> list[str]:
    """Every parameter of a function (positional, keyword-only, *args, **kwargs), self/cls excluded."""
    a = node.args
    names = [p.arg for p in a.posonlyargs + a.args + a.kwonlyargs]
    names += [p.arg for p in (a.vararg, a.kwarg) if p is not None]
    return names[1:] if names[:1] in (["self"], ["cls"]) else names


def _long_functions():
    found = {}
    for rel, tree in _sources():
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = len(parameter_names(node))
                if n > MAX_PARAMETERS:
                    found[(rel, node.name)] = n
    return found


def test_the_parameter_count_reads_every_kind_of_parameter():
    tree = ast.parse("class A:\n    def f(self, a, /, b, *c, d, **e): pass\ndef g(cls, x): pass\n")
    f, g = tree.body[0].body[0], tree.body[1]
    assert parameter_names(f) == ["a", "b", "d", "c", "e"]
    assert parameter_names(g) == ["x"]


def test_no_runtime_function_takes_more_than_eight_parameters():
    found = _long_functions()
    new = {k: v for k, v in found.items() if k not in PENDING_PARAMETERS}
    assert not new, "pass a record instead of these parameter lists: " + ", ".join(
        f"{f}:{name} ({n} parameters)" for (f, name), n in sorted(new.items()))
    fixed = PENDING_PARAMETERS - set(found)
    assert not fixed, f"now within {MAX_PARAMETERS} parameters: remove from PENDING_PARAMETERS: {sorted(fixed)}"


def _packages():
    return sorted(p.parent for p in PACKAGE.rglob("__init__.py") if "generated" not in p.relative_to(ROOT).parts)


def _declares_all(init: Path) -> bool:
    tree = ast.parse(init.read_text(encoding="utf-8"))
    return any(isinstance(node, (ast.Assign, ast.AnnAssign)) and any(
        isinstance(t, ast.Name) and t.id == "__all__" for t in (node.targets if isinstance(node, ast.Assign)
                                                                  else [node.target]))
        for node in tree.body)


def test_every_package_declares_all():
    missing = {p.relative_to(ROOT).as_posix() for p in _packages() if not _declares_all(p / "__init__.py")}
    new = missing - PENDING_ALL
    assert not new, f"declare __all__ (the package's public surface) in: {sorted(new)}"
    fixed = PENDING_ALL - missing
    assert not fixed, f"these declare __all__ now: remove from PENDING_ALL: {sorted(fixed)}"


@pytest.mark.parametrize("package", [p.relative_to(ROOT).as_posix() for p in _packages()
                                     if _declares_all(p / "__init__.py")])
def test_every_name_in_all_exists(package):
    module = importlib.import_module(package.replace("/", "."))
    folder = ROOT / package
    # a submodule is a public name too (``from package import *`` imports it)
    absent = [name for name in module.__all__ if not hasattr(module, name)
              and not (folder / f"{name}.py").is_file() and not (folder / name / "__init__.py").is_file()]
    assert not absent, f"{package}.__all__ names what it does not define: {absent}"
    assert len(set(module.__all__)) == len(module.__all__)
