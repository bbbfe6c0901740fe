"""Figures of the kinetic solver (matplotlib, drawn on an Agg canvas without pyplot).

Each function returns a ``Figure`` (a ``matplotlib.figure.Figure``); the caller saves or
shows it.  The figures are made without :mod:`matplotlib.pyplot`: the library changes no
matplotlib backend and leaves no figure in pyplot's global list (nothing to close, no "more than
20 figures" warning).  In Jupyter a figure that is the last expression of a cell displays
itself as a PNG (``Figure._repr_png_``), with or without ``%matplotlib inline``; elsewhere
``fig.savefig(path)`` saves it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["new_figure", "plot_solution", "plot_convergence", "plot_density"]


def _figure_class():
    """The ``Figure`` class, defined on first use (matplotlib is imported only then)."""
    global _FIGURE
    if _FIGURE is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure as _MplFigure

        class Figure(_MplFigure):
            """A ``matplotlib.figure.Figure`` on its own Agg canvas, outside pyplot, that
            displays itself in Jupyter: :meth:`_repr_png_` gives IPython the PNG of the
            figure (cropped to its content, as ``%matplotlib inline`` would show it)."""

            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                FigureCanvasAgg(self)

            def _repr_png_(self) -> bytes:
                import io

                buffer = io.BytesIO()
                self.savefig(buffer, format="png", bbox_inches="tight")
                return buffer.getvalue()

        Figure.__module__, Figure.__qualname__ = __name__, "Figure"
        _FIGURE = Figure
    return _FIGURE


_FIGURE = None


def __getattr__(name):
    if name == "Figure":
        return _figure_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def new_figure(ncols: int = 1, width: float = 5.0, height: float = 4.0, nrows: int = 1):
    """A new figure of ``nrows`` × ``ncols`` panels, each ``width`` × ``height`` inches:
    ``(fig, axes)`` with ``axes`` of shape (nrows, ncols).

    The figure is a ``Figure`` made without :mod:`matplotlib.pyplot` (no backend is
    switched, nothing is added to pyplot's list of open figures; it is freed when no longer
    referenced).  In Jupyter it displays itself when it is the last expression of a cell.

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
    tuple of (maxwell_kinetics.app.plotting.Figure, numpy.ndarray)
        The figure and its axes, an object array of shape (nrows, ncols).
    """
    fig = _figure_class()(figsize=(width * ncols, height * nrows))
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
    from ..exact import f_hat

    fig, axes = new_figure(2)
    left, right = axes[0]
    q = solution.q
    show = q > 1e-3
    one_d = getattr(solution, "dimension", 1) == 1
    from matplotlib import colormaps

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
    left.legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_convergence(runs):
    """sup_q |G − f̂| against τ for each (r, resolution), and the floor against h.

    Left: the distance to the scaling solution against τ, one line per restitution r and
    resolution.  Right: the error floor against the grid spacing h in ln q, with the line
    h^order of the scheme's order through the finest point.

    Parameters
    ----------
    runs : list of maxwell_kinetics.app.convergence.ConvergenceRun
        The runs of :func:`maxwell_kinetics.app.convergence.convergence_study`; may be empty.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, laid out (``tight_layout``); the caller saves or closes it.
    """
    fig, axes = new_figure(2)
    left, right = axes[0]
    rs = sorted({run.restitution for run in runs})
    styles = ["-", "--", ":", "-."]
    for i, r in enumerate(rs):
        sel = [run for run in runs if run.restitution == r]
        for j, run in enumerate(sel):
            left.loglog(run.tau, run.sup_error, styles[i % 4], color=f"C{j}",
                        label=f"r={r:g} {run.resolution}")
        h = np.array([run.h for run in sel])
        floor = np.array([run.floor for run in sel])
        right.loglog(h, floor, "o" + styles[i % 4], label=f"r = {r:g}")
    if runs:
        h = np.array(sorted({run.h for run in runs}))
        order = runs[0].order
        ref = np.array([run.floor for run in runs if run.h == h[-1]]).max()
        right.loglog(h, ref * (h / h[-1]) ** order, "k:", label=f"h^{order}")
    left.set(xlabel="τ", ylabel="sup_q |G − f̂|", title="approach to f̂")
    left.legend(fontsize=6, ncol=2)
    right.set(xlabel="h (grid spacing in ln q)", ylabel="error floor",
              title="floor against resolution")
    right.legend(fontsize=7)
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
    import numpy as np

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
