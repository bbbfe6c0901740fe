"""The discrete collision and dilation operators of :mod:`maxwell_kinetics.inelastic_boltzmann`
(precomputed tables in NumPy, right-hand sides in JAX float64).

Unknowns: F_i ≈ F(c_i) on the uniform grid c_i = −L + i h of the rescaled velocity.

Collision term, collocated at the nodes.  The gain at c_k is an integral over the partner that
keeps the fraction 1 − p (velocity v; the other had w = (c_k − (1 − p) v)/p, |v − w| =
|v − c_k|/p):

    gain(c_k) = p^{−1−γ} ∫ F(v) F((c_k − (1 − p) v)/p) |v − c_k|^γ dv,
    loss(c_k) = F(c_k) ∫ |c_k − w|^γ F(w) dw,

both by the trapezoid rule over the nodes, F at the off-grid points by Lagrange interpolation
of :data:`INTERPOLATION_POINTS` points (zero beyond the grid).  For 0 < γ < 2 the integrands
are not smooth at v = c_k (a node): the generalised Euler–Maclaurin formula (Navot) gives the
correction −2ζ(−γ) h^{γ+1} F_k² (p^{−1−γ} − 1), after which the rule errs by O(h^{γ+3}) (γ = 0
and 2: smooth, spectrally accurate).  Last, a correction F_k (α + β c_k + δ c_k²) (three numbers
per call, of the size of the discretisation error) makes the discrete mass and momentum change
exactly zero and the energy change exactly −λ Σ_ij h² F_i F_j |c_i − c_j|^{γ+2}: mass,
momentum and the energy identity hold to round-off.

Dilation term ∂_c(c F): the eighth-order central difference in flux form, with no flux through
the grid's two ends (mass exact); its moments of order ≤ 8 equal the continuous term's as long
as F vanishes near the ends.  Every function here must run with float64 enabled.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

__all__ = ["INTERPOLATION_POINTS", "lagrange", "collision_tables", "collision_term",
           "dilation_term", "rescaled_rhs", "CENTRAL_DIFFERENCE"]

#: Points of the Lagrange interpolation of F at the partners' velocities (order 6).
INTERPOLATION_POINTS = 6


def lagrange(x: np.ndarray, n: int, points: int) -> tuple[np.ndarray, np.ndarray]:
    """First index and Lagrange weights of the ``points`` grid nodes around each position.

    Parameters
    ----------
    x : numpy.ndarray
        Positions in units of grid index (clipped to [0, n − 1]).
    n : int
        Number of nodes (≥ ``points``).
    points : int
        Stencil size M.

    Returns
    -------
    first : numpy.ndarray
        int32, the first node of each stencil, in [0, n − M].
    weights : numpy.ndarray
        Shape ``x.shape + (M,)``: Σ_m w_m (first + m)^k = x^k for k < M.
    """
    x = np.clip(x, 0.0, n - 1.0)
    first = np.clip(np.floor(x) - (points // 2 - 1), 0, n - points).astype(np.int32)
    t = x - first
    weights = np.ones(x.shape + (points,))
    for m in range(points):
        for k in range(points):
            if k != m:
                weights[..., m] *= (t - k) / (m - k)
    return first, weights


def collision_tables(c: np.ndarray, keep: float, transfer: float, exponent: float,
                     kink: float) -> dict[str, np.ndarray]:
    """The precomputed tables of the collision term on the grid ``c`` (module docstring).

    Parameters
    ----------
    c : numpy.ndarray
        The uniform grid, shape (N,).
    keep, transfer : float
        1 − p and p.
    exponent : float
        γ of the rate |v − w|^γ.
    kink : float
        −2ζ(−γ) (0 for γ = 0 and 2): the coefficient of the correction of the node v = c_k.

    Returns
    -------
    dict
        ``first`` (N, N) int32 and ``weights`` (N, N, M): interpolation of F at
        w_ki = (c_k − keep c_i)/transfer; ``gain_rate`` (N, N): p^{−1−γ}|c_i − c_k|^γ, zero
        where w_ki is off the grid; ``kernel`` (N, N): |c_i − c_j|^γ; ``energy_kernel`` (N, N):
        |c_i − c_j|^{γ+2}; ``node`` (N,): the correction coefficient h^{γ+1} kink (p^{−1−γ} − 1).
    """
    n = c.size
    h = c[1] - c[0]
    w = (c[:, None] - keep * c[None, :]) / transfer  # [k, i]
    position = (w - c[0]) / h
    first, weights = lagrange(position, n, INTERPOLATION_POINTS)
    inside = (position >= -1e-9) & (position <= n - 1 + 1e-9)
    g = np.abs(c[:, None] - c[None, :])
    kernel = np.ones_like(g) if exponent == 0.0 else g**exponent
    jacobian = transfer ** (-1.0 - exponent)
    return {"first": first, "weights": weights,
            "gain_rate": np.where(inside, jacobian * kernel, 0.0),
            "kernel": kernel, "energy_kernel": g ** (exponent + 2.0),
            "node": np.full(n, kink * h ** (exponent + 1.0) * (jacobian - 1.0))}


def collision_term(F, tables, c, h, lam):
    """Q_h(F) at the nodes, per unit n s^γ (module docstring).

    Parameters
    ----------
    F : jax.Array
        The values on the grid, shape (N,).
    tables : dict
        :func:`collision_tables` as JAX arrays.
    c : jax.Array
        The grid.
    h : float
        Spacing.
    lam : float
        λ = p(1 − p).

    Returns
    -------
    jax.Array
        Shape (N,).
    """
    idx = tables["first"][..., None] + jnp.arange(INTERPOLATION_POINTS, dtype=jnp.int32)
    partner = jnp.sum(F[idx] * tables["weights"], axis=-1)  # F(w_ki), [k, i]
    gain = h * jnp.sum(tables["gain_rate"] * partner * F[None, :], axis=1)
    q = gain - h * F * (tables["kernel"] @ F) + tables["node"] * F * F
    # F (α + β c + δ c²): exact mass, momentum and energy change
    basis = jnp.stack([F, F * c, F * c * c])  # (3, N)
    powers = jnp.stack([jnp.ones_like(c), c, c * c])
    matrix = h * powers @ basis.T  # [moment, basis]
    target = jnp.stack([0.0, 0.0, -lam * h * h * (F @ (tables["energy_kernel"] @ F))])
    coefficients = jnp.linalg.solve(matrix, target - h * powers @ q)
    return q + coefficients @ basis


#: Coefficients a_m of the eighth-order central difference
#: G′(c_i) ≈ Σ_m a_m (G_{i+m} − G_{i−m})/h, m = 1 … 4.
CENTRAL_DIFFERENCE = (4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0, -1.0 / 280.0)


def dilation_term(F, c, h):
    """∂_c(c F) by the eighth-order central difference in flux form, no flux at the ends.

    G_{i+m} − G_{i−m} telescopes over the interfaces between them, so the difference is
    Φ_{i+1/2} − Φ_{i−1/2} with Φ_{i+1/2} = Σ_m a_m Σ_{l=1−m}^{m} G_{i+l}; the two end
    interfaces are closed.  The difference is exact for polynomials of degree ≤ 8, so the term
    changes the moments of order ≤ 8 as the continuous one does while F vanishes near the ends;
    a last correction F (α + β c + δ c²) makes the moments 0, 1, 2 exact whatever F there.

    Parameters
    ----------
    F : jax.Array
        Shape (N,).
    c : jax.Array
        The grid, shape (N,).
    h : float
        Spacing.

    Returns
    -------
    jax.Array
        Shape (N,).
    """
    K = len(CENTRAL_DIFFERENCE)
    n = F.size
    G = jnp.pad(c * F, K)  # G[k + K] = c_k F_k, zero beyond the ends
    # flux[k]: through the interface between nodes k − 1 and k (k = 0 … N)
    flux = jnp.zeros(n + 1)
    for m, a in enumerate(CENTRAL_DIFFERENCE, start=1):
        for l in range(1 - m, m + 1):  # node (k − 1) + l, padded index k − 1 + l + K
            flux = flux + a * G[K - 1 + l:K - 1 + l + n + 1]
    flux = flux.at[0].set(0.0).at[-1].set(0.0)
    d = (flux[1:] - flux[:-1]) / h
    # F (α + β c + δ c²), of the size of what reaches the ends: the moments 0, 1, 2 of the
    # term are exactly those of ∂_c(c F), 0, −Σ c F and −2 Σ c² F, whatever F at the ends
    basis = jnp.stack([F, F * c, F * c * c])
    powers = jnp.stack([jnp.ones_like(c), c, c * c])
    target = -jnp.arange(3.0) * (powers @ F)
    coefficients = jnp.linalg.solve(powers @ basis.T, target - powers @ d)
    return d + coefficients @ basis


def rescaled_rhs(F, tables, c, h, lam):
    """dF/dτ′ of the rescaled equation, dτ′ = n s^γ dt: Q_h(F) + σ′ ∂_c(c F), with
    σ′ = Σ c² Q_h / (2 Σ c² F) (= d ln s/dτ′).

    Parameters
    ----------
    F : jax.Array
        Shape (N,).
    tables : dict
        The collision tables (JAX arrays).
    c : jax.Array
        The grid.
    h : float
        Spacing.
    lam : float
        λ.

    Returns
    -------
    dF : jax.Array
        Shape (N,).
    sigma : jax.Array
        σ′, a scalar (≤ 0: the gas cools).
    """
    q = collision_term(F, tables, c, h, lam)
    c2 = c * c
    sigma = jnp.sum(c2 * q) / (2.0 * jnp.sum(c2 * F))
    return q + sigma * dilation_term(F, c, h), sigma
