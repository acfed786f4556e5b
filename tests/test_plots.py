"""Plots people can read: mount forces one panel per pair of bodies and
direction, styles distinct, symmetric mounts named, the legend beside the
data; benchmark tick labels that do not run into each other."""

import itertools

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from flexbed.plots.bench import Panel, Series, loglog_figure  # noqa: E402
from flexbed.plots.runs import mount_forces_figure, mount_groups, mount_style  # noqa: E402


def reference_like_forces():
    """12 mounts in three groups of four, pairs of them symmetric; u1 carries
    no force, u2 a little, u3 the weight and the motion."""
    t = np.linspace(0.0, 3.0, 301)
    names = [f"M{i + 1}" for i in range(12)]
    body_i = ["base"] * 4 + ["bed"] * 8
    body_j = ["bed"] * 4 + ["equipment A"] * 4 + ["equipment B"] * 4
    f = np.zeros((t.size, 12, 3))
    for m in range(12):
        twin = m - 2 if m % 4 >= 2 else m        # M3 = M1, M4 = M2, ...
        f[:, m, 2] = -1e3 * (1 + m // 4) + 100 * np.sin(2 * np.pi * (1 + 0.1 * twin) * t)
        f[:, m, 1] = 5 * np.cos(2 * np.pi * (1 + 0.1 * twin) * t)
    return t, f, names, body_i, body_j


def overlaps(a, b, gap=0.0):
    """Whether two boxes (display pixels) overlap or come closer than ``gap``."""
    return not (a.x1 + gap <= b.x0 or b.x1 + gap <= a.x0 or a.y1 + gap <= b.y0
                or b.y1 + gap <= a.y0)


def test_mount_forces_one_panel_per_group_and_direction():
    t, f, names, body_i, body_j = reference_like_forces()
    assert [g for g, _ in mount_groups(body_i, body_j)] == [
        "base – bed", "bed – equipment A", "bed – equipment B"]
    fig = mount_forces_figure("forces", t, f, names, body_i, body_j)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        axes = np.array(fig.axes).reshape(3, 2)      # u1 carries nothing: u2 and u3
        assert [ax.get_title() for ax in axes[0]] == ["base – bed: along u2",
                                                      "base – bed: along u3"]
        for row in axes:
            for ax in row:
                styles = [(line.get_color(), line.get_linestyle()) for line in ax.get_lines()]
                assert len(styles) == 4
                assert len({c for c, _ in styles}) == 4 and len({s for _, s in styles}) == 4
            legend = row[-1].get_legend()
            labels = [x.get_text() for x in legend.get_texts()]
            assert labels[2].endswith(f"(= {labels[0]})")
            assert labels[3].endswith(f"(= {labels[1]})") and "(=" not in labels[1]
            box = legend.get_window_extent(renderer)
            for ax in row:
                assert not overlaps(box, ax.get_window_extent(renderer))
    finally:
        plt.close(fig)


def test_mount_styles_differ_for_forty_mounts_and_between_neighbours():
    styles = [(mount_style(i)["color"], mount_style(i)["ls"]) for i in range(40)]
    assert len(set(styles)) == 40
    for a, b in zip(styles, styles[1:]):
        assert a[0] != b[0] and a[1] != b[1]


@pytest.mark.parametrize("x", [
    [0.31, 0.45, 0.62, 0.95, 1.3, 2.1],           # labelled 3×10^-1 and 4×10^-1 on one spot
    [0.021, 0.03, 0.045, 0.062, 0.095],
    [0.07, 0.074, 0.083],                          # a narrow range
    [1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0],
    [0.049, 0.16],                                 # y from 6.5e-5 to 9.6e-4: one style
])
def test_loglog_tick_labels_do_not_overlap(x):
    y = np.geomspace(9.6e-4, 6.5e-5, len(x))     # 0.001 to 5e-5 on one axis
    fig = loglog_figure("t", "solve time [s]", [Panel("error [m]", [Series("a", x, y)]),
                                               Panel("error [N]", [Series("b", x, 1e6 * y)])])
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            for axis in (ax.xaxis, ax.yaxis):
                lo, hi = sorted(axis.get_view_interval())
                shown = [lab for tick, lab in zip(
                    axis.get_majorticklocs().tolist() + axis.get_minorticklocs().tolist(),
                    axis.get_majorticklabels() + axis.get_minorticklabels())
                    if lab.get_visible() and lab.get_text() and lo <= tick <= hi]
                assert len(shown) >= 2, [lab.get_text() for lab in shown]
                texts = [lab.get_text() for lab in shown]
                assert len({t.startswith("$") for t in texts}) == 1, texts   # one style
                boxes = [lab.get_window_extent(renderer) for lab in shown]
                for a, b in itertools.combinations(boxes, 2):     # a space apart at least
                    assert not overlaps(a, b, gap=4.0), [lab.get_text() for lab in shown]
    finally:
        plt.close(fig)
