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

import math

import jax.numpy as jnp
import numpy as np

__all__ = ["INTERPOLATION_POINTS", "lagrange", "collision_tables", "collision_term",
           "dilation_term", "rescaled_rhs", "CENTRAL_DIFFERENCE", "mapped_collision_tables",
           "MAPPED_INTERPOLATION_POINTS",
           "mapped_collision_term", "mapped_dilation_term", "mapped_rescaled_rhs", "grid_rhs"]

#: Points of the Lagrange interpolation of F at the partners' velocities (order 6).
INTERPOLATION_POINTS = 6
#: The same on a mapped grid, in s: no cancellation of the interpolation error in the moments
#: there (the uniform grid's moments of the gain are exact to round-off for a Gaussian), so a
#: higher order: the gain's fourth moment for the unit Gaussian (r = 0.5, 201 points on ±2000,
#: core spacing 0.2) is off by 2.8e-5 with 6 points, 9.6e-7 with 8, 1.4e-8 with 10, 2.3e-9 with
#: 12.
MAPPED_INTERPOLATION_POINTS = 10
#: δ of the partition of the gain on a mapped grid (comment block below), in units of s.
SHARE_WIDTH = 0.3


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


def collision_tables(c: np.ndarray, keep: float, transfer: float, rate: np.ndarray,
                     exponent: float, kink: float) -> dict[str, np.ndarray]:
    """The precomputed tables of the collision term on the grid ``c`` (module docstring).

    Parameters
    ----------
    c : numpy.ndarray
        The uniform grid, shape (N,).
    keep, transfer : float
        1 − p and p.
    rate : numpy.ndarray
        Shape (N, N): the kernel's collision rate of the pair (c_i, c_j)
        (:meth:`particles.kernels.Kernel.rate`), a function of |c_i − c_j| homogeneous of
        degree γ (R(|g|) = R(1) |g|^γ; this module never writes a rate itself).
    exponent : float
        γ, the degree of the rate (the Jacobian p^{−1−γ} of the gain).
    kink : float
        R(1) · (−2ζ(−γ)) (0 for γ = 0 and 2): the coefficient of the correction of the node
        v = c_k.

    Returns
    -------
    dict
        ``first`` (N, N) int32 and ``weights`` (N, N, M): interpolation of F at
        w_ki = (c_k − keep c_i)/transfer; ``gain_rate`` (N, N): p^{−1−γ} R(c_i, c_k), zero
        where w_ki is off the grid; ``kernel`` (N, N): R(c_i, c_j); ``energy_kernel`` (N, N):
        R(c_i, c_j) |c_i − c_j|²; ``node`` (N,): the correction coefficient
        h^{γ+1} kink (p^{−1−γ} − 1).
    """
    n = c.size
    h = c[1] - c[0]
    w = (c[:, None] - keep * c[None, :]) / transfer  # [k, i]
    position = (w - c[0]) / h
    first, weights = lagrange(position, n, INTERPOLATION_POINTS)
    inside = (position >= -1e-9) & (position <= n - 1 + 1e-9)
    g = c[:, None] - c[None, :]
    kernel = np.asarray(rate, dtype=float)
    jacobian = transfer ** (-1.0 - exponent)
    return {"first": first, "weights": weights,
            "gain_rate": np.where(inside, jacobian * kernel, 0.0),
            "kernel": kernel, "energy_kernel": kernel * (g * g),
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


# ---------------------------------------------------------------------------------------------
# The mapped grid c_i = g(s_i) on a uniform grid s_i of step h_s (velocity_grid.MappedGrid)
#
# Quadrature: the trapezoid rule in s, weights ω_i = g′(s_i) h_s (the local spacing).  F at the
# partners' velocities by Lagrange interpolation in s (MAPPED_INTERPOLATION_POINTS).  The gain
# splits into two integrals with the smooth partition of unity χ₁(v, w) + χ₂(v, w) = 1,
#
#     χ₁(v, w) = ½ erfc((ln(ρ(v)/ρ(w)) − ln(p/(1−p)))/δ),  χ₂ = 1 − χ₁,
#
# ρ(x) = ω(x) (the local spacing), δ = SHARE_WIDTH (in units of s, where ln ρ ≈ |s| in the
# tails).  Over v the partner w moves (1−p)/p times as fast, over w the partner v moves
# p/(1−p) times as fast: the integral over v resolves F(w) while ρ(v) ≲ ρ(w) p/(1−p), the one
# over w resolves F(v) while ρ(w) ≲ ρ(v) (1−p)/p, hence the switch at ρ(v)/ρ(w) = p/(1−p)
# (the uniform grid's single integral over v is the limit of equal spacings).  χ₁ falls from
# 1 to 0 there over a few nodes, and its leak beyond is Gaussian-small (γ = 0, r = 0.5, τ = 10,
# 401 points on ±2·10⁵, switch at ρ(v) = ρ(w): the fourth moment of Q_h is off by 1.6e-10
# relative with δ = 0.3, 3.6e-9 with 0.2, 2.2e-8 with 0.5, 6e-6 with 0.8; the rational
# ρ(w)^k/(ρ(v)^k + ρ(w)^k) did no better than 1.3e-8, at k = 8),
#
#     gain(c_k) = p^{−1−γ} ∫ χ₁ F(v) F(w) |v − c_k|^γ dv         (over v, w = (c_k − (1−p) v)/p)
#               + (1−p)^{−1−γ} ∫ χ₂ F(v) F(w) |w − c_k|^γ dw     (over w, v = (c_k − p w)/(1−p)),
#
# each over the partner whose spacing resolves the integrand: on a grid that widens with |c|
# the partner in the core (the peak of F(v) F(w) seen from a tail node c_k) is the variable of
# integration, never the interpolated one.  On the uniform grid the old single integral over v
# is used unchanged.  The kink at v = w = c_k (0 < γ < 2): the correction of the uniform grid
# with the local spacing ω_k, −2ζ(−γ) ω_k^{γ+1} F_k² (χ₁ p^{−1−γ} + χ₂ (1−p)^{−1−γ} − 1), χ at
# (c_k, c_k).  The dilation: ∂_c(c F) = (1/g′(s)) ∂_s(g F), the eighth-order flux difference
# in s divided by ω_i (mass exact); the moment corrections use the ω_i.
#
# The corrections of mass, momentum and energy multiply F by α + β c θ + δ c² θ with the taper
# θ = a²/(a² + c²) (a: the map's scale), bounded by 1, a/2 and a²: the uniform grid's
# α + β c + δ c² would, at |c| of thousands, turn the small δ into a growth rate δ c² of the
# tail.
# ---------------------------------------------------------------------------------------------


def mapped_collision_tables(c: np.ndarray, spacing, position, keep: float, transfer: float,
                            rate: np.ndarray, exponent: float,
                            kink: float) -> dict[str, np.ndarray]:
    """The collision tables on a mapped grid (the comment block above).

    Parameters
    ----------
    c : numpy.ndarray
        The nodes g(s_i), increasing, shape (N,).
    spacing : callable
        Velocity x → the local spacing g′(s(x)) h_s (at the nodes: the trapezoid weights ω_i).
    position : callable
        Velocity → fractional node index (s(x) − s_0)/h_s.
    keep, transfer : float
        1 − p and p.
    rate : numpy.ndarray
        Shape (N, N): the kernel's rate of the pair (c_i, c_j), homogeneous of degree γ in
        |c_i − c_j| (:func:`collision_tables`).
    exponent : float
        γ.
    kink : float
        R(1) · (−2ζ(−γ)) (0 for γ = 0 and 2).

    Returns
    -------
    dict
        ``first``/``weights`` and ``first2``/``weights2``: the interpolation stencils of the
        partner in the integral over v and over w; ``gain_rate``, ``gain_rate2`` (N, N): the
        quadrature weight times the rate and χ₁ or χ₂, zero where the partner is off the grid;
        ``kernel`` (N, N): R(c_k, c_j) ω_j; ``energy_kernel`` (N, N):
        ω_i ω_j R(c_i, c_j) |c_i − c_j|²; ``node`` (N,); ``quadrature`` (N,): the ω_i; ``taper``
        (N,): θ_i = a²/(a² + c_i²), a² = ω(0)² c²/(ω(c)² − ω(0)²) at c = c_{N−1} (the map's
        scale, from ``spacing``).
    """
    from scipy.special import erfc

    n = c.size
    weights = spacing(c)

    def share(x, partner, shift):  # χ of the integral over x
        return 0.5 * erfc((np.log(spacing(x) / spacing(partner)) - shift) / SHARE_WIDTH)

    ratio = math.log(transfer / keep) if keep > 0.0 else math.inf  # ln(p/(1 − p)) ≥ 0

    g = c[:, None] - c[None, :]
    kernel = np.asarray(rate, dtype=float)
    out = {}
    w = (c[:, None] - keep * c[None, :]) / transfer  # [k, i]: the partner of v = c_i
    pos = position(w)
    out["first"], out["weights"] = lagrange(pos, n, MAPPED_INTERPOLATION_POINTS)
    inside = (pos >= -1e-9) & (pos <= n - 1 + 1e-9)
    chi1 = share(c[None, :], w, ratio)
    out["gain_rate"] = np.where(inside, transfer ** (-1.0 - exponent) * kernel * chi1
                                * weights[None, :], 0.0)
    if keep > 0.0:
        v = (c[:, None] - transfer * c[None, :]) / keep  # [k, j]: the partner of w = c_j
        pos = position(v)
        out["first2"], out["weights2"] = lagrange(pos, n, MAPPED_INTERPOLATION_POINTS)
        inside = (pos >= -1e-9) & (pos <= n - 1 + 1e-9)
        chi2 = share(c[None, :], v, -ratio)
        out["gain_rate2"] = np.where(inside, keep ** (-1.0 - exponent) * kernel * chi2
                                     * weights[None, :], 0.0)
        at_node = 0.5 * float(erfc(-ratio / SHARE_WIDTH))  # χ₁(c_k, c_k)
        both = (at_node * transfer ** (-1.0 - exponent)
                + (1.0 - at_node) * keep ** (-1.0 - exponent))
    else:  # r = 1: w = c_k, the integral over v alone is exact (χ₁ would be 1/2 there)
        out["gain_rate"] = np.where(inside, kernel * weights[None, :], 0.0)
        out["first2"], out["weights2"] = out["first"], out["weights"]
        out["gain_rate2"] = np.zeros_like(kernel)
        both = 1.0
    out["kernel"] = kernel * weights[None, :]
    out["energy_kernel"] = weights[:, None] * weights[None, :] * (kernel * (g * g))
    out["node"] = kink * weights ** (exponent + 1.0) * (both - 1.0)
    out["quadrature"] = np.asarray(weights, dtype=float)
    a2 = spacing(0.0) ** 2 * c[-1] ** 2 / (spacing(c[-1]) ** 2 - spacing(0.0) ** 2)
    out["taper"] = a2 / (a2 + c * c)
    return out


def _gathered(F, first, weights):
    idx = first[..., None] + jnp.arange(weights.shape[-1], dtype=jnp.int32)
    return jnp.sum(F[idx] * weights, axis=-1)


def mapped_collision_term(F, tables, c, lam):
    """Q_h(F) at the nodes of a mapped grid, per unit n s^γ (the comment block above).

    Parameters
    ----------
    F : jax.Array
        Shape (N,).
    tables : dict
        :func:`mapped_collision_tables` as JAX arrays.
    c : jax.Array
        The nodes.
    lam : float
        λ = p(1 − p).

    Returns
    -------
    jax.Array
        Shape (N,): mass and momentum change exactly zero (Σ ω_i Q_i c_i^k, k = 0, 1), energy
        change exactly −λ Σ ω_i ω_j F_i F_j |c_i − c_j|^{γ+2}.
    """
    omega = tables["quadrature"]
    gain = (jnp.sum(tables["gain_rate"] * _gathered(F, tables["first"], tables["weights"])
                    * F[None, :], axis=1)
            + jnp.sum(tables["gain_rate2"] * _gathered(F, tables["first2"], tables["weights2"])
                      * F[None, :], axis=1))
    q = gain - F * (tables["kernel"] @ F) + tables["node"] * F * F
    tapered = F * tables["taper"]
    basis = jnp.stack([F, tapered * c, tapered * c * c])
    powers = jnp.stack([omega, omega * c, omega * c * c])
    matrix = powers @ basis.T
    target = jnp.stack([0.0, 0.0, -lam * (F @ (tables["energy_kernel"] @ F))])
    coefficients = jnp.linalg.solve(matrix, target - powers @ q)
    return q + coefficients @ basis


def mapped_dilation_term(F, c, omega, taper):
    """∂_c(c F) = (1/g′(s)) ∂_s(c F) on a mapped grid: the eighth-order flux difference in s
    (no flux at the ends) divided by the local spacing ω_i = g′(s_i) h_s, so Σ ω_i (term)_i = 0
    exactly; then F (α + (β c + δ c²) θ) makes the ω-weighted moments 0, 1, 2 those of
    ∂_c(c F).

    Parameters
    ----------
    F : jax.Array
        Shape (N,).
    c : jax.Array
        The nodes g(s_i).
    omega : jax.Array
        The ω_i.
    taper : jax.Array
        θ_i (:func:`mapped_collision_tables`).

    Returns
    -------
    jax.Array
        Shape (N,).
    """
    K = len(CENTRAL_DIFFERENCE)
    n = F.size
    G = jnp.pad(c * F, K)
    flux = jnp.zeros(n + 1)
    for m, a in enumerate(CENTRAL_DIFFERENCE, start=1):
        for l in range(1 - m, m + 1):
            flux = flux + a * G[K - 1 + l:K - 1 + l + n + 1]
    flux = flux.at[0].set(0.0).at[-1].set(0.0)
    d = (flux[1:] - flux[:-1]) / omega
    tapered = F * taper
    basis = jnp.stack([F, tapered * c, tapered * c * c])
    powers = jnp.stack([omega, omega * c, omega * c * c])
    target = -jnp.arange(3.0) * (powers @ F)
    coefficients = jnp.linalg.solve(powers @ basis.T, target - powers @ d)
    return d + coefficients @ basis


def grid_rhs(F, tables, c, h, lam):
    """:func:`rescaled_rhs` on the uniform grid, :func:`mapped_rescaled_rhs` on a mapped one
    (its tables hold ``quadrature``); the choice is made when tracing."""
    if "quadrature" in tables:
        return mapped_rescaled_rhs(F, tables, c, lam)
    return rescaled_rhs(F, tables, c, h, lam)


def mapped_rescaled_rhs(F, tables, c, lam):
    """:func:`rescaled_rhs` on a mapped grid: Q_h(F) + σ′ ∂_c(c F), σ′ = Σ ω c² Q_h /
    (2 Σ ω c² F).

    Parameters
    ----------
    F : jax.Array
        Shape (N,).
    tables : dict
        :func:`mapped_collision_tables` (JAX arrays).
    c : jax.Array
        The nodes.
    lam : float
        λ.

    Returns
    -------
    dF : jax.Array
        Shape (N,).
    sigma : jax.Array
        σ′.
    """
    omega = tables["quadrature"]
    q = mapped_collision_term(F, tables, c, lam)
    w2 = omega * c * c
    sigma = jnp.sum(w2 * q) / (2.0 * jnp.sum(w2 * F))
    return q + sigma * mapped_dilation_term(F, c, omega, tables["taper"]), sigma
