"""The faces of one tooth and of the gap after it, sampled from the generated surfaces (numpy only).

Every face is sampled on a grid of a profile parameter ``s`` in [0, 1] and the axial position ``z``
(mm, member frame S_i) from the toe to the heel, so that each face's grid rows at the face ends lie
in the toe and heel planes and neighbouring faces share their boundary rows point for point:

* ``flank_left``, ``flank_right``: the generated flank (``geometry.surface``) from the form limit
  (s = 0, where the fillet meets it) to the tip cone (s = 1); l runs linearly in s, u is solved so
  that the point lies in the section z; a modification the root fillet does not carry (tip and end
  relief, lead slope, a user model) is run into the fillet over the lowest ``BLEND_FRACTION`` of s;
* ``fillet_left``, ``fillet_right``: the root transition, from the root cone (s = 0) to the form
  limit (s = 1): :func:`root_transition`, the one place that says where it comes from;
* the form limit of a section (:func:`form_limits`) is where the fillet meets the flank: the tip
  round's junction, or, in an undercut section, where the fillet cuts into the involute
  (``tooth.profile.form_limit``): the tooth is exported as generated, the undercut fillet surface
  below that crossing and the flank above it;
* ``tip``: the tip cone between the left flank's and the right flank's tip curves of the tooth;
* ``root``: the root cone between the right fillet of this tooth and the left fillet of the next
  tooth (turned by one pitch, 2 pi / N, about the axis).

Sampling a face at (s, z) that were not used for a fit gives points of the generated surface there:
the accuracy tests measure the exported surfaces against them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import UserError
from ..names import FLANKS
from .body import is_body

#: the faces of one tooth and the gap after it, in the order the solid is built from
FACES = ("flank_left", "flank_right", "fillet_left", "fillet_right", "tip", "root")
#: the largest step (mm) between a flank and its fillet where they meet that the export accepts
JOIN_TOL_MM = 1e-4
#: the STEP faces' fit tolerance (um off the generated points; beveloid.export.solid.FIT_TOL_UM)
STEP_FIT_TOL_UM = 0.25
#: the deepest fold of a flank toward the axis that a STEP face fitted within STEP_FIT_TOL_UM can follow
#: monotonically (twice the tolerance; measured on the issue-60 pinion: 5 um of profile crowning folds the
#: right flank by 0.36 um and exports, 6 um by 0.87 um and gave an invalid solid)
STEP_FOLD_TOL_UM = 2 * STEP_FIT_TOL_UM
#: profile samples (0 at the form limit .. 1 at the tip) that find a fold next to the form limit, which
#: the 41 even samples of check_buildable step over: every 0.0005 over the first tenth of the profile
FOLD_SAMPLES = np.linspace(0.0, 0.1, 201)
#: a tip land this thin (mm) is refused where the tooth is not pointed nearby (within THIN_LAND_SPAN_MM of
#: where a pointed range begins, the land narrows to zero and ends in a point, which is built)
THIN_LAND_MM = 1e-3
THIN_LAND_SPAN_MM = 0.05
#: an undercut shallower than this (mm) keeps the junction as the form limit: where the undercut begins (a
#: section of ToothSampler.face_pieces) the fillet's crossing of the involute is the junction, which the
#: search for the crossing cannot bracket there; the material it leaves is thinner than this depth
UNDERCUT_MIN_MM = 1e-6
#: the shortest piece (mm) the face is cut into where a face changes how it ends (ToothSampler.face_pieces)
MIN_PIECE_MM = 1e-2
#: a modified flank that does not meet its root fillet at the form limit is run into it over this
#: fraction of the flank's profile parameter s (ToothSampler.flank_points): the step, micrometres,
#: fades out smoothly (C1) below the active profile, which starts higher on any working tooth
BLEND_FRACTION = 0.1


def _smoothstep(t):
    """0 for t <= 0, 1 for t >= 1, C1 between (3 t^2 - 2 t^3)."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


class ExportGeometryError(UserError):
    """A member whose tooth the export cannot build (no involute up to the tip, a bore through the root, ...):
    one line that says why."""


@dataclass(frozen=True)
class ToothSampler:
    """One member of a designed pair, ready to be sampled (mm, rad, member frame S_i)."""

    geometry: object  # beveloid.geometry.PairGeometry
    member: str
    #: (flank, z) -> (l, psi) of the form limit (tooth.profile.form_limit is a search: done once per section)
    _forms: dict = field(default_factory=dict, compare=False, repr=False)
    #: z -> the radius where a pointed section's flanks cross (a root search: once per section)
    _tops: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def data(self):
        return self.geometry.member(self.member)

    @property
    def teeth(self) -> int:
        return int(self.data.teeth)

    @property
    def pitch_angle_rad(self) -> float:
        return 2 * math.pi / self.teeth

    @property
    def z_range_mm(self):
        """(toe, heel) axial positions, toe first (S_i)."""
        return tuple(float(z) for z in self.data.face_limits)

    def root_radius_mm(self, z):
        """Root cone radius at z: where the rack's tip line sweeps (the rack's tip plane rolled on the
        pitch cylinder, tilted by the cone angle): r + (s - a) / cos(gamma) + z tan(gamma)."""
        m = self.data
        return (m.pitch_radius_mm + (m.rack_shift_mm - m.cutter_addendum_mm) / math.cos(m.cone_angle)
                + np.asarray(z, dtype=float) * math.tan(m.cone_angle))

    def tip_radius_mm(self, z):
        return self.data.tip_radius(z)

    def undercut_depth(self, flank, z):
        """How far the rack's form point reaches below the involute's start in the sections z (> 0: undercut)."""
        from . import sections

        return getattr(sections.section(self.geometry, self.member, sections.face_z(self.geometry, self.member, z)),
                       f"undercut_depth_{flank}")

    # ------------------------------------------------------------------ flanks
    def flank_u(self, flank, l, z, u0=None):
        """u of the flank point with rack parameter l in the section z (tooth.profile's section Newton)."""
        from ..tooth.profile import NoSolution, flank_in_section

        try:
            return flank_in_section(self.geometry, self.member, flank, z, l, z if u0 is None else u0)[1]
        except NoSolution:
            raise ExportGeometryError(f"{self.member} {flank} flank: no flank point found in a section "
                                      "(Newton on u)") from None

    def _flank_at(self, flank, z, radius):
        """(point, l, u) of the flank at radii in the sections z (tooth.profile.flank_at_radius)."""
        from ..tooth.profile import NoSolution, flank_at_radius

        try:
            return flank_at_radius(self.geometry, self.member, flank, z, radius,
                                   l0=self.data.tip_height_mm + self.data.cutter_addendum_mm)
        except NoSolution:
            raise ExportGeometryError(f"{self.member} {flank} flank: it does not reach the tip cone") from None

    def angular_width(self, z, radius, strict=True):
        """The tooth's angle (rad) from its left to its right flank at radii in the sections z (< 0: crossed;
        with ``strict=False`` NaN where a flank point is not found, else ExportGeometryError)."""
        if strict:
            return _signed_angle(self._flank_at("left", z, radius)[0], self._flank_at("right", z, radius)[0])
        from ..tooth.profile import flank_at_radius

        l0 = self.data.tip_height_mm + self.data.cutter_addendum_mm
        pts = [flank_at_radius(self.geometry, self.member, f, z, radius, l0=l0, strict=False)[0] for f in FLANKS]
        return _signed_angle(*pts)

    def top_radius_mm(self, z):
        """Where the flanks end in the sections z: the tip cone, or, in a pointed section, the radius where
        the two flanks cross, below the tip cone (the tooth as it really ends: a tip land of zero width)."""
        z = np.asarray(z, dtype=float)
        r = np.array(self.tip_radius_mm(z), dtype=float)
        flat_z, flat_r = np.atleast_1d(z).ravel(), np.atleast_1d(r).ravel().copy()
        pointed = np.nonzero(np.atleast_1d(self.angular_width(z, r)).ravel() <= 0)[0]
        new = [k for k in pointed if float(flat_z[k]) not in self._tops]
        if new:
            for k, radius in zip(new, _crossing_radii(self, flat_z[new], flat_r[new])):
                self._tops[float(flat_z[k])] = radius
        for k in pointed:
            flat_r[k] = self._tops[float(flat_z[k])]
        return flat_r.reshape(np.shape(r))

    def tip_pieces(self, z_range, n=41):
        """[(z_from, z_to, landed)] from the toe to the heel: the face ranges where the tooth has a tip land
        (``landed``) and where it is pointed (its flanks cross below the tip cone).  The land's sign on n
        sections, its changes found by the whole-tooth checks' root finder (tooth.sections.segments) on the
        angle between the flanks at the tip cone; a section where a flank does not reach the tip cone is
        refused (ExportGeometryError)."""
        from . import sections

        def land(z):
            z = np.array([z])
            return float(self.angular_width(z, self.tip_radius_mm(z), strict=False)[0])

        grid = np.linspace(*z_range, n)
        values = self.angular_width(grid, self.tip_radius_mm(grid), strict=False)
        pieces = sections.segments(land, grid, xtol=1e-9, values=values)
        for lo, hi, cls in pieces:
            if cls == sections.INVALID:
                raise ExportGeometryError(f"{self.member}: from z = {lo:.3f} to {hi:.3f} mm a flank does not reach"
                                          " the tip cone (no flank point found there)")
        ends = np.array([lo for lo, _, _ in pieces[1:]])  # where a land begins or ends in the face
        land_mm = values * self.tip_radius_mm(grid)
        for zk, w in zip(grid, land_mm):
            if 0 < w <= THIN_LAND_MM and not np.any(np.abs(ends - zk) <= THIN_LAND_SPAN_MM):
                raise ExportGeometryError(
                    f"{self.member}: the tip land is {1e3 * w:.3f} um wide at z = {zk:.3f} mm without the tooth"
                    f" being pointed there: a tip face under {1e3 * THIN_LAND_MM:g} um is not built (its edges come"
                    " within the export's accuracy of each other and merge at the sewing tolerance, 0.1 um);"
                    " a slightly smaller profile shift or addendum gives a wider land, a slightly larger one a"
                    " pointed tip, and both export")
        return [(lo, hi, cls == sections.POSITIVE) for lo, hi, cls in pieces]

    def face_pieces(self, z_range, n=41):
        """[(z_from, z_to, landed)] from the toe to the heel: the face cut wherever one of the tooth's faces
        changes how it ends -- where the tip land begins or ends (:meth:`tip_pieces`) and where a flank's
        undercut begins or ends (its form limit turns from the tip round's junction to the fillet's
        crossing of the involute, :func:`form_limits`) -- so that each face is smooth over each piece
        (a B-spline fit or a mesh row across such a turn needs a very fine grid).  ``landed``: the piece
        has a tip land.  Breaks closer than MIN_PIECE_MM to one another or to the face's ends are merged."""
        from . import sections

        breaks = [lo for lo, _, _ in self.tip_pieces(z_range, n)[1:]]
        grid = np.linspace(*z_range, n)
        for flank in FLANKS:
            def depth(z, flank=flank):
                return float(self.undercut_depth(flank, np.array([z]))[0])

            cut = sections.segments(depth, grid, xtol=1e-9, values=self.undercut_depth(flank, grid))
            breaks += [lo for lo, _, _ in cut[1:]]
        kept = [float(z_range[0])]
        for b in sorted(breaks):
            if b - kept[-1] > MIN_PIECE_MM and z_range[1] - b > MIN_PIECE_MM:
                kept.append(b)
        kept.append(float(z_range[1]))
        mids = np.array([0.5 * (lo + hi) for lo, hi in zip(kept[:-1], kept[1:])])
        landed = self.angular_width(mids, self.tip_radius_mm(mids), strict=False) > 0
        return [(lo, hi, bool(c)) for lo, hi, c in zip(kept[:-1], kept[1:], landed)]

    def flank_tip(self, flank, z):
        """(l, u) where the flank ends in the sections z (:meth:`top_radius_mm`; tooth.profile.flank_at_radius)."""
        z = np.asarray(z, dtype=float)
        _, l, u = self._flank_at(flank, z, self.top_radius_mm(z))
        return l, u

    def form_limits(self, flank, z):
        """(l, psi) arrays: the flank's rack parameter and the fillet's parameter at the form limit of
        the sections z (:func:`form_limits`)."""
        return form_limits(self, flank, np.asarray(z, dtype=float))

    def flank_points(self, flank, s, z):
        """Flank points on the grid s (n_s,) x z (n_z,): shape (n_s, n_z, 3).  A modified flank that does
        not meet its root fillet (:meth:`flank_blend_mm`) is run into it over s < BLEND_FRACTION."""
        s, z = np.asarray(s, dtype=float), np.asarray(z, dtype=float)
        points = self._generated_flank_points(flank, s, z)
        if is_body(self.geometry, self.member):
            return points
        weight = 1.0 - _smoothstep(s / BLEND_FRACTION)  # 1 at the form limit, 0 from BLEND_FRACTION up
        if not np.any(weight > 0):
            return points
        return points + weight[:, None, None] * self.flank_blend_mm(flank, z)[None]

    def _generated_flank_points(self, flank, s, z):
        l_tip, u_tip = self.flank_tip(flank, z)
        l0 = self.form_limits(flank, z)[0][None, :]
        l = l0 + s[:, None] * (l_tip[None, :] - l0)
        u = self.flank_u(flank, l, z[None, :], u0=u_tip[None, :])
        return self.geometry.surface(self.member, flank, l, u).point

    def flank_blend_mm(self, flank, z):
        """(n_z, 3) the step from the generated flank to its root fillet at the form limit of the sections z:
        zero where the fillet model carries the flank's modification (involute, crowned flanks) or cuts
        into it (undercut); a tip or end relief, a lead slope or a user model's twist leave a step of
        micrometres there, which :meth:`flank_points` closes (a relieved flank runs into the fillet)."""
        z = np.asarray(z, dtype=float)
        return self.fillet_points(flank, np.array([1.0]), z)[0] - self._generated_flank_points(flank, np.array([0.0]), z)[0]

    # ------------------------------------------------------------------ root transition and lands
    def fillet_points(self, flank, s, z):
        """Root transition points, s = 0 on the root cone, s = 1 at the form limit: (n_s, n_z, 3)."""
        return root_transition(self, flank, np.asarray(s, dtype=float), np.asarray(z, dtype=float))

    def tip_points(self, s, z):
        """The tip cone between the left (s = 0) and right (s = 1) flanks' tip curves of the tooth."""
        z = np.asarray(z, dtype=float)
        ends = [self.flank_points(f, np.array([1.0]), z)[0] for f in FLANKS]
        return _cone_strip(ends[0], ends[1], np.asarray(s, dtype=float))

    def root_points(self, s, z):
        """The root cone from this tooth's right fillet (s = 0) to the next tooth's left fillet (s = 1)."""
        z = np.asarray(z, dtype=float)
        right = self.fillet_points("right", np.array([0.0]), z)[0]
        left_next = rotate_z(self.fillet_points("left", np.array([0.0]), z)[0], self.pitch_angle_rad)
        return _cone_strip(right, left_next, np.asarray(s, dtype=float))

    def face_points(self, face, s, z):
        """Points of one of :data:`FACES` on the grid s x z: shape (n_s, n_z, 3)."""
        if face.startswith("flank_"):
            return self.flank_points(face[6:], s, z)
        if face.startswith("fillet_"):
            return self.fillet_points(face[7:], s, z)
        if face == "tip":
            return self.tip_points(s, z)
        if face == "root":
            return self.root_points(s, z)
        raise ValueError(f"face must be one of {FACES}, got {face!r}")

    # ------------------------------------------------------------------ checks
    def check_bore(self, bore_mm: float) -> None:
        """A bore must leave material under the root cone: below the smallest root diameter."""
        root = 2 * float(np.min(self.root_radius_mm(np.array(self.z_range_mm))))
        if not bore_mm < root:
            raise ExportGeometryError(
                f"{self.member}.bore_diameter_mm = {bore_mm:g}: must be below the smallest root diameter,"
                f" {root:.3f} mm (0: no bore)")

    def deepest_fold(self, z) -> tuple:
        """(depth in mm, flank, z in mm) of the deepest place where a flank turns back toward the axis on its
        way from the form limit to the tip (its radius below the largest one passed), over the sections z
        and the profile samples :data:`FOLD_SAMPLES`; depth 0 when no flank does."""
        best = (0.0, FLANKS[0], float(np.asarray(z, dtype=float).flat[0]))
        for flank in FLANKS:
            r = np.hypot(*np.moveaxis(self.flank_points(flank, FOLD_SAMPLES, np.asarray(z, float))[..., :2], -1, 0))
            drop = np.maximum.accumulate(r, axis=0) - r
            k = np.unravel_index(int(np.argmax(drop)), drop.shape)
            if drop[k] > best[0]:
                best = (float(drop[k]), flank, float(np.asarray(z, float)[k[1]]))
        return best

    def check_step_buildable(self, z) -> None:
        """Refuse what STEP's fitted faces cannot follow: a flank that turns back toward the axis by more than
        :data:`STEP_FOLD_TOL_UM` (a fold shallower than twice the fit tolerance lies inside a monotone face
        within it; a deeper one makes every face within it fold, and the solid invalid)."""
        depth, flank, zk = self.deepest_fold(z)
        if depth * 1e3 > STEP_FOLD_TOL_UM:
            raise ExportGeometryError(
                f"{self.member}: the {flank} flank turns back toward the axis by {depth * 1e3:.2f} um just above its"
                f" form limit (z = {zk:.3f} mm), more than the STEP faces, fitted within {STEP_FIT_TOL_UM} um, can"
                " follow (a profile modification near the base circle); --format stl builds it from the generated"
                " points")

    def check_buildable(self, z):
        """Refuse a tooth the export cannot build: no involute up to the tip, a flank that turns back above
        its form limit, no root land.  (A pointed tooth is built: its flanks end where they cross.)"""
        z = np.asarray(z, dtype=float)
        s = np.linspace(0.0, 1.0, 41)
        for flank in FLANKS:
            self.form_limits(flank, z)  # refuses a section without an involute up to the tip
            step = np.linalg.norm(self.fillet_points(flank, np.array([1.0]), z)[0]
                                  - self.flank_points(flank, np.array([0.0]), z)[0], axis=-1)
            if np.max(step) > JOIN_TOL_MM:
                k = int(np.argmax(step))
                raise ExportGeometryError(
                    f"{self.member}: the {flank} flank and its root fillet are {1e3 * step[k]:.1f} um apart at the form"
                    f" limit (z = {z[k]:.3f} mm): the flank's modification ({self.data.tooth_surface} model) is not"
                    " carried by the root fillet model, so the tooth's surfaces do not close")
        for flank in FLANKS:
            r = np.hypot(*np.moveaxis(self.flank_points(flank, s, z)[..., :2], -1, 0))
            if np.any(np.diff(r, axis=0) <= 0):
                k = int(np.nonzero(np.any(np.diff(r, axis=0) <= 0, axis=0))[0][0])
                raise ExportGeometryError(
                    f"{self.member}: the {flank} flank turns back toward the axis above its form limit at"
                    f" z = {z[k]:.3f} mm: its sections are not a single profile the export can build")
        root = [self.fillet_points("right", np.array([0.0]), z)[0],
                rotate_z(self.fillet_points("left", np.array([0.0]), z)[0], self.pitch_angle_rad)]
        land = _signed_angle(root[0], root[1]) * self.root_radius_mm(z)
        if np.min(land) <= 1e-3:
            raise ExportGeometryError(f"{self.member}: the root fillets of neighbouring teeth meet (no root land):"
                                      " export needs a root land")


def _crossing_radii(sampler: ToothSampler, z, tip_radius, scan=24, halvings=45):
    """The radii where pointed sections' two flanks cross (the tooth's angular width is zero), between the
    larger base circle and the tip cone, for the sections z at once: a scan of radii, then bisection on the
    last bracket from a positive width to a crossed one (NaN, a point Newton did not find, is skipped)."""
    from . import sections

    sec = sections.section(sampler.geometry, sampler.member, sections.face_z(sampler.geometry, sampler.member, z))
    lo = np.minimum(np.maximum(sec.base_radius_left, sec.base_radius_right) * (1 + 1e-9), tip_radius)
    t = np.linspace(0.0, 1.0, scan)[:, None]
    radii = lo[None, :] + t * (tip_radius - lo)[None, :]
    width = sampler.angular_width(np.broadcast_to(z, radii.shape), radii, strict=False)
    open_ = (width[:-1] > 0) & (width[1:] <= 0)  # NaN compares False: no bracket through it
    if not open_.any(axis=0).all():
        k = int(np.argmin(open_.any(axis=0)))
        raise ExportGeometryError(f"{sampler.member}: at z = {z[k]:.3f} mm the flanks cross at or inside the base"
                                  " circle (a pointed tooth with no involute up to its point): its flanks cannot be"
                                  " built")
    j = open_.shape[0] - 1 - np.argmax(open_[::-1], axis=0)  # the last bracket, nearest the tip
    cols = np.arange(len(z))
    a, b = radii[j, cols], radii[j + 1, cols]
    for _ in range(halvings):
        mid = 0.5 * (a + b)
        positive = sampler.angular_width(z, mid, strict=False) > 0
        a, b = np.where(positive, mid, a), np.where(positive, b, mid)
    return 0.5 * (a + b)


def form_limits(sampler: ToothSampler, flank, z):
    """THE form limit of the exported tooth, per section z: (l (n_z,), psi (n_z,)) where the root
    transition meets the flank.  The tip round's junction (l_t, psi_J); in an undercut section the
    crossing of the fillet and the flank (``tooth.profile.form_limit``), below which the generated
    tooth is the fillet surface and above which it is the flank."""
    from . import fillet, profile

    tr = fillet.tip_round(sampler.geometry, sampler.member)
    l, psi = np.full(z.shape, float(tr.junction_l)), np.full(z.shape, float(tr.junction_psi))
    cut = sampler.undercut_depth(flank, z)
    for k in np.nonzero(cut > UNDERCUT_MIN_MM)[0]:
        key = (flank, float(z[k]))
        if key not in sampler._forms:
            form = (profile.form_limit(sampler.geometry, sampler.member, flank, float(z[k]), samples=100)
                    or profile.form_limit(sampler.geometry, sampler.member, flank, float(z[k])))  # finer search
            if form is None:
                raise ExportGeometryError(
                    f"{sampler.member}: at z = {z[k]:.3f} mm the {flank} flank has no involute up to the tip (its"
                    " tip circle lies inside the base circle: the section is all fillet and undercut), which the"
                    " exported tooth's faces cannot describe")
            sampler._forms[key] = (form.l_mm, form.psi)
        l[k], psi[k] = sampler._forms[key]
    return l, psi


def root_transition(sampler: ToothSampler, flank, s, z):
    """THE source of the root transition surface, (n_s, n_z, 3): s = 0 on the root cone, 1 at the flank.

    The generated root fillet (``beveloid.tooth.fillet``: the envelope of the rack's tip round, a
    trochoidal surface for a sharp rack), sampled in the transverse sections z.
    """
    from .profile import NoSolution, fillet_in_section

    geometry, member = sampler.geometry, sampler.member
    z2 = np.broadcast_to(z[None, :], (s.size, z.size))
    l_form, psi_form = form_limits(sampler, flank, z)
    psi = s[:, None] * psi_form[None, :]
    u = sampler.flank_u(flank, l_form, z)
    try:
        return fillet_in_section(geometry, member, flank, z2, psi, np.broadcast_to(u[None, :], z2.shape))[0]
    except NoSolution:
        raise ExportGeometryError(f"{member} {flank} fillet: no fillet point found in a section "
                                  "(Newton on u)") from None


def rotate_z(points, angle):
    """Points (..., 3) turned by angle (rad) about the z axis."""
    c, s = math.cos(angle), math.sin(angle)
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y, points[..., 2]], axis=-1)


def _signed_angle(a, b):
    """Angle (rad) from the points a to the points b about the z axis, in (-pi, pi]."""
    return np.angle(np.exp(1j * (np.arctan2(b[..., 1], b[..., 0]) - np.arctan2(a[..., 1], a[..., 0]))))


def _cone_strip(a, b, s):
    """Points between the curves a (s = 0) and b (s = 1), (n_z, 3) each, on the surface of revolution
    through them (angle and radius linear in s): (n_s, n_z, 3).  The end rows are a and b exactly."""
    ta = np.arctan2(a[:, 1], a[:, 0])
    dt = _signed_angle(a, b)
    ra, rb = np.hypot(a[:, 0], a[:, 1]), np.hypot(b[:, 0], b[:, 1])
    t = ta[None] + s[:, None] * dt[None]
    r = ra[None] + s[:, None] * (rb - ra)[None]
    out = np.stack([r * np.cos(t), r * np.sin(t), np.broadcast_to(a[None, :, 2], t.shape)], axis=-1)
    out[s == 0.0] = a
    out[s == 1.0] = b
    return out
