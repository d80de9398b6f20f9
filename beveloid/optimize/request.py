"""What an optimisation asks (:class:`Request`, kept in DIR/request.json) and how its parts are read
from the command line, each refusal one line naming the flag, the value and what is valid.

``--vary KEY=LOW:HIGH`` takes a numeric micro-geometry key of either member (the keys of the
tooth-surface models: ``*_crowning_um``, ``tip_relief_um``, ``tip_relief_height_mm``,
``end_relief_um``, ``end_relief_length_mm``, ``lead_slope_um``, and those of a user model) over a
continuous range.  A key that changes the macro geometry (the design, the tooth body and its FE data)
belongs to ``beveloid explore`` and is refused.

A candidate is the file's tables with the varied keys replaced (:meth:`Request.spec`); a member whose
file names no ``tooth_surface`` gets the first model that takes every varied key of it (and every
model key the file gives), so that all candidates of a run share one surface model per member.
"""
from __future__ import annotations

import copy
import functools
import math
import re
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import UserError
from ..explore.grid import Vary
from ..names import MEMBERS

#: the objectives: command-line name -> the quantity (and JSON key) it is made of
OBJECTIVES = {"te": "te_peak_to_peak_urad", "pressure": "max_pressure_mpa", "root": "root_stress_max_mpa",
              "loss": "mesh_power_loss_w"}
DEFAULT_OBJECTIVES = ("te", "pressure")
#: each torque's quantity over the K error sets: this percentile (numpy's default method)
PERCENTILE = 90.0
#: the default number of candidates: the issue's target configuration (case 1, two variables, three
#: torques, --samples 16); docs/optimize.md gives what it costs today
DEFAULT_BUDGET = 128
MAX_BUDGET = 100_000
MAX_TORQUES = 32
MAX_SAMPLES = 10_000


def micro_keys() -> dict:
    """Every numeric micro-geometry key (dotted ``member.key`` -> KeyDoc): a tooth-surface model's own keys."""
    from ..spec import KEY_DOCS

    return {f"{m}.{k}": doc for m in MEMBERS for k, doc in KEY_DOCS[m].items()
            if doc.model and doc.kind in ("number", "integer")}


def _refusal(key: str, keys: dict) -> str:
    """One line for a --vary key that is not a micro-geometry key (:func:`beveloid.explore.grid.not_a_key`):
    a macro-geometry key is explore's, another numeric key is no flank modification."""
    from ..explore.grid import not_a_key, numeric_keys

    elsewhere = {k: ("changes the macro geometry (the design and the tooth body), not the flank's micro-geometry:"
                     " vary it with `beveloid explore`" if k.partition(".")[0] in (*MEMBERS, "pair") else
                     f"not a flank modification (a [{k.partition('.')[0]}] key)") for k in numeric_keys()}
    return not_a_key(key, keys, "optimize", "the numeric micro-geometry keys", elsewhere)


def parse_vary(text: str) -> Vary:
    """``KEY=LOW:HIGH`` -> Vary, or a one-line UserError."""
    keys = micro_keys()
    key, eq, rng = (part.strip() for part in text.partition("="))
    if not eq:
        raise UserError(f"--vary {text}: must be KEY=LOW:HIGH, e.g. pinion.lead_crowning_um=0:40")
    if key not in keys:
        raise UserError(_refusal(key, keys))
    doc = keys[key]
    m = re.fullmatch(r"([^:]*):([^:]*)", rng)
    if m is None:
        raise UserError(f"--vary {key}={rng}: must be LOW:HIGH, two numbers with LOW < HIGH (a continuous range)")
    bounds = []
    for name, word in zip(("LOW", "HIGH"), m.groups()):
        try:
            x = float(word)
        except ValueError:
            raise UserError(f"--vary {key}={rng}: LOW and HIGH must be numbers, each {doc.valid_text}") from None
        if not (math.isfinite(x) and doc.in_range(x)):
            raise UserError(f"--vary {key}={rng}: {name} = {x:g} must be {doc.valid_text}")
        bounds.append(x)
    if not bounds[0] < bounds[1]:
        raise UserError(f"--vary {key}={rng}: LOW = {bounds[0]:g} must be below HIGH = {bounds[1]:g}")
    return Vary(key, *bounds)  # a continuous range: no count


def parse_numbers(text: str, flag: str, what: str) -> tuple:
    """``"100,200,400"`` -> (100.0, 200.0, 400.0): finite positive numbers, else one line."""
    parts = [p.strip() for p in str(text).split(",")]
    out = []
    for p in parts:
        try:
            x = float(p)
        except ValueError:
            x = math.nan
        if not (math.isfinite(x) and x > 0):
            raise UserError(f"{flag} {text}: {p!r} is not a number > 0; give {what}")
        out.append(x)
    if not 1 <= len(out) <= MAX_TORQUES:
        raise UserError(f"{flag} {text}: give 1 to {MAX_TORQUES} numbers")
    return tuple(out)


def parse_objectives(text: str, tooth_model: str) -> tuple:
    names = tuple(p.strip() for p in str(text).split(","))
    for n in names:
        if n not in OBJECTIVES:
            raise UserError(f"--objectives {text}: {n!r} is not an objective; valid: {', '.join(OBJECTIVES)}")
    if len(set(names)) != len(names):
        raise UserError(f"--objectives {text}: an objective is given twice")
    if "root" in names and tooth_model != "fe":
        raise UserError(f"--objectives {text}: root needs the FE tooth (--tooth-model fe); the {tooth_model} tooth "
                        "has no root fillet")
    return names


def check_loss_objective(objectives, spec) -> None:
    """The objective ``loss`` (mesh power loss, docs/tribology.md) needs the file's [lubricant] and [rating]
    pinion_speed_rpm (one line otherwise)."""
    if "loss" not in objectives:
        return
    if not spec.lubricant.given:
        raise UserError(f"--objectives {','.join(objectives)}: loss needs a [lubricant] section in {spec.source} "
                        "(an oil: iso_vg or the viscosities, temperature_c; docs/tribology.md)")
    if spec.rating.pinion_speed_rpm is None:
        raise UserError(f"--objectives {','.join(objectives)}: loss needs rating.pinion_speed_rpm in {spec.source} "
                        "(the speed of the mesh power loss)")


def default_population(n_vary: int) -> int:
    """NSGA-II's population: 8 per varied key, from 8 to 32."""
    return int(min(32, max(8, 8 * n_vary)))


def _default_ltca():
    from ..ltca.options import Options

    return Options()


def _ltca_json(options) -> dict:
    """An ltca.Options as JSON (its material: the spec's, not written)."""
    d = asdict(options)
    d.pop("material")
    d["grid"] = None if options.grid is None else list(options.grid)
    return d


@dataclass(frozen=True)
class Request:
    """Everything that defines the candidates and their numbers (DIR/request.json)."""

    base: dict  # the file's tables as it gives them
    varies: tuple
    torques_nm: tuple
    weights: tuple
    objectives: tuple = DEFAULT_OBJECTIVES
    samples: int = 0
    seed: int = 0
    tolerances: dict = field(default_factory=dict)
    budget: int = DEFAULT_BUDGET
    population: int = 8
    ltca: object = field(default_factory=_default_ltca)  # the loaded analysis of every candidate: an ltca.Options
    constraints: str = "rating"  # "rating": the local safeties at the highest torque; "none"
    source: str = ""
    code: dict = field(default_factory=dict)

    def __post_init__(self):
        from ..ltca.options import Options

        if not isinstance(self.ltca, Options):
            raise TypeError(f"optimize.Request's ltca must be an ltca.Options, not {type(self.ltca).__name__}")

    def to_json(self) -> dict:
        d = {f: getattr(self, f) for f in self.__dataclass_fields__}
        d["varies"] = [asdict(v) for v in self.varies]
        d["ltca"] = _ltca_json(self.ltca)
        return copy.deepcopy(d)

    @classmethod
    def from_json(cls, d: dict) -> "Request":
        from ..ltca.options import Options

        d = dict(d)
        d["varies"] = tuple(Vary(**v) for v in d["varies"])
        for k in ("torques_nm", "weights", "objectives"):
            d[k] = tuple(d[k])
        lt = dict(d["ltca"])
        lt["grid"] = None if lt.get("grid") is None else tuple(lt["grid"])
        d["ltca"] = Options(**lt)
        return cls(**d)

    @property
    def keys(self) -> list:
        return [v.key for v in self.varies]

    @property
    def quantities(self) -> list:
        """The objectives' quantity names, in the request's order."""
        return [OBJECTIVES[o] for o in self.objectives]

    def surfaces(self) -> dict:
        """{member: tooth_surface} for each varied member whose file names none."""
        from ..generated import surface_models
        from ..spec.keys import model_takes

        out = {}
        docs = micro_keys()
        for m in MEMBERS:
            varied = [k.partition(".")[2] for k in self.keys if k.startswith(m + ".")]
            raw = self.base.get(m, {})
            if not varied or "tooth_surface" in raw:
                continue
            given = [k for k in raw if f"{m}.{k}" in docs]
            need = varied + given
            out[m] = next((s for s in surface_models.MODEL_KEYS if all(model_takes(s, k) for k in need)),
                          surface_models.DEFAULT_MODEL)
        return out

    def raw(self, values: dict) -> dict:
        """The file's tables with ``values`` (dotted keys) in place."""
        data = copy.deepcopy(self.base)
        for m, surface in self.surfaces().items():
            data.setdefault(m, {})["tooth_surface"] = surface
        for key, v in values.items():
            section, _, name = key.partition(".")
            data.setdefault(section, {})[name] = float(v)
        return data

    def spec(self, values: dict):
        """The DesignSpec of a candidate (SpecError when its values are refused)."""
        from ..spec import spec_from_dict

        return spec_from_dict(self.raw(values), source=self.source or "<dict>")

    def base_spec(self):
        from ..spec import spec_from_dict

        return spec_from_dict(self.base, source=self.source or "<dict>")

    def baseline_values(self) -> dict:
        """The file's value of each varied key (the model's default where the file gives none)."""
        spec = self.base_spec()
        docs = micro_keys()
        out = {}
        for key in self.keys:
            m, _, name = key.partition(".")
            opts = dict(getattr(spec, m).surface_options)
            out[key] = float(opts.get(name, docs[key].default))
        return out

    def error_sets(self) -> np.ndarray:
        """(K, 5) error sets (mm, rad): the file's [misalignment] alone (``samples`` 0) or K sets drawn as
        ``beveloid sweep`` draws them about it (sweep.draw_errors: the same for every candidate)."""
        from .. import assembly_errors
        from ..sweep import draw_errors

        spec = self.base_spec()
        if self.samples == 0:
            return assembly_errors.to_layout(spec.misalignment)[None, :]
        nominal = {k: float(getattr(spec.misalignment, k)) for k in assembly_errors.KEYS}
        return draw_errors(self.samples, self.tolerances, self.seed, nominal)

    @functools.cached_property
    def solver(self):
        """The run's :class:`beveloid.solver.Solver` (the default backend), made once per request: every
        candidate's loaded analyses, its rating and the knee's pattern solve with it."""
        from ..solver import Solver

        return Solver()

    def load_case(self, error_sets=None):
        """The loaded analysis' load: the duty cycle's torques at ``error_sets`` ((K, 5); None: the file's)."""
        from ..ltca import LoadCase

        return LoadCase(tuple(float(t) for t in self.torques_nm), None if error_sets is None else error_sets)

    def rating_options(self):
        """The rating at the highest torque: what ``beveloid rating FILE --torque-nm T --flank F --tooth-model M``
        runs (the file's errors): the run's flank and tooth model, the rating's own numerical settings (its
        default positions, grid, pairs and FE tooth refinement), whatever the run's ``--positions`` or ``--grid``
        for the objectives: a front member passes the rating at its defaults (docs/optimize.md 2)."""
        from .. import rating
        from ..ltca.options import Options

        lt = Options(flank=self.ltca.flank, tooth_model=self.ltca.tooth_model, positions=rating.POSITIONS,
                     material=self.ltca.material)
        # the verdict reads neither the FE root stress's convergence estimate (no coarsened FE tooth per candidate)
        # nor the LTCA's grid-convergence indicator
        return rating.Options(ltca=lt, root_stress_check=False, grid_check=False)

    def check(self) -> None:
        """Every corner of the ranges passes the spec's rules between keys (a relief's extent needs the
        relief): one line naming the --vary whose LOW or HIGH is refused."""
        import itertools

        from ..spec import SpecError

        base = self.baseline_values()
        for corner in itertools.product(*((v.start, v.stop) for v in self.varies)):
            values = dict(base, **dict(zip(self.keys, corner)))
            try:
                self.spec(values)
            except SpecError as exc:
                v = next((v for v in self.varies if exc.key and exc.key == v.key), self.varies[0])
                x = values[v.key]
                name = "LOW" if x == v.start else "HIGH"
                others = ", ".join(f"{k} = {values[k]:g}" for k in self.keys if k != v.key)
                raise UserError(f"--vary {v.key}={v.start:g}:{v.stop:g}: {name} = {x:g} is refused by the spec"
                                f"{' with ' + others if others else ''}: {exc.detail}") from None
