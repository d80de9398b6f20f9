"""The whole-tooth checks of a designed pair: ``analyze(pair, options=None, *, solver=None) -> ToothResult``
(a :class:`beveloid.result.Result`), its JSON fields and its table.

Statuses (not refusals: the design stands, the designer decides): ``undercut`` (a flank is
undercut somewhere in the face), ``pointed`` (the tip thickness reaches zero inside the face),
``interference`` (the mating tip reaches a fillet on the aligned pair's path of contact),
``tip inside base circle`` (somewhere in the face the tip circle lies inside a flank's base circle:
no involute reaches the tip there, its tip thickness is null), ``no contact`` (the contact ratio
could not be measured: it is then null), ``no form limit`` (the interference check could not
find where a flank's involute starts) and ``contact ratio below 1`` (the unmodified pair does not mesh
continuously on a flank; ``beveloid design`` puts it first, as a warning, with the design's numbers a
unit slip shows in).  Every value that could not be computed is ``None`` (JSON
``null``, a dash in the table), with the status that says why.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import OptionError
from ..result import Frozen, Result
from ..solver.patch_cover import UnboundedPatch
from ..tca import NoContactError
from ..names import FLANKS, MEMBERS
from ..status import ToothStatus
from . import contact, tip, undercut

STATUSES = tuple(ToothStatus)


def _mm(x, digits=4) -> str:
    """A length for the table: a dash when it could not be computed."""
    return "-" if x is None else f"{x:.{digits}f}"


@dataclass(frozen=True)
class Options(Frozen):
    """What the checks sample: the contact ratio's grid (angles per pinion pitch)."""
    contact_per_pitch: int = 24

    def __post_init__(self):
        super().__post_init__()
        if not (isinstance(self.contact_per_pitch, int) and not isinstance(self.contact_per_pitch, bool)
                and 8 <= self.contact_per_pitch <= 1000):
            raise OptionError("contact_per_pitch", self.contact_per_pitch, "must be an integer from 8 to 1000")


#: what the design's contact ratio is, in its JSON and table
RATIO_BASIS = {"unmodified": "the unmodified flanks (crowning, relief and lead slope taken off)",
               "as designed": "the flanks as designed (they carry no modification)"}
#: why the modified flanks' unloaded contact ratio is not the designer's one
MODIFIED_NOTE = ("crowned or relieved flanks touch one tooth pair at a time without load (their unloaded contact "
                 "ratio is at most 1 or barely more); the loaded one: `beveloid ltca` (loaded_contact_ratio)")


@dataclass(frozen=True)
class ToothResult(Result):
    """The whole-tooth checks of ``pair`` under ``options`` (a :class:`Options`); deep-frozen."""

    undercut: dict  # {member: {flank: undercut.Undercut or None}}
    tip: dict  # {member: tip.TipThickness}
    contact: dict  # {flank: contact.FlankContact or None}: the flanks as designed (interference)
    statuses: tuple = ()  # ((status, message), ...)
    #: {flank: contact.FlankContact or None} of the unmodified flanks (None: the flanks carry no modification)
    unmodified: dict | None = None

    @property
    def contact_ratio(self) -> dict:
        """{flank: the contact ratio a designer means (the unmodified flanks'), or None}."""
        src = self.contact if self.unmodified is None else self.unmodified
        return {fl: (c.contact_ratio if c is not None else None) for fl, c in src.items()}

    @property
    def contact_ratio_basis(self) -> str:
        return RATIO_BASIS["as designed" if self.unmodified is None else "unmodified"]

    def member_json(self, member: str) -> dict:
        return {"tip_transverse_thickness_mm": self.tip[member].to_json(),
                "undercut": {fl: (u.to_json() if u is not None else None)
                             for fl, u in self.undercut[member].items()}}

    def pair_json(self) -> dict:
        modified = None if self.unmodified is None else {
            fl: (c.contact_ratio if c is not None else None) for fl, c in self.contact.items()}
        return {"contact_ratio": self.contact_ratio, "contact_ratio_basis": self.contact_ratio_basis,
                "contact_ratio_modified_unloaded": modified,
                "tooth_status": [{"status": s, "message": m} for s, m in self.statuses]}

    def to_json(self) -> dict:
        """The whole-tooth JSON: per member its tip thickness and undercut, and the pair's fields
        (what :meth:`add_to` puts into the design JSON)."""
        return {**{member: self.member_json(member) for member in MEMBERS}, **self.pair_json()}

    def add_to(self, design: dict) -> dict:
        """The design JSON (beveloid design --json) with the whole-tooth fields added."""
        for member in MEMBERS:
            design[member].update(self.member_json(member))
        design.update(self.pair_json())
        return design

    def table(self) -> str:
        lines = ["", "Whole tooth (face coordinate z from the face centre, toe at -W/2; mm):",
                 "member | flank | tip thickness toe / middle / heel (transverse arc) | undercut z range (depth)"]
        for member in MEMBERS:
            t = self.tip[member]
            for fl in FLANKS:
                u = self.undercut[member][fl]
                cut = "none" if u is None else f"{u.from_mm:.3f} .. {u.to_mm:.3f} ({u.depth_mm:.4f})"
                thick = " / ".join(_mm(x) for x in (t.toe_mm, t.middle_mm, t.heel_mm)) if fl == "left" else ""
                lines.append(f"{member} | {fl} | {thick} | {cut}")
        ratio = " | ".join(f"{fl} {v:.4f}" if v is not None else f"{fl} -" for fl, v in self.contact_ratio.items())
        lines.append(f"contact ratio (aligned TCA, per pinion pitch) of {self.contact_ratio_basis}: {ratio}")
        if self.unmodified is not None:
            mod = " | ".join(f"{fl} {c.contact_ratio:.4f}" if c is not None else f"{fl} -"
                             for fl, c in self.contact.items())
            lines.append(f"  with the modifications, unloaded: {mod}: {MODIFIED_NOTE}")
        lines += [f"status {s}: {m}" for s, m in self.statuses]
        return "\n".join(lines)


def export_statuses(geom) -> list:
    """What `beveloid export` would refuse, said before anyone tries: per member the checks of its tooth
    (both formats) and of its STEP faces (:mod:`beveloid.tooth.sampling`), as ``not exportable`` statuses."""
    import numpy as np

    from .sampling import ExportGeometryError, ToothSampler

    out = []
    for member in MEMBERS:
        try:
            sampler = ToothSampler(geom, member)
            z = np.linspace(*sorted(sampler.z_range_mm), 21)
            sampler.check_buildable(z)
        except ExportGeometryError as exc:
            out.append((ToothStatus.NOT_EXPORTABLE, f"export (STEP and STL): {exc}"))
            continue
        try:
            sampler.check_step_buildable(z)
        except ExportGeometryError as exc:
            out.append((ToothStatus.NOT_EXPORTABLE, f"export as STEP: {exc}"))
    return out


def _contacts(geom, options, solver, statuses, what) -> dict:
    """{flank: contact.FlankContact or None} of ``geom``; a flank without one adds its ``no contact`` status."""
    out = {}
    for fl in FLANKS:
        try:
            out[fl] = contact.flank_contact(geom, fl, per_pitch=options.contact_per_pitch, solver=solver)
        except (contact.NoContact, NoContactError, UnboundedPatch) as err:
            out[fl] = None
            statuses.append((ToothStatus.NO_CONTACT, f"{what}, {fl} flank: {err}"))
    return out


def analyze(pair, options: Options | None = None, *, solver=None) -> ToothResult:
    """Every whole-tooth check of a :class:`beveloid.pair.Pair` (or a PairGeometry) under ``options`` (None:
    the default :class:`Options`); the contact ratio solved by ``solver`` (a :class:`beveloid.solver.Solver`;
    None: the default, compiled when numba is
    installed)."""
    if options is None:
        options = Options()
    elif not isinstance(options, Options):
        raise TypeError(f"tooth.analyze(pair, options, *, solver=None) needs a tooth.Options, not "
                        f"{type(options).__name__}")
    geom = getattr(pair, "geometry", pair)
    cut = undercut.undercut(geom)
    tips = tip.tip_thicknesses(geom)
    statuses = []
    for member in MEMBERS:
        statuses += [(ToothStatus.UNDERCUT, u.message()) for u in cut[member].values() if u is not None]
        if tips[member].pointed:
            statuses.append((ToothStatus.POINTED, tips[member].message()))
        if tips[member].no_involute:
            statuses.append((ToothStatus.TIP_INSIDE_BASE_CIRCLE, tips[member].no_involute_message()))
    statuses += export_statuses(geom)
    bare = geom.unmodified()  # the contact ratio a designer means: the unmodified flanks'
    unmodified = None if bare is geom else _contacts(bare, options, solver, statuses,
                                                     "contact ratio of the unmodified flanks")
    flanks = _contacts(geom, options, solver, statuses, "contact ratio" if unmodified is None
                       else "interference (the modified flanks' contact)")
    for fl, c in (flanks if unmodified is None else unmodified).items():
        if c is not None and c.contact_ratio < 1.0:
            statuses.append((ToothStatus.CONTACT_RATIO_BELOW_ONE,
                             f"{fl} flank: the unmodified pair's contact ratio is {c.contact_ratio:.4f} < 1: a tooth"
                             " pair leaves its contact before the next one engages (no continuous mesh on this flank)"))
    for fl in FLANKS:
        if flanks[fl] is None:
            continue
        for member, margin in flanks[fl].form_margin_mm.items():
            if margin is None:
                statuses.append((ToothStatus.NO_FORM_LIMIT,
                                 f"interference, {fl} flank: the {member}'s form limit was not found in the sections"
                                 " of the path of contact (no involute up to the tip there): interference with its"
                                 " fillet is not checked"))
        for boundary in flanks[fl].interference:
            owner = boundary.split()[0]
            mate = "gear" if owner == "pinion" else "pinion"
            margin = flanks[fl].form_margin_mm[owner]
            below = -margin if margin is not None else 0.0
            depth = f" by {below:.4f} mm along the rack edge" if below > 0 else ""
            statuses.append((ToothStatus.INTERFERENCE,
                             f"interference: {fl} flank, the {mate}'s tip reaches below the {owner}'s form"
                             f" limit{depth} (into its fillet) on the aligned pair's path of contact"))
    return ToothResult(cut, tips, flanks, statuses, unmodified, pair=pair, options=options)
