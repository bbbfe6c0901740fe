"""Exact results of the 1D Ulam model (NumPy): the scaling solution and the moment hierarchy.

Conventions: P̂(k) = ∫ e^{ikv} P(v) dv; the rescaled characteristic function is
G(q, τ) = P̂(q / v0(τ), τ) with v0² = ⟨v²⟩; x = v / v0 is the rescaled velocity.
"""

from __future__ import annotations

import numpy as np

from .model import MaxwellModel

__all__ = ["f_hat", "f_density", "moment_hierarchy", "rescaled_moments"]


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
        f̂(q), float.
    """
    a = np.abs(np.asarray(q, dtype=float))
    return (1.0 + a) * np.exp(-a)


def f_density(x) -> np.ndarray:
    """Scaling solution in velocity space, f(x) = 2 / (π (1 + x²)²) (unit variance, x⁻⁴ tail).

    Parameters
    ----------
    x : array_like
        Rescaled velocities v/v0.

    Returns
    -------
    numpy.ndarray
        f(x), the inverse Fourier transform of :func:`f_hat`.
    """
    x = np.asarray(x, dtype=float)
    return 2.0 / (np.pi * (1.0 + x * x) ** 2)


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
        Shape (len(tau), len(initial_moments)): row i holds M_0..M_nmax at tau[i].
    """
    from scipy.integrate import solve_ivp

    m0 = np.asarray(initial_moments, dtype=float)
    nmax = len(m0) - 1
    coef = model.gain_moment_coefficients(nmax)

    def rhs(_, M):
        out = -M.copy()
        for n in range(nmax + 1):
            out[n] += np.dot(coef[n, : n + 1], M[: n + 1] * M[n::-1])
        return out

    taus = np.atleast_1d(np.asarray(tau, dtype=float))
    if taus.max() == 0.0:
        return np.tile(m0, (taus.size, 1))
    sol = solve_ivp(rhs, (0.0, float(taus.max())), m0, t_eval=taus, rtol=1e-12, atol=1e-300,
                    method="DOP853")
    return sol.y.T


def rescaled_moments(model: MaxwellModel, initial_moments, tau) -> np.ndarray:
    """M_n / M_2^{n/2} along the hierarchy (zero mean assumed): the moments of x = v / v0.

    Parameters
    ----------
    model : maxwell_kinetics.model.MaxwellModel
        The model.
    initial_moments : array_like
        M_0, M_1, ..., M_nmax at τ = 0; needs nmax ≥ 2.
    tau : float or array_like
        Collisions per particle τ ≥ 0 (increasing).

    Returns
    -------
    numpy.ndarray
        Shape (len(tau), len(initial_moments)): the rescaled moments ⟨xⁿ⟩, computed from
        :func:`moment_hierarchy`.
    """
    M = moment_hierarchy(model, initial_moments, tau)
    n = np.arange(M.shape[1])
    return M / M[:, 2:3] ** (n / 2.0)
