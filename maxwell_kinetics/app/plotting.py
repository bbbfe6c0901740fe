"""The figure of the convergence study (:func:`plot_convergence`), drawn with the library's
:func:`maxwell_kinetics.figures.new_figure` (matplotlib on an Agg canvas, without pyplot).

The figures of the kinetic library moved to :mod:`maxwell_kinetics.figures`: ``new_figure``,
``plot_solution``, ``plot_density`` and ``Figure``.  Their old names here still work for a
while, with a :class:`DeprecationWarning` that names the new home.
"""

from __future__ import annotations

import warnings

import numpy as np

from .. import figures as _figures
from ..figures import new_figure as _new_figure

__all__ = ["plot_convergence"]

#: Names that moved to :mod:`maxwell_kinetics.figures` (an import from here warns and says so).
MOVED = ("new_figure", "plot_solution", "plot_density", "Figure")


def __getattr__(name):
    if name in MOVED:
        warnings.warn(f"maxwell_kinetics.app.plotting.{name} moved to "
                      f"maxwell_kinetics.figures.{name}; import it from there",
                      DeprecationWarning, stacklevel=2)
        return getattr(_figures, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
    fig, axes = _new_figure(2)
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
    left.legend(ncol=2)
    right.set(xlabel="h (grid spacing in ln q)", ylabel="error floor",
              title="floor against resolution")
    right.legend()
    fig.tight_layout()
    return fig

