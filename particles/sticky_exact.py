"""The sticky gas's exact late-time laws: white-noise Burgers turbulence.

At late times the sticky gas with independent initial velocities of variance T₀ is inviscid
Burgers turbulence with white-noise initial velocity (a Brownian velocity potential), whose
one-point statistics are known in closed form (Frachebourg and Martin, J. Fluid Mech. 417, 323
(2000); Groeneboom, Probab. Th. Rel. Fields 81, 79 (1989)). This module evaluates them in the
scaled variables w = v (n t/T₀)^{1/3} and μ = m/(n² T₀ t²)^{1/3} (n the number density): the
velocity law of a particle (:func:`exact_velocity_density`), of the field
(:func:`exact_eulerian_velocity_density`), the cluster-mass law (:func:`exact_mass_density`),
the tail survival and its local exponent, the asymptotes and moments, Chernoff's law of the
displacements (:func:`chernoff_density`).
:class:`particles.sticky_comparison.ExactLawComparison` compares pooled engine states with them.
The derivation is in the docstring of :func:`exact_shock_density`. This module is the one home of
these names and imports nothing of the engine (:mod:`particles.sticky`).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .validation import InvalidArgumentError, check_count, check_positive, check_real_array

__all__ = [
    "chernoff_density",
    "displacement_scale",
    "CHERNOFF_VARIANCE",
    "CHERNOFF_REACH",
    "exact_shock_density",
    "exact_mass_density",
    "exact_velocity_density",
    "exact_eulerian_velocity_density",
    "exact_velocity_survival",
    "exact_velocity_tail_exponent",
    "exact_asymptotes",
    "exact_moments",
]


#: Var Z of Chernoff's law, Z = argmax_t (W(t) − t²) for a two-sided standard Brownian motion W
#: (Groeneboom and Wellner, J. Comput. Graph. Stat. 10, 388 (2001): 0.26355964); the quadrature
#: of :func:`chernoff_density` gives 0.2635596413
#: (``tests/test_particles/test_sticky_displacement.py``).
CHERNOFF_VARIANCE = 0.26355964


def chernoff_density(z, *, cutoff: float = 40.0, nodes: int = 800) -> np.ndarray:
    """Chernoff's density f(z) = g(z) g(−z) / 2 of Z = argmax_t (W(t) − t²) (Groeneboom,
    Probab. Th. Rel. Fields 81, 79 (1989)), where g has the Fourier transform
    ĝ(λ) = ∫ e^{iλz} g(z) dz = 2^{1/3} / Ai(i 2^{−1/3} λ).  ĝ(−λ) is the conjugate of ĝ(λ), so
    g(z) = (1/π) ∫_0^∞ Re[e^{−iλz} ĝ(λ)] dλ, computed by Gauss–Legendre quadrature with
    ``nodes`` nodes on [0, ``cutoff``]: |ĝ(λ)| falls like exp(−(√2/3) (2^{−1/3} λ)^{3/2}), below
    1e-23 at λ = 40, and the integrand's phase λ|z| needs |z| ≲ 10 for 800 nodes.  f is even,
    ∫ f = 1 and Var Z = :data:`CHERNOFF_VARIANCE` (both checked by the tests).  The absolute
    accuracy is about 1e-17 (beyond |z| ≈ 4, where f < 1e-17, the values are that noise);
    f = 0 is returned for |z| > :data:`CHERNOFF_REACH` = 10, where f ~ exp(−2|z|³/3) < 1e-280
    (the phase there reached NaN at |z| = 1e308).

    Parameters
    ----------
    z : array_like of float
        Where to evaluate f.
    cutoff : float
        The upper end of the λ integral.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        f(z).

    Raises
    ------
    InvalidArgumentError
        Naming ``z`` (not finite reals), ``cutoff`` (not a finite number > 0) or ``nodes``
        (not an integer >= 1).
    """
    from scipy.special import airy

    z = _check_finite_array(z, "z")
    cutoff = check_positive(cutoff, "cutoff")
    x, w = _leggauss(check_count(nodes, "nodes", 1))
    lam = 0.5 * cutoff * (x + 1.0)
    w = 0.5 * cutoff * w
    ghat = 2.0 ** (1.0 / 3.0) / airy(1j * 2.0 ** (-1.0 / 3.0) * lam)[0]

    def g(values):
        phase = np.exp(-1j * np.multiply.outer(values, lam))
        return (phase * ghat).real @ w / math.pi

    flat = z.ravel()
    out = np.zeros(flat.shape)
    near = np.abs(flat) <= CHERNOFF_REACH  # beyond, f < 1e-280 and the phase λ|z| overflows
    out[near] = 0.5 * g(flat[near]) * g(-flat[near])
    return out.reshape(z.shape)


def displacement_scale(density: float = 1.0, variance: float = 1.0) -> float:
    """b with displacement / t^{2/3} → b Z in law (Z of :func:`chernoff_density`), for
    independent initial velocities of ``variance`` σ² and number ``density`` n, at t ≫ 1/n:
    b = 2^{2/3} σ^{2/3} n^{−1/3}, so ⟨D²⟩ t^{−4/3} → b² Var Z (= 0.664129 at σ = n = 1).

    Derivation (module docstring, "Energy decay", for the scaling m = a s, a = (σ n t)^{2/3}):
    a particle's position is the slope of the convex minorant of F, and its initial position
    that of m²/(2n), so D = σ^{2/3} n^{−1/3} t^{2/3} (X(s) − s), X(s) the slope at s of the
    convex minorant of W(s) + s²/2.  X(s) − s is stationary in s and, by the switching
    relation X(0) ≤ x ⇔ argmin_u (W(u) + u²/2 − x u) ≥ 0, distributed as
    argmax_u (W(u) − u²/2) = 2^{2/3} Z.

    Parameters
    ----------
    density : float
        n.
    variance : float
        σ², the variance of the initial velocities.

    Returns
    -------
    float
        b.
    """
    n = check_positive(density, "density")
    s2 = check_positive(variance, "variance")
    return 2.0 ** (2.0 / 3.0) * s2 ** (1.0 / 3.0) * n ** (-1.0 / 3.0)



# ---------------------------------------------------------------------------------------------
# Exact late-time laws (white-noise Burgers): velocity and cluster-mass distributions
#
# Everything below is a function of the scaled variables w = v (n t / T₀)^{1/3} and
# μ = m / (n² T₀ t²)^{1/3}, where n is the number density and T₀ = ⟨v²⟩ the initial variance of
# the velocities (the engine draws T₀ = 1).  The derivation is in :func:`exact_shock_density`.

_CUBE = 2.0 ** (-1.0 / 3.0)  # 2^{-1/3}: the Airy scale of the parabola s²/2
_N_ZEROS = 400  # zeros of Ai in the residue sums (enough for μ ≥ _K_SPLIT and τ ≤ _PSI_SPLIT)
_K_SPLIT = 0.5  # k(μ): residue sum for μ ≥ this, Hankel contour below
_PSI_SPLIT = -2.0  # ψ(τ): residue sum for τ ≤ this, saddle-point contour above
_PSI_TABLE = (-2.0, 26.0, 2.0, 28)  # ψ's interpolation table: [lo, hi], panel width, degree
#: |z| beyond which :func:`chernoff_density` returns 0.
CHERNOFF_REACH = 10.0
_MU_MAX = 40.0  # F(μ) < 1e-1100 beyond: returned as 0
_W_MAX = 30.0  # P(w), P_E(w) < 1e-1900 beyond: returned as 0
#: Below this w the tail exponent takes −ln S from ∫₀^w P (16 Gauss–Legendre nodes), since
#: S = 2 P_>(w) → 1 and its logarithm cancels (β was −inf at w = 1e-20, off by 9 % at 1e-16).
_W_SMALL = 0.5


@functools.lru_cache(maxsize=32)
def _leggauss(nodes: int):
    """Gauss–Legendre nodes and weights, cached: the exact laws ask for the same few rules many
    times.  From ``scipy.special.roots_legendre`` (Golub–Welsch below 150 nodes, asymptotic
    formulas above: 2 ms at 300 nodes where ``numpy.polynomial.legendre.leggauss`` takes ~1 s;
    the two agree to 1e-13 relative).  The arrays are shared: read-only."""
    from scipy.special import roots_legendre

    x, w = roots_legendre(int(nodes))
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def _check_finite_array(x, name: str) -> np.ndarray:
    """Finite real numbers (booleans, complex numbers and strings refused), as a float array."""
    arr = check_real_array(x, name, finite=False)
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)].ravel()[0]
        raise InvalidArgumentError(name, float(bad), "finite real numbers")
    return arr


def _airy_zeros():
    """(a_k, Ai'(a_k)) for the first :data:`_N_ZEROS` zeros of Ai, cached."""
    cache = _airy_zeros.__dict__
    if "value" not in cache:
        from scipy.special import ai_zeros

        a, _, _, aip = ai_zeros(_N_ZEROS)
        cache["value"] = (a, aip)
    return cache["value"]


def _log_airy(z):
    """(log Ai(z), Ai'(z)/Ai(z)) for complex z (principal branches), from the exponentially
    scaled Airy functions, so that neither under- nor overflows for |z| up to ~1e10."""
    from scipy.special import airye

    z = np.asarray(z, dtype=complex)
    e_ai, e_aip, _, _ = airye(z)
    return np.log(e_ai) - (2.0 / 3.0) * z**1.5, e_aip / e_ai


def _saddle(c, p: int) -> np.ndarray:
    """The real saddle x₀ > a₁ of e^{−c z} / Ai(z)^p: the root of p Ai'(x)/Ai(x) = −c (the left
    side decreases from +∞ at a₁ to −∞), by Newton's method kept inside a shrinking bracket."""
    a1 = _airy_zeros()[0][0]
    c = np.asarray(c, dtype=float)
    lo = np.full(c.shape, a1)
    hi = (np.maximum(c, 0.0) / p) ** 2 + 2.0
    x = np.clip((c / p) ** 2 * (c > 0), a1 + 0.3, None)
    x = np.where(x < hi, x, 0.5 * (lo + hi))
    for _ in range(80):
        ratio = _log_airy(x)[1].real
        g = p * ratio + c
        lo = np.where(g > 0, x, lo)
        hi = np.where(g <= 0, x, hi)
        step = g / (p * (x - ratio * ratio))
        new = x - step
        inside = (new > lo) & (new < hi)
        new = np.where(inside, new, 0.5 * (lo + hi))
        done = np.abs(new - x) <= 1e-15 * np.maximum(1.0, np.abs(x))
        x = new
        if np.all(done):
            break
    return x


def _contour_log(tau, p: int, nodes: int = 72) -> np.ndarray:
    """log I_p(τ), I_p(τ) = (1/2πi) ∫ e^{−2^{−1/3} τ z} Ai(z)^{−p} dz upward on a path to the
    right of the zeros of Ai, for p = 1, 2 (I_p > 0 for real τ).

    The path leaves the real saddle x₀ (:func:`_saddle`) vertically and bends to the directions
    ±2π/3, where 1/Ai decays fastest: z = x₀ − (s/√3)(cosh u − 1) + i s sinh u, s the Gaussian
    width at the saddle.  The integrand is real-symmetric, so I_p = (1/π) Im ∫_0^∞ … du, done by
    the trapezoidal rule in u (double-exponential decay) with ``nodes`` steps up to |Im z| =
    max(14 s, 24).  The integrand is scaled by its value at the saddle, so there is no
    cancellation and the relative error is that of the rule (~1e-14, checked against the
    residue sums and at twice the nodes in the tests) for every τ."""
    tau = np.asarray(tau, dtype=float)
    c = _CUBE * tau
    x0 = _saddle(c, p)
    l0, r0 = _log_airy(x0)
    r0 = r0.real
    s = 1.0 / np.sqrt(p * (r0 * r0 - x0))
    e0 = -c * x0 - p * l0.real
    u_max = np.arcsinh(np.maximum(14.0 * s, 24.0) / s)
    t = np.linspace(0.0, 1.0, nodes + 1)
    u = u_max[..., None] * t
    h = u_max / nodes
    ss = s[..., None]
    z = x0[..., None] - (ss / math.sqrt(3.0)) * (np.cosh(u) - 1.0) + 1j * ss * np.sinh(u)
    dz = -(ss / math.sqrt(3.0)) * np.sinh(u) + 1j * ss * np.cosh(u)
    log_f = -c[..., None] * z - p * _log_airy(z)[0] - e0[..., None]
    terms = np.exp(log_f) * dz
    terms[..., 0] *= 0.5
    value = np.imag(terms.sum(axis=-1)) * h / math.pi
    return np.log(value) + e0


def _log_psi_direct(tau) -> np.ndarray:
    """log ψ(τ) without the table: the residue sum for τ ≤ −2, the contour above."""
    tau = np.asarray(tau, dtype=float)
    out = np.empty(tau.shape)
    low = tau <= _PSI_SPLIT
    if np.any(low):
        a, aip = _airy_zeros()
        terms = np.exp(np.multiply.outer(tau[low], -_CUBE * a)) / aip
        out[low] = math.log(2.0 ** (1.0 / 3.0)) + np.log(terms.sum(axis=-1))
    if np.any(~low):
        out[~low] = math.log(2.0 ** (1.0 / 3.0)) + _contour_log(tau[~low], 1)
    return out


def _psi_table():
    """Chebyshev coefficients of log ψ on the panels of :data:`_PSI_TABLE`, cached (built from
    :func:`_log_psi_direct` at the Chebyshev points: ~0.2 s on first use)."""
    cache = _psi_table.__dict__
    if "value" not in cache:
        lo, hi, width, deg = _PSI_TABLE
        panels = int(round((hi - lo) / width))
        k = np.arange(deg + 1)
        x = np.cos(np.pi * (k + 0.5) / (deg + 1))  # Chebyshev points of the first kind
        centres = lo + width * (np.arange(panels) + 0.5)
        values = _log_psi_direct(centres[:, None] + 0.5 * width * x[None, :])
        # coefficients by the discrete cosine transform on the points of the first kind
        basis = np.cos(np.outer(k, np.arccos(x)))  # T_j(x_i), shape (deg+1, deg+1)
        coef = values @ basis.T * (2.0 / (deg + 1))
        coef[:, 0] *= 0.5
        cache["value"] = coef
    return cache["value"]


def _log_psi(tau) -> np.ndarray:
    """log ψ(τ) (see :func:`exact_shock_density`): piecewise Chebyshev interpolation of log ψ on
    [−2, 26] (degree 28 on panels of width 2; interpolation error < 1e-13, checked), the residue
    sum below −2 and the contour above 26."""
    tau = np.asarray(tau, dtype=float)
    lo, hi, width, deg = _PSI_TABLE
    out = np.empty(tau.shape)
    inside = (tau > lo) & (tau < hi)
    if np.any(~inside):
        out[~inside] = _log_psi_direct(tau[~inside])
    if np.any(inside):
        coef = _psi_table()
        t = tau[inside]
        idx = np.minimum(((t - lo) / width).astype(int), coef.shape[0] - 1)
        x = 2.0 * (t - (lo + width * idx)) / width - 1.0
        c = coef[idx]
        b1 = np.zeros_like(t)
        b2 = np.zeros_like(t)
        for j in range(deg, 0, -1):  # Clenshaw
            b1, b2 = 2.0 * x * b1 - b2 + c[:, j], b1
        out[inside] = x * b1 - b2 + c[:, 0]
    return out


def _airy_log_derivative_series(terms: int) -> np.ndarray:
    """b_j of the large-z expansion Ai'(z)/Ai(z) ~ Σ_j b_j z^{(1−3j)/2} (|arg z| < π), from
    the Riccati equation L' + L² = z: b₀ = −1, Σ_{i+j=n} b_i b_j + b_{n−1}(4 − 3n)/2 = 0."""
    b = np.zeros(terms)
    b[0] = -1.0
    for n in range(1, terms):
        conv = sum(b[i] * b[n - i] for i in range(1, n))
        b[n] = (conv + b[n - 1] * (4.0 - 3.0 * n) / 2.0) / 2.0
    return b


def _k_contour_parts(nodes: int = 24, series: int = 7):
    """Nodes and weights of the Hankel contour used by :func:`_log_k` at small μ, cached:
    Gauss–Legendre with ``nodes`` nodes on each of the panels [0, 1], [1, 3], … [81, 243] of
    r along the ray x₀ + r e^{3πi/4}, x₀ = 1."""
    cache = _k_contour_parts.__dict__
    key = (nodes, series)
    if key not in cache:
        from scipy.special import gamma

        b = _airy_log_derivative_series(series)
        powers = (1.0 - 3.0 * np.arange(series)) / 2.0
        edges = np.array([0.0, 1.0, 3.0, 9.0, 27.0, 81.0, 243.0])
        x, w = _leggauss(nodes)
        half = 0.5 * np.diff(edges)
        r = (edges[:-1, None] + half[:, None] * (x[None, :] + 1.0)).ravel()
        wr = (half[:, None] * w[None, :]).ravel()
        direction = np.exp(0.75j * math.pi)
        z = 1.0 + r * direction
        remainder = _log_airy(z)[1] - (b[None, :] * z[:, None] ** powers[None, :]).sum(axis=1)
        cache[key] = (z, remainder * direction * wr, b, powers, gamma(-powers))
    return cache[key]


def _log_k(mu, nodes: int = 24) -> np.ndarray:
    """log k(μ), k(μ) = 2 Σ_k exp(2^{−1/3} a_k μ) (a_k the zeros of Ai): twice the density at
    0 of a killed Airy-drift bridge (:func:`exact_shock_density`).

    μ ≥ 0.5: the residue sum over the first 400 zeros (the rest below 1e-17 relative).
    μ < 0.5: the sum is (1/2πi) ∫ e^{cz} Ai'(z)/Ai(z) dz (c = 2^{−1/3} μ) on a contour around
    the negative axis, here the rays x₀ + r e^{±3πi/4} from x₀ = 1.  Subtracting the large-z
    expansion Σ_{j<7} b_j z^{(1−3j)/2} of Ai'/Ai, whose integrals are c^{(3j−3)/2}/Γ((3j−1)/2)
    exactly (Hankel), leaves a remainder O(|z|^{−19/2}), integrated by Gauss–Legendre on
    panels up to r = 243 (:func:`_k_contour_parts`).  The j = 0, 1 terms give
    k(μ) = √(2/π) μ^{−3/2} − 1/2 + O(μ^{3/2})."""
    mu = np.asarray(mu, dtype=float)
    out = np.empty(mu.shape)
    big = mu >= _K_SPLIT
    if np.any(big):
        a = _airy_zeros()[0]
        m = mu[big]
        terms = np.exp(np.multiply.outer(m, _CUBE * (a - a[0])))
        out[big] = math.log(2.0) + _CUBE * a[0] * m + np.log(terms.sum(axis=-1))
    if np.any(~big):
        z, weights, b, powers, gam = _k_contour_parts(nodes)
        c = _CUBE * mu[~big]
        # the series over its leading term b₀ c^{−3/2}/Γ(1/2 ... ) (> 0), in logarithms: the
        # term itself overflows below μ ~ 1e-206 where log k is still ~710
        lead = b[0] / gam[0]
        with np.errstate(divide="ignore"):  # μ = 0: log k = +inf
            log_lead = math.log(lead) - 1.5 * np.log(c)
        relative = (b[None, :] / gam[None, :] * c[:, None] ** (powers[0] - powers[None, :])
                    ).sum(axis=1) / lead
        integral = (np.exp(np.multiply.outer(c, z)) @ weights).imag / math.pi
        out[~big] = math.log(2.0) + log_lead + np.log(relative + integral * c**1.5 / lead)
    return out


def _log_psi_convolution(mu) -> np.ndarray:
    """log (ψ∗ψ)(μ), (ψ∗ψ)(μ) = ∫ ψ(a) ψ(μ − a) da = 2 I₂(μ) (:func:`_contour_log`): the
    Fourier transform of ψ is 2^{2/3}/Ai(i 2^{1/3} λ), so that of ψ∗ψ is its square."""
    return math.log(2.0) + _contour_log(mu, 2)


def exact_shock_density(a, b) -> np.ndarray:
    """J(a, b): the late-time density, per unit of scaled mass, of clusters whose particles
    came from the scaled labels [ξ − a, ξ + b] and which sit at the scaled position ξ.
    J(a, b) = ¼ (a + b) k(a + b) ψ(a) ψ(b) for a + b > 0, else 0; the cluster's scaled mass is
    μ = a + b and its scaled velocity w = (a − b)/2.

    Scaling.  Label the particles by their mass coordinate m and let Σ_{j<m} v_j = σ B(m)
    (σ² = T₀, B a Brownian motion for any law of finite variance).  The free-streamed partial
    sums are F(m) = m²/(2n) + t σ B(m) + (terms smaller by 1/(n σ t)), and the clusters at time t
    are the segments of the convex minorant of F (module docstring).  With m = ℓ s,
    ℓ = (σ n t)^{2/3} = (n² T₀ t²)^{1/3}, F = σ^{4/3} n^{1/3} t^{4/3} (W(s) + s²/2), W a
    standard two-sided Brownian motion: a cluster is a segment [s₁, s₂] of the convex minorant of
    W(s) + s²/2, its mass is m = ℓ (s₂ − s₁) = ℓ μ, its velocity σ ΔB/Δm = σ^{2/3} (n t)^{−1/3}
    ΔW/Δs, i.e. w = ΔW/Δs, and its position is ℓ/n times the slope ξ of the segment.  So the
    scaled laws below hold for every n, T₀ and initial law of finite variance, at n t ≫ 1.  In
    Burgers' terms: each particle carries its velocity over a spacing 1/n, so the initial
    velocity potential ∫₀^x u₀ = (1/n) Σ_{x_j < x} v_j = (σ/n) B(n x) is a Brownian motion of
    variance T₀/n per unit length (white-noise velocity of strength T₀/n).

    The segment of slope ξ.  H_ξ(s) = W(s) + (s − ξ)²/2 takes its minimum at s₁ = ξ − a and
    s₂ = ξ + b; then W(s₂) − W(s₁) = (a² − b²)/2, so w = (a − b)/2: the cluster's velocity is
    its position minus the centre of its initial labels, over t.  Shifting s and ξ together
    leaves the law of W's increments unchanged, so the clusters form a stationary process in ξ
    and J is a rate per unit ξ, i.e. per unit scaled mass (the slopes advance by as much as the
    labels on average).  Particles: a fraction μ J of the mass sits in such clusters, whence
    ∫∫ (a + b) J(a, b) da db = 1.

    Computing J.  Fix ξ = 0 and follow Z(s) = H₀(s) − h (h the minimum) to the right of a point
    τ where Z = x > 0: dZ = s ds + dW, a Brownian path with the drift s.  Girsanov's theorem
    turns this drift into the potential ∫ X ds of a driftless path X, so the density of Z killed
    at 0 is q(s₀, x; s₁, y) = e^{s₁ y − s₀ x − (s₁³ − s₀³)/6} K(s₁ − s₀; x, y), K the kernel of
    exp(−t(−½ ∂² + x)) on x > 0 with a Dirichlet wall.  Its eigenfunctions are Ai(2^{1/3} x +
    a_k) with eigenvalues −2^{−1/3} a_k, and ∂_x ∂_y K(t; 0, 0) = k(t) =
    2 Σ_k e^{2^{−1/3} a_k t} (``_log_k``).  The probability that Z, started at x at the point
    τ, never returns to 0 is S(τ, x) ≈ φ(τ) x for small x, and ψ(τ) = e^{−τ³/6} φ(τ) has the
    Fourier transform ∫ e^{iλτ} ψ(τ) dτ = 2^{2/3}/Ai(i 2^{1/3} λ) (Laplace transform of the
    backward equation in τ: the solution vanishing at x = 0 whose growth in x is that of
    e^{τx − τ³/6}).  Hence
    ψ(τ) = 2^{1/3} (1/2πi) ∫ e^{−2^{−1/3} τ z}/Ai(z) dz (:func:`_contour_log`), also
    ψ(τ) = 2^{1/3} Σ_k e^{−2^{−1/3} a_k τ}/Ai'(a_k) for τ < 0, and ψ(τ) ≈ 2τ e^{−τ³/6} as
    τ → ∞.  This is Groeneboom's function (1989): his g(t) is 2^{1/3} ψ(2^{2/3} t), and the
    density of argmin H₀ is ½ ψ(s) ψ(−s), Chernoff's law rescaled.

    Now count jumps of the argmin s*(ξ) between ξ = 0 and δ.  Let W start from Lebesgue
    measure (each level h then counts once, and the count is that of W(0) = 0).  The minimum of
    H₀ sits at s₁ = −a (left part: a path from the left that stays above h, entrance factor
    φ(a) after the reflection s → −s), a second dip to within δμ of h sits at s₂ = b (right
    part: φ(b)), and between them runs a bridge of Z killed at 0.  Each touching point
    contributes the flux ½ ∂ of a killed density (as in the joint law of the place and value
    of a Brownian minimum), the bridge contributes ∂_x∂_y q = e^{−(s₂³ − s₁³)/6} k(μ), and the
    dip may lie anywhere in a window of width δμ.  Altogether
    J = ¼ μ k(μ) φ(a) e^{−a³/6} φ(b) e^{−b³/6} = ¼ μ k(μ) ψ(a) ψ(b).
    Checks (tests): ∫∫ μ J = 1, and the jump rate across s = 0, ∫∫_{a,b>0} J = ½ ψ(0)², equals
    the density of argmin H₀ at 0; the engine reproduces the laws.

    ``a`` and ``b`` broadcast; not finite → ``InvalidArgumentError``.  Computed as above: ψ from
    its table (:func:`_log_psi`), k from :func:`_log_k`, in logarithms (no underflow before the
    final exponential).

    Parameters
    ----------
    a, b : array_like of float
        Scaled label distances (broadcast together).

    Returns
    -------
    numpy.ndarray
        J(a, b).

    Raises
    ------
    InvalidArgumentError
        Naming ``a`` or ``b`` when a value is not finite.
    """
    a = _check_finite_array(a, "a")
    b = _check_finite_array(b, "b")
    a, b = np.broadcast_arrays(a, b)
    mu = a + b
    out = np.zeros(mu.shape)
    ok = (mu > 0) & (mu < _MU_MAX + 2.0 * _W_MAX)
    if np.any(ok):
        m = mu[ok]
        out[ok] = 0.25 * m * np.exp(_log_k(m) + _log_psi(a[ok]) + _log_psi(b[ok]))
    return out


def exact_mass_density(mu) -> np.ndarray:
    """F(μ), the late-time cluster-mass law: the number of clusters of mass m per particle is
    n(m, t) ≈ (n² T₀ t²)^{−2/3} F(μ) at μ = m/(n² T₀ t²)^{1/3}, so ∫ μ F(μ) dμ = 1 (the mass
    fraction in clusters of scaled mass μ is μ F(μ)) and ∫ F dμ = :func:`exact_moments`
    ``["clusters"]``.

    F(μ) = ∫ J(a, μ − a) da = ¼ μ k(μ) (ψ∗ψ)(μ) (:func:`exact_shock_density`), with
    (ψ∗ψ)(μ) = 2 (1/2πi) ∫ e^{−2^{−1/3} μ z}/Ai(z)² dz computed on the steepest-descent path
    through the real saddle (:func:`_contour_log`; (ψ∗ψ)(0) = 2 ∫ Chernoff = 2) and k(μ) from
    :func:`_log_k`.  Asymptotes (:func:`exact_asymptotes`): F ≈ μ^{−1/2}/√(2π) as μ → 0 (the
    free Brownian bridge, k ≈ √(2/π) μ^{−3/2}); F ≈ √(π/2) μ^{5/2} exp(−μ³/24 − λ₁ μ) as
    μ → ∞, λ₁ = −2^{−1/3} a₁ = 1.8557… (ψ∗ψ ≈ √(2π) μ^{3/2} e^{−μ³/24} by the saddle at
    a = b = μ/2, and k ≈ 2 e^{−λ₁ μ}).

    Vectorised; F = 0 for μ < 0, +∞ at μ = 0, and 0 (below 1e-1100) for μ > 40.  Relative
    accuracy better than 1e-10 (tests: two node counts of the contour, the residue sum against
    the Hankel contour for k, ψ∗ψ against the convolution of ψ, ∫ μ F = 1 to 1e-11).
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    mu : array_like of float
        Scaled masses μ.

    Returns
    -------
    numpy.ndarray
        F(μ) (0 for μ ≤ 0).

    Raises
    ------
    InvalidArgumentError
        Naming ``mu`` when a value is not finite.
    """
    mu = _check_finite_array(mu, "mu")
    out = np.zeros(mu.shape)
    out[mu == 0.0] = math.inf
    ok = (mu > 0.0) & (mu <= _MU_MAX)
    if np.any(ok):
        m = mu[ok]
        # one exponential of the summed logarithms: k alone overflows below μ ~ 1e-206
        out[ok] = np.exp(np.log(0.25 * m) + _log_k(m) + _log_psi_convolution(m))
    return out


def _log_velocity_density(w, nodes: int = 80) -> np.ndarray:
    """log P(w) for w ≥ 0 (:func:`exact_velocity_density`)."""
    w = np.asarray(w, dtype=float)
    # Where the integrand matters: a scan of its logarithm on a geometric grid of u = √μ.
    scan = np.geomspace(1e-3, 8.0, 96)

    def log_integrand(u, ww):
        m = u * u
        return (math.log(2.0) + np.log(u) + 2.0 * np.log(m) + _log_k(m)
                + _log_psi(0.5 * m + ww) + _log_psi(0.5 * m - ww))

    grid = log_integrand(scan[None, :], w[:, None])
    top = grid.max(axis=1)
    last = np.array([np.flatnonzero(row > t - 50.0)[-1] for row, t in zip(grid, top,
                                                                          strict=True)])
    u_hi = scan[np.minimum(last + 1, scan.size - 1)]
    x, weight = _leggauss(nodes)
    u = 0.5 * u_hi[:, None] * (x[None, :] + 1.0)
    values = log_integrand(u, w[:, None]) - top[:, None]
    total = (np.exp(values) * weight[None, :]).sum(axis=1) * 0.5 * u_hi
    return np.log(0.25 * total) + top


def exact_velocity_density(w, *, nodes: int = 80) -> np.ndarray:
    """P(w), the late-time law of a particle's scaled velocity w = v (n t/T₀)^{1/3} (a particle
    chosen at random, i.e. clusters weighted by their mass, as the engine's per-particle
    velocities count them): P(w) = ∫ μ J(μ/2 + w, μ/2 − w) dμ
    = ¼ ∫₀^∞ μ² k(μ) ψ(μ/2 + w) ψ(μ/2 − w) dμ (:func:`exact_shock_density`).  Even, ∫ P = 1,
    ∫ w² P dw = :func:`exact_moments` ``["velocity_variance"]`` = lim E (n t)^{2/3} T₀^{−2/3}.

    Computed with μ = u² (the integrand is smooth in u: μ² k ~ μ^{1/2} at 0), Gauss–Legendre
    with ``nodes`` nodes on [0, u_max], u_max where the integrand has fallen by e^{−50} from its
    maximum (found on a scan); ψ from its table, k from :func:`_log_k`, all in logarithms.
    Relative accuracy ~1e-11 (tests: 80 against 160 nodes, ∫ P = 1).

    Tail: P(w) ≈ 2^{11/6}/Ai'(a₁) · |w|^{−2} exp(−|w|³/6 − λ₁ |w|) (:func:`exact_asymptotes`):
    the fast particles sit in small clusters (μ ~ 4/w²) far from their labels' centre, so the
    cubic rate 1/6 is that of the Eulerian field (:func:`exact_eulerian_velocity_density`), and
    P(v) ∝ exp(−n t |v|³/(6 T₀)) in the engine's units.  Zero (below 1e-1900) for |w| > 30.
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        P(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not a finite real number, ``nodes`` when it is not an
        integer >= 1.
    """
    w = np.abs(_check_finite_array(w, "w"))
    nodes = check_count(nodes, "nodes", 1)
    out = np.zeros(w.shape)
    ok = w <= _W_MAX
    if np.any(ok):
        out[ok] = np.exp(_log_velocity_density(w[ok], nodes))
    return out


def exact_eulerian_velocity_density(w) -> np.ndarray:
    """P_E(w) = ½ ψ(w) ψ(−w): the late-time law of the Burgers velocity field u(x, t) at a
    fixed point x (not mass-weighted), in w = u (n t/T₀)^{1/3}.

    The field at x is (x − q(x))/t with q(x) the label that the minimising parabola picks,
    so w = ξ − argmin_s (W(s) + (s − ξ)²/2), of density ½ ψ(w) ψ(−w) (the argmin density of
    :func:`exact_shock_density`).  This is also the law of the particles' scaled
    displacements (:func:`~particles.sticky_observables.displacements` / (ℓ/n)): w ≡ 2^{2/3} Z, Z
    of Chernoff's law (:func:`chernoff_density`), variance 2^{4/3} · 0.2635596 = 0.664129.  Tail
    P_E ≈ 2^{1/3}/Ai'(a₁) · |w| exp(−|w|³/6 − λ₁|w|).  ψ from its table; zero for |w| > 30.
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.

    Returns
    -------
    numpy.ndarray
        P_E(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite.
    """
    w = np.abs(_check_finite_array(w, "w"))
    out = np.zeros(w.shape)
    ok = w <= _W_MAX
    if np.any(ok):
        out[ok] = 0.5 * np.exp(_log_psi(w[ok]) + _log_psi(-w[ok]))
    return out


def _log_velocity_survival(w, nodes: int = 60) -> np.ndarray:
    """log P_>(w) for w ≥ 0 (:func:`exact_velocity_survival`), −inf beyond w = 30."""
    out = np.full(w.shape, -math.inf)
    x, weight = _leggauss(int(nodes))
    core = w <= 1.0
    if np.any(core):
        lim = w[core]
        pts = 0.5 * lim[:, None] * (x[None, :] + 1.0)
        dens = exact_velocity_density(pts, nodes=80)
        out[core] = np.log(0.5 - 0.5 * lim * (dens * weight[None, :]).sum(axis=1))
    tail = (w > 1.0) & (w <= _W_MAX)
    if np.any(tail):
        v = w[tail]
        length = np.array([np.roots([1.0 / 6.0, 0.5 * a, 0.5 * a * a, -65.0]) for a in v])
        length = np.max(np.where(np.abs(length.imag) < 1e-9, length.real, 0.0), axis=1)
        pts = v[:, None] + 0.5 * length[:, None] * (x[None, :] + 1.0)
        log_dens = _log_velocity_density(pts.ravel(), 80).reshape(pts.shape)
        top = log_dens[:, 0]
        total = (np.exp(log_dens - top[:, None]) * weight[None, :]).sum(axis=1)
        out[tail] = top + np.log(0.5 * length * total)
    return out


def exact_velocity_survival(w, *, nodes: int = 60) -> np.ndarray:
    """``P_>(w) = ∫_w^∞ P(w') dw'``: the probability that a particle's scaled velocity exceeds w
    (:func:`exact_velocity_density`; P(|w'| > w) = 2 P_>(w) for w ≥ 0, P_>(−w) = 1 − P_>(w)).

    For |w| ≤ 1: ½ ∓ ∫_0^{|w|} P by Gauss–Legendre with ``nodes`` nodes.  For |w| > 1 the tail
    integral ∫_w^{w+L} P with the same rule, L the root of x³/6 + w x²/2 + w² x/2 = 65 (the
    cubic part of −ln P(w + x)/P(w), which bounds it: the rest of the decay only adds), so the
    neglected part is below e^{−65} of the kept one.  Relative accuracy ~1e-10 (tests: 60
    against 120 nodes; the two formulas against each other at w = 1; dP_>/dw = −P).  Not finite →
    ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        P_>(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not a finite real number, ``nodes`` when it is not an
        integer >= 1.
    """
    w = _check_finite_array(w, "w")
    nodes = check_count(nodes, "nodes", 1)
    flat = np.abs(w.ravel())
    out = np.exp(_log_velocity_survival(flat, nodes)).reshape(w.shape)
    return np.where(w < 0, 1.0 - out, out)


def exact_velocity_tail_exponent(w) -> np.ndarray:
    """β(w) = d ln(−ln P(|v| > w)) / d ln w from the exact law: the local exponent that
    :func:`~particles.sticky_observables.velocity_tail_exponent` estimates from a sample (a scale
    change of w leaves it unchanged, so normalising by √E or not does not matter).  With
    S = 2 P_>(w) (two-sided survival, :func:`exact_velocity_survival`) and dS/dw = −2 P(w):
    β = 2 w P(w)/(S (−ln S)).

    β → 3 only as −ln S ≈ w³/6 + λ₁ w + 4 ln w + const, i.e.
    β ≈ (w³/2 + λ₁ w + 4)/(w³/6 + λ₁ w + 4 ln w − ln(2^{17/6}/Ai'(a₁))): the linear Airy
    term λ₁ w and the power prefactor w^{−4} hold β well below 3 over every range a simulation
    can sample (values in the tests and ``benchmarks/sticky_exact.py``).  For w > 0;
    w ≤ 0 or not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities, > 0 and not beyond the range where the survival is representable.

    Returns
    -------
    numpy.ndarray
        β(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite, not positive or too large.
    """
    w = _check_finite_array(w, "w")
    if np.any(w <= 0):
        raise InvalidArgumentError("w", float(w[w <= 0].ravel()[0]), "positive velocities")
    if np.any(w > _W_MAX):
        raise InvalidArgumentError("w", float(w[w > _W_MAX].ravel()[0]),
                                   f"w <= {_W_MAX} (the survival underflows beyond)")
    flat = w.ravel()
    log_s = math.log(2.0) + _log_velocity_survival(flat)
    log_p = _log_velocity_density(flat)
    minus_log_s = -log_s
    small = flat < _W_SMALL  # S = 1 − 2∫₀^w P: −ln S by log1p of the integral, not 1 − S
    if np.any(small):
        x, weights = _leggauss(16)
        u = 0.5 * np.multiply.outer(flat[small], x + 1.0)  # nodes on [0, w], one row per w
        mass = 0.5 * flat[small] * (np.exp(_log_velocity_density(u.ravel())).reshape(u.shape)
                                    @ weights)
        minus_log_s[small] = -np.log1p(-2.0 * mass)
        log_s[small] = np.log1p(-2.0 * mass)
    return (2.0 * flat * np.exp(log_p - log_s) / minus_log_s).reshape(w.shape)


def exact_asymptotes() -> dict[str, float]:
    """The constants of the asymptotic forms of the exact laws (derived in the docstrings of
    :func:`exact_mass_density`, :func:`exact_velocity_density` and
    :func:`exact_eulerian_velocity_density`; a₁ = −2.33811 the first zero of Ai):

    * ``airy_rate`` λ₁ = −2^{−1/3} a₁: k(μ) ≈ 2 e^{−λ₁ μ}, ψ(τ) ≈ (2^{1/3}/Ai'(a₁)) e^{λ₁ τ};
    * ``mass_small`` 1/√(2π): F(μ) ≈ μ^{−1/2}/√(2π) as μ → 0;
    * ``mass_large`` √(π/2) and ``mass_cubic`` 1/24: F ≈ √(π/2) μ^{5/2} e^{−μ³/24 − λ₁ μ};
    * ``velocity_tail`` 2^{11/6}/Ai'(a₁) and ``velocity_cubic`` 1/6:
      P(w) ≈ 2^{11/6}/Ai'(a₁) |w|^{−2} e^{−|w|³/6 − λ₁ |w|} (c = 1/6 in P ∝ e^{−c|w|³});
    * ``eulerian_tail`` 2^{1/3}/Ai'(a₁): P_E(w) ≈ 2^{1/3}/Ai'(a₁) |w| e^{−|w|³/6 − λ₁ |w|}.

    Returns
    -------
    dict of float
    """
    a, aip = _airy_zeros()
    return {
        "airy_rate": float(-_CUBE * a[0]),
        "mass_small": 1.0 / math.sqrt(2.0 * math.pi),
        "mass_large": math.sqrt(0.5 * math.pi),
        "mass_cubic": 1.0 / 24.0,
        "velocity_tail": float(2.0 ** (11.0 / 6.0) / aip[0]),
        "velocity_cubic": 1.0 / 6.0,
        "eulerian_tail": float(2.0 ** (1.0 / 3.0) / aip[0]),
    }


def exact_moments() -> dict[str, float]:
    """Moments of the exact late-time laws, by Gauss–Legendre quadrature of the densities
    (300 nodes on w ∈ [0, 15], and on u = √μ ∈ [0, 6] for the mass law: beyond, the densities
    are below 1e-160), cached:

    * ``velocity_variance`` ∫ w² P(w) dw = lim_{t→∞} E (n t)^{2/3} T₀^{−2/3} (E the energy per
      particle, ⟨v²⟩): 0.44275…;
    * ``eulerian_variance`` ∫ w² P_E(w) dw = 2^{4/3} Var Z (Chernoff) = 0.664129, the limit of
      ⟨D²⟩ (n/T₀)^{2/3} t^{−4/3} for the displacements D;
    * ``clusters`` ∫ F dμ: the number of clusters is ≈ N (n² T₀ t²)^{−1/3} × this (1.32826…);
    * ``mean_mass`` ∫ μ² F dμ: the mean scaled mass of the cluster of a random particle.

    Returns
    -------
    dict of float
    """
    cache = exact_moments.__dict__
    if "value" not in cache:
        x, weight = _leggauss(300)
        w = 7.5 * (x + 1.0)
        p = exact_velocity_density(w) * 7.5 * weight
        pe = exact_eulerian_velocity_density(w) * 7.5 * weight
        u = 3.0 * (x + 1.0)
        f = exact_mass_density(u * u) * 2.0 * u * 3.0 * weight
        cache["value"] = {
            "velocity_variance": float(2.0 * np.sum(w * w * p)),
            "eulerian_variance": float(2.0 * np.sum(w * w * pe)),
            "clusters": float(np.sum(f)),
            "mean_mass": float(np.sum(u**4 * f)),
        }
    return dict(cache["value"])
