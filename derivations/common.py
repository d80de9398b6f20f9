"""Shared machinery: equation records and the 50-digit numeric identity check.

Every equation of the paper becomes an :class:`Equation`: the printed form (from
``paper.py``), the form derived by a model, the derivation steps (for
docs/derivations.md) and a sampler of the physical domain.  ``check`` proves the
two equal symbolically where that is quick, else numerically at random points of
the domain in 50-digit arithmetic.  ``simplify()`` of a large trigonometric
expression is never called.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Callable

import mpmath
import sympy as sp

DIGITS = 50
N_POINTS = 24
REL_TOL = mpmath.mpf("1e-40")

deg = sp.pi / 180


@dataclass
class Equation:
    """One numbered equation of the paper and how the models obtain it."""

    number: int
    title: str
    status: str  # "derived" (checked against the print) or "definition"
    printed: object = None  # sympy Expr/Matrix or a list of them (sub-forms, e.g. upper/lower sign)
    derived: object = None
    steps: list[str] = field(default_factory=list)  # markdown with $latex$
    sampler: Callable[[random.Random], dict] | None = None
    symbolic: bool = False  # try an exact check (expand/trigsimp of a small difference)
    note: str = ""
    used_by: str = ""  # for definitions: which model uses the statement
    extra_checks: list = field(default_factory=list)  # list of (label, Callable[[], sympy-able diff]) numeric identities


@dataclass
class CheckResult:
    equation: int
    title: str
    status: str  # "verified" | "definition" | "differs"
    method: str
    max_rel_diff: float | None
    note: str = ""


# ---------------------------------------------------------------------------------------------
# walks over an expression as the DAG it is
# ---------------------------------------------------------------------------------------------
# A derived jet is a tree in which the same subexpression appears many times (the chain rule
# repeats the inner derivatives): sympy's ``xreplace``, ``free_symbols`` and ``atoms`` walk every
# appearance.  These walk each distinct subexpression once, shared over a list of expressions, and
# give exactly what sympy's give (the generator and the staged models use them).


def free_symbols_of(exprs, memo=None) -> set:
    """The union of ``e.free_symbols`` over ``exprs``."""
    memo = {} if memo is None else memo
    default = sp.Basic.free_symbols

    def walk(node):
        got = memo.get(node)
        if got is None:
            if type(node).free_symbols is default:  # the union over the arguments (sympy's Basic)
                got = set().union(*(walk(a) for a in node.args))
            else:  # a symbol, or a node that binds its own variables (Derivative, Lambda, ...)
                got = node.free_symbols
            memo[node] = got
        return got

    return set().union(*(walk(sp.sympify(e)) for e in exprs))


def xreplace_all(exprs, rule) -> list:
    """``[e.xreplace(rule) for e in exprs]``."""
    if not rule:
        return [sp.sympify(e) for e in exprs]
    memo = {}

    def walk(node):
        got = memo.get(node)
        if got is None:
            if node in rule:
                got = rule[node]
            else:
                args = tuple(walk(a) if isinstance(a, sp.Basic) else a for a in node.args)
                got = node.func(*args) if any(x is not y for x, y in zip(args, node.args)) else node
            memo[node] = got
        return got

    return [walk(sp.sympify(e)) for e in exprs]


def on_entries(expr, fn):
    """``fn`` (a list of expressions -> a list) applied to the entries of a Matrix (kept in its shape
    and type) or to a single expression: how the staged models run the walks above on either."""
    if isinstance(expr, sp.MatrixBase):
        return type(expr)(expr.rows, expr.cols, fn(list(expr)))
    return fn([expr])[0]


def atoms_of(exprs, kind) -> set:
    """The union of ``e.atoms(kind)`` over ``exprs``: every subexpression of that type."""
    seen, out = set(), set()
    stack = [sp.sympify(e) for e in exprs]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, kind):
            out.add(node)
        stack.extend(a for a in node.args if isinstance(a, sp.Basic))
    return out


def _as_list(x):
    if x is None:
        return []
    if isinstance(x, (list, tuple)):
        return list(x)
    return [x]


def _flat(expr):
    if isinstance(expr, sp.MatrixBase):
        return list(expr)
    return [expr]


def symbolic_zero(diff) -> bool:
    """Cheap exact test: expand (with trig expansion) then cancel. Never simplify()."""
    for d in _flat(diff):
        d = sp.expand(sp.expand_trig(d))
        if d == 0:
            continue
        if sp.cancel(sp.together(d)) != 0:
            return False
    return True


def numeric_max_rel_diff(printed, derived, sampler, n_points=N_POINTS, seed=20130000):
    """Largest relative difference |d-p|/max(|p|,|d|,1e-30) over random domain points, 50 digits."""
    rng = random.Random(seed)
    p_list, d_list = _flat(printed), _flat(derived)
    assert len(p_list) == len(d_list)
    syms = sorted(set().union(*[e.free_symbols for e in p_list + d_list]), key=str)
    # common subexpressions evaluated once (Eq 18's derived form, ~7 700 operations, repeats its
    # inner terms: 0.6 s for its 24 points against 4.1 s evaluated as a tree)
    f_p = sp.lambdify(syms, p_list, modules="mpmath", cse=True)
    f_d = sp.lambdify(syms, d_list, modules="mpmath", cse=True)
    worst = mpmath.mpf(0)
    with mpmath.workdps(DIGITS):
        for _ in range(n_points):
            point = sampler(rng)
            missing = [s for s in syms if s not in point]
            if missing:
                raise KeyError(f"sampler gives no value for {missing}")
            args = [mpmath.mpf(point[s]) if not isinstance(point[s], mpmath.mpf) else point[s] for s in syms]
            pv, dv = f_p(*args), f_d(*args)
            num = mpmath.sqrt(sum(abs(a - b) ** 2 for a, b in zip(pv, dv)))
            den = max(mpmath.sqrt(sum(abs(a) ** 2 for a in pv)), mpmath.sqrt(sum(abs(b) ** 2 for b in dv)), mpmath.mpf("1e-30"))
            worst = max(worst, num / den)
    return worst


def check(eq: Equation) -> CheckResult:
    if eq.status == "definition":
        return CheckResult(eq.number, eq.title, "definition", "definition (used by " + eq.used_by + ")", None, eq.note)
    pairs = list(zip(_as_list(eq.printed), _as_list(eq.derived)))
    worst = mpmath.mpf(0)
    methods = set()
    for p, d in pairs:
        if eq.symbolic and symbolic_zero(sp.Matrix(_flat(d)) - sp.Matrix(_flat(p))):
            methods.add("symbolic")
            continue
        worst = max(worst, numeric_max_rel_diff(p, d, eq.sampler))
        methods.add(f"50-digit at {N_POINTS} points")
    for _label, fn in eq.extra_checks:
        worst = max(worst, _abs_check(fn(), eq.sampler))
        methods.add(f"50-digit at {N_POINTS} points")
    ok = worst < REL_TOL
    method = " + ".join(sorted(methods))
    status = "verified" if ok else "differs"
    return CheckResult(eq.number, eq.title, status, method, float(worst), eq.note)


def _abs_check(residual, sampler, n_points=N_POINTS, seed=20130001):
    """Largest |residual| (already relative by construction) at random points."""
    rng = random.Random(seed)
    items = _flat(residual)
    syms = sorted(set().union(*[e.free_symbols for e in items]), key=str)
    f = sp.lambdify(syms, items, modules="mpmath", cse=True)
    worst = mpmath.mpf(0)
    with mpmath.workdps(DIGITS):
        for _ in range(n_points):
            point = sampler(rng)
            v = f(*[mpmath.mpf(point[s]) for s in syms])
            worst = max(worst, max(abs(x) for x in v))
    return worst


def uniform(rng: random.Random, lo, hi):
    """A 50-digit uniform sample (extra digits so the point is not a float-rounded value)."""
    with mpmath.workdps(DIGITS):
        t = mpmath.mpf(rng.getrandbits(160)) / mpmath.mpf(2) ** 160
        return mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * t


def uniform_deg(rng, lo_deg, hi_deg):
    with mpmath.workdps(DIGITS):
        return uniform(rng, lo_deg, hi_deg) * mpmath.pi / 180


# ---- elementary homogeneous transforms (right-handed, active) -------------------------
def rot_x(t):
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def rot_y(t):
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


def rot_z(t):
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def trans(x, y, z):
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


def hom(v):
    return sp.Matrix([v[0], v[1], v[2], 1])


def latex(expr) -> str:
    return sp.latex(expr)
