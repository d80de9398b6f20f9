"""The facade: a designed gear pair, in the user's terms.

``Pair.from_spec(...)`` reads and validates a spec (a TOML path, a :class:`DesignSpec` or a
nested mapping as ``tomllib`` gives it), runs the direct design once and builds the geometry
the solver sees once.  Every analysis takes a ``Pair``::

    from beveloid.pair import Pair
    pair = Pair.from_spec("my.toml")          # or Pair.example("case1")
    pair.design.working_normal_pressure_angle # the design result (beveloid.design)
    pair.geometry                             # the pair as the solver sees it (beveloid.geometry)
    pair.errors                               # the spec's [misalignment], as an error vector (mm, rad)
"""
from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from . import assembly_errors
from .design import DesignResult, design
from .geometry import PairGeometry
from .spec import DesignSpec, load_example, load_spec, spec_from_dict


@dataclass(frozen=True)
class Pair:
    """A designed crossed beveloid pair: its spec, its design and its geometry (mm, rad)."""

    spec: DesignSpec
    design: DesignResult
    geometry: PairGeometry

    @classmethod
    def from_spec(cls, source: "str | os.PathLike | DesignSpec | Mapping") -> "Pair":
        """Design the pair of a spec: a TOML file path, a :class:`DesignSpec` or a spec mapping.

        Bad input raises :class:`beveloid.spec.SpecError` (one line naming the key, the value and
        what is valid); a request without a physical design raises
        :class:`beveloid.design.DesignError`.
        """
        if isinstance(source, DesignSpec):
            spec = source
        elif isinstance(source, Mapping):
            spec = spec_from_dict(dict(source))
        elif isinstance(source, (str, os.PathLike)):
            spec = load_spec(source)
        else:
            raise TypeError(f"Pair.from_spec needs a path, a DesignSpec or a mapping, not {type(source).__name__}")
        result = design(spec)
        return cls(spec=spec, design=result, geometry=PairGeometry.from_design(result))

    @classmethod
    def example(cls, name: str) -> "Pair":
        """A packaged example (``"case1"``, ``"case2"``: the paper's Table 1)."""
        return cls.from_spec(load_example(name))

    @property
    def errors(self) -> np.ndarray:
        """The spec's ``[misalignment]`` as an error vector (dx, dy, dz in mm; vertical, horizontal in rad)."""
        return assembly_errors.to_layout(self.spec.misalignment)
