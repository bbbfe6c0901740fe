"""The linearisation of the stationary rescaled equation around f̂, and its decay rates.

Around f̂ the linearised operator is

    L u = λ q u' − u + f̂((1 − p) q) u(p q) + f̂(p q) u((1 − p) q).

Near q = 0, L qˢ ≈ g(s) qˢ.  g(4) > 0, so analytic perturbations (q⁴, q⁵, ...) "grow"; they are not
admissible perturbations of a characteristic function with the |q|³ singularity of f̂, and a
Chebyshev discretisation of L in q is meaningless for the decay rates.  :func:`linear_decay_rates`
works instead with the weighted variable u = q^σ w(y), y = ln q, by Chebyshev collocation in y:

    L_σ w = λ w_y + (λσ − 1) w + p^σ f̂((1−p) e^y) w(y + ln p) + (1−p)^σ f̂(p e^y) w(y + ln(1−p)),

for y ∈ [ln q_min, ln q_max], with w = 0 below ln q_min (the perturbation lives on q ≥ q_min) and
at the inflow end ln q_max (transport moves information toward small q).

What the eigenvalues mean.  As y → −∞, L_σ has constant coefficients and maps e^{ity} to
g(σ + it) e^{ity}: on the whole half-line q > 0 with the norm sup |u| / q^σ (the d_σ metric), the
curve {g(σ + it) : t ∈ ℝ} is continuous spectrum and its rightmost point is g(σ) = −γ(σ), the
Bobylev–Cercignani–Toscani rate, which is therefore sharp in d_σ; there is no gap and no isolated
slowest mode.  With a cut-off q_min the weight q^σ is a similarity transformation, so the discrete
eigenvalues do not depend on σ; a perturbation supported on q ≥ q_min lies in every d_s, so it
decays at least at rate γ(s) for every s ∈ (2, 3) (the linear flow preserves positivity, and the
truncated flow, which discards what is carried below q_min, is dominated by the full one).  The
rightmost eigenvalues are real (complex ones, with imaginary parts near 2πkλ/|ln p|, lie further
left; for r = 0 there are exact copies μ + 2πikλ/ln 2 with the same real part, because p = 1 − p)
and tend to −γ*, γ* = max_{2<s<3} γ(s) =
γ(s*), from the side of faster decay, like a Dirichlet problem of log-length ℓ = ln(1/q_min)
around the double root s* of g(s) = −γ*:

    slowest rate ≈ γ* + g''(s*) π² / (2 ℓ²),    the k-th one ≈ γ* + g''(s*) π² k² / (2 ℓ²).

Measured (n = 96..256, σ = s*): r = 0.5, γ* = 0.0129409 at s* = 2.4605 (γ(2.5) = 0.0128607):
slowest rate 0.0141655 (ℓ = 20), 0.0132551 (ℓ = 40), 0.0130203 (ℓ = 80), 0.0129609 (ℓ = 160);
(rate − γ*) is 0.95, 0.98, 0.99, 0.994 of the formula (the effective length is ≈ ℓ + 0.5).
The numbers for other r are in the tests and in the report of :func:`linear_decay_rates`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from particles.validation import InvalidArgumentError, check_count, check_positive

from .chebyshev import barycentric_matrix, chebyshev_nodes, differentiation_matrix
from .exact import f_hat
from .model import MaxwellModel
from .stationary import check_inelastic, collocation_operators

__all__ = [
    "LinearRates",
    "linear_decay_rates",
    "weighted_operator",
    "linearised_operator",
    "GAMMA_EXPONENTS",
]

GAMMA_EXPONENTS = (2.25, 2.5, 2.75)


@dataclass(frozen=True)
class LinearRates:
    """Slowest decay rates of the linearisation around f̂ (see :func:`linear_decay_rates`).

    ``eigenvalues``: the rightmost eigenvalues μ of the discrete operator, by decreasing Re μ.
    ``rates``: the ``count`` smallest distinct decay rates −Re μ (complex pairs and the
    log-periodic copies μ + 2πikλ/ln 2 of r = 0, which share a real part, are counted once).
    ``gamma``: γ(s) for s in :data:`GAMMA_EXPONENTS`; ``s_star``, ``gamma_star``: the maximiser and
    maximum of γ on (2, 3); ``predicted_slowest`` = γ* + g''(s*) π² / (2 ln²(1/q_min)), the
    finite-domain correction of the slowest rate (a Dirichlet problem of log-length ln(1/q_min)
    around the double root s* of g(s) = −γ*).  Rates are per unit τ (collisions per particle).

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1).
    sigma : float
        Weight exponent σ ∈ (2, 3) of u = q^σ w(ln q).
    q_min, q_max : float
        The domain [q_min, q_max] of rescaled wave numbers.
    n : int
        Chebyshev degree in y = ln q.
    eigenvalues : numpy.ndarray
        The 2·count + 4 rightmost eigenvalues μ (complex), by decreasing Re μ.
    rates : tuple of float
        The ``count`` smallest distinct decay rates −Re μ.
    gamma : dict of float to float
        γ(s) for s in ``GAMMA_EXPONENTS``.
    s_star : float
        The maximiser s* of γ on (2, 3).
    gamma_star : float
        γ* = γ(s*).
    predicted_slowest : float
        γ* + g''(s*) π² / (2 ln²(1/q_min)).
    seconds : float
        Wall-clock time of the computation.
    """

    restitution: float
    sigma: float
    q_min: float
    q_max: float
    n: int
    eigenvalues: np.ndarray = field(repr=False)
    rates: tuple[float, ...]
    gamma: dict[float, float]
    s_star: float
    gamma_star: float
    predicted_slowest: float
    seconds: float


def _gamma_star(model: MaxwellModel) -> tuple[float, float, float]:
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(
        model.growth_rate, bounds=(2.0, 3.0), method="bounded", options={"xatol": 1e-12}
    )
    s = float(res.x)
    p, m = model.p, model.complement
    curvature = p**s * math.log(p) ** 2 + (m**s * math.log(m) ** 2 if m > 0 else 0.0)
    return s, -float(res.fun), curvature


def weighted_operator(
    restitution: float, sigma: float, q_min: float, q_max: float, n: int
) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev matrix of L_σ on y = ln q ∈ [ln q_min, ln q_max] (module docstring).

    Returns ``(y, A)``; A acts on w at the nodes y_0..y_{n−1} (w(y_n = ln q_max) = 0 is the
    inflow condition and is removed).  Shifted values w(y + ln c) come from barycentric
    interpolation, and are 0 where y + ln c < ln q_min (no perturbation below q_min).

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1).
    sigma : float
        Weight exponent σ of u = q^σ w(ln q).
    q_min, q_max : float
        The domain of q (0 < q_min < q_max; not checked here).
    n : int
        Chebyshev degree in y (n + 1 nodes before the inflow node is removed).

    Returns
    -------
    y : numpy.ndarray
        Shape (n,): the nodes y_0..y_{n−1}.
    A : numpy.ndarray
        Shape (n, n): the matrix of L_σ on them.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not in [0, 1) (from
        :func:`maxwell_kinetics.stationary.check_inelastic`).
    """
    model = check_inelastic(restitution)
    p, lam = model.p, model.lam
    a, b = math.log(q_min), math.log(q_max)
    y = a + chebyshev_nodes(n, b - a)
    A = lam * differentiation_matrix(y) + (lam * sigma - 1.0) * np.eye(n + 1)
    for c, other in ((p, model.complement), (model.complement, p)):
        if c == 0.0:
            continue
        t = y + math.log(c)
        S = barycentric_matrix(y, np.clip(t, a, b))
        S[t < a] = 0.0
        A += c**sigma * f_hat(other * np.exp(y))[:, None] * S
    return y[:-1], A[:-1, :-1]


#: Dense (n + 1)² matrices held at once by the collocation and the eigenvalue solver.
_MATRICES = 12


def _check_degree(n, minimum: int) -> int:
    """A Chebyshev degree >= ``minimum`` whose dense matrices fit in the memory available (an
    absurd n was a MemoryError, or the process killed, instead of an error naming ``n``)."""
    from particles.budget import available_memory, format_bytes

    n = check_count(n, "n", minimum)
    need = _MATRICES * 8.0 * (n + 1) ** 2
    available = available_memory()
    if not need <= available:
        raise InvalidArgumentError("n", n, f"a degree whose dense matrices fit in the "
                                   f"{format_bytes(available)} available (estimate "
                                   f"{format_bytes(need)})")
    return n


def linearised_operator(restitution: float, n: int = 64, q_max: float = 40.0):
    """Chebyshev matrix of L in q on [0, q_max]: ``(q, L)``, for checks of exact identities.

    L(q f̂') = 0 (scale invariance) and L(q f̂) = λ q f̂ (a velocity shift: the rescaled mean
    grows like e^{λτ}) hold exactly.  Do not read decay rates from its eigenvalues: on
    polynomials the spectrum of L is not that of admissible perturbations (module docstring);
    measured, with u(0) = u''(0) = u(q_max) = 0 imposed and r = 0.5, its leading eigenvalue
    after the shift mode λ drifts with n (−0.085, −0.053, −0.041 at n = 32, 48, 64).

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1).
    n : int, default 64
        Chebyshev degree (≥ 8).
    q_max : float, default 40.0
        End Q of the interval [0, Q] (> 0).

    Returns
    -------
    q : numpy.ndarray
        Shape (n + 1,): Chebyshev–Lobatto nodes on [0, Q].
    L : numpy.ndarray
        Shape (n + 1, n + 1): the collocation matrix of L (no boundary conditions imposed).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not in [0, 1), ``n`` is not a count ≥ 8 whose dense matrices fit
        in the memory available, or ``q_max`` is not positive.
    """
    model = check_inelastic(restitution)
    q, D, Bp, Bm = collocation_operators(model, _check_degree(n, 8),
                                         check_positive(q_max, "q_max"))
    p = model.p
    L = (model.lam * q[:, None] * D - np.eye(len(q)) + f_hat(model.complement * q)[:, None] * Bp
         + f_hat(p * q)[:, None] * Bm)
    return q, L


def linear_decay_rates(
    restitution: float,
    *,
    sigma: float | None = None,
    q_min: float = math.exp(-80.0),
    q_max: float = 40.0,
    n: int = 160,
    count: int = 3,
) -> LinearRates:
    """Slowest decay rates of L u = λ q u' − u + f̂((1−p)q) u(pq) + f̂(pq) u((1−p)q).

    The perturbation is written u = q^σ w(ln q) on q ∈ [q_min, q_max] (zero below q_min and at
    the inflow end q_max), discretised by Chebyshev collocation of degree ``n`` in y = ln q, and
    all eigenvalues are computed densely.  u(0) = u''(0) = 0 hold by construction (u = O(q^σ),
    σ > 2).  On this truncated domain the weight is a similarity transformation, so the
    eigenvalues do not depend on σ in exact arithmetic; they converge to −γ* (γ* =
    max_{2<s<3} γ(s)) as q_min → 0, from the side of faster decay: see :class:`LinearRates` and
    the module docstring.  ``sigma`` defaults to s*: the slow eigenfunctions behave like q^{s*},
    so w is O(1) across the whole log grid.  A weight far from s* makes w vary by e^{|σ−s*| ℓ}
    (ℓ = ln(1/q_min)) and round-off then moves the computed eigenvalues (σ = 2.75 with
    ln q_min = −80 gives wrong rates, below γ*, that change with n).

    γ(s) is the Bobylev–Cercignani–Toscani contraction rate of the d_s metric (Bobylev,
    Cercignani & Toscani, J. Stat. Phys. 2003); eigenvalues by :func:`scipy.linalg.eigvals`.

    Parameters
    ----------
    restitution : float or particles.kernels.Kernel
        r ∈ [0, 1), or the Maxwell kernel of r (:func:`maxwell_kinetics.model.maxwell_restitution`).
    sigma : float, optional
        Weight exponent in (2, 3); None for s*.
    q_min : float, default e^{−80}
        Lower end of the domain, 0 < q_min < min(1, q_max).
    q_max : float, default 40.0
        Upper (inflow) end of the domain (> 0).
    n : int, default 160
        Chebyshev degree in y = ln q (≥ 16).
    count : int, default 3
        Number of distinct slowest rates to report (≥ 1).

    Returns
    -------
    LinearRates
        The rightmost eigenvalues, the slowest rates and the reference values γ(s), s*, γ* and
        the predicted slowest rate.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``sigma`` if it is not in (2, 3), ``q_min`` if it is not in (0, min(1, q_max)),
        and for a restitution not in [0, 1) or a non-positive ``q_max``, ``n`` out of range
        (or too large for the memory available) or ``count`` not in [1, n + 1].
    """
    t0 = time.perf_counter()
    model = check_inelastic(restitution)
    s_star, g_star, curvature = _gamma_star(model)
    sigma = s_star if sigma is None else check_positive(sigma, "sigma")
    if not 2.0 < sigma < 3.0:
        raise InvalidArgumentError("sigma", sigma, "a weight exponent in (2, 3)")
    q_min = check_positive(q_min, "q_min")
    q_max = check_positive(q_max, "q_max")
    if not q_min < min(1.0, q_max):
        raise InvalidArgumentError("q_min", q_min, f"0 < q_min < min(1, q_max={q_max})")
    n = _check_degree(n, 16)
    count = check_count(count, "count", 1)
    if count > n + 1:
        raise InvalidArgumentError("count", count, f"at most n + 1 = {n + 1} rates (the "
                                   "operator has n + 1 eigenvalues)")

    from scipy.linalg import eigvals

    _, A = weighted_operator(model.restitution, sigma, q_min, q_max, n)
    mu = eigvals(A)
    mu = mu[np.argsort(-mu.real, kind="stable")]
    rates: list[float] = []
    for value in -mu.real:
        # Same rate within 1e-4: a conjugate pair, or (r = 0) a log-periodic copy.  Distinct
        # rates differ by ≥ g''(s*) π²/(2ℓ²) ≈ 0.5 % of γ* even at ℓ = ln(1/q_min) = 160.
        if not rates or value - rates[-1] > 1e-4 * abs(value):
            rates.append(float(value))
        if len(rates) == count:
            break
    ell = math.log(1.0 / q_min)
    return LinearRates(
        restitution=model.restitution,
        sigma=sigma,
        q_min=q_min,
        q_max=q_max,
        n=n,
        eigenvalues=mu[: 2 * count + 4],
        rates=tuple(rates),
        gamma={s: model.contraction_rate(s) for s in GAMMA_EXPONENTS},
        s_star=s_star,
        gamma_star=g_star,
        predicted_slowest=g_star + curvature * math.pi**2 / (2.0 * ell**2),
        seconds=time.perf_counter() - t0,
    )
