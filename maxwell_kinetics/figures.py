"""Figures of the kinetic library (matplotlib, drawn on an Agg canvas without pyplot).

:func:`new_figure` makes a figure of panels, :func:`plot_solution` draws a solution of the
kinetic solver and :func:`plot_density` a density against the Gaussian of its variance.  Each
returns a ``Figure`` (a ``matplotlib.figure.Figure``); the caller saves or shows it.  The
figures are made without :mod:`matplotlib.pyplot`: the library changes no matplotlib backend
and leaves no figure in pyplot's global list (nothing to close, no "more than 20 figures"
warning).  In Jupyter a figure that is the last expression of a cell displays itself as a PNG
(``Figure._repr_png_``), with or without ``%matplotlib inline``; elsewhere
``fig.savefig(path)`` saves it.

Legends stay legible: on the axes of these figures a legend's text (and its title) is never
smaller than the axes' tick labels, nor than :data:`MIN_LEGEND_POINTS`, in points at the
figure's own size (its ``figsize`` in inches, the size it is saved at); a smaller size asked
for is raised to that.

matplotlib is imported on first use, not with this module.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MIN_LEGEND_POINTS", "legend_floor", "new_figure", "plot_solution", "plot_density"]

#: The smallest legend text of the figures made here, in points at the figure's size.
MIN_LEGEND_POINTS = 8.0


def _points(size) -> float:
    """A matplotlib font size (a number of points or a name such as ``"small"``) in points."""
    from matplotlib.font_manager import FontProperties

    return float(FontProperties(size=size).get_size_in_points())


def legend_floor() -> float:
    """The smallest legend text on the axes of these figures, in points: the larger of the tick
    labels' size (matplotlib's ``xtick.labelsize`` and ``ytick.labelsize``, 10 points by
    default) and :data:`MIN_LEGEND_POINTS`.

    Returns
    -------
    float
        The size in points.
    """
    import matplotlib

    ticks = max(_points(matplotlib.rcParams["xtick.labelsize"]),
                _points(matplotlib.rcParams["ytick.labelsize"]))
    return max(ticks, MIN_LEGEND_POINTS)


def _legible(kwargs: dict) -> dict:
    """The keyword arguments of a ``legend`` call with its text and title raised to
    :func:`legend_floor`."""
    import matplotlib
    from matplotlib.font_manager import FontProperties

    floor = legend_floor()
    kwargs = dict(kwargs)
    prop = kwargs.get("prop")
    if prop is not None:  # a FontProperties, a dict of its arguments or a fontconfig pattern
        given = prop.get("size") if isinstance(prop, dict) else None
        prop = (FontProperties(**prop) if isinstance(prop, dict)
                else prop.copy() if isinstance(prop, FontProperties) else FontProperties(prop))
        if given is None and not isinstance(kwargs["prop"], FontProperties):
            given = matplotlib.rcParams["legend.fontsize"]
        prop.set_size(max(_points(given if given is not None else prop.get_size()), floor))
        kwargs["prop"] = prop
    else:
        size = kwargs.get("fontsize")
        kwargs["fontsize"] = max(_points(size if size is not None
                                         else matplotlib.rcParams["legend.fontsize"]), floor)
    title = kwargs.get("title_fontsize", matplotlib.rcParams["legend.title_fontsize"])
    if title is not None:
        kwargs["title_fontsize"] = max(_points(title), floor)
    return kwargs


def _classes():
    """The ``Figure`` class and its axes class, defined on first use (matplotlib is imported
    only then)."""
    global _FIGURE
    if _FIGURE is None:
        from matplotlib.axes import Axes
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure as _MplFigure

        class LegibleAxes(Axes):
            """Axes whose legends are never smaller than :func:`legend_floor`."""

            def legend(self, *args, **kwargs):
                return super().legend(*args, **_legible(kwargs))

        class Figure(_MplFigure):
            """A ``matplotlib.figure.Figure`` on its own Agg canvas, outside pyplot, that
            displays itself in Jupyter: :meth:`_repr_png_` gives IPython the PNG of the
            figure (cropped to its content, as ``%matplotlib inline`` would show it).  Its
            axes (made by ``subplots``, ``add_subplot``, ``add_axes`` or ``twinx``) and its own
            legends keep their text at least :func:`legend_floor` points."""

            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                FigureCanvasAgg(self)

            def add_subplot(self, *args, **kwargs):
                if not {"projection", "polar", "axes_class"} & set(kwargs):
                    kwargs["axes_class"] = LegibleAxes
                return super().add_subplot(*args, **kwargs)

            def add_axes(self, *args, **kwargs):
                if not {"projection", "polar", "axes_class"} & set(kwargs):
                    kwargs["axes_class"] = LegibleAxes
                return super().add_axes(*args, **kwargs)

            def legend(self, *args, **kwargs):
                return super().legend(*args, **_legible(kwargs))

            def _repr_png_(self) -> bytes:
                import io

                buffer = io.BytesIO()
                self.savefig(buffer, format="png", bbox_inches="tight")
                return buffer.getvalue()

        for cls in (Figure, LegibleAxes):
            cls.__module__, cls.__qualname__ = __name__, cls.__name__
        _FIGURE = Figure
    return _FIGURE


_FIGURE = None


def __getattr__(name):
    if name == "Figure":
        return _classes()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def new_figure(ncols: int = 1, width: float = 5.0, height: float = 4.0, nrows: int = 1):
    """A new figure of ``nrows`` × ``ncols`` panels, each ``width`` × ``height`` inches:
    ``(fig, axes)`` with ``axes`` of shape (nrows, ncols).

    The figure is a ``Figure`` made without :mod:`matplotlib.pyplot` (no backend is
    switched, nothing is added to pyplot's list of open figures; it is freed when no longer
    referenced).  In Jupyter it displays itself when it is the last expression of a cell.  Its
    legends are never smaller than the tick labels (:func:`legend_floor`).

    Parameters
    ----------
    ncols : int, optional
        Number of panels side by side (default 1).
    width, height : float, optional
        Size of one panel in inches (default 5 × 4).
    nrows : int, optional
        Number of rows of panels (default 1).

    Returns
    -------
    tuple of (maxwell_kinetics.figures.Figure, numpy.ndarray)
        The figure and its axes, an object array of shape (nrows, ncols).
    """
    fig = _classes()(figsize=(width * ncols, height * nrows))
    return fig, fig.subplots(nrows, ncols, squeeze=False)


def plot_solution(solution):
    """Left: Re G(q, τ) against q (with f̂ in d = 1).  Right: in d = 1, |G − f̂| against q on
    log axes; in d ≥ 2, where f̂ is not the scaling solution, the density of the rescaled
    speed P(s) (:meth:`~maxwell_kinetics.solution.Solution.speed_density`) on a log scale.

    G(q, τ) is the characteristic function of the rescaled velocity at the recorded times τ
    (collisions per particle); f̂(q) = (1 + q) e^(−q) is the 1D scaling solution.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solution of the kinetic solver (its ``q``, ``tau``, ``G`` and, in d = 1,
        ``deviation``; in d ≥ 2, ``dimension``, ``angular`` and ``speed_density``).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, laid out (``tight_layout``); the caller saves or closes it.
    """
    from matplotlib import colormaps

    from .exact import f_hat

    fig, axes = new_figure(2)
    left, right = axes[0]
    q = solution.q
    show = q > 1e-3
    one_d = getattr(solution, "dimension", 1) == 1
    colors = colormaps["viridis"](np.linspace(0, 0.9, len(solution.tau)))
    speeds = np.linspace(0.0, 12.0, 241)
    for k, tau in enumerate(solution.tau):
        left.plot(q[show], solution.G[k, show].real, color=colors[k], label=f"τ = {tau:g}")
        if one_d:
            right.loglog(q[show], np.abs(solution.deviation[k, show]) + 1e-300, color=colors[k])
        else:
            p = solution.speed_density(speeds, k)[1]
            right.semilogy(speeds, np.where(p > 0, p, np.nan), color=colors[k])
    title = f"r = {solution.restitution:g}, initial {solution.initial}"
    if one_d:
        left.plot(q[show], f_hat(q[show]), "k--", label=r"$\hat f=(1+q)\,e^{-q}$")
        right.set(xlabel="q", ylabel="|G − f̂|", ylim=(1e-16, 2),
                  title="distance to the scaling solution")
    else:
        title += f", d = {solution.dimension} ({solution.angular})"
        right.set(xlabel="s = |v| / v0", ylabel="P(s)", ylim=(1e-8, 1),
                  title="density of the rescaled speed")
    left.set_xscale("log")
    left.set(xlabel="q", ylabel="Re G(q, τ)", title=title)
    left.legend()
    fig.tight_layout()
    return fig


def plot_density(x, P, variance: float, title: str = "", ax=None):
    """ln P(x) against x with the Gaussian of the same variance (arrays only; returns the
    Figure).

    Values of P and of the Gaussian below 1e-14 are not drawn (round-off far out).

    Parameters
    ----------
    x : array_like
        Velocities, shape (m,).
    P : array_like
        The density at ``x``, shape (m,).
    variance : float
        Variance of the Gaussian drawn for comparison.
    title : str, optional
        Title of the panel (default none).
    ax : matplotlib.axes.Axes, optional
        Panel to draw in; default a new figure of one panel.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax`` (or the new one), laid out.
    """
    if ax is None:
        fig, axes = new_figure()
        ax = axes[0, 0]
    else:
        fig = ax.figure
    x = np.asarray(x, dtype=float)
    P = np.asarray(P, dtype=float)
    keep = P > 1e-14
    ax.semilogy(x[keep], P[keep], label="P(v)")
    gauss = np.exp(-0.5 * x**2 / variance) / np.sqrt(2 * np.pi * variance)
    show = gauss > 1e-14
    ax.semilogy(x[show], gauss[show], "--", label="Gaussian, same variance")
    ax.set_xlabel("v")
    ax.set_ylabel("P(v)")
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    return fig
