"""The checkout works as a checkout: ``python -m pytest``, a REPL or a script run inside it
import the whole package (``beveloid.generated``, ``beveloid.derivations``), as an install does;
the runtime modules import each other without cycles."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_script_in_the_checkout_imports_the_whole_package():
    code = ("import sys; sys.path.insert(0, '.'); import beveloid, beveloid.generated.tca_kernels, "
            "beveloid.derivations.codegen, beveloid.solver.core; from pathlib import Path; "
            "print(Path(beveloid.__file__).resolve().parent.parent)")
    # -I: isolated (no user site, no PYTHONPATH); '.' first: the checkout shadows any install
    proc = subprocess.run([sys.executable, "-I", "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert Path(proc.stdout.strip()) == ROOT


def _runtime_imports():
    """{module: set of beveloid modules it imports at module level or in functions}."""
    out = {}
    for path in (ROOT / "beveloid").rglob("*.py"):
        mod = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
        deps = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level:
                base = pkg.split(".")
                base = base[:len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
                for alias in node.names:
                    deps.add(target if node.module else f"{target}.{alias.name}")
        out[mod] = {d for d in deps if d.startswith("beveloid") and not d.startswith("beveloid.generated")}
    return out


def test_runtime_has_no_import_cycles():
    graph = _runtime_imports()
    assert "beveloid.tca" in graph and "beveloid.solver.core" in graph
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for dep in sorted(graph.get(node, ())):
            if dep not in graph or dep == node:
                continue
            assert state.get(dep) != "open", "import cycle: " + " -> ".join(stack + [node, dep])
            if dep not in state:
                visit(dep, stack + [node])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [])


def test_every_runtime_package_is_installed():
    """pyproject.toml lists packages by name: a new beveloid/ subpackage must be listed too."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    present = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "beveloid").rglob("__init__.py")}
    assert present <= listed, f"not installed by pip install .: {sorted(present - listed)}"
    assert {"beveloid.derivations", "beveloid.generated"} <= listed
