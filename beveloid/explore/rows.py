"""One row per design: status, working data, FPD angles, sensitivities, worst path shift, Monte Carlo.

Column names follow ``beveloid design --json`` (pair values by their names, member values with a
``pinion_`` / ``gear_`` prefix) and carry their unit.  Sensitivities are those of
``tca.sensitivity`` at the aligned pitch point, in its units (mm and rad per mm or per rad of the
generated error layout): ``<flank>_pinion_contact_<x|y|z>_mm_per_<error>``,
``<flank>_gear_contact_<x|y|z>_mm_per_<error>`` and ``<flank>_gear_angle_rad_per_<error>`` with
<error> one of dx_mm, dy_mm, dz_mm, vertical_rad, horizontal_rad.  The worst first-order path
shift inside the tolerance box (half-widths t_i) is sum_i |dz/de_i| t_i, the axial (z, along the
face width) shift of the contact point on each member; ``worst_path_shift_mm`` is the largest over
both members and flanks.  A design that is not ``ok``, or a flank whose aligned contact at P is not
a surface contact, carries its status and no number (NaN in the arrays, empty in the CSV).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .. import assembly_errors, tca
from ..generated import design_equations
from ..solver import Solver
from ..status import DesignStatus, ExploreStatus, Status
from ..design import design_arrays
from ..names import Member
from ..spec import KEY_DOCS
from ..spec.validate import implied_surface_model
from . import contact, tooth

AXES = ("x", "y", "z")
#: the design's working data: (column, q key or a function of (q, values), degrees?)
#: (column stem, member record field (generated layouts.MemberDesignOutputs), in degrees)
MEMBER_COLUMNS = (
    ("helix_angle_deg", "helix_angle", True), ("cone_angle_deg", "cone_angle", True),
    ("transverse_angular_factor", "transverse_angular_factor", False),
    ("mounting_distance_mm", "mounting_distance_mm", False),
    ("working_mounting_distance_mm", "working_mounting_distance_mm", False),
    ("working_cone_angle_deg", "working_cone_angle", True), ("working_helix_angle_deg", "working_helix_angle", True),
    ("working_pitch_radius_mm", "working_pitch_radius_mm", False),
    ("reference_pitch_radius_mm", "reference_pitch_radius_mm", False),
    ("transverse_pressure_angle_left_deg", "transverse_pressure_angle_left", True),
    ("transverse_pressure_angle_right_deg", "transverse_pressure_angle_right", True),
    ("working_transverse_pressure_angle_left_deg", "working_transverse_pressure_angle_left", True),
    ("working_transverse_pressure_angle_right_deg", "working_transverse_pressure_angle_right", True),
    ("fpd_angle_left_deg", "fpd_angle_left", True), ("fpd_angle_right_deg", "fpd_angle_right", True),
)
MC_COLUMNS = ("mc_sets", "mc_edge_fraction", "mc_off_flank_fraction", "mc_te_peak_to_peak_urad_mean",
              "mc_te_peak_to_peak_urad_p95", "mc_te_peak_to_peak_urad_max")


def sensitivity_columns(flank: str) -> list[str]:
    cols = []
    for member in ("pinion", "gear"):
        cols += [f"{flank}_{member}_contact_{a}_mm_per_{e}" for a in AXES for e in tca.ERROR_NAMES]
    cols += [f"{flank}_gear_angle_rad_per_{e}" for e in tca.ERROR_NAMES]
    return cols + [f"{flank}_worst_pinion_path_shift_mm", f"{flank}_worst_gear_path_shift_mm",
                   f"{flank}_worst_gear_angle_urad"]


def models(plan, values: dict) -> list[tuple[str, str]]:
    """Each design's (pinion, gear) tooth-surface model: the file's ``tooth_surface``, else the spec's rule
    (``beveloid.spec.validate.implied_surface_model``) on the design's keys (those of the file and the
    varied ones), once per distinct set of the member's model keys."""
    n = next(iter(values.values())).size
    out = []
    for member in Member:
        section = plan.base.get(member, {})
        if section.get("tooth_surface"):
            out.append(np.full(n, section["tooth_surface"], dtype=object))
            continue
        docs = KEY_DOCS[member]
        given = [k for k, doc in docs.items() if doc.model and (k in section or f"{member}.{k}" in plan.keys)]
        numeric = [k for k, doc in docs.items() if doc.model and f"{member}.{k}" in values]
        fixed = {k: section.get(k, doc.default) for k, doc in docs.items() if doc.model and k not in numeric}
        rows, which = np.unique(np.stack([values[f"{member}.{k}"] for k in numeric], axis=1), axis=0,
                                return_inverse=True)
        chosen = [implied_surface_model({**fixed, **dict(zip(numeric, row))}, given, docs) for row in rows.tolist()]
        out.append(np.array(chosen, dtype=object)[which.ravel()])
    return list(zip(out[0], out[1]))


def compute(plan, start: int, stop: int, tolerances: dict, *, solver: Solver | None = None,
            tooth_checks: bool = True) -> dict:
    """The rows of designs start..stop-1 of a :class:`beveloid.explore.grid.Plan` (columns by name), their
    contacts solved by ``solver`` (a :class:`beveloid.solver.Solver`; None: the default); the whole-tooth
    checks (explore/tooth.py) unless ``tooth_checks`` is False."""
    solver = Solver.of(solver)
    varied = plan.values(start, stop)
    n = stop - start
    values = {k: np.full(n, v) for k, v in plan.base_values().items()}
    values.update({k: np.asarray(v, dtype=float) for k, v in varied.items()})
    d = design_arrays(values)
    ok = d.ok  # the sensitivities and the tooth checks are of the designs that pass the design's checks
    with np.errstate(invalid="ignore"):
        q = {k: np.where(ok, v, np.nan) for k, v in d.q.items()}
    alpha = np.where(ok, d.alpha_nw, np.nan)
    q["offset_residual_mm"] = np.where(ok, d.offset_residual_mm, np.nan)
    cols: dict = {"design": np.arange(start, stop)}
    cols.update(varied)
    cols["status"] = d.labels()
    deg = np.degrees
    cols["working_normal_pressure_angle_deg"] = deg(alpha)
    cols["fpd_angle_left_deg"] = deg(q["xi_L"])
    cols["fpd_angle_right_deg"] = deg(q["xi_R"])
    cols["max_fpd_angle_deg"] = np.maximum(np.abs(cols["fpd_angle_left_deg"]), np.abs(cols["fpd_angle_right_deg"]))
    cols["normal_angular_factor"] = q["xi_n"]
    cols["offset_residual_mm"] = q["offset_residual_mm"]
    for name in Member:
        o = design_equations.MEMBER_OUTPUTS[name]  # which design output fills each member field
        for col, field, is_deg in MEMBER_COLUMNS:
            x = q[o[field]]
            cols[f"{name}_{col}"] = deg(x) if is_deg else x
        cols[f"{name}_profile_shift"] = (np.where(ok, values["pinion.profile_shift"], np.nan) if name == "pinion"
                                         else q["x_t2"])
        ppa = np.full(n, np.nan)
        ppa[ok] = [math.degrees(math.atan2(s, c))
                   for s, c in zip(q[o["sin_pitch_point_angle"]][ok], q[o["cos_pitch_point_angle"]][ok])]
        cols[f"{name}_pitch_point_angle_deg"] = ppa
        cols[f"{name}_rack_shift_mm"] = (cols[f"{name}_profile_shift"] * values["pair.normal_module_mm"]
                                         * np.cos(q[o["cone_angle"]]) / np.cos(q[o["helix_angle"]]))
    groups = [(idx, contact.geometry(values, q, idx, pair_models)) for pair_models, idx in model_groups(plan, values, ok)]
    _sensitivities(cols, plan, values, groups, tolerances, solver)
    tooth.whole_tooth(cols, d.outcome, tooth.Designs(lambda j: design_spec(plan, values, j), groups), check=tooth_checks)
    return cols


def model_groups(plan, values: dict, ok: np.ndarray) -> list[tuple[dict, np.ndarray]]:
    """The designs that pass the design's checks, grouped by their (pinion, gear) tooth-surface models:
    [({"pinion": model, "gear": model}, row indices)], in the models' sorted order."""
    per_design = models(plan, values)
    rows_ok = np.nonzero(ok)[0]
    return [(dict(zip(("pinion", "gear"), pair_models)),
             np.array([i for i in rows_ok if per_design[i] == pair_models], dtype=np.int64))
            for pair_models in sorted(set(per_design[i] for i in rows_ok))]


def _box_max(D, tol):
    """max over the box |e_i| <= tol_i of |sum_i D_i e_i| = sum_i |D_i| tol_i, summed in a fixed order
    (the same bits whatever the number of rows)."""
    out = np.zeros(D.shape[0])
    for e in range(D.shape[1]):
        out = out + np.abs(D[:, e]) * tol[e]
    return out


def _sensitivities(cols, plan, values, groups, tolerances, solver):
    n = len(cols["design"])
    tol = np.abs(assembly_errors.to_layout(tolerances))
    flank_status = {fl: np.full(n, "", dtype=object) for fl in tca.FLANKS}
    for fl in tca.FLANKS:
        for c in sensitivity_columns(fl):
            cols[c] = np.full(n, np.nan)
    for idx, geom in groups:
        sens = contact.sensitivities(geom, solver=solver)
        for fl, s in sens.items():
            good = s["status"] == int(Status.OK)
            flank_status[fl][idx[good]] = Status.OK.label
            for j in idx[~good]:  # the first-touch search decides what it is: the one-design path
                flank_status[fl][j] = _scalar_status(plan, values, j, fl, solver)
            k = idx[good]
            for m in ("pinion", "gear"):
                D = s[f"{m}_contact_D_errors"][good]
                for a, axis in enumerate(AXES):
                    for e, err in enumerate(tca.ERROR_NAMES):
                        cols[f"{fl}_{m}_contact_{axis}_mm_per_{err}"][k] = D[:, a, e]
                cols[f"{fl}_worst_{m}_path_shift_mm"][k] = _box_max(D[:, AXES.index("z"), :], tol)
            G = s["gear_angle_D_errors"][good]
            for e, err in enumerate(tca.ERROR_NAMES):
                cols[f"{fl}_gear_angle_rad_per_{err}"][k] = G[:, e]
            cols[f"{fl}_worst_gear_angle_urad"][k] = _box_max(G, tol) * 1e6
    for fl in tca.FLANKS:
        cols[f"{fl}_contact_status"] = flank_status[fl]
    shifts = [cols[f"{fl}_worst_{m}_path_shift_mm"] for fl in tca.FLANKS for m in ("pinion", "gear")]
    cols["worst_path_shift_mm"] = np.max(shifts, axis=0)  # nan unless every flank has its numbers


def design_spec(plan, values: dict, j: int):
    """The DesignSpec of design j of a chunk (values: every numeric key, by dotted key)."""
    from ..spec import spec_from_dict

    from .grid import numeric_keys

    data = {s: dict(d) for s, d in plan.base.items()}
    for key in plan.keys:
        section, name = key.split(".")
        x = float(values[key][j])
        data.setdefault(section, {})[name] = int(round(x)) if numeric_keys()[key].kind == "integer" else x
    return spec_from_dict(data)


def _scalar_status(plan, values, j, flank, solver) -> str:
    from ..pair import Pair

    try:
        return tca.sensitivity(Pair.from_spec(design_spec(plan, values, j)).geometry, flank, solver=solver)["status"]
    except RuntimeError:  # no contact at the pitch point
        return Status.FAILED.label


class MonteCarloRequest(NamedTuple):
    """Each design's Monte Carlo sweep: ``samples`` error sets x ``positions`` on ``flank``, seeded from ``seed``."""

    samples: int
    positions: int
    flank: str
    seed: int


def monte_carlo_request(req) -> MonteCarloRequest:
    """The Monte Carlo part of an explore request (``--mc``, ``--mc-positions``, ``--mc-flank``, ``--seed``)."""
    return MonteCarloRequest(samples=req.mc, positions=req.mc_positions, flank=req.mc_flank, seed=req.plan.seed)


def monte_carlo(cols: dict, plan, rows: slice, tolerances: dict, mc: MonteCarloRequest, *,
                solver: Solver | None = None) -> None:
    """The sweep of ``mc.samples`` error sets inside the tolerance box, per ok design of the plan's
    ``rows`` (columns MC_COLUMNS), solved by ``solver`` (a :class:`beveloid.solver.Solver`; None: the default).

    Error sets are uniform within the tolerance half-widths about the design's [misalignment]; the
    seed of design i is derived from (seed, i) alone, so a design's sets do not depend on its chunk.
    """
    from ..pair import Pair
    from .. import sweep

    start, stop = rows.start, rows.stop
    samples, positions, flank, seed = mc.samples, mc.positions, mc.flank, mc.seed
    n = stop - start
    for c in MC_COLUMNS:
        cols[c] = np.full(n, np.nan)
    cols["mc_status"] = np.full(n, "", dtype=object)
    values = {k: np.full(n, v) for k, v in plan.base_values().items()}
    values.update(plan.values(start, stop))
    for j in range(n):
        if cols["status"][j] != DesignStatus.OK:
            continue
        if cols[f"{flank}_contact_status"][j] != Status.OK.label:
            cols["mc_status"][j] = ExploreStatus.NO_ALIGNED_CONTACT
            continue
        spec = design_spec(plan, values, j)
        nominal = {k: float(getattr(spec.misalignment, k)) for k in assembly_errors.KEYS}
        design_seed = int(np.random.SeedSequence([seed, start + j]).generate_state(1, np.uint64)[0]) >> 1
        options = sweep.Options(flank=flank, samples=samples, positions=positions, seed=design_seed,
                                ranges=dict(tolerances), nominal=nominal)
        try:
            res = sweep.analyze(Pair.from_spec(spec), options, solver=solver).to_json()
        except RuntimeError:  # the aligned flank has no engagement to sample
            cols["mc_status"][j] = ExploreStatus.NO_ALIGNED_CONTACT
            continue
        te = res["te_peak_to_peak_urad"]
        cols["mc_status"][j] = Status.OK.label
        cols["mc_sets"][j] = samples
        cols["mc_edge_fraction"][j] = res["fraction_sets_with_edge_contact"]
        cols["mc_off_flank_fraction"][j] = res["fraction_sets_with_contact_off_flank"]
        if te.get("count"):
            cols["mc_te_peak_to_peak_urad_mean"][j] = te["mean"]
            cols["mc_te_peak_to_peak_urad_p95"][j] = te["p95"]
            cols["mc_te_peak_to_peak_urad_max"][j] = te["max"]
