"""The designs of an exploration: the varied spec keys and their grid or sample.

``--vary KEY=START:STOP:COUNT`` replaces one numeric spec key (any key of ``beveloid example
--schema`` that is a number or an integer, by its dotted name) with COUNT values from START to
STOP; several ``--vary`` make the full grid (the first key varies slowest).  With ``--samples N``
the N designs are a Latin hypercube sample (scipy.stats.qmc.LatinHypercube, seeded by ``--seed``)
over the same ranges instead (COUNT is then ignored); integer keys are rounded.

Design i is found from i alone (:meth:`Plan.values`), so a chunk of designs is rebuilt the same
way on any worker.
"""
from __future__ import annotations

import difflib
import math
from dataclasses import dataclass

import numpy as np

from ..errors import UserError
from ..spec import KEY_DOCS, SpecError, spec_from_dict

#: at most this many designs in one exploration
MAX_DESIGNS = 100_000_000


def numeric_keys() -> dict:
    """Every numeric key of a spec (dotted name -> KeyDoc) that a file may give."""
    return {f"{section}.{key}": doc for section, docs in KEY_DOCS.items() for key, doc in docs.items()
            if doc.kind in ("number", "integer") and doc.requirement != "result"}


#: which design inputs fix a design result (the package docstring of beveloid.design)
_RESULT_INPUTS = {"gear.helix_angle_deg": "pinion.helix_angle_deg and pair.shaft_angle_deg, Eqs 16 and 26",
                  "gear.profile_shift": "pair.offset_mm and pinion.profile_shift, Eq 27"}


def not_a_key(key: str, keys: dict, command: str, what: str, elsewhere: dict | None = None) -> str:
    """The one line for ``--vary KEY`` when KEY is not one of ``keys`` (``what`` ``command`` varies): a key
    that is another command's (``elsewhere``: {key: why}), a design result (which inputs fix it), a key of
    the spec of another kind, or no spec key (the closest keys, difflib)."""
    section, _, name = key.partition(".")
    doc = KEY_DOCS.get(section, {}).get(name)
    listed = f"{what}: {', '.join(keys)}"
    if elsewhere and key in elsewhere:
        return f"--vary {key}: {elsewhere[key]}; {command} varies {listed}"
    if doc is not None and doc.requirement == "result":
        inputs = _RESULT_INPUTS.get(key, "the design inputs")
        return (f"--vary {key}: a design result, not a design input (the design computes it from {inputs});"
                f" vary those inputs instead ({command} varies {listed})")
    if doc is not None:
        return f"--vary {key}: a {doc.kind} key of [{section}], not one that {command} varies; it varies {listed}"
    close = difflib.get_close_matches(key, list(keys), n=3, cutoff=0.6)
    hint = f"did you mean {' or '.join(close)}? " if close else ""
    return f"--vary {key}: not a spec key that {command} varies; {hint}it varies {listed}"


@dataclass(frozen=True)
class Vary:
    """One varied numeric spec key over [start, stop]: ``count`` values from start to stop on a grid
    (explore), or the continuous range (``count`` None: optimize's search)."""

    key: str
    start: float
    stop: float
    count: int | None = None

    def values(self) -> np.ndarray:
        """The grid's values (integer keys rounded)."""
        v = np.linspace(self.start, self.stop, self.count)
        return np.round(v) if numeric_keys()[self.key].kind == "integer" else v


def parse_vary(text: str) -> Vary:
    """``KEY=START:STOP:COUNT`` -> Vary; one-line UserError naming the key, the value and what is valid."""
    keys = numeric_keys()
    if "=" not in text:
        raise UserError(f"--vary {text}: must be KEY=START:STOP:COUNT, e.g. pinion.cone_angle_deg=1:4:7")
    key, _, spec = text.partition("=")
    key = key.strip()
    if key not in keys:
        raise UserError(not_a_key(key, keys, "explore", "the numeric design inputs"))
    doc = keys[key]
    parts = spec.split(":")
    if len(parts) != 3:
        raise UserError(f"--vary {key}={spec}: must be START:STOP:COUNT (COUNT an integer >= 1)")
    try:
        start, stop = float(parts[0]), float(parts[1])
    except ValueError:
        raise UserError(f"--vary {key}={spec}: START and STOP must be numbers ({doc.valid_text_in(key.split('.')[0])})") from None
    try:
        count = int(parts[2])
    except ValueError:
        count = 0
    if not 1 <= count <= 100_000:
        raise UserError(f"--vary {key}={spec}: COUNT = {parts[2]} must be an integer from 1 to 100000")
    if count == 1 and start != stop:
        raise UserError(f"--vary {key}={spec}: COUNT = 1 needs START = STOP")
    for name, x in (("START", start), ("STOP", stop)):
        if not doc.in_range(x) if doc.bound_key is None else not math.isfinite(x):
            raise UserError(f"--vary {key}={spec}: {name} = {parts[0 if name == 'START' else 1]} must be"
                            f" {doc.valid_text_in(key.split('.')[0])}")
    v = Vary(key, start, stop, count)
    if doc.kind == "integer":
        vals = np.linspace(start, stop, count)
        if not np.array_equal(vals, np.round(vals)):
            raise UserError(f"--vary {key}={spec}: {key} takes integers; START:STOP:COUNT must give whole numbers"
                            f" (e.g. {int(start)}:{int(start) + count - 1}:{count})")
    return v


@dataclass(frozen=True)
class Plan:
    """The base spec (nested dict, as the file gives it) and the designs to explore."""

    base: dict
    varies: tuple
    samples: int | None = None
    seed: int = 0

    @property
    def keys(self) -> tuple:
        return tuple(v.key for v in self.varies)

    @property
    def count(self) -> int:
        return self.samples if self.samples else int(np.prod([v.count for v in self.varies]))

    def values(self, start: int, stop: int) -> dict:
        """The varied keys' values of designs start..stop-1, by dotted key."""
        idx = np.arange(start, stop)
        if not self.varies:
            return {}
        if self.samples:
            u = self._sample()[start:stop]
            out = {}
            for j, v in enumerate(self.varies):
                x = v.start + (v.stop - v.start) * u[:, j]
                out[v.key] = np.round(x) if numeric_keys()[v.key].kind == "integer" else x
            return out
        shape = tuple(v.count for v in self.varies)
        pos = np.unravel_index(idx, shape)
        return {v.key: v.values()[p] for v, p in zip(self.varies, pos)}

    def _sample(self) -> np.ndarray:
        from scipy.stats import qmc

        return qmc.LatinHypercube(d=len(self.varies), seed=np.random.default_rng(self.seed)).random(self.samples)

    def base_values(self) -> dict:
        """Every numeric key of the base spec (defaults filled in), by dotted key."""
        from ..spec import spec_to_dict

        full = spec_to_dict(spec_from_dict(self.base))
        out = {}
        for key in numeric_keys():
            section, name = key.split(".")
            if name in full.get(section, {}):
                out[key] = float(full[section][name])
            elif section in ("pinion", "gear"):  # a surface model's own key the base leaves at its default
                doc = KEY_DOCS[section][name]
                out[key] = float(doc.default) if doc.default is not None else math.nan
        return out

    def check(self) -> None:
        """Every design is a valid spec: the spec rules are ranges and linear bounds between keys, so a
        box of values is valid when its corners are (one line, the key, the value: a UserError)."""
        if self.count > MAX_DESIGNS:
            raise UserError(f"--vary: {self.count} designs; at most {MAX_DESIGNS} per exploration")
        corners = np.array(np.meshgrid(*[[v.start, v.stop] for v in self.varies], indexing="ij")).reshape(
            len(self.varies), -1).T
        for corner in corners[:64]:
            data = {s: dict(d) for s, d in self.base.items()}
            for v, x in zip(self.varies, corner):
                section, name = v.key.split(".")
                kind = numeric_keys()[v.key].kind
                data.setdefault(section, {})[name] = int(round(x)) if kind == "integer" else float(x)
            try:
                spec_from_dict(data)
            except SpecError as err:
                raise UserError(f"--vary: {err.detail} (at the corner "
                                + ", ".join(f"{v.key} = {x:g}" for v, x in zip(self.varies, corner))
                                + " of the varied ranges)") from None
