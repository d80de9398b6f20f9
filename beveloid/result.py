"""What every analysis returns: a :class:`Result`, deep-frozen when it is made.

A result's fields are frozen all the way down the moment it is created (:func:`freeze`): every writable
numpy array becomes a read-only copy, every mapping a :class:`FrozenMap`, every list a tuple (a NamedTuple
keeps its type, its fields frozen), every set a frozenset; a nested :class:`Frozen` record is frozen
by its own creation.  Nothing is filled in afterwards.  A :class:`Result` holds the ``pair`` it was
computed for and its ``options``, and writes its JSON with :meth:`Result.to_json`, which needs
nothing passed in and returns a dict that ``json.dumps`` takes (``null``, never ``nan``, for a
number that is not known).
"""
from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, is_dataclass
from typing import Any

import numpy as np

__all__ = ["Frozen", "FrozenMap", "Result", "freeze", "num", "thaw"]


class FrozenMap(Mapping):
    """A read-only mapping (a dict's items, frozen): lookups, iteration and equality as a dict's; no
    writes.  Unlike :class:`types.MappingProxyType` it pickles (results cross process pools)."""

    __slots__ = ("_items",)

    def __init__(self, items=()):
        object.__setattr__(self, "_items", dict(items))

    def __getitem__(self, key):
        return self._items[key]

    def __iter__(self):
        return iter(self._items)

    def __len__(self):
        return len(self._items)

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is read-only")

    def __reduce__(self):
        return (type(self), (self._items,))

    def __repr__(self):
        return f"{type(self).__name__}({self._items!r})"

    def __hash__(self):
        return hash(frozenset(self._items.items()))


#: values that are immutable as they are (a StrEnum member is a str, numpy's scalars are np.generic)
_ATOMS = (str, bytes, int, float, complex, type(None), np.generic)


def freeze(value):
    """``value`` made immutable all the way down: a writable array a read-only copy, a mapping a
    :class:`FrozenMap`, a list or tuple a tuple (a NamedTuple of the same type), a set a frozenset, each
    of their items frozen the same way.  A :class:`Frozen` record is frozen already; another dataclass
    record becomes a copy with its fields frozen (itself when they are already); anything else (a number,
    a string, an enum) is returned as it is."""
    if isinstance(value, _ATOMS):
        return value
    if isinstance(value, np.ndarray):
        if value.dtype == object:
            items = value
            value = np.empty(items.shape, dtype=object)
            for index, item in np.ndenumerate(items):
                value[index] = freeze(item)
        elif not value.flags.writeable:
            return value
        else:  # a copy: the maker's array may still be written by whoever else holds it
            value = value.copy()
        value.setflags(write=False)
        return value
    if isinstance(value, FrozenMap):
        return value
    if isinstance(value, Mapping):
        return FrozenMap({k: freeze(v) for k, v in value.items()})
    if isinstance(value, tuple) and hasattr(value, "_fields"):  # a NamedTuple: its own type, frozen fields
        return type(value)(*(freeze(v) for v in value))
    if isinstance(value, (list, tuple)):
        if all(isinstance(v, _ATOMS) for v in value):  # the common case (statuses, names): one pass, no copy
            return value if isinstance(value, tuple) else tuple(value)
        return tuple(freeze(v) for v in value)
    if isinstance(value, (set, frozenset)):
        return frozenset(freeze(v) for v in value)
    if is_dataclass(value) and not isinstance(value, (type, Frozen)):  # a record of another kind: a frozen copy
        changed = {}
        for f in fields(value):
            item = getattr(value, f.name)
            frozen = freeze(item)
            if frozen is not item:
                changed[f.name] = frozen
        if not changed:
            return value
        value = copy.copy(value)
        for name, item in changed.items():
            object.__setattr__(value, name, item)
    return value


def thaw(value):
    """The JSON of a frozen value: mappings dicts, tuples lists, arrays nested lists, all the way down;
    a non-finite float None."""
    if isinstance(value, Mapping):
        return {k: thaw(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [thaw(v) for v in value]
    if isinstance(value, np.ndarray):
        return thaw(value.tolist())
    if isinstance(value, (float, np.floating)):
        return num(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def num(value) -> float | None:
    """A JSON number: a float, None where ``value`` is None or not finite."""
    if value is None:
        return None
    v = float(value)
    return v if math.isfinite(v) else None


@dataclass(frozen=True, eq=False)
class Frozen:
    """A record frozen all the way down when created (:func:`freeze` on every field but the inputs it
    holds, ``INPUTS``).  A subclass that defines ``__post_init__`` calls ``super().__post_init__()``."""

    #: fields that hold an input as given (the analysed pair): not the result's to freeze
    INPUTS = ()

    def __post_init__(self):
        for f in fields(self):
            if f.name in self.INPUTS:
                continue
            value = getattr(self, f.name)
            frozen = freeze(value)
            if frozen is not value:
                object.__setattr__(self, f.name, frozen)


@dataclass(frozen=True, eq=False)
class Result(Frozen):
    """What an analysis returns: frozen records (:class:`Frozen`) holding the ``pair`` analysed (a
    :class:`beveloid.pair.Pair`, or the PairGeometry it was given) and the analysis' ``options``, and its
    JSON by :meth:`to_json` (nothing passed in)."""

    INPUTS = ("pair",)

    pair: Any = field(default=None, kw_only=True, repr=False)
    options: Any = field(default=None, kw_only=True, repr=False)

    def to_json(self) -> dict:
        """The JSON of the result (what the command's ``--json`` prints): a dict ``json.dumps`` takes."""
        raise NotImplementedError(f"{type(self).__name__}.to_json")

    @property
    def geometry_of_pair(self):
        """The analysed PairGeometry (the pair's, or the pair when it was given as a geometry)."""
        return getattr(self.pair, "geometry", self.pair)
