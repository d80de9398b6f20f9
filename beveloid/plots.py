"""Figures like the paper's Figs 10-22: contact paths on the flanks and TE over the mesh cycle.

matplotlib is imported lazily with the non-interactive Agg backend, so importing beveloid
stays cheap and plotting works without a display.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from .status import PointStatus


#: A TE peak-to-peak below this (urad) is zero to the solver tolerance: the Newton solves to ~1e-12 mm,
#: i.e. ~1e-8 urad, and 1e-3 urad (1 nrad) is far below anything a gear measurement can resolve.
TE_ZERO_URAD = 1e-3
#: Half-height (urad) of the TE axis when the TE is zero to the solver tolerance.
TE_FLAT_HALF_SPAN_URAD = 1.0
#: The pinion angle's axis label and table head on every TCA and LTCA figure and table: one quantity,
#: one unit (degrees); :func:`pinion_angle_text` writes a value in the same words
PINION_ANGLE_SYMBOL = "phi'_1"
PINION_ANGLE_UNIT = "deg"
PINION_ANGLE_LABEL = f"pinion angle {PINION_ANGLE_SYMBOL} ({PINION_ANGLE_UNIT})"


def pinion_angle_deg(phi_rad):
    """A pinion angle (rad; a number or an array) in the unit of :data:`PINION_ANGLE_LABEL`."""
    return np.degrees(phi_rad)


def pinion_angle_text(phi_rad: float, decimals: int = 2, words: bool = True) -> str:
    """One pinion angle in the words and unit of :data:`PINION_ANGLE_LABEL`: "pinion angle phi'_1 = 6.43
    deg" (``words=False``: "phi'_1 = 6.43 deg")."""
    value = f"{PINION_ANGLE_SYMBOL} = {float(pinion_angle_deg(phi_rad)):.{decimals}f} {PINION_ANGLE_UNIT}"
    return f"pinion angle {value}" if words else value


#: the legend's key to the faded TE points
FADED_LABEL = "faded: the window's ends (a pair beyond those solved may carry)"


def te_axis(ax, centre_urad, ptp_urad):
    """Scale a TE axis: when every curve's peak-to-peak is below TE_ZERO_URAD, show +-1 urad about
    ``centre_urad`` and say on the figure that the TE is zero to the solver tolerance (instead of
    autoscaling round-off to fill the axis).  Returns True when it did so."""
    ptp = [p for p in ptp_urad if np.isfinite(p)]
    if not ptp or max(ptp) >= TE_ZERO_URAD:
        return False
    c = float(np.mean(centre_urad)) if len(centre_urad) else 0.0
    ax.set_ylim(c - TE_FLAT_HALF_SPAN_URAD, c + TE_FLAT_HALF_SPAN_URAD)
    ax.ticklabel_format(axis="y", useOffset=False, style="plain")
    # at the bottom: the legend goes to the top (upper right) where a flat TE leaves room
    ax.text(0.5, 0.05, f"TE is zero to the solver tolerance\n(peak-to-peak {max(ptp):.1e} urad"
            f" < {TE_ZERO_URAD:g} urad)", transform=ax.transAxes, ha="center", va="bottom", fontsize=8,
            bbox=dict(facecolor="white", edgecolor="0.7", alpha=0.9))
    return True


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, out_png, title="", dpi=110, suptitle=True):
    """Title (wrapped to the figure's width: a long one would run off both sides), layout, PNG."""
    import textwrap

    plt = _plt()
    if title:
        title = textwrap.fill(title, width=max(30, int(fig.get_figwidth() * 10)))
        (fig.suptitle if suptitle else fig.axes[0].set_title)(title)
    fig.tight_layout()
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)


@functools.lru_cache(maxsize=16)
def flank_outline(geom, which, flank, n=60):
    """Boundary of a member's active flank in (axial position z, radius): toe, tip, heel, form.
    Computed once per (geometry, member, flank, n): every panel of a figure draws it (read-only arrays)."""
    from .tca import surface

    m = geom.pinion if which == "pinion" else geom.gear
    toe, heel = m.face_limits
    lo, hi = min(toe, heel), max(toe, heel)
    z = np.linspace(lo, hi, n)
    tip = np.array([m.tip_radius(zz) for zz in z])
    # form limit l = 0: the generating line's point at axial position z (scipy's brentq on u, the
    # line's axial position being monotone in u; bracketed on a vectorised scan of the line)
    from scipy.optimize import brentq

    us = np.linspace(2 * lo - hi - 1.0, 2 * hi - lo + 1.0, 401)  # u is near z on the generating line
    zu = surface(geom, which, flank, np.zeros_like(us), us).point[:, 2]
    form = np.empty(n)
    for i, zz in enumerate(z):
        k = np.flatnonzero(np.diff(np.sign(zu - zz)))[0]  # the bracketing step
        u = brentq(lambda v: surface(geom, which, flank, 0.0, v).point[2] - zz, us[k], us[k + 1], xtol=1e-10)
        p = surface(geom, which, flank, 0.0, u).point
        form[i] = math.hypot(p[0], p[1])
    zs = np.concatenate([z, z[::-1], z[:1]])
    rs = np.concatenate([form, tip[::-1], form[:1]])
    zs.flags.writeable = rs.flags.writeable = False  # shared by every caller (the cache)
    return zs, rs


def contact_paths(results, labels, geom, flank, out_png, title=""):
    """Contact path on the pinion and gear flanks, one line per result (error set)."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, which, key in ((axes[0], "pinion", "pinion_contact"), (axes[1], "gear", "gear_contact")):
        zb, rb = flank_outline(geom, which, flank)
        ax.plot(zb, rb, color="0.3", lw=1.2, label="flank boundary")
        for res, lab in zip(results, labels):
            fr = res.flanks[flank]
            P = getattr(fr, key)
            ok = np.array([s in (PointStatus.OK, PointStatus.EDGE) for s in fr.status]) & (fr.tooth_pair == 0)
            if ok.any():
                r = np.hypot(P[ok, 0], P[ok, 1])
                ax.plot(P[ok, 2], r, lw=1.6, label=lab)
            else:
                ax.plot([], [], lw=1.6, label=lab + " (off the flank)")
        ax.set_xlabel("axial position z (mm)  toe -> heel")
        ax.set_ylabel("radius (mm)")
        ax.set_title(f"{which}, {flank} flank")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=8, loc="best")
    _save(fig, out_png, title)


def transmission_error(results, labels, flank, out_png, title=""):
    """TE (urad) of the contacting pair against pinion angle (deg) over the mesh cycle.

    Each curve is drawn about its own mean: a misalignment also turns the gear by a constant
    angle, which is given in the legend, and would hide the fluctuation the figure is about.
    """
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    ptps, faded = [], False
    for res, lab in zip(results, labels):
        fr = res.flanks[flank]
        phi = pinion_angle_deg(fr.pinion_angle)
        te = fr.transmission_error * 1e6
        act = fr.active & np.isfinite(te)
        ptp = fr.te_peak_to_peak * 1e6
        if not act.any():
            ax.plot([], [], ".", label=f"{lab} (no contact on the flanks)")
            continue
        mean = float(np.mean(te[act]))
        ptps.append(ptp)
        complete = np.tile(fr.te_envelope_complete, len(te) // fr.te_envelope_complete.size)
        line, = ax.plot(phi[act & complete], te[act & complete] - mean, ".", ms=3,
                        label=f"{lab}: mean {mean:+.1f} urad, peak-to-peak {ptp:.2e} urad from"
                              f" {int((act & complete).sum())} points")
        ax.plot(phi[act & ~complete], te[act & ~complete] - mean, ".", ms=3, color=line.get_color(), alpha=0.25)
        faded = faded or bool((act & ~complete).any())
    if faded:  # the key to the faded points, as a legend entry (a sentence as the axis label runs off the figure)
        ax.plot([], [], ".", ms=3, color="0.5", alpha=0.25, label=FADED_LABEL)
    flat = te_axis(ax, [0.0], ptps)
    ax.set_xlabel(PINION_ANGLE_LABEL)
    ax.set_ylabel("TE minus its mean (urad)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right" if flat else "best")
    _save(fig, out_png, title, suptitle=False)


def tca_summary(result, geom, out_png, title=""):
    """One figure for `beveloid tca --plot`: contact path on both members and TE, per flank."""
    plt = _plt()
    flanks = list(result.flanks)
    fig, axes = plt.subplots(len(flanks), 3, figsize=(15, 4.0 * len(flanks)), squeeze=False)
    for row, flank in zip(axes, flanks):
        fr = result.flanks[flank]
        for ax, which, P in ((row[0], "pinion", fr.pinion_contact), (row[1], "gear", fr.gear_contact)):
            zb, rb = flank_outline(geom, which, flank)
            ax.plot(zb, rb, color="0.3", lw=1.2, label="flank boundary")
            for k in sorted(set(fr.tooth_pair.tolist())):
                sel = (fr.tooth_pair == k) & np.isfinite(P[:, 0])
                if not sel.any():
                    continue
                r = np.hypot(P[sel, 0], P[sel, 1])
                ax.plot(P[sel, 2], r, lw=1.5, label=f"tooth pair {k:+d}" if k else "tooth pair 0")
            if fr.contact_ellipse is not None:
                draw_bearing_pattern(ax, geom, fr, which, outline=(zb, rb))
            ax.set_xlabel("axial position z (mm)  toe -> heel")
            ax.set_ylabel("radius (mm)")
            ax.set_title(f"{which}, {flank} flank: contact path"
                         + (" and bearing pattern" if fr.contact_ellipse is not None else ""), fontsize=10)
            ax.grid(alpha=0.3)
        row[1].legend(fontsize=8)
        ax = row[2]
        phi = pinion_angle_deg(fr.pinion_angle)
        te = fr.transmission_error * 1e6
        act = fr.active & np.isfinite(te)
        for k in sorted(set(fr.tooth_pair.tolist())):
            sel = (fr.tooth_pair == k) & np.isfinite(te)
            # each pair faint where it does not carry the contact (its curve runs far outside the
            # envelope there), solid where it does
            line, = ax.plot(phi[sel], te[sel], lw=0.8, alpha=0.35)
            carry = np.where(act & (fr.tooth_pair == k), te, np.nan)[fr.tooth_pair == k]
            ax.plot(phi[fr.tooth_pair == k], carry, lw=1.6, color=line.get_color(), label=f"pair {k:+d}")
        ax.plot(phi[act], te[act], "k.", ms=2, label="contact (envelope)")
        ax.set_xlabel(PINION_ANGLE_LABEL)
        ax.set_ylabel("TE (urad)")
        ptp = fr.te_peak_to_peak * 1e6
        flat = act.any() and te_axis(ax, te[act], [ptp])
        if act.any() and not flat:
            lo, hi = float(te[act].min()), float(te[act].max())
            pad = max(0.25 * (hi - lo), 0.5)
            ax.set_ylim(lo - pad, hi + pad)  # the envelope, not each pair's whole path
        if np.isfinite(ptp):
            ax.set_title(f"{flank} flank: TE (peak-to-peak {ptp:.3g} urad,\n{int(act.sum())} contact points;"
                         f" faint: pairs out of contact)", fontsize=10)
        elif act.any():
            ax.set_title(f"{flank} flank: TE at one position\n(peak-to-peak not available)", fontsize=10)
        else:
            st = list(fr.status)
            ax.set_title(f"{flank} flank: no TE: no contact on the flanks\n({st.count(PointStatus.OUTSIDE)} outside,"
                         f" {st.count(PointStatus.FAILED)} not solved)", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right" if flat else "best")
    _save(fig, out_png, title, dpi=100)


def _ellipse_outlines(geom, fr, which):
    """(z, radius) outlines of the truncated contact ellipses of a flank's active points on one
    member (fr.contact_ellipse: tca.Options.approach_mm)."""
    from .contact_ellipse import ellipse_outline
    from .generated import placement

    ce = fr.contact_ellipse
    out = []
    phi1 = fr.pinion_angle - fr.tooth_pair * geom.pitch_angles[0]
    for i in np.nonzero(fr.active)[0]:
        pts = ellipse_outline(ce, i)
        if pts is None:
            continue
        if which == "pinion":
            P = placement.pinion_placement(phi1[i], geom.placement())
        else:
            P = placement.gear_placement(fr.unknowns[i, 4], ce.errors[i], geom.placement())
        q = (pts - P.translation) @ P.rotation  # S_f -> member frame (rotation about the axis keeps z, r)
        out.append((q[:, 2], np.hypot(q[:, 0], q[:, 1])))
    return out


def draw_bearing_pattern(ax, geom, fr, which, color="tab:orange", label="bearing pattern", outline=None):
    """Fill the union of the truncated contact ellipses of the active points on one member's flank,
    clipped to the flank's ``outline`` (z, radius) when given (an ellipse reaching past the heel or
    the tip is drawn only where the flank is); the axes then span the flank.  Returns the number of
    ellipses.

    The ellipses are one compound path, all turning the same way, so that the nonzero fill rule paints
    their union once (one patch to draw and clip, however many ellipses)."""
    from matplotlib.patches import PathPatch, Polygon
    from matplotlib.path import Path

    outlines = _ellipse_outlines(geom, fr, which)
    if outlines:
        verts, codes = [], []
        for z, r in outlines:
            ring = np.column_stack([z, r])
            x, y = ring[:, 0], ring[:, 1]
            if np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) < 0:  # clockwise: turn it round
                ring = ring[::-1]
            verts += [ring, ring[:1]]
            codes += [[Path.MOVETO] + [Path.LINETO] * (len(ring) - 1), [Path.CLOSEPOLY]]
        verts = np.concatenate(verts)
        patch = PathPatch(Path(verts, np.concatenate(codes)), facecolor=color, alpha=0.35, lw=0, label=label)
        # add_artist, not add_patch: add_patch finds the data limits by walking the path's segments one by
        # one in Python (~1 s per thousand ellipses); the vertices' bounds are the same limits here
        ax.add_artist(patch)
        ax.update_datalim(verts)
        if outline is not None:
            clip = Polygon(np.column_stack(outline), closed=True, transform=ax.transData, fill=False, lw=0)
            patch.set_clip_path(clip)
    if outline is not None:
        _span(ax, *outline)
    else:
        ax.autoscale_view()
    return len(outlines)


def _span(ax, z, r, margin=0.05):
    """Axes limits: the flank outline and a margin (what is drawn past it is clipped anyway)."""
    dz, dr = np.ptp(z) * margin, np.ptp(r) * margin
    ax.set_xlim(np.min(z) - dz, np.max(z) + dz)
    ax.set_ylim(np.min(r) - dr, np.max(r) + dr)


def bearing_patterns(results, labels, geom, flank, out_png, title=""):
    """Bearing pattern (union of truncated contact ellipses over the mesh) on the pinion and gear
    flanks, one row per result (error set), like the light-load patterns of Figs 24a / 25a."""
    plt = _plt()
    fig, axes = plt.subplots(len(results), 2, figsize=(11, 3.4 * len(results)), squeeze=False)
    for row, res, lab in zip(axes, results, labels):
        fr = res.flanks[flank]
        for ax, which in zip(row, ("pinion", "gear")):
            zb, rb = flank_outline(geom, which, flank)
            ax.plot(zb, rb, color="0.3", lw=1.2, label="flank boundary")
            n = draw_bearing_pattern(ax, geom, fr, which, outline=(zb, rb))
            approach = fr.contact_ellipse.approach_mm * 1e3
            ax.set_title(f"{which}, {flank} flank, {lab}: {n} ellipses, approach {approach:g} um", fontsize=9)
            ax.set_xlabel("axial position z (mm)  toe -> heel")
            ax.set_ylabel("radius (mm)")
            ax.grid(alpha=0.3)
        row[1].legend(fontsize=8, loc="best")
    _save(fig, out_png, title)
