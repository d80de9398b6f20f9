"""Batched reference contact and exact first-order sensitivities of many designs (tca.sensitivity).

For the designs that :func:`beveloid.design.design_arrays` found ``ok`` this builds their
``beveloid.geometry.PairGeometry`` (one geometry whose fields are arrays over the designs:
``Member.from_design`` on the design's members, the parameter vectors packed by layout field name with a
leading axis over the designs), finds the pitch point on both members (solver.section.point_at_radius, one 2x2 Newton over all
designs at once), solves the aligned contact at P and classifies it with the compiled core (one
compiled loop over the designs calling the core's own ``solve_point`` and ``solve_paths``, exactly
what ``tca.sensitivity`` calls for one design: explore/aligned.py), then takes the implicit-function
derivatives with the generated numpy contact system over all designs at once.

A design whose aligned contact at P is not a surface contact (edge, outside, failed) needs the
first-touch search and its patch cover: it is handed back (``fallback``) and the caller runs
``tca.sensitivity`` on it.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from .. import tca
from typing import NamedTuple

from ..design import checks
from ..generated import layouts, surface_models, tca_kernels
from ..geometry import Member as GeometryMember
from ..geometry import PairGeometry
from ..names import Member
from ..solver import Solver, backends, section
from ..status import Status
from . import aligned

_OK = int(Status.OK)


class MemberSource(NamedTuple):
    """What a member's spec section gives the geometry (PairGeometry.from_design reads the same names)."""

    tooth_surface: str
    surface_options: dict
    cutter_tip_radius_coefficient: np.ndarray


def geometry(values: dict, q: dict, idx: np.ndarray, models: dict) -> PairGeometry:
    """The designs idx as one PairGeometry of arrays: Member.from_design over the design's members
    (beveloid.design.checks.member_arrays), as PairGeometry.from_design builds one design."""
    sub = {k: np.asarray(v)[idx] for k, v in values.items()}
    qs = {k: np.asarray(v)[idx] for k, v in q.items()}
    m_n = sub["pair.normal_module_mm"]
    alpha_n = np.radians(sub["pair.normal_pressure_angle_deg"])
    members = []
    for name in Member:
        model = models[name]
        source = MemberSource(model, {key: sub[f"{name}.{key}"] for key in surface_models.MODEL_KEYS[model]},
                              sub[f"{name}.cutter_tip_radius_coefficient"])
        members.append(GeometryMember.from_design(checks.member_arrays(sub, qs, name), m_n, alpha_n, source))
    return PairGeometry(m_n, alpha_n, sub["pair.offset_mm"], np.radians(sub["pair.shaft_angle_deg"]), *members)


class Batch(NamedTuple):
    """The designs of one call of :func:`beveloid.explore.aligned.aligned_contacts`, one row each: the members' surface
    parameters and blanks, the placement, the Newton start ``x0`` and the pinion angle ``phi`` at P."""

    pinion_params: np.ndarray
    gear_params: np.ndarray
    pair: np.ndarray
    pinion_blank: np.ndarray
    gear_blank: np.ndarray
    x0: np.ndarray
    phi: np.ndarray


class BatchLimits(NamedTuple):
    """Per design ``scale_mm`` and ``tol_mm``; the solver's iteration, homotopy and patch settings."""

    scale_mm: np.ndarray
    tol_mm: np.ndarray
    max_iter: int
    homotopy_steps: int
    patch_tol_mm: float


class BatchOutput(NamedTuple):
    """What :func:`beveloid.explore.aligned.aligned_contacts` writes: the contact's unknowns and its status
    code (-1: none)."""

    x: np.ndarray
    code: np.ndarray


@functools.lru_cache(maxsize=None)
def _kernel(compiled: bool):
    """aligned.aligned_contacts on a solver's backend: as it is (numpy), or its compiled twin
    (beveloid.solver.compiled: the module executed again among the core's twins, where the core's
    functions it imports are numba's dispatchers), compiled by numba and cached on disk per version of
    the core it calls."""
    if not compiled:
        return aligned.aligned_contacts
    backends.namespace("compiled")  # the core's twins, loaded before the twin that imports them
    from ..solver import compiled

    return compiled.load([aligned], _jit)[aligned].aligned_contacts


def _jit(fn, module):
    import numba

    fn.__qualname__ = f"{fn.__name__}__{backends.core_stamp()}"  # its cache entry: this version of the core
    return numba.njit(cache=True, nogil=True)(fn)


def sensitivities(geom: PairGeometry, *, solver: Solver | None = None) -> dict:
    """tca.sensitivity(geom, flank) at the aligned pitch point for the n designs of a PairGeometry of
    arrays (:func:`geometry`), both flanks.

    Returns per flank a dict: ``status`` (codes, -1: no reference contact), and for the designs
    whose status is OK: ``pinion_contact_D_errors`` (n, 3, 5), ``gear_contact_D_errors`` (n, 3, 5),
    ``gear_angle_D_errors`` (n, 5), ``unknowns_D_errors`` (n, 5, 5); nan elsewhere.  Solved by ``solver``
    (a :class:`beveloid.solver.Solver`, its backend and tolerances; None: the default).
    """
    solver = Solver.of(solver)
    options = solver.options
    p, g = geom.pinion, geom.gear
    pp, gp = geom.surface_params("pinion"), geom.surface_params("gear")
    pair = geom.placement()
    pb, gb = p.blank(), g.blank()
    alpha_n = geom.normal_pressure_angle
    eps = np.finfo(float).eps
    tol = np.maximum(options.tol_mm, 64 * eps * (np.abs(g.axial_placement_mm) + geom.offset_mm
                                                          + g.working_pitch_radius_mm))
    scale = g.working_pitch_radius_mm
    n = np.size(geom.normal_module_mm)
    out = {}
    pm, gm = p.tooth_surface, g.tooth_surface
    for flank in tca.FLANKS:
        ends = {}
        for name, m, params in (("pinion", p, pp), ("gear", g, gp)):
            l0 = np.array([a / math.cos(b) for a, b in zip(m.cutter_addendum_mm, alpha_n)])
            sp = section.point_at_radius(m.tooth_surface, flank, params, m.working_pitch_radius_mm,
                                         m.reference_section_offset_mm, l0)
            ends[name] = sp.l_mm, sp.u_mm, np.arctan2(sp.point[:, 1], sp.point[:, 0])
        l1, u1, psi1 = ends["pinion"]
        l2, u2, psi2 = ends["gear"]
        phi1 = p.pitch_point_angle - psi1
        x0 = np.ascontiguousarray(np.stack(layouts.ContactUnknowns(
            pinion_l_mm=l1, pinion_u_mm=u1, gear_l_mm=l2, gear_u_mm=u2, gear_angle_rad=g.pitch_point_angle - psi2),
            axis=-1))
        x = np.full((n, 5), np.nan)
        code = np.empty(n, dtype=np.int64)
        batch = Batch(pinion_params=pp, gear_params=gp, pair=pair, pinion_blank=pb, gear_blank=gb, x0=x0, phi=phi1)
        limits = BatchLimits(scale_mm=scale, tol_mm=tol, max_iter=options.max_iter,
                             homotopy_steps=options.homotopy_steps, patch_tol_mm=options.patch_tol_mm)
        with np.errstate(all="ignore"):  # (interpreted: a diverging Newton iterate is answered by its status)
            _kernel(solver.compiled)(tca_kernels.model_id(pm), tca_kernels.model_id(gm), tca_kernels.flank_id(flank), batch,
                             limits, BatchOutput(x=x, code=code))
        res = {"status": code, "pinion_contact_D_errors": np.full((n, 3, 5), np.nan),
               "gear_contact_D_errors": np.full((n, 3, 5), np.nan), "gear_angle_D_errors": np.full((n, 5), np.nan),
               "unknowns_D_errors": np.full((n, 5, 5), np.nan)}
        k = np.nonzero(code == _OK)[0]
        if k.size:
            s = tca_kernels.contact_system(pm, gm, flank, x[k], phi1[k], np.zeros((k.size, 5)), pp[k], gp[k], pair[k])
            derr = -np.linalg.solve(s.residual_D_unknowns, s.residual_D_errors)
            u = tca.unknowns(x[k])
            J1 = tca_kernels.surface_jet(pm, flank, u.pinion_l_mm, u.pinion_u_mm, pp[k]).point_D_lu
            J2 = tca_kernels.surface_jet(gm, flank, u.gear_l_mm, u.gear_u_mm, gp[k]).point_D_lu
            res["unknowns_D_errors"][k] = derr
            d = tca.unknowns(np.swapaxes(derr, -1, -2))  # rows of d(unknowns)/d(errors), by name
            res["pinion_contact_D_errors"][k] = J1 @ np.stack([d.pinion_l_mm, d.pinion_u_mm], axis=-2)
            res["gear_contact_D_errors"][k] = J2 @ np.stack([d.gear_l_mm, d.gear_u_mm], axis=-2)
            res["gear_angle_D_errors"][k] = d.gear_angle_rad
        out[flank] = res
    return out
