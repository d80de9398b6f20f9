"""``beveloid design --plot OUT.png``: transverse sections of both members at the toe, the face
centre and the heel, one tooth each: flanks (generated surface), root fillets (generated fillet),
tip, root, form-limit and base circles; undercut flanks and pointed tips are marked.

Each panel is drawn in the section's plane, turned so that the tooth's centre line is vertical
(x: across the tooth, y: radial, both mm, origin on the member's axis).
"""
from __future__ import annotations

import numpy as np

from ..names import FLANKS, MEMBERS
from . import fillet as fillet_kernels
from . import profile, sections

_COLOURS = {"left": "tab:blue", "right": "tab:orange"}


def _polar(points):
    return np.hypot(points[..., 0], points[..., 1]), np.arctan2(points[..., 1], points[..., 0])


def _flank_curves(geometry, member, z, tip_radius):
    """{flank: (flank points or None, fillet points or None, form limit or None)} of the section z (S_i).

    A flank whose involute does not reach the tip circle there (tip inside its base circle) is not
    drawn; nor is a fillet the section Newton finds no point of."""
    out = {}
    tr = fillet_kernels.tip_round(geometry, member)
    for fl in FLANKS:
        form = profile.form_limit(geometry, member, fl, z)  # the junction, or the top of the undercut
        flank_pts = fillet_pts = None
        try:
            if form is not None:
                _, l_tip, _ = profile.flank_at_radius(geometry, member, fl, z, tip_radius)
                flank_pts, _ = profile.flank_in_section(geometry, member, fl, z, np.linspace(form.l_mm, l_tip, 80))
        except profile.NoSolution:
            pass
        top = float(tr.junction_psi) if form is None else form.psi
        try:
            fillet_pts, _ = profile.fillet_in_section(geometry, member, fl, z, np.linspace(0.0, top, 60))
        except profile.NoSolution:
            pass
        out[fl] = (flank_pts, fillet_pts, form)
    return out


def _arc(ax, radius, centre_angle, half_width, **kw):
    t = np.linspace(-half_width, half_width, 60)
    ax.plot(radius * np.sin(t), radius * np.cos(t), **kw)


def _panel(ax, geometry, member, label, z_face, tooth):
    z = float(sections.member_z(geometry, member, z_face))
    s = sections.section(geometry, member, z_face)
    r_tip = float(s.tip_radius)
    curves = _flank_curves(geometry, member, z, r_tip)
    # the tooth's centre line: halfway between the flanks at the tip radius
    ends = [curves[fl][0][-1] if curves[fl][0] is not None else
            curves[fl][1][-1] if curves[fl][1] is not None else None for fl in FLANKS]
    if any(e is None for e in ends):  # nothing of a flank in this section: the tooth's nominal centre
        angles = [0.0, 0.0]
    else:
        angles = [_polar(e)[1] for e in ends]
    centre = 0.5 * (angles[0] + angles[1])
    half = 1.6 * abs(angles[1] - angles[0]) + 0.6 * 2 * np.pi / geometry.member(member).teeth

    def local(points):
        rr, th = _polar(points)
        return rr * np.sin(centre - th), rr * np.cos(centre - th)

    for fl in FLANKS:
        fpts, rpts, _ = curves[fl]
        if fpts is not None:
            ax.plot(*local(fpts), color=_COLOURS[fl], lw=1.4, label=f"{fl} flank")
        if rpts is not None:
            ax.plot(*local(rpts), color=_COLOURS[fl], lw=1.0, ls="--", label=f"{fl} fillet")
    _arc(ax, r_tip, centre, half, color="k", lw=0.8, label="tip" if label == "toe" else None)
    _arc(ax, float(s.root_radius), centre, half, color="0.4", lw=0.8, label="root" if label == "toe" else None)
    for fl in FLANKS:
        _arc(ax, float(getattr(s, f"base_radius_{fl}")), centre, half, color=_COLOURS[fl], lw=0.6, ls=":",
             label=f"base ({fl})" if label == "toe" else None)
        cut = float(getattr(s, f"undercut_depth_{fl}"))
        if curves[fl][2] is not None:
            _arc(ax, curves[fl][2].radius_mm, centre, half, color=_COLOURS[fl], lw=0.6, ls="-.",
                 label=f"form limit ({fl})")
        if cut > 0 and curves[fl][0] is not None:
            x, y = local(curves[fl][0][:1])
            ax.plot(x, y, marker="o", ms=4, color="red")
            ax.annotate(f"undercut {fl}\n{cut:.3f} mm", (x[0], y[0]), color="red", fontsize=7,
                        xytext=(-30 if fl == "right" else 30, -8), textcoords="offset points", ha="center")
    title = f"{member} {label} (z = {z_face:+.2f} mm)"
    thick = float(s.tip_arc_thickness)
    if not np.isfinite(thick):
        title += ": NO INVOLUTE AT THE TIP"
    elif thick <= 0:
        title += ": POINTED"
        ax.plot([0.0], [r_tip], marker="x", color="red")
    else:
        title += f", tip {thick:.3f} mm"
    ax.set_title(title, fontsize=8, color="k" if thick > 0 else "red")
    drawn = [c for fl in FLANKS for c in curves[fl][:2] if c is not None]
    width = max([abs(local(c)[0]).max() * 1.6 for c in drawn] + [1.0])
    ax.set_xlim(-width, width)
    lo, hi = sorted((float(s.root_radius), r_tip))
    ax.set_ylim(lo - 1.0, hi + 1.0)
    ax.set_aspect("equal", adjustable="box")
    ax.tick_params(labelsize=6)


def plot_sections(pair, tooth, path):
    """Write the figure to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    geometry = getattr(pair, "geometry", pair)
    fig, axes = plt.subplots(2, 3, figsize=(12, 8.5))
    for row, member in enumerate(MEMBERS):
        w = sections.half_face(geometry, member)
        for col, (label, frac) in enumerate(sections.ENDS):
            _panel(axes[row, col], geometry, member, label, frac * w, tooth)
    legend = {}  # one entry per label, from whichever panel draws it (a flank may be missing at the toe)
    for ax in axes.ravel():
        for handle, text in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(text, handle)
    handles, labels = list(legend.values()), list(legend)
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=7)
    fig.suptitle("Transverse sections (mm; face coordinate z from the face centre, toe at -W/2)", fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    fig.savefig(path, dpi=130)
    plt.close(fig)
