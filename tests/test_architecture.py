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
PENDING_PARAMETERS: set = {
    # the batched LTCA's compiled contact solve (issue 43): its arrays still to be packed in records
    ("beveloid/ltca/kernel.py", "_factor_solve"), ("beveloid/ltca/kernel.py", "active_set"),
    ("beveloid/ltca/kernel.py", "solve_positions"), ("beveloid/ltca/lcp.py", "solve_contact")}
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


# ---------------------------------------------------------------------------------------------
# issue 42: one definition per vocabulary, one Solver below the CLI, no cloned code, layering
# ---------------------------------------------------------------------------------------------

#: the vocabularies that names.py defines once (an alias, ``FLANKS = names.FLANKS``, is no definition)
VOCABULARIES = ("MEMBERS", "FLANKS")
#: (file, name) still defining a vocabulary of its own, owned by other work items
PENDING_VOCABULARIES: set = set()
#: (file, function) below cli/ still taking a backend name instead of a Solver (solver/backends.py
#: resolves the names: it is where a backend name belongs)
PENDING_BACKEND_PARAMETERS = {
    ("beveloid/explore/contact.py", "_kernel"), ("beveloid/explore/contact.py", "sensitivities"),
    ("beveloid/explore/rows.py", "_sensitivities"), ("beveloid/explore/rows.py", "compute"),
    ("beveloid/explore/rows.py", "monte_carlo"), ("beveloid/sweep.py", "engagement_window"),
    ("beveloid/tca/backlash.py", "backlash"), ("beveloid/tca/contact.py", "resolve_backend"),
    ("beveloid/tca/flank.py", "mesh_flank"), ("beveloid/tca/grid.py", "solve_grid"),
    ("beveloid/tca/grid.py", "solved_contact_points"), ("beveloid/tca/sensitivity.py", "sensitivity"),
    ("beveloid/tooth/contact.py", "__init__"), ("beveloid/tooth/contact.py", "_pair0"),
    ("beveloid/tooth/contact.py", "flank_contact")}
#: files that still reach a function's code object (a clone of compiled code), owned by other work items
PENDING_CODE_OBJECTS: set = set()


def _vocabulary_definitions():
    found = set()
    for rel, tree in _sources():
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign) and isinstance(node.value, (ast.Tuple, ast.List)):
                for t in node.targets:
                    if isinstance(t, ast.Name) and t.id in VOCABULARIES:
                        found.add((rel, t.id))
    return found


def test_each_vocabulary_is_defined_once_in_names():
    found = _vocabulary_definitions() - {("beveloid/names.py", v) for v in VOCABULARIES}
    new = found - PENDING_VOCABULARIES
    assert not new, f"take these from beveloid.names instead of defining them again: {sorted(new)}"
    fixed = PENDING_VOCABULARIES - found
    assert not fixed, f"these use beveloid.names now: remove from PENDING_VOCABULARIES: {sorted(fixed)}"


def _backend_parameters():
    found = set()
    for rel, tree in _sources():
        if rel.startswith("beveloid/cli/") or rel == "beveloid/solver/backends.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and "backend" in parameter_names(node):
                found.add((rel, node.name))
    return found


def test_below_the_cli_analyses_take_a_solver_not_a_backend_name():
    found = _backend_parameters()
    new = found - PENDING_BACKEND_PARAMETERS
    assert not new, f"take a beveloid.solver.Solver (solver=...), not a backend name: {sorted(new)}"
    fixed = PENDING_BACKEND_PARAMETERS - found
    assert not fixed, f"these take a Solver now: remove from PENDING_BACKEND_PARAMETERS: {sorted(fixed)}"


def test_no_code_object_is_cloned():
    found = {rel for rel, tree in _sources() for node in ast.walk(tree)
             if isinstance(node, ast.Attribute) and node.attr in ("__code__", "CodeType", "co_code")}
    new = found - PENDING_CODE_OBJECTS
    assert not new, f"call the compiled core through its namespace, do not clone code objects: {sorted(new)}"
    fixed = PENDING_CODE_OBJECTS - found
    assert not fixed, f"no code objects here now: remove from PENDING_CODE_OBJECTS: {sorted(fixed)}"


def test_the_sampled_tooth_lies_below_the_analyses_that_build_solids():
    """tooth/ (the sampled tooth, the body) imports none of export/, fe/, fecheck/: they build on it."""
    above = ("beveloid.export", "beveloid.fe", "beveloid.fecheck", "beveloid.ltca", "beveloid.rating")
    bad = []
    for rel, tree in _sources():
        if not rel.startswith("beveloid/tooth/"):
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                target = _absolute(rel, node)
                if any(target == a or target.startswith(a + ".") for a in above):
                    bad.append(f"{rel}:{node.lineno} imports {target}")
    assert not bad, bad


def _absolute(rel: str, node: ast.ImportFrom) -> str:
    """The absolute module an ``from ... import`` in file ``rel`` names."""
    if node.level == 0:
        return node.module or ""
    parts = rel[:-3].split("/")
    base = parts[: len(parts) - node.level]
    return ".".join(base + ([node.module] if node.module else []))
