"""Array-level drawing helpers of the comparison figures (matplotlib, Agg).  They take arrays and
axes and import nothing that computes."""

from __future__ import annotations

import numpy as np

from particles.validation import InvalidArgumentError

from ..plotting import new_figure

__all__ = ["panels", "colors"]


def panels(n: int, ax=None, width: float = 5.0, height: float = 4.0):
    """``(figure, axes)``: ``n`` side-by-side panels of ``width`` × ``height`` inches on a new
    figure, or the ``n`` axes of ``ax`` (a sequence of matplotlib axes, or one axis when
    ``n == 1``) and their figure.

    Parameters
    ----------
    n : int
        Panels.
    ax : sequence of matplotlib.axes.Axes, optional
        Existing axes.
    width, height : float
        Inches per panel.

    Returns
    -------
    tuple
        (figure, axes).

    Raises
    ------
    InvalidArgumentError
        Naming ``ax`` when it does not hold ``n`` axes.
    """
    if ax is None:
        fig, grid = new_figure(n, width=width, height=height)
        return fig, list(grid[0])
    axes = [ax] if hasattr(ax, "plot") else list(np.ravel(ax))
    if len(axes) != n:
        raise InvalidArgumentError("ax", f"{len(axes)} axes", f"{n} axes (one per panel)")
    return axes[0].figure, axes


def colors(n: int):
    """``n`` colours of the viridis map, dark to light (0 to 0.9).

    Parameters
    ----------
    n : int

    Returns
    -------
    numpy.ndarray
        RGBA rows, one per colour.
    """
    import matplotlib

    return matplotlib.colormaps["viridis"](np.linspace(0, 0.9, max(n, 1)))
