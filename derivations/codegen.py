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

from .common import atoms_of, free_symbols_of, xreplace_all
from .interface import Field, Layout  # noqa: F401  (the models' interface; re-exported)

TEMPLATE_DIR = Path(__file__).parent / "templates"


class GenerationError(ValueError):
    pass


@dataclass(frozen=True)
class Arg:
    """A kernel argument: a scalar symbol, a sympy Matrix of symbols (a vector or matrix
    argument, e.g. a surface point) or a :class:`Layout` (a named parameter vector)."""
    name: str
    symbol: object
    unit: str = ""
    doc: str = ""

    def entries(self):
        """[(local name, symbol, index)] with index None (scalar), i or (i, j)."""
        s = self.symbol
        if isinstance(s, Layout):
            return [(f.name, f.symbol, i) for i, f in enumerate(s.fields)]
        if isinstance(s, sp.MatrixBase):
            rows, cols = s.shape
            if cols == 1:
                return [(f"{self.name}_{i}", s[i, 0], i) for i in range(rows)]
            return [(f"{self.name}_{i}{j}", s[i, j], (i, j)) for i in range(rows) for j in range(cols)]
        return [(self.name, s, None)]

    @property
    def shape(self):
        s = self.symbol
        if isinstance(s, Layout):
            return (len(s.fields),)
        if isinstance(s, sp.MatrixBase):
            return (s.shape[0],) if s.shape[1] == 1 else tuple(s.shape)
        return ()

    @property
    def symbols(self):
        return [e[1] for e in self.entries()]


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
    #: named intermediate values ((Symbol, expr), ... in order; an expr may use earlier ones) that
    #: the outputs are written over: computed first, with their own common-subexpression pass, so
    #: that a model composed on another's jets never becomes one expression tree (only those the
    #: outputs need are emitted)
    stages: tuple = ()

    @property
    def outputs_class(self):
        """Name of the generated NamedTuple that the numpy kernel returns."""
        return "".join(w.capitalize() for w in self.name.split("_"))


@dataclass
class ModuleSpec:
    """One generated module: its file name, source model and functions."""
    module: str
    source: str  # derivations/<file>
    doc: str
    functions: list[Function] = field(default_factory=list)
    scalar_twin: bool = False  # also write <module>_scalar.py (one point per call) for the compiled path
    constants: dict = field(default_factory=dict)  # name -> python literal (repr'd into the module)
    extra_layouts: tuple = ()  # layouts the runtime reads results with, beyond the arguments' own

    def layouts(self):
        out = {lay.name: lay for lay in self.extra_layouts}
        for fn in self.functions:
            for a in fn.inputs:
                if isinstance(a.symbol, Layout):
                    out[a.symbol.name] = a.symbol
        return out


_PRINTER_SETTINGS = {"fully_qualified_modules": True, "inline": True, "allow_unknown_functions": False}


class _NoCode(GenerationError):
    """An expression a printer has no code for: one sympy cannot differentiate (``floor``, an
    undefined function) stays an unevaluated Derivative; the second derivative of ``Abs`` is a
    ``DiracDelta``.  :func:`_rendered` names it as the model wrote it (the printer sees it after the
    common-subexpression pass, over ``_x`` symbols)."""

    def __init__(self, node, module):
        self.node, self.module = node, module
        super().__init__(self.explain(node))

    def explain(self, node):
        if isinstance(node, sp.Derivative):
            return f"sympy cannot differentiate {_short(node.expr)} (its derivative stays unevaluated)"
        return f"{_short(node)} has no {self.module} code"

    def in_terms_of(self, exprs):
        """The explanation with the node found in ``exprs`` (those before the reduction)."""
        found = atoms_of(exprs, type(self.node))
        return self.explain(min(found, key=sp.default_sort_key) if found else self.node)


def _short(expr, limit=100):
    text = sp.sstr(expr)
    return text if len(text) <= limit else text[:limit - 3] + "..."


class _Strict:
    """What a printer has no code for raises _NoCode (sympy's strict printing names only a class);
    the calls it printed into other modules than ``module`` (``erf``: a math form, no numpy one)
    are :meth:`foreign_calls`."""

    #: the one module the generated code may call (its template imports only that)
    module = ""

    def _print_not_supported(self, expr):
        raise _NoCode(expr, self.module)

    def _print_Derivative(self, expr):
        raise _NoCode(expr, self.module)

    def foreign_calls(self):
        return sorted(f"{m}.{f}" for m, fs in self.module_imports.items() if m != self.module for f in fs)


class _Printer(_Strict, NumPyPrinter):
    module = "numpy"

    def __init__(self, **settings):
        super().__init__({**_PRINTER_SETTINGS, **settings})


class _ScalarPrinter(_Strict, PythonCodePrinter):
    module = "math"

    def __init__(self, **settings):
        super().__init__({**_PRINTER_SETTINGS, **settings})


def _entries(expr):
    if isinstance(expr, sp.MatrixBase):
        return list(expr), tuple(expr.shape) if expr.shape[1] != 1 else (expr.shape[0],)
    return [sp.sympify(expr)], ()


def _unpack_line(arg, local, index, scalar):
    if index is None:
        return None
    if isinstance(index, tuple):
        idx = f"{index[0]}, {index[1]}"
    else:
        idx = str(index)
    return f"{local} = {arg.name}[{idx}]" if scalar else f"{local} = {arg.name}[..., {idx}]"


@dataclass(frozen=True)
class _Reduced:
    """What a function's numpy kernel and its scalar twin share: the arguments' entries, the
    outputs' flattened expressions and shapes, the stage levels and the common-subexpression
    passes (symbolic work, done once for both printings)."""

    entries: list
    flat: list
    shapes: list
    stage_levels: list  # [(group of (symbol, expr), (replacements, reduced)) per level]
    repl: list
    reduced: list
    ops: int


def _reduce(fn: Function, cse: bool) -> _Reduced:
    entries = [(a, local, sym, idx) for a in fn.inputs for local, sym, idx in a.entries()]
    allowed = {sym for _, _, sym, _ in entries}
    if len(allowed) != len(entries):
        raise GenerationError(f"{fn.name}: a symbol appears twice among the arguments")
    flat, shapes = [], []
    memo = {}
    for o in fn.outputs:
        ents, shape = _entries(o.expr)
        free = free_symbols_of(ents, memo) - allowed
        free -= {sym for sym, _ in fn.stages}
        if free:
            raise GenerationError(f"{fn.name}: output {o.name} has free symbols {sorted(map(str, free))} "
                                  f"missing from its arguments")
        flat.append(ents)
        shapes.append(shape)
    names = [a.name for a in fn.inputs]
    locals_ = [local for _, local, _, _ in entries]
    if len(set(names)) != len(names) or len(set(locals_) | set(names)) != len(set(locals_) | set(names)) \
            or len(set(locals_)) != len(locals_):
        raise GenerationError(f"{fn.name}: duplicate argument names")
    for o in fn.outputs:
        if o.name in names or o.name in locals_ or o.name.startswith("_"):
            raise GenerationError(f"{fn.name}: output name {o.name!r} clashes with an argument or a generated name")
    rename = {sym: sp.Symbol(local, real=True) for _, local, sym, _ in entries}
    # derived layout entries (a layout's trig setting) replace the expressions they hold
    derived = {f.derived: f.symbol for a in fn.inputs if isinstance(a.symbol, Layout) for f in a.symbol.derived_fields()}
    all_exprs = xreplace_all(xreplace_all([e for ents in flat for e in ents], derived), rename)
    stages = _needed_stages(fn, all_exprs, allowed)
    stage_exprs = xreplace_all(xreplace_all([e for _, e in stages], derived), rename)
    levels = []
    for level, group in enumerate(_stage_levels(stages, stage_exprs)):
        # the intermediate values first, level by level (a level uses only earlier ones), each level
        # with its own CSE (symbols _y, _y1_, ...)
        exprs = [e for _, e in group]
        prefix = "_y" if level == 0 else f"_y{level}_"
        levels.append((group, sp.cse(exprs, symbols=sp.numbered_symbols(prefix), order="canonical") if cse
                       else ([], exprs)))
    if cse:
        repl, reduced = sp.cse(all_exprs, symbols=sp.numbered_symbols("_x"), order="canonical")
    else:
        repl, reduced = [], all_exprs
    ops = sum(sp.count_ops(v) for _, v in repl) + sum(sp.count_ops(e) for e in reduced)
    for _group, (srepl, sreduced) in levels:
        ops += sum(sp.count_ops(v) for _, v in srepl) + sum(sp.count_ops(e) for e in sreduced)
    return _Reduced(entries, flat, shapes, levels, repl, reduced, ops)


def render_function(fn: Function, cse=True, scalar=False, reduced_by=None):
    """The template's view of one function.  ``reduced_by``: a dict shared by the renderings of
    one module (its numpy kernels and their scalar twins reduce each function once)."""
    key = (fn.name, cse)
    if reduced_by is not None and key in reduced_by:
        red = reduced_by[key]
    else:
        red = _reduce(fn, cse)
        if reduced_by is not None:
            reduced_by[key] = red
    entries, flat, shapes, repl, reduced = red.entries, red.flat, red.shapes, red.repl, red.reduced
    # The committed (CSE) build prints sums in sympy's canonical term order; the plain build exists
    # only to be compared numerically, so it skips that ordering (a third of its printing time).
    order = {} if cse else {"order": "none"}
    printer = _ScalarPrinter(**order) if scalar else _Printer(**order)
    full_name = fn.name + ("_point" if scalar else "")
    body = []
    stage_lines = []
    for group, (srepl, sreduced) in red.stage_levels:
        stage_lines += [f"{s_} = {printer.doprint(v)}" for s_, v in srepl]
        stage_lines += [f"{sym} = {printer.doprint(v)}" for (sym, _), v in zip(group, sreduced)]
    if not scalar:
        # every output carries the broadcast shape of all inputs, used or not
        def batch(a):
            k = len(a.shape)
            return f"numpy.shape({a.name})" + (f"[:-{k}]" if k else "")
        body.append(f"_shape = numpy.broadcast_shapes({', '.join(batch(a) for a in fn.inputs)})")
    for a, local, _, idx in entries:
        line = _unpack_line(a, local, idx, scalar)
        if line:
            body.append(line)
    body.extend(stage_lines)
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
    if printer.foreign_calls():
        raise GenerationError(f"{full_name}: {', '.join(printer.foreign_calls())} has no {printer.module} form"
                              f" (the module calls {printer.module} only)")
    shape_doc = lambda sh: "" if sh == () else ", " + ", ".join(map(str, sh))  # noqa: E731
    outs = [dict(name=o.name, doc=o.doc, unit=o.unit, shape_doc=shape_doc(sh)) for o, sh in zip(fn.outputs, shapes)]
    args = [a.name for a in fn.inputs] + ([f"out_{o.name}" for o in fn.outputs] if scalar else [])

    def arg_doc(a):
        if isinstance(a.symbol, Layout):
            return dict(name=a.name, doc=f"{a.doc} (layouts.{a.symbol.name})", unit=a.unit or "see layout",
                        shape_doc=shape_doc(a.shape))
        return dict(name=a.name, doc=a.doc, unit=a.unit, shape_doc=shape_doc(a.shape))

    return dict(name=full_name, doc=fn.doc, signature=_signature(full_name, args),
                out_names=[f"out_{o.name}" for o in fn.outputs], outputs_class=fn.outputs_class,
                inputs=[arg_doc(a) for a in fn.inputs],
                outputs=outs, ops=red.ops, body=body, returns=", ".join(returns))


def _needed_stages(fn, exprs, allowed):
    """The stages (fn.stages, in order) that the expressions need, directly or through other stages."""
    if not fn.stages:
        return []
    names = {sym for sym, _ in fn.stages}
    memo = {}
    need = free_symbols_of(exprs, memo) & names
    out = []
    for sym, expr in reversed(fn.stages):
        if sym in need:
            free = free_symbols_of([expr], memo)
            if free - allowed - names:
                raise GenerationError(f"{fn.name}: stage {sym} has free symbols {sorted(map(str, free - allowed - names))}")
            need |= free & names
            out.append((sym, expr))
    return out[::-1]


def _stage_levels(stages, exprs):
    """[[(symbol, expr), ...] per level]: level 0 uses no other stage, level k only levels < k."""
    names = {sym for sym, _ in stages}
    level = {}
    memo = {}
    for (sym, _), e in zip(stages, exprs):
        deps = free_symbols_of([e], memo) & names
        level[sym] = 1 + max((level[d] for d in deps), default=-1)
    groups = [[] for _ in range(1 + max(level.values(), default=-1))]
    for (sym, _), e in zip(stages, exprs):
        groups[level[sym]].append((sym, e))
    return groups


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


def _rendered(fn: Function, **options):
    """render_function; what it fails on names the kernel (a GenerationError's message, else the
    note ``generating <kernel>`` on sympy's exception)."""
    try:
        return render_function(fn, **options)
    except _NoCode as exc:
        exprs = [e for o in fn.outputs for e in _entries(o.expr)[0]] + [e for _, e in fn.stages]
        raise GenerationError(f"{fn.name}: {exc.in_terms_of(exprs)}") from None
    except GenerationError:
        raise
    except Exception as exc:
        exc.add_note(f"generating {fn.name}")
        raise


def render_module(spec: ModuleSpec, cse=True, reduced_by=None) -> str:
    """A module of numpy kernels (``reduced_by``: see :func:`render_function`)."""
    tpl = _env().get_template("module.py.jinja")
    fns = [_rendered(f, cse=cse, reduced_by=reduced_by) for f in spec.functions]
    return tpl.render(source=spec.source, doc=spec.doc, functions=fns,
                      constants=[(k, repr(v)) for k, v in spec.constants.items()])


def render_scalar_module(spec: ModuleSpec, cse=True, reduced_by=None) -> str:
    """The scalar (one point, math-module) twin of a module, for the compiled path."""
    tpl = _env().get_template("scalar_module.py.jinja")
    fns = [_rendered(f, cse=cse, scalar=True, reduced_by=reduced_by) for f in spec.functions]
    return tpl.render(source=spec.source, doc=spec.doc, functions=fns, numpy_module=spec.module)


def render_layouts(specs) -> str:
    """generated/layouts.py: one NamedTuple per parameter layout used by any kernel."""
    layouts = {}
    for spec in specs:
        for name, lay in spec.layouts().items():
            if name in layouts and layouts[name] != lay:
                raise GenerationError(f"two different layouts are both named {name}")
            layouts[name] = lay
    printer = _Printer()

    def derived_code(lay, f):
        names = {b.symbol: sp.Symbol(b.name, real=True) for b in lay.base_fields()}
        return printer.doprint(f.derived.xreplace(names))

    return _env().get_template("layouts.py.jinja").render(layouts=[
        dict(name=lay.name, doc=lay.doc, fields=lay.fields, base=lay.base_fields(),
             derived=[dict(name=f.name, code=derived_code(lay, f)) for f in lay.derived_fields()])
        for lay in (layouts[k] for k in sorted(layouts))])


def render_template(template, **context) -> str:
    """Render one of derivations/templates/ (the glue modules of kernels.py)."""
    return _env().get_template(template).render(**context)


def generate(out_dir, specs, cse=True, progress=None, extra=None, rendered_by=None):
    """Render every module; returns {filename: text}.  ``extra``: {filename: text} rendered
    elsewhere (the glue modules that compose kernels), listed in the package like the others.
    ``rendered_by``: a dict kept by the caller across calls; a spec object rendered before (with
    the same ``cse``) is not rendered again (a registry variant shares every module but its
    surfaces with the registry)."""
    files = {}
    for spec in specs:
        if progress:
            progress(spec.module)
        key = (id(spec), cse)
        if rendered_by is not None and key in rendered_by:
            files.update(rendered_by[key][1])
            continue
        reduced_by = {}  # the module's functions, reduced once for both of its files
        texts = {f"{spec.module}.py": render_module(spec, cse=cse, reduced_by=reduced_by)}
        if spec.scalar_twin:
            texts[f"{spec.module}_scalar.py"] = render_scalar_module(spec, cse=cse, reduced_by=reduced_by)
        if rendered_by is not None:
            rendered_by[key] = (spec, texts)  # the spec is kept: its id stays its own
        files.update(texts)
    files["layouts.py"] = render_layouts(specs)
    files.update(extra or {})
    files["__init__.py"] = _init_text(specs, extra or {})
    return files


def _init_text(specs, extra):
    lines = ["# Generated by `beveloid derive` (derivations/codegen.py). Do not edit.",
             '"""Numeric kernels generated from the symbolic models (numpy; the *_scalar twins use math)."""', ""]
    lines.append("MODULES = (" + "".join(f"\n    {s.module!r}," for s in specs) + "\n)")
    lines.append("SCALAR_MODULES = (" + "".join(f"\n    {s.module + '_scalar'!r}," for s in specs if s.scalar_twin) + "\n)")
    lines.append("SUPPORT_MODULES = (" + "".join(f"\n    {n[:-3]!r}," for n in ["layouts.py"] + sorted(extra)) + "\n)")
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
