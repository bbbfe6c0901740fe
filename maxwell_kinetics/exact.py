"""Exact results of the 1D Ulam model (NumPy): the scaling solution and the moment hierarchy.

Conventions: P̂(k) = ∫ e^{ikv} P(v) dv; the rescaled characteristic function is
G(q, τ) = P̂(q / v0(τ), τ) with v0² = ⟨v²⟩; x = v / v0 is the rescaled velocity.
"""

from __future__ import annotations

import numpy as np

from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_real_array,
    check_times,
)

from .model import MaxwellModel

__all__ = ["f_hat", "f_density", "f_samples", "moment_hierarchy", "rescaled_moments"]


def f_hat(q) -> np.ndarray:
    """Scaling solution in Fourier space, f̂(q) = (1 + |q|) e^{−|q|}.

    The same for every r < 1: λ q f̂′ − f̂ + f̂(pq) f̂((1 − p)q) = 0 because λ = p(1 − p).

    Parameters
    ----------
    q : array_like
        Rescaled wave numbers.

    Returns
    -------
    numpy.ndarray
        f̂(q), float (0 at q = ±inf).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``q``) if ``q`` is not real (booleans, complex numbers, strings) or has a NaN.
    """
    a = np.abs(_real_no_nan(q, "q"))
    if np.all(np.isfinite(a)):
        return (1.0 + a) * np.exp(-a)
    with np.errstate(invalid="ignore"):  # inf · 0 at |q| = inf, where f̂ is 0
        return np.where(np.isinf(a), 0.0, (1.0 + a) * np.exp(-a))


def f_density(x) -> np.ndarray:
    """Scaling solution in velocity space, f(x) = 2 / (π (1 + x²)²) (unit variance, x⁻⁴ tail).

    Parameters
    ----------
    x : array_like
        Rescaled velocities v/v0.

    Returns
    -------
    numpy.ndarray
        f(x), the inverse Fourier transform of :func:`f_hat` (0 at x = ±inf).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``x``) if ``x`` is not real (booleans, complex numbers, strings) or has a NaN.
    """
    x = _real_no_nan(x, "x")
    with np.errstate(over="ignore"):  # |x| > 1e77: (1 + x²)² is inf and f is 0
        return 2.0 / (np.pi * (1.0 + x * x) ** 2)


def f_samples(rng: np.random.Generator, shape) -> np.ndarray:
    """Independent draws of the scaling solution f(x) = 2 / (π (1 + x²)²).

    With x = tan θ, f(x) dx = (2/π) cos²θ dθ on (−π/2, π/2): θ is drawn uniformly and kept
    with probability cos²θ (rejection, exact; half the draws are kept), then x = tan θ.

    Parameters
    ----------
    rng : numpy.random.Generator
        The random generator (the draws are a function of its state).
    shape : int or tuple of int
        The shape of the result.

    Returns
    -------
    numpy.ndarray
        Float array of ``shape``.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``rng``) if ``rng`` is not a ``numpy.random.Generator``; (argument ``shape``)
        if it has a negative size.
    """
    if not isinstance(rng, np.random.Generator):
        raise InvalidArgumentError("rng", rng, "a numpy.random.Generator")
    dims = shape if isinstance(shape, (tuple, list)) else (shape,)
    try:
        shape = tuple(check_count(n, "shape", 0) for n in dims)
    except InvalidArgumentError:
        raise InvalidArgumentError("shape", shape, "a non-negative int or tuple of them") from None
    size = int(np.prod(shape, dtype=np.int64))
    out = np.empty(size)
    filled = 0
    while filled < size:
        theta = rng.uniform(-0.5 * np.pi, 0.5 * np.pi, 2 * (size - filled) + 64)
        theta = theta[rng.random(theta.size) < np.cos(theta) ** 2][: size - filled]
        out[filled:filled + theta.size] = np.tan(theta)
        filled += theta.size
    return out.reshape(shape)


def _real_no_nan(values, name: str) -> np.ndarray:
    arr = check_real_array(values, name, finite=False)
    if np.any(np.isnan(arr)):
        raise InvalidArgumentError(name, arr.tolist() if arr.size <= 40 else f"shape {arr.shape}",
                                   "real numbers (±inf allowed, no NaN)")
    return arr


def _hierarchy_arguments(model, initial_moments, tau, fewest: int):
    """The checked (model, M_0..M_nmax, τ) of :func:`moment_hierarchy`."""
    if not isinstance(model, MaxwellModel):
        raise InvalidArgumentError("model", model, "a maxwell_kinetics.model.MaxwellModel")
    m0 = check_real_array(initial_moments, "initial_moments", ndim=1, min_size=fewest)
    return m0, check_times(tau, "tau", strictly=False)


def moment_hierarchy(model: MaxwellModel, initial_moments, tau) -> np.ndarray:
    """Raw moments M_n(τ), n = 0..len(initial_moments)−1, of the unscaled master equation.

    dM_n/dτ = −M_n + Σ_{m=0..n} C(n,m) p^m (1−p)^{n−m} M_m M_{n−m} .
    The hierarchy is closed and triangular: the terms m = 0 and m = n give (pⁿ + (1−p)ⁿ) M_n
    (with M_0 = 1), the rest only involve lower moments (Ben-Naim & Krapivsky, Phys. Rev. E
    2000).  The truncated system is integrated with scipy's ``solve_ivp`` (DOP853, rtol 1e-12).

    Parameters
    ----------
    model : maxwell_kinetics.model.MaxwellModel
        The model (its p = (1 + r)/2 enters the coefficients).
    initial_moments : array_like
        M_0, M_1, ..., M_nmax at τ = 0 (M_0 = 1 for a normalised distribution).
    tau : float or array_like
        Collisions per particle τ ≥ 0 at which to report the moments (increasing).

    Returns
    -------
    numpy.ndarray
        Shape (len(tau), len(initial_moments)): row i holds M_0..M_nmax at tau[i].  Moments
        below ~1e-300 are lost to underflow (M_2 ∝ e^{−2λτ}: τ beyond ~690/(2λ)); use
        :func:`rescaled_moments` for the shape at late times.

    Raises
    ------
    particles.InvalidArgumentError
        If ``model`` is not a :class:`~maxwell_kinetics.model.MaxwellModel`,
        ``initial_moments`` is not a non-empty one-dimensional array of finite reals, or
        ``tau`` is not a list of finite times >= 0 in increasing order.
    """
    m0, taus = _hierarchy_arguments(model, initial_moments, tau, 1)
    sol = _integrate(model.gain_moment_coefficients(len(m0) - 1), m0, taus, rescaled=False)
    return sol


def _integrate(coef: np.ndarray, m0: np.ndarray, taus: np.ndarray, *, rescaled: bool):
    """Integrate the hierarchy (raw moments) or its rescaled form (module functions)."""
    from scipy.integrate import solve_ivp

    nmax = len(m0) - 1
    orders = np.arange(nmax + 1)

    def raw(M):
        out = -M.copy()
        for n in range(nmax + 1):
            out[n] += np.dot(coef[n, : n + 1], M[: n + 1] * M[n::-1])
        return out

    def rhs(_, M):
        if not rescaled:
            return raw(M)
        # μ_n = M_n / s^n with s² = M_2: the products are homogeneous of degree n, so the
        # hierarchy keeps its form in μ, less n μ_n d(ln s)/dτ (which holds μ_2 = 1).
        out = raw(M)
        return out - orders * M * (0.5 * out[2] / M[2])

    if taus.max() == 0.0:
        return np.tile(m0, (taus.size, 1))
    sol = solve_ivp(rhs, (0.0, float(taus.max())), m0, t_eval=taus, rtol=1e-12, atol=1e-300,
                    method="DOP853")
    return sol.y.T


def rescaled_moments(model: MaxwellModel, initial_moments, tau) -> np.ndarray:
    """M_n / M_2^{n/2} along the hierarchy (zero mean assumed): the moments of x = v / v0.

    Integrated directly in the rescaled moments μ_n = M_n / M_2^{n/2} (the hierarchy keeps its
    form, plus the term −n μ_n d ln √M_2 / dτ), so the result stays exact at late times, where
    M_2 ∝ e^{−2λτ} underflows (the ratio of :func:`moment_hierarchy`'s columns gave inf and
    then NaN beyond τ ≈ 950 at r = 0.5).  The moments of order ≥ 3 of x grow without bound
    (the scaling solution has x⁻⁴ tails): a value beyond 1.8e308 is inf.

    Parameters
    ----------
    model : maxwell_kinetics.model.MaxwellModel
        The model.
    initial_moments : array_like
        M_0, M_1, ..., M_nmax at τ = 0; needs nmax ≥ 2 and M_2 > 0.
    tau : float or array_like
        Collisions per particle τ ≥ 0 (increasing).

    Returns
    -------
    numpy.ndarray
        Shape (len(tau), len(initial_moments)): the rescaled moments ⟨xⁿ⟩.

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`moment_hierarchy`, and if there are fewer than three moments or M_2 ≤ 0.
    """
    m0, taus = _hierarchy_arguments(model, initial_moments, tau, 3)
    if not m0[2] > 0.0:
        raise InvalidArgumentError("initial_moments", m0.tolist()[:20], "M_2 > 0 (the third)")
    mu0 = m0 / m0[2] ** (np.arange(m0.size) / 2.0)
    with np.errstate(over="ignore", invalid="ignore"):
        return _integrate(model.gain_moment_coefficients(len(m0) - 1), mu0, taus, rescaled=True)
