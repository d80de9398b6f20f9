"""What `tca --plot` and `ltca --plot` draw (issue 29, item 11): the bearing pattern only on the flank,
the TE note box clear of the legend, and no matplotlib warnings (`ltca --plot`'s own: tests/fe/test_fe_ltca.py,
on the suite's coarse FE tooth)."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, plots, tca

REPO = Path(__file__).resolve().parents[2]
C1 = str(REPO / "examples" / "case1.toml")


@pytest.fixture
def kept_figures(monkeypatch):
    """The figures the plotting functions save, kept open for inspection."""
    figs = []
    real = plots._save

    def save(fig, out_png, *a, **k):
        figs.append(fig)
        import matplotlib.pyplot as plt
        monkeypatch.setattr(plt, "close", lambda *_: None)
        real(fig, out_png, *a, **k)

    monkeypatch.setattr(plots, "_save", save)
    return figs


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_tca_plot_clips_the_pattern_to_the_flank_and_keeps_the_note_off_the_legend(tmp_path, kept_figures):
    """Case 1 aligned: the TE is flat (the note box is shown) and the contact ellipses near the face
    ends reach past the flank; every filled ellipse is clipped to the flank outline."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cli.main(["tca", C1, "--positions", "30", "--plot", str(tmp_path / "t.png")]) == 0
    fig, = kept_figures
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    pattern = [p for ax in fig.axes for p in ax.patches if p.get_alpha() == 0.35]  # the filled ellipses
    assert pattern, "no bearing pattern drawn"
    assert all(p.get_clip_path() is not None for p in pattern)
    notes = [(ax, t) for ax in fig.axes for t in ax.texts if "TE is zero" in t.get_text()]
    assert notes, "case 1 aligned has a flat TE: the note should be there"
    for ax, text in notes:
        legend = ax.get_legend()
        assert legend is not None
        assert not _overlap(legend.get_window_extent(renderer), text.get_window_extent(renderer))


def test_the_pattern_axes_span_the_flank(pair1, tmp_path):
    """The axes of a clipped pattern are the flank's outline and a margin, not the ellipses' extent."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = tca.analyze(pair1, tca.Options(flanks=("right",), positions=30))
    fr = res.flanks["right"]
    assert fr.contact_ellipse is not None
    zb, rb = plots.flank_outline(pair1.geometry, "pinion", "right")
    fig, ax = plt.subplots()
    plots.draw_bearing_pattern(ax, pair1.geometry, fr, "pinion", outline=(zb, rb))
    x0, x1 = ax.get_xlim()
    assert x0 < zb.min() and x1 > zb.max() and (x1 - x0) < 1.2 * np.ptp(zb)
    plt.close(fig)


def test_cell_corners_of_a_folded_raster_give_no_warning():
    """The LTCA's raster nodes are cell centres; where the raster folds in (z, radius) matplotlib's
    own "nearest" shading warns.  The corners are the midpoints on a regular grid (an independent
    check) and draw without a warning on a folded one."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from beveloid.ltca.results import plots as lplots

    z, r = np.meshgrid(np.arange(4.0), np.array([0.0, 1.0, 3.0]), indexing="ij")
    corners = lplots._cell_corners(r)
    assert np.allclose(corners[0], [-0.5, 0.5, 2.0, 4.0]) and np.allclose(corners[:, 1], 0.5)
    folded = r.copy()
    folded[:, 1] = [1.0, 1.2, 0.8, 1.1]  # not monotonic along either index
    fig, ax = plt.subplots()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ax.pcolormesh(lplots._cell_corners(z), lplots._cell_corners(folded), np.ones(z.shape), shading="flat")
        fig.canvas.draw()
    plt.close(fig)


def test_the_te_figures_axis_labels_fit_and_name_the_pinion_angle_in_degrees(pair1, tmp_path, kept_figures):
    """Every TCA figure with a pinion-angle axis labels it the same (degrees, as the tables) and every
    axis label lies inside its figure: the key to the faded points is in the legend, not the label."""
    res = tca.analyze(pair1, tca.Options(flanks=("right", "left"), positions=40))
    plots.transmission_error([res, res], ["aligned", "again"], "right", tmp_path / "te.png", "Fig 13 - a title")
    plots.tca_summary(res, pair1.geometry, tmp_path / "tca.png")
    for fig in kept_figures:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        box = fig.bbox
        for ax in fig.axes:
            for label in (ax.xaxis.label, ax.yaxis.label):
                e = label.get_window_extent(renderer)
                assert box.x0 <= e.x0 and e.x1 <= box.x1 and box.y0 <= e.y0 and e.y1 <= box.y1, label.get_text()
    te_axes = [ax for fig in kept_figures for ax in fig.axes if ax.get_xlabel().startswith("pinion angle")]
    assert len(te_axes) == 3 and {ax.get_xlabel() for ax in te_axes} == {plots.PINION_ANGLE_LABEL}
    legend = [t.get_text() for t in kept_figures[0].axes[0].get_legend().get_texts()]
    assert plots.FADED_LABEL in legend
