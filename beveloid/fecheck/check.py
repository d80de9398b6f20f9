"""``beveloid fe-check``: the pair's full-contact FE model (CalculiX) beside the LTCA at one position.

The LTCA (``beveloid.ltca.analyze``) runs over a mesh cycle at the torque; the position is the
one with the most loaded tooth pairs (the first of those with the largest smallest pair load) or
the one asked for.  The FE model (:mod:`beveloid.fecheck.pair_model`) is solved by ``ccx`` and
read back: per tooth pair the normal load and contact area (CalculiX's contact totals, CF) and the
peak contact pressure (CPRESS on the gear's flank nodes); the loaded TE (the pinion's rotation under
the moment, as TE = unloaded TE + (N1/N2) x rotation, the TCA's TE formula); the largest principal
stress on each member's root fillets; the moment of the contact forces about the pinion axis.
"""
from __future__ import annotations

import contextlib
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import OptionError, UserError
from ..fe.sizes import MAX_STRIP_ELEMENTS
from ..outputs import check_output_dir
from ..names import MEMBERS
from ..status import LoadedStatus
from .result import CheckResult, ContactNumbers

__all__ = ["CheckResult", "Options", "PEAK_RESOLVED_PER_SEMI_AXIS", "analyze", "choose_position"]

#: a pair's peak pressure and contact area count as resolved where the elements over its contact are
#: at most this many times its half-width b (docs/validation.md section 11: at 0.76-1.1 b the FE's
#: peak sits 0-5 % below Hertz; at 1.3 b 8 % above the 0.76 b peak, at 2.6 b 2.5 times it)
PEAK_RESOLVED_PER_SEMI_AXIS = 1.1


def _default_ltca():
    from ..ltca.options import Options as LTCAOptions

    return LTCAOptions()


@dataclass(frozen=True)
class Options:
    """How the check is computed: the LTCA beside it (``ltca``, an ``ltca.Options``: flank, positions,
    tooth model, ...), the position (None: the most pairs in contact), the mesh refinement, the folder to
    keep (None: a temporary one), every element size times ``coarsen``, the local refinement over the
    LTCA's patches (docs/fe_check.md).  The torque is the load case's (``ltca.LoadCase``).  A bad value
    raises :class:`beveloid.errors.OptionError` naming the key."""

    ltca: object = field(default_factory=_default_ltca)
    position: int | None = None
    refinement: int = 1
    out_dir: str | None = None
    coarsen: float = 1.0  #: multiplies every element size (tests and quick looks; beveloid.fe.mesh's coarsen)
    local_refinement: bool = True  #: refine the mesh over the LTCA's loaded patches (beveloid.fecheck.strips)
    contact_size_um: float | None = None  #: the element size there (None: b / 3 of each patch)
    max_strip_elements: int = MAX_STRIP_ELEMENTS  #: cap on the estimated elements in one sector's strips at refinement 3, the FE tooth's sizes (beveloid.fe.sizes.strip_sizes)
    fine_fillets: bool = False  #: the fillets of the teeth in tooth pairs at the FE tooth's sizes (pair_model.sector_meshes)

    def __post_init__(self):
        from ..ltca.options import Options as LTCAOptions

        if not isinstance(self.ltca, LTCAOptions):
            raise OptionError("ltca", self.ltca, "must be an ltca.Options")
        if not (isinstance(self.refinement, int) and 1 <= self.refinement <= 4):
            raise OptionError("refinement", self.refinement, "must be an integer from 1 to 4")
        if self.contact_size_um is not None and not (isinstance(self.contact_size_um, (int, float))
                                                     and 10 <= self.contact_size_um <= 2000):
            raise OptionError("contact_size_um", self.contact_size_um, "must be a number from 10 to 2000 (um)")
        if not (isinstance(self.coarsen, (int, float)) and 0.125 <= self.coarsen <= 2.5):
            raise OptionError("coarsen", self.coarsen, "must be a number from 0.125 to 2.5")
        if not isinstance(self.fine_fillets, bool):
            raise OptionError("fine_fillets", self.fine_fillets, "must be true or false")
        if not (isinstance(self.max_strip_elements, int) and self.max_strip_elements >= 1000):
            raise OptionError("max_strip_elements", self.max_strip_elements, "must be an integer >= 1000")
        n = self.ltca.positions
        if self.position is not None and not (isinstance(self.position, int) and 0 <= self.position < n):
            raise OptionError("position", self.position, f"must be an integer from 0 to {n - 1} (the LTCA's "
                              "positions over one mesh cycle)")

    @property
    def flank(self) -> str:
        return self.ltca.flank


def _request(pair, load, options):
    """(load, options) checked: one torque, the pair's own errors (the FE model is placed with them)."""
    from ..ltca.load import LoadCase

    if not isinstance(load, LoadCase):
        raise TypeError(f"fecheck.analyze(pair, load, options=None, *, solver=None) needs an ltca.LoadCase as load, "
                        f"not {type(load).__name__}")
    if load.is_map:
        raise OptionError("torque_nm", load.torque_nm, "fe-check takes one torque and one error set")
    own = getattr(pair, "errors", None)
    if load.errors is not None and (own is None or not np.array_equal(np.asarray(load.errors), np.asarray(own))):
        raise OptionError("errors", load.errors, "fe-check takes the pair's own [misalignment] (None); set the "
                          "errors in the pair's spec")
    options = Options() if options is None else options
    if not isinstance(options, Options):
        raise TypeError(f"fecheck.analyze(pair, load, options=None, *, solver=None) needs a fecheck.Options or None, "
                        f"not {type(options).__name__}")
    return load, options


def choose_position(result) -> int:
    """The converged position with the most loaded pairs; among those the largest smallest load."""
    best, key = None, None
    for j in range(len(result.status)):
        if result.status[j] != LoadedStatus.OK:
            continue
        loads = np.nan_to_num(result.pair_load_n[j])
        loaded = loads[loads > 1e-6 * max(loads.sum(), 1e-300)]
        k = (loaded.size, loaded.min() if loaded.size else 0.0)
        if key is None or k > key:
            best, key = j, k
    if best is None:
        raise UserError("the LTCA converged at no position: fe-check has no position to compare at")
    return best


def _root(result, member, j):
    """The LTCA's largest root stress of the position's pairs (its FE tooth), None without one (plate)."""
    a = getattr(result, "pair_root_stress_mpa", {}).get(member)
    row = None if a is None else np.asarray(a)[j]
    return float(np.nanmax(row)) if row is not None and np.isfinite(row).any() else None


def _ltca_block(result, j) -> ContactNumbers:
    """The LTCA's numbers at position ``j``."""
    cells = result.cell_area_mm2[j]
    area = [(result.pressure_mpa[j, k] > 0).sum() * cells[k] for k in range(len(result.tooth_pairs))]
    return ContactNumbers.of(result.pair_load_n[j], result.pair_max_pressure_mpa[j], area, result.loaded_te[j] * 1e6,
                             {m: _root(result, m, j) for m in MEMBERS}, result.pinion_moment_nmm[j] * 1e-3)


def _resolution_notes(about) -> list[str]:
    """Where the mesh does not resolve a contact's width: its peak pressure and area are mesh numbers."""
    if about is None:
        return ["no local refinement: the flank elements are about ten contact half-widths, so the peak "
                "pressures and contact areas are not resolved; the loads, the TE and the torque balance are"]
    out = []
    for e in about:
        b, h = e["semi_axes_mm"][0], max(e["pinion_element_mm"], e["gear_element_mm"])
        if h > PEAK_RESOLVED_PER_SEMI_AXIS * b:
            out.append(f"tooth pair {e['tooth_pair']}: elements of {h:.3f} mm over the contact, {h / b:.1f} x its "
                       f"half-width b = {b:.3f} mm: its peak pressure and contact area are not resolved (the loads "
                       "and TE are; docs/validation.md section 11.2); a higher --refinement or a larger --max-strip-elements "
                       "resolves them")
    return out


def root_stress_notes(calculix, ltca, refinement: int, fillets: dict | None = None) -> list[str]:
    """Where the two FE models' root stresses differ by more than ROOT_STRESS_AGREEMENT: the numbers and what
    the difference can come from (the rating's local S_F divides by the LTCA's).  ``fillets``: {member:
    (the fillet's smallest radius, the sector's fillet element, the FE tooth's fillet element), mm}, named
    in the note; a radius below the FE tooth's element is a notch neither mesh resolves."""
    from .result import ROOT_STRESS_AGREEMENT, root_stress_agreement

    out = []
    for m, a in root_stress_agreement(calculix, ltca).items():
        if a["agrees"] is False:
            line = (f"{m}: root stress {a['calculix_mpa']:.1f} MPa (calculix) against {a['ltca_mpa']:.1f} MPa (the "
                    f"LTCA's FE tooth), ratio {a['ratio']:.3f}, beyond +-{ROOT_STRESS_AGREEMENT:.0%}: the sectors' "
                    f"fillet elements at refinement {refinement} and the LTCA's tooth data (its --fe-refinement) are the two meshes, the LTCA's "
                    "fillet stresses read on a grid fixed by the geometry (a local fit of the nodes'), CalculiX's its "
                    "nodal maximum")
            if fillets and m in fillets:
                rho, here, tooth = fillets[m]
                line += (f" (fillet elements {here:.3f} mm here, {tooth:.3f} mm in the FE tooth; the fillet's "
                         f"smallest radius {rho:.3f} mm")
                line += (", a notch neither mesh resolves: both readings are mesh numbers, see the rating's "
                         "root_stress_convergence)" if rho < tooth else ")")
                if here > 1.01 * tooth:
                    line += "; --fine-fillets meshes the sectors' fillets at the FE tooth's sizes"
            out.append(line + "; rerun with --refinement 2 to see which moves; the rating's local S_F divides "
                       "by the LTCA's")
    return out


#: the steps fe_check reports to its progress: the LTCA, the meshes, CalculiX (its lines between), done
STEPS = 3


def analyze(pair, load, options: Options | None = None, *, solver=None, progress=None) -> CheckResult:
    """The FE check of ``pair`` under ``load`` (an ``ltca.LoadCase``: one pinion torque; its errors None
    or the pair's own, which the FE model is placed with) with ``options`` (None: the defaults): a
    :class:`beveloid.fecheck.result.CheckResult`, its ``to_json()`` the contract (docs/fe_check.md);
    ``progress``: a :class:`beveloid.progress.Progress` (its steps, and CalculiX's lines) or None."""
    from .. import ltca, tca
    from ..solver import Solver
    from .deck import write_deck
    from .pair_model import LEVEL_1_COARSEN, SECTOR_TEETH, ModelRequest, pair_model, sector_meshes, sector_teeth
    from .strips import ltca_strips
    from .run import ccx_path, ccx_version, run_ccx
    from .pair_results import read_pair_results

    load, options = _request(pair, load, options)
    if options.out_dir:  # the one output rule (beveloid/outputs.py), before any work
        check_output_dir(str(options.out_dir), "out_dir")
    if ccx_path() is None:
        from .run import CCX_MISSING

        raise UserError(CCX_MISSING)
    geom = pair.geometry
    def say(step, text):
        if progress is not None:
            progress(step, STEPS, text)

    say(0, f"fe-check: LTCA at {load.torque_nm:g} N m over {options.ltca.positions} positions")
    result = ltca.analyze(pair, load, options.ltca, solver=Solver.of(solver))
    j = choose_position(result) if options.position is None else options.position
    if result.status[j] != LoadedStatus.OK or not np.isfinite(result.unloaded_te[j]):
        raise UserError(f"position = {j}: the LTCA has no converged contact there ({result.status[j]}); choose "
                        f"one of {[i for i, s in enumerate(result.status) if s == LoadedStatus.OK]}")
    ratio = geom.pinion.teeth / geom.gear.teeth
    ref = tca.reference_contact(geom, options.flank, Solver.of(solver).options)
    phi1 = float(result.pinion_angle[j])
    phi2 = float(result.unloaded_te[j] + tca.unknowns(ref.x).gear_angle_rad - ratio * (phi1 - ref.pinion_angle))
    say(1, f"fe-check: position {j} (pinion angle {phi1:.6f} rad); meshing both sectors (refinement "
        f"{options.refinement})")
    t0 = time.perf_counter()
    strips, about = {"pinion": None, "gear": None}, []
    _, teeth = sector_teeth(pair, phi1, phi2, tuple(result.tooth_pairs))
    if options.local_refinement:
        size = None if options.contact_size_um is None else options.contact_size_um * 1e-3
        strips, about = ltca_strips(result, j, geom, teeth, size, options.max_strip_elements)
    meshes = sector_meshes(pair, options.refinement, options.coarsen, strips, teeth, options.fine_fillets)
    for m in ("pinion", "gear"):
        for entry, h in zip(about, meshes[m].strip_sizes_mm):
            entry[f"{m}_element_mm"] = h
    req = ModelRequest(pair, options.flank, load.torque_nm, phi1, phi2,
                       float(np.nanmax(result.pair_max_pressure_mpa[j])),
                       float((result.loaded_te[j] - result.unloaded_te[j]) / ratio), tuple(result.tooth_pairs))
    model = pair_model(req, meshes)
    mesh_s = time.perf_counter() - t0
    with contextlib.ExitStack() as stack:
        folder = Path(options.out_dir) if options.out_dir else Path(
            stack.enter_context(tempfile.TemporaryDirectory(prefix="beveloid_fecheck_")))
        deck_path = folder / "fe_check.inp"
        info = write_deck(model.deck, deck_path)
        say(2, f"fe-check: {model.elements} C3D10 elements, {model.dof} degrees of freedom; running ccx in {folder}")
        run = run_ccx(deck_path, progress=lambda n, total, line: say(2, f"ccx: {line.strip()}"))
        fe = read_pair_results(run, model, info, folder / "fe_check.vtu" if options.out_dir else None)
    te_fe = float(result.unloaded_te[j]) + ratio * model.phi_sign * fe.rotation_rad
    calculix = ContactNumbers.of(fe.pair_load_n, fe.pair_max_pressure_mpa, fe.pair_area_mm2, te_fe * 1e6,
                                 fe.root_stress_mpa, fe.moment_nmm * 1e-3)
    files = {"deck": str(deck_path), "frd": str(run.file("frd")), "dat": str(run.file("dat")),
             "vtu": str(folder / "fe_check.vtu")} if options.out_dir else {}
    notes = [f"position {j} of {options.ltca.positions} over one mesh cycle, {options.flank} flank, pinion torque "
             f"{load.torque_nm:g} N m; tooth pairs {list(model.tooth_pairs)} in the LTCA's order in both blocks",
             f"calculix: C3D10 sectors of {SECTOR_TEETH} teeth (beveloid.fe.mesh; the teeth of the tooth pairs "
             "at the loaded tooth's sizes, the radial cuts free), frictionless surface-to-surface penalty "
             "contact (slope 50 E per mm), gear rim fixed, pinion rim a rigid body under the moment; pair loads "
             "and areas are CalculiX's contact totals (CF), peak pressure the largest nodal CPRESS on the gear "
             "flank",
             "root_stress_max_mpa: the largest principal stress on each member's fillet faces (calculix, the "
             "teeth of the tooth pairs, nodal values); the LTCA's largest pair root stress at the position (its FE "
             "tooth, the fillet stresses read on its fixed grid as the rating's S_F reads them; null with the plate tooth), tooth "
             f"model here: {getattr(result, 'tooth_model', 'plate')}",
             "loaded_transmission_error_urad: unloaded TE + (N1/N2) x the pinion's rotation under the moment "
             "(calculix); the LTCA's loaded TE",
             f"mesh {mesh_s:.1f} s, CalculiX {run.wall_s:.1f} s wall ({run.cpu_s:.1f} s CPU), {model.elements} "
             f"elements, {model.dof} DOF",
             "local_refinement: per loaded LTCA pair a strip on each flank (the LTCA's patch: centre line, "
             "half-width 1.5 b) meshed at b / 3 (or --contact-size-um), graded to the far size; the sizes are "
             "scaled up together when a sector's strips would exceed the element cap; null: not refined"]
    notes += [f"tooth pair {k}: outside the {SECTOR_TEETH}-tooth sectors (null)" for k, p in zip(model.tooth_pairs,
                                                                                         model.pairs) if p is None]
    notes += _resolution_notes(about if options.local_refinement else None)
    # the FE tooth's sizes scale like the sector's fillet (beveloid.fe.mesh.mesh_sizes: every size / refinement x
    # coarsen; the sectors' fillets at that rule x LEVEL_1_COARSEN, or x 1 with fine_fillets)
    tooth_scale = (result.fe_coarsen or 1.0) / (result.fe_refinement or 1) / (
        (1.0 if options.fine_fillets else LEVEL_1_COARSEN) * options.coarsen / options.refinement)
    fillets = {m: (meshes[m].sizes.fillet_radius_mm, meshes[m].sizes.fillet_mm, meshes[m].sizes.fillet_mm * tooth_scale)
               for m in ("pinion", "gear")}
    notes += root_stress_notes(calculix, _ltca_block(result, j), options.refinement, fillets)
    return CheckResult(
        run.version or ccx_version(), int(j), phi1, getattr(result, "tooth_model", "plate"),
        tuple(model.tooth_pairs), float(result.unloaded_te[j] * 1e6), model.elements, model.dof, run.wall_s,
        run.cpu_s, mesh_s, calculix, _ltca_block(result, j), files, notes, result.pair_hertz_max_pressure_mpa[j],
        result.patch_semi_axes_mm()[j], about if options.local_refinement else None, pair=pair, options=options,
        load=load)
