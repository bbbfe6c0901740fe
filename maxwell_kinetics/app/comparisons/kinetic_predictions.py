"""What the kinetic theory predicts for the comparisons: the solver's solutions (cached per
run of ``reproduce``) and the bin probabilities of P(x, τ) that the particle histograms are
compared with.

Conventions: x = v/v0(τ) with v0 = e^{−λτ}; G(q, τ) is the characteristic function of
P(x, τ); bin probabilities come from :func:`maxwell_kinetics.statistics.interval_probabilities`
(G cut at the grid's q_max).  Solutions handed out by :func:`kinetic_solution` are shared
between callers, so their arrays are read-only.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from particles.initial import get_law
from particles.validation import InvalidArgumentError

from ... import statistics as st
from ...model import MaxwellModel

__all__ = [
    "kinetic_solution",
    "law_cdf",
    "solution_bin_probabilities",
    "fft_bin_probabilities",
    "never_collided_cut",
]


#: Most solutions :func:`kinetic_solution` keeps (the least recently used goes first); a
#: ``reproduce`` run needs fewer at once.
MAX_CACHED_SOLUTIONS = 16
_SOLUTIONS: OrderedDict = OrderedDict()


def kinetic_solution(restitution: float, law: str, taus, resolution: str = "coarse",
                     progress: bool | None = None):
    """The solver's :class:`~maxwell_kinetics.solution.Solution`, cached per (r, law, τ list,
    resolution) so that the comparisons of one ``reproduce`` run share solves (each new
    (r, law, resolution) costs seconds of JIT compilation).

    At most ``MAX_CACHED_SOLUTIONS`` solutions are kept (the least recently used is dropped
    first).  The cached solution's ``tau``, ``G`` and ``deviation`` arrays are made read-only:
    every caller shares them.

    Parameters
    ----------
    restitution : float
        Coefficient of restitution r in [0, 1].
    law : str
        Name of a built-in initial law (zero mean, unit variance), e.g. ``"gaussian"``.
    taus : sequence of float
        Times τ (collisions per particle) at which the solution is recorded.
    resolution : str or maxwell_kinetics.grid.Resolution, optional
        Name of the solver's grid resolution (default ``"coarse"``), or a grid (hashable: it is
        part of the cache key).
    progress : bool or None, optional
        Show the solver's progress (first solve only; None, the default: a bar on a terminal or
        in a notebook, nothing otherwise).

    Returns
    -------
    maxwell_kinetics.solution.Solution
        The (shared) solution of :func:`maxwell_kinetics.solver.solve`.
    """
    from ...solver import solve  # JAX: imported when a solution is first needed

    key = (float(restitution), str(law), tuple(float(t) for t in taus), resolution)
    if key not in _SOLUTIONS:
        sol = solve(restitution, law, list(key[2]), resolution, progress=progress)
        for a in (sol.tau, sol.G, sol.deviation):
            if isinstance(a, np.ndarray):
                a.flags.writeable = False  # shared by every caller: nobody may change it
        _SOLUTIONS[key] = sol
        while len(_SOLUTIONS) > MAX_CACHED_SOLUTIONS:  # bounded: drop the least recently used
            _SOLUTIONS.popitem(last=False)
    _SOLUTIONS.move_to_end(key)
    return _SOLUTIONS[key]


def law_cdf(law: str, v) -> np.ndarray:
    """CDF of the built-in initial law ``law`` (zero mean, unit variance) at ``v``: the law's own
    (:meth:`particles.initial.InitialLaw.cdf`), so no parameter of a law is written twice.

    Parameters
    ----------
    law : str
        Name of a built-in initial law.
    v : array_like
        Velocities.

    Returns
    -------
    numpy.ndarray
        P(V ≤ v), the shape of ``v``.
    """
    return get_law(law).cdf(v)


def solution_bin_probabilities(sol, tau_index: int, edges, far: float = 200.0):
    """Predicted probabilities of the bins ``edges`` and the mass below ``edges[0]`` at
    ``sol.tau[tau_index]``, as two parts:

    * the particles that never collided, a fraction e^{−τ} distributed as the initial law
      rescaled by e^{λτ}: G_free(q) = e^{−τ} φ(q e^{λτ}), whose bin probabilities are exact
      (:func:`law_cdf`).  This part carries the jumps of discontinuous laws, whose 1/q
      Fourier tail a cut at q_max would misrepresent;
    * the rest, G − G_free, transformed by
      :func:`maxwell_kinetics.statistics.interval_probabilities` on [0, q_max]
      (mass below −``far`` neglected: < 1e-7 for the laws here).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        A solution of the kinetic solver (1D), e.g. from :func:`kinetic_solution`.
    tau_index : int
        Index into ``sol.tau`` of the time τ (collisions per particle).
    edges : array_like
        Increasing bin edges in the rescaled velocity x = v/v0(τ), shape (m + 1,).
    far : float, optional
        The mass below −``far`` is neglected in ``below`` (default 200).

    Returns
    -------
    prob : numpy.ndarray
        Predicted probability of each bin, shape (m,).
    below : float
        Predicted probability of x < ``edges[0]``.
    """
    from ...kinetic_histogram import bin_probabilities

    # one home with Solution.histogram (maxwell_kinetics.kinetic_histogram)
    return bin_probabilities(sol, sol.time_index(tau_index), np.asarray(edges, dtype=float), far)


def fft_bin_probabilities(sol, tau_index: int, edges, refine: int = 8):
    """The solver's band-limited inverse-FFT density and its integral over the bins ``edges``.

    Returns ``(prob, x, P)``: ``(x, P)`` is
    :func:`maxwell_kinetics.kinetic_histogram.band_limited_density` (pyfftw inverse FFT of all
    of G cut at q_max, not :meth:`Solution.density`, whose never-collided part is exact; spacing
    dx ≈ 0.061 for the "fine" grid) restricted to [edges[0], edges[-1]],
    what the figure draws; ``prob`` its integral over each bin.  P is a trigonometric polynomial
    (no frequency above q_max), so it is first interpolated exactly onto a grid ``refine`` times
    finer (zero padding of its spectrum) and then integrated with a cubic spline: a spline
    through the native samples alone misses up to 1e-4 per bin near a jump, where P rings at
    frequency q_max ≈ 2.2/dx (measured against the refined grid).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        A solution of the kinetic solver (1D), e.g. from :func:`kinetic_solution`.
    tau_index : int
        Index into ``sol.tau`` of the time τ (collisions per particle).
    edges : array_like
        Increasing bin edges in the rescaled velocity x = v/v0(τ), shape (m + 1,).
    refine : int, optional
        Factor of the exact (spectral) refinement before the spline integration (default 8).

    Returns
    -------
    prob : numpy.ndarray
        Integral of P over each bin, shape (m,).
    x, P : numpy.ndarray
        The FFT grid points in [edges[0], edges[-1]] and the density there.
    """
    from scipy.interpolate import CubicSpline

    from ...kinetic_histogram import band_limited_density

    x, P = band_limited_density(sol, sol.time_index(tau_index))
    m = P.size
    spec = np.fft.rfft(np.fft.ifftshift(P))
    fine = np.zeros(refine * m // 2 + 1, dtype=complex)
    fine[: spec.size] = spec
    pf = np.fft.fftshift(np.fft.irfft(fine, n=refine * m)) * refine
    dx = (x[1] - x[0]) / refine
    xf = dx * (np.arange(refine * m) - refine * m // 2)
    edges = np.asarray(edges, dtype=float)
    sel = (xf >= edges[0] - 1.0) & (xf <= edges[-1] + 1.0)
    prob = np.diff(CubicSpline(xf[sel], pf[sel]).antiderivative()(edges))
    show = (x >= edges[0]) & (x <= edges[-1])
    return prob, x[show], P[show]


def never_collided_cut(sol, tau_index: int, edges) -> np.ndarray:
    """What cutting the never-collided part G_free(q) = e^{−τ} φ(q e^{λτ}) at q_max does to the
    bin probabilities: its bins from ∫_0^{q_max} minus its exact bins.  This is the term that
    :func:`fft_bin_probabilities` (all of G cut at q_max) and
    :func:`solution_bin_probabilities` (G − G_free cut at q_max, G_free exact) treat
    differently by design; it is ≈ 0 (< 1e-16) for smooth laws and carries the Gibbs ringing
    of a jump.  The rest of their difference is their quadratures of G − G_free (a refined
    inverse FFT against :func:`maxwell_kinetics.statistics.interval_probabilities`): measured
    at r = 0.5, τ = 0.5 on 40 bins of [−4, 4], up to 1.5e-3 per bin on the "coarse" grid and
    1.2e-4 on the default grid for the uniform and asymmetric laws, 1e-8 for the Gaussian.

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        A solution of the kinetic solver (1D), e.g. from :func:`kinetic_solution`.
    tau_index : int
        Index into ``sol.tau`` of the time τ (collisions per particle).
    edges : array_like
        Increasing bin edges in the rescaled velocity x = v/v0(τ), shape (m + 1,).

    Returns
    -------
    numpy.ndarray
        Cut minus exact probability of each bin, shape (m,).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``sol`` when its initial law is a user's (no CDF), whatever its name.
    """
    q_max = sol.resolution.q_max
    tau = float(sol.tau[tau_index])
    law = sol.initial_law()  # None for a user's law, whatever its name
    if law is None or law.distribution is None:
        raise InvalidArgumentError("sol", f"a solution of initial law {sol.initial!r}",
                                   "a solution of a built-in law (a user's law has no CDF)")
    weight = math.exp(-tau)
    stretch = math.exp(MaxwellModel(sol.restitution).lam * tau)
    edges = np.asarray(edges, dtype=float)
    cut = st.interval_probabilities(lambda q: weight * law.phi(q * stretch), edges, q_max)
    return cut - weight * np.diff(law.cdf(edges / stretch))
