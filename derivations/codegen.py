"""Code generator: symbolic models -> numpy-only modules in generated/.

One jinja2 template renders each module.  Every function is printed from one
common-subexpression elimination over all of its outputs (values and Jacobians together),
with the op count in a comment.  Output is deterministic: regeneration is byte-identical
for the pinned sympy range.

A generated function whose expressions have a free symbol missing from its argument list
is a generation-time error (after PyDy).
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from pathlib import Path

import jinja2
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.pycode import PythonCodePrinter

TEMPLATE_DIR = Path(__file__).parent / "templates"


class GenerationError(ValueError):
    pass


@dataclass(frozen=True)
class Arg:
    name: str
    symbol: sp.Symbol
    unit: str
    doc: str


@dataclass
class Output:
    name: str
    expr: object  # scalar Expr or Matrix
    unit: str
    doc: str


@dataclass
class Function:
    name: str
    doc: str
    inputs: list[Arg]
    outputs: list[Output]


@dataclass
class ModuleSpec:
    """One generated module: its file name, source model and functions."""
    module: str
    source: str  # derivations/<file>
    doc: str
    functions: list[Function] = field(default_factory=list)
    scalar_twin: bool = False  # also write <module>_scalar.py (one point per call) for the compiled path


class _Printer(NumPyPrinter):
    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "inline": True, "allow_unknown_functions": False})


class _ScalarPrinter(PythonCodePrinter):
    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "inline": True, "allow_unknown_functions": False})


def _entries(expr):
    if isinstance(expr, sp.MatrixBase):
        return list(expr), tuple(expr.shape) if expr.shape[1] != 1 else (expr.shape[0],)
    return [sp.sympify(expr)], ()


def render_function(fn: Function, cse=True, scalar=False):
    allowed = {a.symbol for a in fn.inputs}
    flat, shapes = [], []
    for o in fn.outputs:
        ents, shape = _entries(o.expr)
        free = set().union(*[sp.sympify(e).free_symbols for e in ents]) - allowed
        if free:
            raise GenerationError(f"{fn.name}: output {o.name} has free symbols {sorted(map(str, free))} "
                                  f"missing from its arguments")
        flat.append(ents)
        shapes.append(shape)
    rename = {a.symbol: sp.Symbol(a.name, real=True) for a in fn.inputs}
    if len({a.name for a in fn.inputs}) != len(fn.inputs):
        raise GenerationError(f"{fn.name}: duplicate argument names")
    names = {a.name for a in fn.inputs}
    for o in fn.outputs:
        if o.name in names or o.name.startswith("_"):
            raise GenerationError(f"{fn.name}: output name {o.name!r} clashes with an argument or a generated name")
    all_exprs = [sp.sympify(e).xreplace(rename) for ents in flat for e in ents]
    printer = _ScalarPrinter() if scalar else _Printer()
    body = []
    if cse:
        syms = sp.numbered_symbols("_x")
        repl, reduced = sp.cse(all_exprs, symbols=syms, order="canonical")
    else:
        repl, reduced = [], all_exprs
    ops = sum(sp.count_ops(v) for _, v in repl) + sum(sp.count_ops(e) for e in reduced)
    if not scalar:
        # every output carries the broadcast shape of all inputs, used or not
        body.append(f"_shape = numpy.broadcast_shapes({', '.join(f'numpy.shape({a.name})' for a in fn.inputs)})")
    for s_, v in repl:
        body.append(f"{s_} = {printer.doprint(v)}")
    k = 0
    returns = []
    for o, ents, shape in zip(fn.outputs, flat, shapes):
        exprs = reduced[k:k + len(ents)]
        k += len(ents)
        printed = [printer.doprint(e) for e in exprs]
        if scalar:
            for idx, text in zip(_indices(shape), printed):
                body.append(f"out_{o.name}[{idx}] = {text}")
            returns.append(o.name)
            continue
        if shape == ():
            body.append(f"{o.name} = _full({printed[0]}, _shape)")
        else:
            body.append(f"{o.name} = _stack([{', '.join(printed)}], {shape!r}, _shape)")
        returns.append(o.name)
    shape_doc = lambda sh: "" if sh == () else ", " + ", ".join(map(str, sh))  # noqa: E731
    outs = [dict(name=o.name, doc=o.doc, unit=o.unit, shape_doc=shape_doc(sh)) for o, sh in zip(fn.outputs, shapes)]
    args = [a.name for a in fn.inputs] + ([f"out_{o.name}" for o in fn.outputs] if scalar else [])
    full_name = fn.name + ("_point" if scalar else "")
    return dict(name=full_name, doc=fn.doc, signature=_signature(full_name, args),
                out_names=[f"out_{o.name}" for o in fn.outputs],
                inputs=[dict(name=a.name, doc=a.doc, unit=a.unit) for a in fn.inputs],
                outputs=outs, ops=ops, body=body, returns=", ".join(returns) + ("," if len(returns) == 1 else ""))


def _indices(shape):
    """Index expressions of an output array in C order ('0' for a scalar held in a 1-array)."""
    if shape == ():
        return ["0"]
    if len(shape) == 1:
        return [str(i) for i in range(shape[0])]
    return [f"{i}, {j}" for i in range(shape[0]) for j in range(shape[1])]


def _signature(name, args, width=100):
    """Argument list wrapped to ``width`` columns (black-like hanging indent)."""
    one = ", ".join(args)
    if len(name) + len(one) + 7 <= width:
        return one
    lines, cur = [], ""
    for a in args:
        piece = a + ", "
        if len(cur) + len(piece) + 4 > width:
            lines.append(cur.rstrip())
            cur = ""
        cur += piece
    lines.append(cur.rstrip())
    return "\n        " + "\n        ".join(lines) + "\n"


def _env():
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATE_DIR)), keep_trailing_newline=True,
                              trim_blocks=True, lstrip_blocks=False, undefined=jinja2.StrictUndefined)


def render_module(spec: ModuleSpec, cse=True) -> str:
    tpl = _env().get_template("module.py.jinja")
    fns = [render_function(f, cse=cse) for f in spec.functions]
    return tpl.render(source=spec.source, doc=spec.doc, functions=fns)


def render_scalar_module(spec: ModuleSpec, cse=True) -> str:
    """The scalar (one point, math-module) twin of a module, for the compiled path."""
    tpl = _env().get_template("scalar_module.py.jinja")
    fns = [render_function(f, cse=cse, scalar=True) for f in spec.functions]
    return tpl.render(source=spec.source, doc=spec.doc, functions=fns, numpy_module=spec.module)


def generate(out_dir, specs, cse=True, progress=None):
    """Render every module; returns {filename: text}."""
    files = {}
    for spec in specs:
        if progress:
            progress(spec.module)
        files[f"{spec.module}.py"] = render_module(spec, cse=cse)
        if spec.scalar_twin:
            files[f"{spec.module}_scalar.py"] = render_scalar_module(spec, cse=cse)
    files["__init__.py"] = _init_text(specs)
    return files


def _init_text(specs):
    lines = ["# Generated by `beveloid derive` (derivations/codegen.py). Do not edit.",
             '"""Numeric kernels generated from the symbolic models (numpy; the *_scalar twins use math)."""', ""]
    lines.append("MODULES = (" + "".join(f"\n    {s.module!r}," for s in specs) + "\n)")
    lines.append("SCALAR_MODULES = (" + "".join(f"\n    {s.module + '_scalar'!r}," for s in specs if s.scalar_twin) + "\n)")
    return "\n".join(lines) + "\n"


def write(out_dir, files):
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out_dir / name).write_text(text)


def diff(out_dir, files):
    """Unified diff between committed files and freshly generated ones ('' when up to date)."""
    out_dir = Path(out_dir)
    chunks = []
    present = {p.name for p in out_dir.glob("*.py")} if out_dir.exists() else set()
    for name in sorted(set(files) | present):
        old = (out_dir / name).read_text() if name in present else ""
        new = files.get(name, "")
        if old != new:
            chunks.extend(difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                               f"{out_dir.name}/{name} (committed)", f"{out_dir.name}/{name} (regenerated)"))
    return "".join(chunks)
