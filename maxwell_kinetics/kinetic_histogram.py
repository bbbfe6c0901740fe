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
law stretched by e^{λτ}: G_free(q) = e^{−τ} φ(q e^{λτ}), the solution of ∂τ G = λ q ∂q G − G)
are counted exactly from the law's CDF and only the collided part H = G − G_free is
transformed (:func:`collided_part`).  G_free is subtracted on the grid's nodes, where it is
known exactly, and never interpolated: a law with a jump has a 1/q oscillating φ that a coarse
grid cannot follow (on "coarse" the uniform law's φ(q) has a period of 3.6 in q, the node
spacing near q_max), and interpolating it made the density ring (Gibbs) and go negative.  At
τ = 0, H = 0 on the nodes and the histogram is the law's own, to round-off.  A negative
probability (round-off, or a grid that does not resolve H) is replaced by 0, which is nearer
the truth.

Numerical error (:func:`bin_errors`), the ``error`` of :func:`solution_histogram`: the sum of

* a grid term: the bin probabilities read from every node, every second and every fourth
  (spacings h, 2h, 4h) differ by d₁ = |P_h − P_2h| and d₂ = |P_2h − P_4h|; with ρ = max d₂ /
  max d₁ (≈ 2^order where H is resolved, ≈ 1 where it is not) the term is d₁/√max(ρ, 1), its
  envelope over two bins on each side (d₁ changes sign from bin to bin).  Richardson's d₁/(ρ −
  1) would be the read-out's interpolation error alone; the solver's nodes carry the same
  interpolation error accumulated in the gain term, measured at 2–10 times that, which the
  square root covers;
* a cut term: the transform of |H| over the top octave [q_max/2, q_max] (the largest change
  of the bin that an error of that modulus can make,
  :func:`maxwell_kinetics.statistics.interval_bound`), extrapolated beyond q_max as a power
  law: divided by half the ratio ρ_c of the octave below to it (at least 1); ρ_c = 2^β for
  |H| ~ q^{−β}, whose tail beyond q_max is the octave's divided by 2^β − 1.

Measured against a solve with h = 0.0125 and q_max = 398 (r = 0.3; laws uniform, asymmetric,
Gaussian, Laplace, bimodal; τ = 0.5, 1, 3; 120 bins of width 0.1 on [−6, 6]): on "coarse",
"default" and "fine" the largest estimate is 1.0–17 times the largest actual error, and the
estimate bounds the actual error bin by bin except in a few bins of the smooth laws at the
1e-8 level and below.
"""

from __future__ import annotations

import math

import numpy as np

from particles.validation import check_edges as _check_edges

__all__ = ["check_edges", "free_part", "collided_part", "bin_probabilities", "bin_errors",
           "law_density", "solution_density", "band_limited_density",
           "XARRAY_DENSITY_X",
           "solution_histogram", "solution_to_xarray"]


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


def law_density(law, v: np.ndarray) -> np.ndarray:
    """A built-in law's density at ``v``, from its CDF F: the sixth-order central difference
    of F with step 0.01 (error about 1e-12 for the smooth laws), or, within 0.03 of a kink of
    F (the jump of the uniform or the asymmetric law), where that difference is wrong and can
    be negative, the same difference with the largest of the steps 1e-3, 1e-4, 1e-5 that agrees
    with the next smaller one to 1e-9 (a difference of a piecewise-linear F is exact farther
    than 3 steps from its kinks, so the error there is below about 1e-9); failing that (within
    about 3e-5 of a kink), (F(v + δ) − F(v − δ))/2δ with δ = 1e-6, never negative because F
    increases.  The result is never negative.

    Parameters
    ----------
    law : particles.initial.InitialLaw
        A law with a CDF.
    v : numpy.ndarray
        Velocities.

    Returns
    -------
    numpy.ndarray
        The density, of the shape of ``v``, ≥ 0.
    """
    v = np.asarray(v, dtype=float)

    def sixth(d):
        diff = [law.cdf(v + j * d) - law.cdf(v - j * d) for j in (1, 2, 3)]
        return (45.0 * diff[0] - 9.0 * diff[1] + diff[2]) / (60.0 * d)

    steps = (1e-2, 1e-3, 1e-4, 1e-5)
    estimates = [sixth(d) for d in steps]
    out = (law.cdf(v + 1e-6) - law.cdf(v - 1e-6)) / 2e-6
    pairs = zip(estimates[:-1], estimates[1:], strict=True)
    for coarse, fine in reversed(list(pairs)):  # the largest step wins
        out = np.where(np.abs(coarse - fine) <= 1e-9, coarse, out)
    return np.maximum(out, 0.0)


def solution_density(sol, k: int, x=None):
    """P(x) at ``sol.tau[k]``: in d = 1 with a built-in law, the never-collided particles
    exactly, e^{−τ} times the initial law's density stretched by e^{λτ} (:func:`free_part`,
    :func:`law_density`), plus the transform of the collided part H = G − G_free
    (:func:`collided_part`) cut at q_max, so that a law with a jump does not ring (Gibbs) nor
    go negative; otherwise the transform of G cut at q_max
    (:meth:`maxwell_kinetics.solution.Solution.density`).  At the given x, or on the FFT grid
    (``x`` None) of :func:`maxwell_kinetics.velocity.inverse_transform`; there the exact free
    part has frequencies above q_max: the band-limited transform of all of G is
    :func:`band_limited_density`.

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    x : array_like, optional
        Rescaled velocities (checked by :func:`maxwell_kinetics.velocity.invert`, naming
        ``x``); None for the FFT grid.

    Returns
    -------
    x, P : numpy.ndarray
        The velocities and the density there.
    """
    from .velocity import cut_at, invert

    free = free_part(sol, k)
    if free is None:
        return band_limited_density(sol, k, x)
    q_max = sol.resolution.q_max
    x, P = invert(cut_at(collided_part(sol, k), q_max), q_max=q_max, x=x)
    weight, stretch, law = free
    return x, P + weight * law_density(law, x / stretch) / stretch


def band_limited_density(sol, k: int, x=None):
    """The inverse FFT of all of G(q, ``sol.tau[k]``) cut at the grid's end q_max, at ``x`` or
    on the FFT grid of :func:`maxwell_kinetics.velocity.inverse_transform` (period 1000 in x): a
    trigonometric polynomial with no frequency above q_max, of mass G(0) = 1 on that grid,
    which spectral refinement (zero padding of its spectrum) interpolates exactly.  It rings
    (Gibbs) and can go negative near the jump of a law; the density itself is
    :func:`solution_density` (:meth:`maxwell_kinetics.solution.Solution.density`).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    x : array_like, optional
        Rescaled velocities (checked by :func:`maxwell_kinetics.velocity.invert`, naming
        ``x``); None (the default) for the FFT grid.

    Returns
    -------
    x, P : numpy.ndarray
        The velocities (the FFT grid for ``x`` None) and the band-limited density there.
    """
    from .velocity import cut_at, invert

    q_max = sol.resolution.q_max
    return invert(cut_at(lambda q: sol.evaluate(q, k), q_max), q_max=q_max, x=x)


def _interpolate(values: np.ndarray, s_min: float, h: float, order: int, q: np.ndarray):
    """Centred Lagrange interpolation in s = ln q of ``values`` on the nodes s_min + j h (the
    rule of :meth:`maxwell_kinetics.solution.Solution.evaluate`, on any spacing)."""
    n = values.size
    pos = (np.log(q) - s_min) / h
    first = np.clip(np.floor(pos) - order // 2 + 1, 0, n - order).astype(int)
    x = pos - first
    out = np.zeros(x.shape, dtype=complex)
    for j in range(order):
        wj = np.ones_like(x)
        for m in range(order):
            if m != j:
                wj *= (x - m) / (j - m)
        out += wj * values[first + j]
    return out


def collided_part(sol, k: int, step: int = 1):
    """H(q) = G(q, τ) − G_free(q, τ), the characteristic function of the particles that have
    collided, at ``sol.tau[k]`` as a callable on q ≥ 0 (module docstring).

    With c = 1 − e^{−τ} the collided mass, H = c f̂ + I[Y], I the solver's Lagrange
    interpolation in s = ln q of the node values Y = (G − f̂) − e^{−τ}(φ(q e^{λτ}) − f̂): the
    free part, which the grid may not resolve (the 1/q oscillations of a law with a jump), is
    subtracted on the nodes, where it is exact, never interpolated.  Below q_min, H = g − G_free
    (g the small-q reference); above the last node used, H keeps its value there (the
    transform is cut at q_max).  In d ≥ 2 or for a user's law there is no exact free part, and
    H = G = f̂ + I[G − f̂], :meth:`~maxwell_kinetics.solution.Solution.evaluate`'s value.

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    step : int, optional
        Use every ``step``-th node only (spacing ``step`` h), for the error estimate
        (:func:`bin_errors`); default 1, every node.

    Returns
    -------
    callable
        H(q) for an array of q ≥ 0, complex.
    """
    from .deviation import reference
    from .exact import f_hat

    grid = sol.resolution
    free = free_part(sol, k)
    values = np.asarray(sol.deviation[k], dtype=complex)
    c = 1.0
    if free is not None:
        weight, stretch, law = free
        c = 1.0 - weight
        values = values - weight * (law.phi(grid.q * stretch) - f_hat(grid.q))
    n = (grid.n - 1) // step + 1
    nodes, h = values[::step][:n], grid.h * step
    q_last = math.exp(grid.s_min + h * (n - 1))

    def H(q):
        q = np.minimum(np.asarray(q, dtype=float), q_last)
        out = np.asarray(reference(q, sol.skewness), dtype=complex)
        if free is not None:
            out = out - weight * law.phi(q * stretch)
        inside = q >= grid.q_min
        out[inside] = c * f_hat(q[inside]) + _interpolate(nodes, grid.s_min, h, grid.order,
                                                          q[inside])
        return out

    return H


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
    H = collided_part(sol, k)
    prob = st.interval_probabilities(H, edges, q_max)
    below = float(st.interval_probabilities(H, [-far, float(edges[0])], q_max)[0])
    free = free_part(sol, k)
    if free is not None:
        weight, stretch, law = free
        cdf_free = weight * law.cdf(edges / stretch)
        prob = prob + np.diff(cdf_free)
        below += float(cdf_free[0] - weight * law.cdf(np.array([-far / stretch]))[0])
    # a probability is >= 0: a negative value (round-off, or an unresolved grid) is nearer the
    # truth at 0
    return np.maximum(prob, 0.0), below


def bin_errors(sol, k: int, edges) -> np.ndarray:
    """The numerical error of :func:`bin_probabilities`, estimated from the solution itself:
    the sum of a grid term and a truncation term (module docstring), ≥ 0.

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    k : int
        Non-negative index of the saved time.
    edges : numpy.ndarray
        Checked edges in x (:func:`check_edges`).

    Returns
    -------
    numpy.ndarray
        Shape (B,): the estimated error of each bin probability.
    """
    from . import statistics as st

    grid = sol.resolution
    q_max = grid.q_max
    H = collided_part(sol, k)
    # Grid: the transform read from every node, every second and every fourth.
    grid_term = np.zeros(edges.size - 1)
    if (grid.n - 1) // 4 + 1 >= 2 * grid.order:
        p1, p2, p4 = (st.interval_probabilities(collided_part(sol, k, step), edges, q_max)
                      for step in (1, 2, 4))
        d1, d2 = np.abs(p1 - p2), float(np.max(np.abs(p2 - p4)))
        ratio = d2 / float(d1.max()) if d1.max() > 0 else 1.0
        grid_term = d1 / math.sqrt(max(ratio, 1.0))
        # the envelope over the two neighbours on each side: d1 crosses zero from bin to bin
        padded = np.pad(grid_term, 2, mode="edge")
        grid_term = np.max([padded[i:i + grid_term.size] for i in range(5)], axis=0)
    # Truncation: the top two octaves of |H| below q_max, extrapolated beyond it.

    def modulus(q):
        return np.abs(H(q))

    upper = st.interval_bound(modulus, edges, 0.5 * q_max, q_max)
    lower = st.interval_bound(modulus, edges, 0.25 * q_max, 0.5 * q_max)
    ratio = float(lower.max()) / float(upper.max()) if upper.max() > 0 else 2.0
    return grid_term + upper / max(0.5 * ratio, 1.0)


def solution_histogram(sol, k: int, edges):
    """The kinetic prediction at ``sol.tau[k]`` as a :class:`particles.observables.Histogram`
    on ``edges``: ``density`` = bin probability / width, ``error`` = its estimated numerical
    error / width (:func:`bin_errors`), ``count`` 0, ``samples`` 0 (a prediction, not a sample),
    ``v0`` = v0(τ) (module docstring).

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
    error = bin_errors(sol, k, edges)
    width = np.diff(edges)
    rate = sol.model.energy_rate(sol.dimension, sol.angular)  # Λ; 2λ in d = 1
    v0 = math.exp(-0.5 * rate * float(sol.tau[k]))
    return Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), prob / width, error / width,
                     np.zeros(width.size, dtype=np.int64), 0, v0)


#: The default x of :meth:`maxwell_kinetics.solution.Solution.to_xarray`'s density.
XARRAY_DENSITY_X = np.linspace(-20.0, 20.0, 801)


def solution_to_xarray(sol, x=None):
    """``sol`` as an ``xarray.Dataset`` (see :meth:`maxwell_kinetics.solution.Solution.to_xarray`).

    Parameters
    ----------
    sol : maxwell_kinetics.solution.Solution
        The solution.
    x : array_like, optional
        The rescaled velocities of the density (default :data:`XARRAY_DENSITY_X`).

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
    from particles.validation import check_real_array

    x = XARRAY_DENSITY_X if x is None else check_real_array(x, "x", ndim=1, min_size=1)
    density = np.empty((len(sol.tau), x.size))
    for k in range(len(sol.tau)):
        density[k] = sol.density(x, tau_index=k)[1]
    coords["x"] = x
    data["density"] = (("tau", "x"), density)
    attrs = {"restitution": float(sol.restitution), "initial": str(sol.initial),
             "dimension": int(sol.dimension), "angular": str(sol.angular),
             "resolution": json.dumps(sol.resolution.__dict__, default=str)}
    return xr.Dataset(data, coords=coords, attrs=attrs)
