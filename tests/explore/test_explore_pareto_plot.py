"""explore's pareto.png keeps its y-axis label inside the figure on a narrow log range (issue 60: the
minor ticks' 2.05x10^-1 labels pushed it off the left edge)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from beveloid.explore import report
from beveloid.status import DesignStatus


@pytest.mark.parametrize("low, high", [(0.21, 0.24), (2.1e-3, 2.4e-3), (1e-3, 1.0)])
def test_the_y_label_stays_inside_the_figure(monkeypatch, low, high):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figures = []
    monkeypatch.setattr(report, "_save", lambda fig, path: figures.append(fig))
    n = 30
    table = {"status": np.array([DesignStatus.OK] * n, dtype=object), "max_fpd_angle_deg": np.linspace(1, 5, n),
             "worst_path_shift_mm": np.linspace(low, high, n), "pareto": np.arange(n) % 3 == 0}
    report.pareto_scatter("pareto.png", SimpleNamespace(mc=0), table, None)
    fig = figures[0]
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    label = ax.yaxis.label.get_window_extent(renderer)
    assert ax.get_ylabel().startswith("worst first-order path shift") and label.x0 >= 0
    ticks = [t for t in ax.get_yticklabels(minor=True) + ax.get_yticklabels() if t.get_text()]
    assert ticks and all(t.get_window_extent(renderer).x0 >= 0 for t in ticks)
    assert not any("times" in t.get_text() for t in ticks) or high / low >= 10
