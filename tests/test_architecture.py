"""Rules of the runtime's shape, read from the source with ``ast`` (docs/architecture.md):

* no function or method of beveloid/ takes more than MAX_PARAMETERS parameters (self and cls not
  counted; generated code excluded): a longer list is a record to pass (beveloid/solver/records.py);
* every package of beveloid/ declares its public surface in ``__all__``, and every name there exists;
* every status is built from its enum in beveloid/status.py, never written out as a string elsewhere;
* MEMBERS and FLANKS are defined in beveloid/names.py only; below cli/ a function takes a Solver, not a
  backend name, and every ``analyze`` / ``analyze_many`` takes it keyword-only (``analyze(pair, options,
  *, solver=None)``; the older call forms are refused); no code object is cloned; tooth/ imports none of
  the packages that build on it;
* the layers: every unit of the runtime (package, top-level module, generated/) has one layer in
  docs/architecture.md (its lines ``layer N  unit ...``), no import runs up the layers, no units import
  each other round a loop; derivations/ imports nothing of the runtime but generated/; the runtime never
  imports sympy and reaches derivations/ only from cli/derive.py and cli/verify.py; no private name
  crosses a package; the solver imports only itself, the generated kernels and the status codes.

An import inside a function counts as one at module level (it runs all the same); a module loaded by
``importlib`` from a string is not seen.

Functions, files and packages that other work items still have to bring under the rules are listed
by name below (PENDING_*): each entry must still exist and still break the rule, so a fix
fails this test until its entry is removed, and nothing new can join the lists unseen.
"""
from __future__ import annotations

import ast
import functools
import importlib
import re
import subprocess
import sys
import typing
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "beveloid"
MAX_PARAMETERS = 8

#: (file relative to the checkout, function) still over MAX_PARAMETERS, owned by other work items
PENDING_PARAMETERS: set = set()
#: packages (folders relative to the checkout) that do not declare __all__ yet
PENDING_ALL: set = set()


@functools.lru_cache(maxsize=None)
def _parsed(folder: str) -> tuple:
    """(file relative to the checkout, its ast) of every module under ``folder``, generated code excluded:
    parsed once for every rule below."""
    out = []
    for path in sorted((ROOT / folder).rglob("*.py")):
        if "generated" in path.relative_to(ROOT).parts:
            continue
        out.append((path.relative_to(ROOT).as_posix(), ast.parse(path.read_text(encoding="utf-8"), filename=str(path))))
    return tuple(out)


def _sources():
    yield from _parsed("beveloid")


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
PENDING_BACKEND_PARAMETERS: set = set()
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


#: (file, function) named analyze / analyze_many that still takes its solver positionally, owned by other work items
PENDING_POSITIONAL_SOLVER: set = set()
ANALYSES = ("analyze", "analyze_many")


def _positional_solvers():
    found = set()
    for rel, tree in _sources():
        if rel.startswith("beveloid/cli/"):
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name in ANALYSES:
                if "solver" not in [p.arg for p in node.args.kwonlyargs]:
                    found.add((rel, node.name))
    return found


def test_every_analysis_takes_its_solver_keyword_only():
    only_pending({k: f"{k[0]}:{k[1]}" for k in _positional_solvers()}, PENDING_POSITIONAL_SOLVER,
                 "analyze(pair, options, *, solver=None): a keyword-only solver", "PENDING_POSITIONAL_SOLVER")


def test_the_older_call_forms_are_refused():
    """The forms before Options and Solver (errors or a torque in place of the options, keyword options,
    a backend name for a solver) raise at once, before any work; the deprecated helpers are gone."""
    import numpy as np

    from beveloid import contact_ellipse, ltca, sweep, tca
    from beveloid.solver import Solver

    for call in (lambda: tca.analyze(None, np.zeros(5)), lambda: tca.analyze(None, positions=3),
                 lambda: ltca.analyze(None, 100.0, "right"), lambda: ltca.analyze(None, ltca.Options()), lambda: sweep.analyze(None, flank="right"),
                 lambda: tca.analyze(None, tca.Options(), Solver()), lambda: Solver.of("numpy")):
        with pytest.raises(TypeError):
            call()
    assert not hasattr(sweep, "sweep") and not hasattr(contact_ellipse, "attach")
    assert not hasattr(ltca, "GridOptions") and not hasattr(tca, "as_solver") and not hasattr(tca, "resolve_backend")


#: (file, status string) still written as a literal outside beveloid/status.py, owned by other work items
PENDING_STATUS_LITERALS: set = set()


def _status_values() -> set:
    """The strings of every status enum of beveloid/status.py (one StrEnum per kind of status)."""
    import enum

    from beveloid import status

    kinds = [v for v in vars(status).values()
             if isinstance(v, type) and issubclass(v, enum.StrEnum) and v.__module__ == status.__name__]
    assert len(kinds) >= 5, kinds
    return {member.value for kind in kinds for member in kind}


def _status_literals(rel: str, tree: ast.AST, values: set) -> dict:
    """{(file, string): where} of the string constants of ``tree`` that are a status, besides docstrings,
    dict keys and subscripts (a field name, not a status), ``__all__`` (a submodule) and the members of an
    enum (errors.ErrorCode's own codes)."""
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Expr):
            skip.add(id(node.value))
        elif isinstance(node, ast.Dict):
            skip.update(id(k) for k in node.keys if k is not None)
        elif isinstance(node, ast.Subscript):
            skip.add(id(node.slice))
        elif isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            skip.update(id(n) for n in ast.walk(node.value))
        elif isinstance(node, ast.ClassDef) and any("Enum" in ast.unparse(b) for b in node.bases):
            skip.update(id(n) for stmt in node.body if isinstance(stmt, ast.Assign) for n in ast.walk(stmt.value))
    return {(rel, node.value): f"{rel}:{node.lineno} {node.value!r}" for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in values
            and id(node) not in skip}


def test_the_status_finder_finds_a_status_literal_and_only_it():
    tree = ast.parse('"""ok"""\n__all__ = ["edge"]\nclass E(enum.StrEnum):\n    A = "failed"\n'
                     'd = {"ok": x["edge"]}\ns = ("ok" if a else "no contact")\n')
    found = _status_literals("m.py", tree, {"ok", "edge", "failed", "no contact"})
    assert set(found) == {("m.py", "ok"), ("m.py", "no contact")}
    assert found[("m.py", "ok")] == "m.py:6 'ok'"


def _written_statuses(rel: str, tree: ast.AST) -> dict:
    """{(file, string): where} of the strings written as a status whatever their value: ``x["status"] = "..."``,
    ``status="..."`` and ``{"status": "..."}`` (a status missing from every enum escapes _status_literals)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Subscript) and isinstance(t.slice, ast.Constant)
                                                and t.slice.value == "status" for t in node.targets):
            found.append(node.value)
        elif isinstance(node, ast.keyword) and node.arg == "status":
            found.append(node.value)
        elif isinstance(node, ast.Dict):
            found += [v for k, v in zip(node.keys, node.values) if isinstance(k, ast.Constant) and k.value == "status"]
    return {(rel, v.value): f"{rel}:{v.lineno} {v.value!r}" for v in found
            if isinstance(v, ast.Constant) and isinstance(v.value, str)}


def test_the_written_status_finder_finds_a_status_outside_the_enums():
    tree = ast.parse('r["status"] = "incomplete"\nf(status="odd")\nd = {"status": "new", "x": "y"}\n'
                     'r["status"] = S.OK\nr["other"] = "z"\n')
    assert set(_written_statuses("m.py", tree)) == {("m.py", "incomplete"), ("m.py", "odd"), ("m.py", "new")}


def test_statuses_are_built_from_the_enums_of_status_py():
    """A status (of a point, a loaded position, an ellipse, a tooth, a design, ...) is a member of its enum in
    beveloid/status.py, never a string written out elsewhere (docs/architecture.md, "Statuses")."""
    values = _status_values()
    found = {}
    for rel, tree in _sources():
        if rel != "beveloid/status.py":
            found.update(_status_literals(rel, tree, values))
            found.update(_written_statuses(rel, tree))
    only_pending(found, PENDING_STATUS_LITERALS, "build a status from its enum in beveloid/status.py",
                 "PENDING_STATUS_LITERALS")


def test_the_status_enums_are_their_json_strings_and_label_the_codes():
    import json

    from beveloid.status import DesignStatus, LoadedStatus, Outcome, PointStatus, Status

    assert [s.name for s in Status] == [p.name for p in PointStatus]
    assert [o.name for o in Outcome] == [d.name for d in DesignStatus]
    assert [s.label for s in Status] == ["ok", "edge", "outside", "failed"]
    assert Status.labels([3, 0]) == [PointStatus.FAILED, PointStatus.OK]
    assert Outcome.POINTED_TEETH.label == "pointed_teeth"
    statuses = [PointStatus.EDGE, LoadedStatus.NO_CONTACT]
    assert json.dumps({s: s for s in statuses}) == '{"edge": "edge", "no contact": "no contact"}'
    assert f"{LoadedStatus.NOT_CONVERGED}|{PointStatus.OK:>4}" == "not converged|  ok"


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


# ---------------------------------------------------------------------------------------------
# the layers of docs/architecture.md, imports and names across packages
# ---------------------------------------------------------------------------------------------

ARCHITECTURE = ROOT / "docs" / "architecture.md"
#: (file, the unit it imports) that runs up the layers, owned by other work items
PENDING_UPWARD = {
    ("beveloid/spec/validate.py", "rating/"),  # the hardness check of a spec reads rating/materials.py
    ("beveloid/spec/validate.py", "tribology/"),  # [lubricant]'s check reads tribology/lubricant.py (grades, oils)
    ("beveloid/ltca/results/plots.py", "plots.py"),  # the LTCA's figures draw the flank outline of the top-level plots
    ("beveloid/tribology/plots.py", "plots.py"),  # so do the tribology's
    ("beveloid/rating/analysis.py", "plots.py"),  # the pinion angle's text of its notes
}
#: groups of units that import each other (an import cycle between packages), owned by other work items
PENDING_PACKAGE_CYCLES = {frozenset({"spec/", "rating/"})}
#: files of derivations/ that import the runtime (beyond beveloid.generated)
PENDING_DERIVATIONS_RUNTIME = {"derivations/user_model.py"}  # it builds a Pair to check a user model
#: (file, name) importing a private name of another package, owned by other work items
PENDING_PRIVATE_IMPORTS = {("beveloid/optimize/report.py", "_plt"), ("beveloid/optimize/report.py", "_colorbar")}
#: what the solver core may import of the package: itself, the generated kernels and the status codes
SOLVER_IMPORTS = {"solver/", "generated/", "status.py"}
#: (file, unit) of solver/ importing more, owned by other work items
PENDING_SOLVER_IMPORTS = {("beveloid/solver/patch_cover.py", "errors.py")}  # UnboundedPatch is a UserError
#: the only modules of beveloid/ that reach derivations/ (sympy): inside their ``run``
DERIVATIONS_CALLERS = {"beveloid/cli/derive.py", "beveloid/cli/verify.py"}


class Import(typing.NamedTuple):
    file: str  # relative to the checkout
    line: int
    module: str  # absolute
    name: str | None  # of ``from module import name``
    in_function: bool


def only_pending(found: dict, pending: set, rule: str, name: str) -> None:
    """``found`` ({finding: where, said in a few words}) breaks ``rule`` only in the entries of the
    pending list ``name`` (``pending``), and each of those still breaks it."""
    new = [where for key, where in sorted(found.items(), key=lambda kv: str(kv[0])) if key not in pending]
    assert not new, f"{rule}: {new}"
    fixed = pending - set(found)
    assert not fixed, f"these keep the rule ({rule}) now: remove them from {name}: {sorted(map(str, fixed))}"


def _scoped(node, in_function=False):
    """Every node below ``node`` with whether it lies inside a function."""
    for child in ast.iter_child_nodes(node):
        yield child, in_function
        yield from _scoped(child, in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)))


@functools.lru_cache(maxsize=None)
def _imports(folder: str) -> tuple:
    out = []
    for rel, tree in _parsed(folder):
        for node, in_function in _scoped(tree):
            if isinstance(node, ast.Import):
                out += [Import(rel, node.lineno, a.name, None, in_function) for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                out += [Import(rel, node.lineno, _absolute(rel, node), a.name, in_function) for a in node.names]
    return tuple(out)


def _unit(module: str) -> str | None:
    """The unit of an absolute module name: "tca/" (beveloid.tca and its modules), "pair.py", "generated/"
    (beveloid.generated, or generated in a checkout), "derivations/"; None outside the package and for
    names of the root package itself (``__version__``)."""
    parts = module.split(".")
    if parts[0] in ("generated", "derivations"):
        return parts[0] + "/"
    if parts[0] != "beveloid" or len(parts) == 1:
        return None
    if parts[1] in ("generated", "derivations") or (PACKAGE / parts[1] / "__init__.py").is_file():
        return parts[1] + "/"
    return f"{parts[1]}.py" if (PACKAGE / f"{parts[1]}.py").is_file() else None


def _target(imp: Import) -> str | None:
    """The unit an import reaches (``from beveloid import tca``: tca/, not the root package)."""
    return _unit(f"{imp.module}.{imp.name}") if imp.module == "beveloid" and imp.name else _unit(imp.module)


def _unit_of_file(rel: str) -> str | None:
    return _unit(rel[:-3].replace("/", ".").removesuffix(".__init__"))


def _runtime_units() -> set:
    """generated/, every package of beveloid/ and every top-level module but __init__.py."""
    packages = {p.parent.name + "/" for p in PACKAGE.glob("*/__init__.py")}
    modules = {p.name for p in PACKAGE.glob("*.py") if p.name != "__init__.py"}
    return packages | modules | {"generated/"}


def layers() -> dict:
    """{unit: layer} from the lines ``layer N  unit unit ...`` of docs/architecture.md."""
    out = {}
    for line in ARCHITECTURE.read_text(encoding="utf-8").splitlines():
        m = re.match(r"layer (\d+) +(\S.*)$", line)
        if m:
            for unit in m.group(2).split():
                assert unit not in out, f"docs/architecture.md puts {unit} in two layers"
                out[unit] = int(m.group(1))
    return out


def test_architecture_places_every_unit_of_the_runtime_in_one_layer():
    placed, units = set(layers()), _runtime_units()
    assert units - placed == set(), f"give these a layer in docs/architecture.md: {sorted(units - placed)}"
    assert placed - units == set(), f"docs/architecture.md places what does not exist: {sorted(placed - units)}"


def test_no_import_runs_up_the_layers():
    """A unit imports units of its own layer or below (in a function too: it runs all the same)."""
    layer = layers()
    found = {}
    for imp in _imports("beveloid"):
        src, dst = _unit_of_file(imp.file), _target(imp)
        if src in layer and dst in layer and layer[dst] > layer[src]:
            found.setdefault((imp.file, dst), f"{imp.file}:{imp.line} imports {dst}")
    only_pending(found, PENDING_UPWARD, "no import runs up the layers of docs/architecture.md", "PENDING_UPWARD")


def _unit_graph() -> dict:
    graph = {}
    for imp in _imports("beveloid"):
        src, dst = _unit_of_file(imp.file), _target(imp)
        if src and dst and src != dst:
            graph.setdefault(src, {}).setdefault(dst, f"{imp.file}:{imp.line}")
    return graph


def _cycles(graph: dict) -> set:
    """The groups of nodes that reach each other (strongly connected, more than one node)."""
    reach = {}
    for start in graph:
        seen, todo = set(), [start]
        while todo:
            for nxt in graph.get(todo.pop(), ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        reach[start] = seen
    return {frozenset({a} | {b for b in reach[a] if a in reach.get(b, ())}) for a in graph if a in reach[a]}


def test_the_cycle_finder_finds_a_cycle_and_only_it():
    assert _cycles({"a": {"b": ""}, "b": {"c": ""}, "c": {"a": ""}, "d": {"a": ""}}) == {frozenset("abc")}
    assert _cycles({"a": {"b": ""}, "b": {}}) == set()


def test_no_import_cycle_between_packages():
    """No two units import each other, directly or round a loop (between modules: tests/docs/test_docs_checkout.py)."""
    graph = _unit_graph()
    found = {c: ", ".join(f"{a} -> {b} ({graph[a][b]})" for a in sorted(c) for b in sorted(c) if b in graph.get(a, ()))
             for c in _cycles(graph)}
    only_pending(found, PENDING_PACKAGE_CYCLES, "no import cycle between units", "PENDING_PACKAGE_CYCLES")


def test_derivations_do_not_import_the_runtime():
    """derivations/ (sympy, build time) reads nothing of beveloid/ but the kernels it generated."""
    found = {}
    for imp in _imports("derivations"):
        dst = _target(imp)
        if dst is not None and dst not in ("generated/", "derivations/"):
            found.setdefault(imp.file, f"{imp.file}:{imp.line} imports {dst}")
    only_pending(found, PENDING_DERIVATIONS_RUNTIME, "derivations/ imports nothing of the runtime",
                 "PENDING_DERIVATIONS_RUNTIME")


def test_the_runtime_never_imports_sympy_and_reaches_derivations_only_from_derive_and_verify():
    bad = []
    for imp in _imports("beveloid"):
        if imp.module.split(".")[0] == "sympy":
            bad.append(f"{imp.file}:{imp.line} imports sympy")
        elif _target(imp) == "derivations/" and not (imp.file in DERIVATIONS_CALLERS and imp.in_function):
            bad.append(f"{imp.file}:{imp.line} imports {imp.module} (only {sorted(DERIVATIONS_CALLERS)}, in a function)")
    assert not bad, bad
    assert {i.file for i in _imports("beveloid") if _target(i) == "derivations/"} == DERIVATIONS_CALLERS


def test_no_private_name_crosses_a_package():
    """``from x import _name`` only within a unit: a private name is not another package's to use."""
    found = {}
    for imp in _imports("beveloid"):
        if imp.name and imp.name.startswith("_") and not imp.name.startswith("__"):
            if _target(imp) not in (None, _unit_of_file(imp.file)):
                found.setdefault((imp.file, imp.name), f"{imp.file}:{imp.line} imports {imp.name} of {_target(imp)}")
    only_pending(found, PENDING_PRIVATE_IMPORTS, "no private name crosses a package", "PENDING_PRIVATE_IMPORTS")


def test_the_solver_imports_only_itself_the_generated_kernels_and_the_status_codes():
    found = {}
    for imp in _imports("beveloid"):
        if imp.file.startswith("beveloid/solver/"):
            dst = _target(imp)
            if dst is not None and dst not in SOLVER_IMPORTS:
                found.setdefault((imp.file, dst), f"{imp.file}:{imp.line} imports {dst}")
    only_pending(found, PENDING_SOLVER_IMPORTS, f"the solver imports only {sorted(SOLVER_IMPORTS)}",
                 "PENDING_SOLVER_IMPORTS")


# ---------------------------------------------------------------------------------------------
# The contract of every analysis (docs/api.md): ``beveloid.<analysis>.analyze(pair, options=None, *,
# solver=None)`` (unloaded) or ``analyze(pair, load, options=None, *, solver=None)`` (loaded, with an
# ``ltca.LoadCase``) -> a :class:`beveloid.result.Result`: deep-frozen, holding its pair and options, its
# JSON by ``to_json()`` with nothing passed in.

#: each analysis and whether it takes a load case
CONTRACT = {"tca": False, "sweep": False, "tooth": False, "ltca": True, "rating": True, "fecheck": True}
#: analyses whose ``analyze`` does not have the contract's signature yet, owned by other work items
PENDING_CONTRACT: set = set()


def _signature_breaks(fn, loaded: bool) -> str | None:
    """What is wrong with ``fn``'s signature against the contract (None: nothing)."""
    import inspect

    if fn is None:
        return "no analyze on the package's face"
    params = list(inspect.signature(fn).parameters.values())
    if any(p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in params):
        return "takes *args or **kwargs"
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    expected = ["pair", "load", "options"] if loaded else ["pair", "options"]
    if [p.name for p in positional] != expected:
        return f"positional parameters {[p.name for p in positional]}, not {expected}"
    if any(p.default is not p.empty for p in positional[:-1]) or positional[-1].default is not None:
        return f"{', '.join(expected[:-1])} without a default and options=None"
    keywords = {p.name: p for p in params if p.kind == p.KEYWORD_ONLY}
    if "solver" not in keywords or keywords["solver"].default is not None:
        return "no keyword-only solver=None"
    if any(p.default is p.empty for p in keywords.values()):
        return "a keyword-only parameter without a default"
    return None


def test_the_signature_checker_finds_what_breaks_the_contract():
    def good(pair, options=None, *, solver=None, progress=None): ...
    def loaded(pair, load, options=None, *, solver=None): ...
    def positional_solver(pair, options=None, solver=None): ...
    def options_required(pair, options, *, solver=None): ...
    def no_load(pair, options=None, *, solver=None): ...
    assert _signature_breaks(good, False) is None and _signature_breaks(loaded, True) is None
    assert all(_signature_breaks(f, loaded) for f, loaded in ((positional_solver, False), (options_required, False),
                                                               (no_load, True), (good, True), (None, False)))


def test_every_analysis_has_the_contract_signature():
    found = {}
    for name, loaded in CONTRACT.items():
        why = _signature_breaks(getattr(importlib.import_module(f"beveloid.{name}"), "analyze", None), loaded)
        if why is not None:
            found[name] = f"beveloid.{name}.analyze: {why}"
    only_pending(found, PENDING_CONTRACT, "analyze(pair[, load], options=None, *, solver=None)", "PENDING_CONTRACT")


def _writable(obj, path: str, seen: set, inputs=("pair",)) -> list:
    """Every place under ``obj`` that takes a write (by trying it, then undoing it): an array element, a key
    of a mapping, a list, a set, a dataclass field; walked through arrays of objects, mappings, sequences
    and dataclass fields, the inputs a result holds as given (``inputs``, its pair) left out."""
    import dataclasses
    from collections.abc import Mapping

    import numpy as np

    if id(obj) in seen or obj is None or isinstance(obj, (str, bytes, int, float, complex, type)):
        return []
    seen.add(id(obj))
    out = []
    if isinstance(obj, np.ndarray):
        if obj.size:
            try:
                obj.flat[0] = obj.flat[0]
                out.append(f"{path}[0] (array)")
            except ValueError:
                pass
        elif obj.flags.writeable:
            out.append(f"{path} (empty array, writeable)")
        if obj.dtype == object:
            for i, item in enumerate(obj.ravel()):
                out += _writable(item, f"{path}.flat[{i}]", seen)
        return out
    if isinstance(obj, Mapping):
        probe = object()
        try:
            obj[probe] = None  # type: ignore[index]
            out.append(f"{path}[new key] (mapping)")
            del obj[probe]  # type: ignore[attr-defined]
        except TypeError:
            pass
        for key, value in obj.items():
            out += _writable(value, f"{path}[{key!r}]", seen)
        return out
    if isinstance(obj, (list, set, bytearray)):
        return [f"{path} ({type(obj).__name__})"]
    if isinstance(obj, (tuple, frozenset)):
        for i, item in enumerate(obj):
            out += _writable(item, f"{path}[{i}]", seen)
        return out
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            value = getattr(obj, f.name)
            try:
                setattr(obj, f.name, value)
                out.append(f"{path}.{f.name} (field)")
            except (dataclasses.FrozenInstanceError, AttributeError):
                pass
            if f.name not in inputs:
                out += _writable(value, f"{path}.{f.name}", seen)
    return out


def test_the_walker_finds_every_kind_of_write():
    import dataclasses

    import numpy as np

    from beveloid.result import Frozen

    @dataclasses.dataclass
    class Open:
        x: int = 0

    @dataclasses.dataclass(frozen=True)
    class Shut:
        a: object
        b: object = None

    found = _writable(Shut((np.zeros(2), {"k": [1]}), Open()), "r", set())
    assert found == ["r.a[0][0] (array)", "r.a[1][new key] (mapping)", "r.a[1]['k'] (list)", "r.b.x (field)"]
    assert _writable(Frozen.__new__(Frozen), "r", set()) == []

    @dataclasses.dataclass(frozen=True)
    class Deep(Frozen):
        a: object
        b: object = None

    assert _writable(Deep((np.zeros(2), {"k": [1]}), Shut([1], np.ones(1))), "r", set()) == []


@pytest.fixture(scope="module")
def contract_results(pair1):
    """One small run of every analysis (the plate tooth for the loaded ones; fe-check's result built from
    its parts, its run is slow: tests/fecheck)."""
    import math

    from beveloid import ltca, rating, sweep, tca, tooth
    from beveloid import fecheck
    from beveloid.fecheck.result import CheckResult, ContactNumbers

    lt = ltca.Options(positions=3, tooth_model="plate")  # its JSON's patterns: ~0.6 s a result
    numbers = ContactNumbers.of([10.0, None], [900.0, math.inf], [0.5, 0.0], 12.5, {"pinion": 300.0, "gear": None}, 1.0)
    return {
        "tca": tca.analyze(pair1, tca.Options(positions=5)),
        "sweep": sweep.analyze(pair1, sweep.Options(samples=4, positions=5)),
        "tooth": tooth.analyze(pair1),
        "ltca": ltca.analyze(pair1, ltca.LoadCase(150.0), lt),
        "ltca.analyze_many": ltca.analyze_many(pair1, ltca.LoadCase([100.0]), lt),
        "rating": rating.analyze(pair1, ltca.LoadCase(150.0), rating.Options(lt)),
        "fecheck": CheckResult("2.21", 3, 0.25, "plate", [0, 1], -1.5, 1000, 4000, 1.0, 2.0, 3.0, numbers, numbers,
                               {"deck": "d.inp"}, ["a note"], [1000.0, None], [[0.2, 5.0], [0.1, math.nan]],
                               [{"tooth_pair": 0, "semi_axes_mm": [0.2, 5.0]}], pair=pair1,
                               options=fecheck.Options(), load=ltca.LoadCase(200.0)),
    }


@pytest.mark.parametrize("name", list(CONTRACT) + ["ltca.analyze_many"])
def test_every_result_is_a_result_with_its_pair_and_strict_json(contract_results, pair1, name):
    import json

    from beveloid.result import Result

    r = contract_results[name]
    assert isinstance(r, Result) and r.pair is pair1 and r.options is not None
    out = r.to_json()
    assert isinstance(out, dict) and out
    assert json.loads(json.dumps(out, allow_nan=False)) == out


@pytest.mark.parametrize("name", list(CONTRACT) + ["ltca.analyze_many"])
def test_every_result_is_frozen_all_the_way_down(contract_results, name):
    """Every nested array, mapping, sequence and dataclass field of a result refuses a write."""
    found = _writable(contract_results[name], name, set())
    assert not found, f"{len(found)} writable places, e.g. {found[:8]}"


def _run_results():
    """How a run of explore and of optimize ended (explore.run.ExploreRun, optimize.search.OptimizeRun),
    built from their parts: their runs are tested in tests/explore and tests/optimize."""
    from beveloid.errors import StopReason
    from beveloid.explore import run as explore_run
    from beveloid.explore.grid import Plan
    from beveloid.optimize import search
    from beveloid.optimize.request import Request, Vary
    from beveloid.spec import load_example, spec_to_dict

    plan = Plan(spec_to_dict(load_example("case1")), ())
    opt = Request(base={"pair": {"x": [1.0]}}, varies=(Vary("pinion.lead_crowning_um", 0.0, 40.0),),
                  torques_nm=(100.0,), weights=(1.0,))
    record = {"candidate": 0, "values": {"pinion.lead_crowning_um": 5.0}, "status": "ok",
              "objectives": {"pressure_mpa": 1.5}, "per_torque": {"pressure_mpa": [1.5]}}
    return {"explore": explore_run.ExploreRun("run", StopReason.INTERRUPTED, "interrupted (Ctrl-C)",
                                              options=explore_run.Request(plan, {"dx_mm": 0.5})),
            "optimize": search.OptimizeRun("opt", None, "", [record], options=opt)}


@pytest.mark.parametrize("name", ["explore", "optimize"])
def test_a_runs_result_is_frozen_all_the_way_down_with_strict_json(name):
    """explore's and optimize's runs return a Result too (no tuple): frozen, its JSON strict."""
    import json

    from beveloid.result import Result

    r = _run_results()[name]
    assert isinstance(r, Result) and r.pair is None and r.options is not None
    found = _writable(r, name, set())
    assert not found, f"{len(found)} writable places, e.g. {found[:8]}"
    out = r.to_json()
    assert isinstance(out, dict) and out["request"] and out["out_dir"]
    assert json.loads(json.dumps(out, allow_nan=False)) == out


#: a bad value of each analysis' options: (the analysis, the Options' import path, keyword arguments)
BAD_OPTIONS = [
    ("tca", "beveloid.tca:Options", {"positions": 0}),
    ("tca", "beveloid.tca:Options", {"approach_mm": -1.0}),
    ("sweep", "beveloid.sweep:Options", {"samples": 0}),
    ("sweep", "beveloid.sweep:Options", {"samples": 10_000_000, "positions": 10_000}),
    ("sweep", "beveloid.sweep:Options", {"ranges": {"dx_mm": -1.0}}),
    ("tooth", "beveloid.tooth:Options", {"contact_per_pitch": 2}),
    ("ltca", "beveloid.ltca:Options", {"positions": 0}),
    ("ltca", "beveloid.ltca:Options", {"flank": "up"}),
    ("ltca", "beveloid.ltca:Options", {"tooth_model": "beam"}),
    ("ltca", "beveloid.ltca:LoadCase", {"torque_nm": -1.0}),
    ("ltca", "beveloid.ltca:LoadCase", {"torque_nm": 100.0, "errors": (0.0, 1.0)}),
    ("rating", "beveloid.rating:Options", {"ltca": "positions=0"}),
    ("fecheck", "beveloid.fecheck:Options", {"refinement": 9}),
    ("fecheck", "beveloid.fecheck:Options", {"position": 20}),
    ("export", "beveloid.export:ExportOptions", {"chord_um": 9.0}),
]
#: (analysis, the refused keyword) still refused otherwise than by an OptionError naming its key, owned by
#: other work items
PENDING_OPTION_ERRORS: set = set()


def test_a_bad_option_is_one_option_error_naming_its_key_not_a_flag():
    """One error type for a bad option: an OptionError with the key, the value and what is valid; its
    line names the option's key, never a command-line flag (the CLI maps keys to flags)."""
    from beveloid.errors import OptionError

    found = {}
    for analysis, where, kwargs in BAD_OPTIONS:
        module, _, name = where.partition(":")
        bad = [k for k in kwargs if k != "torque_nm"][-1] if len(kwargs) > 1 or "torque_nm" not in kwargs else "torque_nm"
        try:
            getattr(importlib.import_module(module), name)(**kwargs)
        except OptionError as exc:
            if exc.key.split(".")[0] not in kwargs or "--" in str(exc) or not exc.requirement:
                found[(analysis, bad)] = f"{where}({kwargs}): {exc!r}"
            continue
        except Exception as exc:  # noqa: BLE001  (the wrong type is the finding)
            found[(analysis, bad)] = f"{where}({kwargs}): {type(exc).__name__}: {exc}"
            continue
        found[(analysis, bad)] = f"{where}({kwargs}) accepted"
    only_pending(found, PENDING_OPTION_ERRORS, "a bad option raises OptionError(key, value, requirement)",
                 "PENDING_OPTION_ERRORS")


def test_reading_a_spec_imports_no_analysis_and_the_lazy_names_resolve(tmp_path):
    """Issue 59: the spec's checks of a material and a lubricant (rating.materials, tribology.lubricant) import
    neither the rating's nor the tribology's analysis (nor the LTCA, scipy.special, sympy): their packages'
    names are imported on first use, and every one of them still resolves."""
    heavy = ("beveloid.rating.analysis", "beveloid.tribology.analysis", "beveloid.ltca", "scipy.special", "sympy")
    code = ("import sys; from beveloid.spec import load_example; load_example('case1');"
            " assert 'beveloid.rating.materials' in sys.modules and 'beveloid.tribology.lubricant' in sys.modules;"
            f" print([m for m in {heavy!r} if m in sys.modules])")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr
    from beveloid import rating, tribology
    from beveloid.rating import analysis
    from beveloid.tribology import cells

    assert rating.analyze is analysis.analyze and rating.RatingResult.__name__ == "RatingResult"
    assert rating.verdict.__module__ == "beveloid.rating.verdict"  # the function, not its module
    assert tribology.Cells is cells.Cells and tribology.build is cells.build
    assert callable(tribology.evaluate_cells) and tribology.PitchPoint.__name__ == "PitchPoint"
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        rating.nothing  # noqa: B018


def test_reading_ltca_results_imports_no_contact_sizing(tmp_path):
    """Issue 59: ``beveloid ltca --samples``'s own process asks the LTCA for a load case, the box's tasks and
    results to report (its workers analyse): ``beveloid.ltca`` names its compliance operator and patterns
    lazily (the Hertz sizing imports no scipy.special at all: its elliptic integrals are its own), so that process
    imports neither."""
    code = ("import sys, beveloid.ltca, beveloid.ltca.results.result, beveloid.ltca.studies;"
            " print([m for m in ('scipy.special', 'beveloid.ltca.model.compliance', 'numba') if m in sys.modules])")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr
    from beveloid import ltca
    from beveloid.ltca.mechanics import hertz
    from beveloid.ltca.model import compliance
    from beveloid.ltca.results import pattern, result

    assert ltca.BeveloidCompliance is compliance.BeveloidCompliance and ltca.LTCAResult is result.LTCAResult
    assert ltca.flank_pattern is pattern.flank_pattern and ltca.FlankPattern is pattern.FlankPattern
    assert hertz.hertz_point_contact(1e-3, 2e-3, 100.0, 2.3e5).semi_major_mm > 0
