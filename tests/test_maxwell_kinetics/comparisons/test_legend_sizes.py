"""The legends of every registered comparison's figure are legible at the figure's saved size:
drawn from the small run's data (the session's ``comparison`` fixture), every legend's text and
title is at least 8 points at the figure's own size in inches (``savefig`` keeps that size; the
PNG holds size × dpi pixels), and never smaller than its axes' tick labels."""

from __future__ import annotations

import pytest

from maxwell_kinetics.app.comparisons import COMPARISONS

#: The smallest legend text allowed, in points at the figure's size in inches.
MIN_POINTS = 8.0


def legend_faults(fig) -> list[str]:
    """Each legend text of ``fig`` smaller than :data:`MIN_POINTS` or than the tick labels of
    its axes, with its size and the figure's size."""
    width, height = fig.get_size_inches()
    faults = []
    legends = [(ax, ax.get_legend()) for ax in fig.axes] + [(None, leg) for leg in fig.legends]
    for ax, legend in legends:
        if legend is None:
            continue
        ticks = 0.0
        if ax is not None:
            labels = ax.xaxis.get_ticklabels() + ax.yaxis.get_ticklabels()
            ticks = max((label.get_fontsize() for label in labels), default=0.0)
        texts = list(legend.get_texts()) + [legend.get_title()]
        for text in texts:
            if not text.get_text():
                continue
            size = text.get_fontsize()
            if size < max(MIN_POINTS, ticks):
                faults.append(f"{text.get_text()!r}: {size:g} pt (ticks {ticks:g} pt) on a "
                              f"{width:g} x {height:g} in figure")
    return faults


def test_the_check_finds_a_small_legend():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 3))
    ax = fig.subplots()
    ax.plot([0, 1], label="small")
    ax.legend(fontsize=6)
    assert legend_faults(fig) == ["'small': 6 pt (ticks 10 pt) on a 8 x 3 in figure"]


@pytest.mark.parametrize("name", sorted(COMPARISONS))
def test_every_legend_of_a_comparison_figure_is_legible(comparison, name):
    fig = comparison(name).figure()
    assert fig.axes, name
    assert any(ax.get_legend() is not None for ax in fig.axes) or fig.legends, name
    faults = legend_faults(fig)
    assert not faults, f"{name}: " + "; ".join(faults)
