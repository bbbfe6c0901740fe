"""The kinetic prediction in the bins of a particle histogram, and a solution as labelled arrays:
the machinery behind :meth:`maxwell_kinetics.solution.Solution.histogram` and
:meth:`~maxwell_kinetics.solution.Solution.to_xarray`.

Convention: x = v/v0(τ) with v0² the variance of one Cartesian component, e^{−2λτ} in d = 1
(e^{−Λτ} in d ≥ 2) for a unit initial variance.  In the kinetic theory this *is* the energy
per component at τ, so x is the particle runs' x = v/√E
(:func:`particles.observables.rescaled_histogram`; one Cartesian component in d ≥ 2): a kinetic
histogram and a particle histogram on the same edges describe the same variable.

Bin probabilities (exact up to the cut of G at the grid's end q_max):

    Pr(a ≤ x < b) = (1/π) Re ∫_0^{q_max} G(q, τ) · 2 sin(qh)/q · e^{−iqm} dq,  m = (a+b)/2,
    h = (b−a)/2,

by composite Gauss–Legendre quadrature
(:func:`maxwell_kinetics.statistics.interval_probabilities`).  In d = 1 with a built-in
initial law, the particles that never collided (a fraction e^{−τ}, distributed as the initial
law stretched by e^{λτ}: G_free(q) = e^{−τ} φ(q e^{λτ})) are counted exactly from the law's CDF
and only G − G_free is transformed, so a law with a jump (whose 1/q Fourier tail the cut would
misrepresent) is exact too.
"""

from __future__ import annotations

import math

import numpy as np

from particles.validation import check_edges as _check_edges

__all__ = ["check_edges", "free_part", "bin_probabilities", "solution_histogram",
           "solution_to_xarray"]


def check_edges(edges, name: str = "edges") -> np.ndarray:
    """At least two finite, strictly increasing edges, as a float array: the project's one
    rule, :func:`particles.validation.check_edges`.

    Parameters
    ----------
    edges : array_like
        The bin edges.
    name : str, optional
        The argument name in errors (default ``"edges"``).

    Returns
    -------
    numpy.ndarray
        The edges, shape (B + 1,), B ≥ 1.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``name`` for anything else.
    """
    return _check_edges(edges, name)


def free_part(sol, k: int):
    """The never-collided particles at ``sol.tau[k]`` (d = 1, a built-in law): a fraction
    e^{−τ} of them, with the initial law stretched by e^{λτ} in x = v/v0.

    Parameters
    ----------
    sol : Solution
        A solution.
    k : int
        Index of the time.

    Returns
    -------
    tuple or None
        ``(weight, stretch, law)``, or None in d ≥ 2 (no exact free part) or for a user's law
        (known by its characteristic function only, even under a built-in name).
    """
    law = sol.initial_law()  # None for a user's law, whatever its name
    if sol.dimension != 1 or law is None or law.distribution is None:
        return None
    tau = float(sol.tau[k])
    return math.exp(-tau), math.exp(sol.model.lam * tau), law


def bin_probabilities(sol, k: int, edges, far: float = 200.0):
    """Predicted probabilities of the bins ``edges`` at ``sol.tau[k]`` and the mass below
    ``edges[0]`` (module docstring; the mass below −``far`` is neglected in the latter).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    edges : numpy.ndarray
        Checked edges in x (:func:`check_edges`).
    far : float, optional
        Lower end of the integral of the mass below the first edge (default 200).

    Returns
    -------
    prob : numpy.ndarray
        Shape (B,).
    below : float
        Pr(x < edges[0]).
    """
    from . import statistics as st

    q_max = sol.resolution.q_max
    free = free_part(sol, k)
    if free is None:
        def H(q):
            return sol.evaluate(np.minimum(q, q_max), k)

        prob = st.interval_probabilities(H, edges, q_max)
        below = float(st.interval_probabilities(H, [-far, float(edges[0])], q_max)[0])
        return prob, below
    weight, stretch, law = free

    def H(q):  # noqa: F811 (the part without the never-collided particles)
        q = np.minimum(q, q_max)
        return sol.evaluate(q, k) - weight * law.phi(q * stretch)

    cdf_free = weight * law.cdf(edges / stretch)
    prob = st.interval_probabilities(H, edges, q_max) + np.diff(cdf_free)
    below = float(st.interval_probabilities(H, [-far, float(edges[0])], q_max)[0]
                  + cdf_free[0] - weight * law.cdf(np.array([-far / stretch]))[0])
    return prob, below


def solution_histogram(sol, k: int, edges):
    """The kinetic prediction at ``sol.tau[k]`` as a :class:`particles.observables.Histogram`
    on ``edges``: ``density`` = bin probability / width, ``error`` 0, ``count`` 0, ``samples``
    0 (a prediction, not a sample), ``v0`` = v0(τ) (module docstring).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    edges : array_like
        Bin edges in x (checked, naming ``edges``).

    Returns
    -------
    particles.observables.Histogram
        The predicted histogram.
    """
    from particles.observables import Histogram

    edges = check_edges(edges)
    prob, _ = bin_probabilities(sol, k, edges)
    width = np.diff(edges)
    rate = sol.model.energy_rate(sol.dimension, sol.angular)  # Λ; 2λ in d = 1
    v0 = math.exp(-0.5 * rate * float(sol.tau[k]))
    return Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), prob / width, np.zeros(width.size),
                     np.zeros(width.size, dtype=np.int64), 0, v0)


def solution_to_xarray(sol):
    """``sol`` as an ``xarray.Dataset`` (see :meth:`maxwell_kinetics.solution.Solution.to_xarray`).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.

    Returns
    -------
    xarray.Dataset
        The labelled arrays.
    """
    import json

    from particles.driver.result import import_xarray

    xr = import_xarray("Solution.to_xarray()")
    data = {"G": (("tau", "q"), np.asarray(sol.G)),
            "deviation": (("tau", "q"), np.asarray(sol.deviation))}
    coords = {"tau": np.asarray(sol.tau, dtype=float), "q": np.asarray(sol.q, dtype=float)}
    x, first = sol.density(tau_index=0)
    density = np.empty((len(sol.tau), x.size))
    density[0] = first
    for k in range(1, len(sol.tau)):
        density[k] = sol.density(tau_index=k)[1]
    coords["x"] = x
    data["density"] = (("tau", "x"), density)
    attrs = {"restitution": float(sol.restitution), "initial": str(sol.initial),
             "dimension": int(sol.dimension), "angular": str(sol.angular),
             "resolution": json.dumps(sol.resolution.__dict__, default=str)}
    return xr.Dataset(data, coords=coords, attrs=attrs)
