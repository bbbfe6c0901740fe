"""Array-level drawing helpers of the comparison figures (matplotlib, Agg).  They take arrays and
axes and import nothing that computes."""

from __future__ import annotations

import numpy as np

from particles.validation import InvalidArgumentError

from ...figures import new_figure

__all__ = ["panels", "colors"]


def panels(n: int, ax=None, width: float = 5.0, height: float = 4.0):
    """``(figure, axes)``: ``n`` side-by-side panels of ``width`` × ``height`` inches on a new
    figure, or the ``n`` axes of ``ax`` (a sequence of matplotlib axes, or one axis when
    ``n == 1``) and their figure.

    Parameters
    ----------
    n : int
        Number of panels.
    ax : matplotlib.axes.Axes or sequence of them, optional
        Axes to draw in, one per panel; default a new figure.
    width, height : float, optional
        Size of one panel in inches for a new figure (default 5 × 4).

    Returns
    -------
    tuple of (matplotlib.figure.Figure, list of matplotlib.axes.Axes)
        The figure and its ``n`` axes, left to right.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``ax`` if it does not hold exactly ``n`` axes.
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
        Number of colours (at least one is returned).

    Returns
    -------
    numpy.ndarray
        RGBA colours, shape (max(n, 1), 4).
    """
    import matplotlib

    return matplotlib.colormaps["viridis"](np.linspace(0, 0.9, max(n, 1)))
