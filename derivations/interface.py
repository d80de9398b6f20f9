"""What a model states to the generator: named parameter layouts and their fields.

The sympy models (derivations/*.py) import these, not the generator (derivations/codegen.py):
a model says which parameters it takes and in what units; how they are printed, packed and
unpacked is the generator's business.  A layout's ``trig`` setting names the angles whose sine,
cosine and tangent the generated ``pack`` computes once (a speed setting the generator honours:
the kernels read the packed entries instead of evaluating the functions on every call); the
model only says which of its parameters are such constant angles.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Field:
    """One named entry of a parameter layout.  A *derived* entry (``derived``: a sympy expression
    of the layout's other entries, e.g. sin of an angle) is computed by the layout's ``pack``;
    the kernels read it wherever the expression occurs instead of evaluating it on every call."""
    name: str
    symbol: sp.Symbol
    unit: str
    doc: str
    derived: object = None


def _trig_entries(fields, angles):
    """``fields`` followed by derived entries sin_<a>, cos_<a>, tan_<a> for each field named in
    ``angles``: a layout's angles are constant over a solve, so their trigonometry is computed
    once, when the vector is packed (a profile of the compiled W2 sweep had 25 % of its samples in
    these calls: docs/performance.md)."""
    by_name = {f.name: f for f in fields}
    out = list(fields)
    for name in angles:
        f = by_name[name]
        for fn in (sp.sin, sp.cos, sp.tan):
            tag = fn.__name__
            out.append(Field(f"{tag}_{name}", sp.Symbol(f"{tag}_{name}", real=True), "1",
                             f"{tag}({name}), computed by pack", derived=fn(f.symbol)))
    return tuple(out)


@dataclass(frozen=True)
class Layout:
    """A named parameter vector.

    The generator emits a ``typing.NamedTuple`` class ``name`` with these fields into
    ``generated/layouts.py``; a kernel takes the vector as one array argument whose last axis
    holds the fields in this order (``numpy.asarray(Params(...))`` builds it), and unpacks it
    inside the generated code.  Callers fill it by field name and never count positions.
    ``trig``: names of angle fields whose sin, cos and tan the generated ``pack`` appends as
    derived entries (``fields`` then holds them after the stated ones).
    """
    name: str
    doc: str
    fields: tuple
    trig: tuple = ()

    def __post_init__(self):
        if self.trig:
            object.__setattr__(self, "fields", _trig_entries(self.fields, self.trig))

    def symbols(self):
        return [f.symbol for f in self.fields]

    def base_fields(self):
        """The entries a caller supplies (the rest are derived from them by ``pack``)."""
        return [f for f in self.fields if f.derived is None]

    def derived_fields(self):
        return [f for f in self.fields if f.derived is not None]
