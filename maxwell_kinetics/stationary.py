"""The stationary rescaled equation, solved directly, and its linearisation around f̂.

Fixed point
-----------
The rescaled characteristic function G(q) of SPEC §2 is stationary when, for q ≥ 0,

    R[G](q) = λ q G'(q) − G(q) + G(p q) G((1 − p) q) = 0,     G(0) = 1,  G''(0) = −1.

The exact solution is f̂(q) = (1 + q) e^{−q} for every r < 1.  :func:`fixed_point` does not use
it: it solves R[G] = 0 by a Gauss–Newton iteration from a generic start (e^{−q²/2} by default).

*Discretisation.*  G is a polynomial of degree N on [0, Q] given by its values at the
Chebyshev–Lobatto points q_j = Q (1 − cos(jπ/N)) / 2, j = 0..N.  G' comes from the Chebyshev
differentiation matrix and G(p q_j), G((1 − p) q_j) from barycentric interpolation (both
arguments lie in [0, Q], so the interpolant is never extrapolated).  f̂ is entire, so the error
falls spectrally with N (Q = 40: f̂(40) ≈ 1.7e-16).

*Why three conditions.*  Expanding G = Σ c_n qⁿ gives g(n) c_n = −Σ_{0<m<n} c_m c_{n−m} pᵐ(1−p)ⁿ⁻ᵐ
with g(s) = λs − 1 + pˢ + (1−p)ˢ.  Since g(2) = g(3) = 0, both c_2 and c_3 are free: near q = 0
the stationary equation has a two-parameter family of solutions.  c_2 = −1/2 (G''(0) = −1) fixes
the scale invariance G(q) → G(cq).  c_3 is fixed only globally: every c_3 ≠ 1/3 gives a solution
that grows like q^{1/λ} at large q (where G ≈ 0 and λ q G' ≈ G).  The collocation therefore also
imposes G(Q) = 0 (the truncation error of this condition is f̂(Q)).  With R = 0 at all N + 1
nodes and the three conditions the system is overdetermined by two rows; it is solved in the
least-squares sense (each Gauss–Newton step is a ``lstsq`` on the Jacobian, computed with
``jax.jacfwd``), and the residual left at the solution measures the discretisation error.

At r = 1 the problem degenerates (λ = 0, p = 1: R[G] = G(q)(G(0) − 1) vanishes for every G with
G(0) = 1), so r = 1 is rejected.  As r → 1 the Jacobian approaches that degenerate operator: near
q = 0 it behaves like −(1 − p)² q ∂_q, so its condition number grows like (1 − r)^{−2}; r = 0.99
still converges (see the tests).

Linearised decay rates
----------------------
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
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import jax
import jax.numpy as jnp
import numpy as np

from particles.validation import InvalidArgumentError, check_count, check_positive

from .exact import f_hat
from .model import MaxwellModel

__all__ = [
    "FixedPoint",
    "fixed_point",
    "chebyshev_nodes",
    "barycentric_matrix",
    "stationary_residual",
    "LinearRates",
    "linear_decay_rates",
    "weighted_operator",
    "linearised_operator",
    "GAMMA_EXPONENTS",
]

GAMMA_EXPONENTS = (2.25, 2.5, 2.75)


def _check_restitution_below_one(restitution) -> MaxwellModel:
    model = MaxwellModel(restitution)  # checks finite and in [0, 1]
    if model.restitution >= 1.0:
        raise InvalidArgumentError(
            "restitution",
            restitution,
            "a number in [0, 1): at r = 1 (elastic) λ = 0 and every G with G(0) = 1 is "
            "stationary, so the fixed-point problem has no unique solution",
        )
    return model


# --------------------------------------------------------------------------------------------
# Chebyshev machinery (NumPy)
# --------------------------------------------------------------------------------------------


def chebyshev_nodes(n: int, length: float) -> np.ndarray:
    """Chebyshev–Lobatto points q_j = Q (1 − cos(jπ/n)) / 2, j = 0..n, increasing from 0 to Q."""
    j = np.arange(n + 1)
    q = 0.5 * length * (1.0 - np.cos(np.pi * j / n))
    q[0], q[-1] = 0.0, float(length)
    return q


def _barycentric_weights(n: int) -> np.ndarray:
    w = (-1.0) ** np.arange(n + 1)
    w[0] *= 0.5
    w[-1] *= 0.5
    return w


def barycentric_matrix(nodes: np.ndarray, targets) -> np.ndarray:
    """Matrix B with (B @ values)[i] = interpolant through (nodes, values) at targets[i].

    ``nodes`` are Chebyshev–Lobatto points (any affine image); the barycentric formula of the
    second kind is used, and a target that coincides with a node copies that node's value.
    """
    nodes = np.asarray(nodes, dtype=float)
    targets = np.atleast_1d(np.asarray(targets, dtype=float))
    w = _barycentric_weights(len(nodes) - 1)
    diff = targets[:, None] - nodes[None, :]
    exact = diff == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        c = w[None, :] / diff
        B = c / c.sum(axis=1, keepdims=True)
    rows = exact.any(axis=1)
    B[rows] = exact[rows].astype(float)
    return B


def _differentiation_matrix(nodes: np.ndarray) -> np.ndarray:
    """Chebyshev differentiation matrix on the given Lobatto nodes (negative-sum trick)."""
    n = len(nodes) - 1
    w = _barycentric_weights(n)
    dx = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(dx, 1.0)
    D = (w[None, :] / w[:, None]) / dx
    np.fill_diagonal(D, 0.0)
    np.fill_diagonal(D, -D.sum(axis=1))
    return D


# --------------------------------------------------------------------------------------------
# Fixed point
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FixedPoint:
    """A solution of the stationary rescaled equation on the Chebyshev grid of [0, Q].

    ``q`` and ``G`` are the nodes and values; ``residual`` is max_j |R[G](q_j)| at the nodes,
    ``check_residual`` the same on a fine off-node grid (through the interpolant);
    ``max_error`` is max |G − f̂| over the nodes and a fine grid of [0, Q] (NaN for
    ``dimension`` ≥ 2, where f̂ is not the scaling solution); ``iterations`` counts
    Gauss–Newton steps.  Call the object (or :meth:`evaluate`) for G at any real q: G is even,
    and G(|q| > Q) = 0 (the truncation error is f̂(Q) in d = 1).  ``dimension``, ``angular``
    and ``angular_nodes`` name the model (:func:`fixed_point`).
    """

    restitution: float
    q: np.ndarray = field(repr=False)
    G: np.ndarray = field(repr=False)
    residual: float
    check_residual: float
    iterations: int
    max_error: float
    converged: bool
    seconds: float
    dimension: int = 1
    angular: str = "uniform"
    angular_nodes: int = 1

    @property
    def n(self) -> int:
        return len(self.q) - 1

    @property
    def q_max(self) -> float:
        return float(self.q[-1])

    def evaluate(self, q) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        a = np.abs(q).ravel()
        out = np.zeros_like(a)
        inside = a <= self.q_max
        if np.any(inside):
            out[inside] = barycentric_matrix(self.q, a[inside]) @ self.G
        return out.reshape(q.shape)

    def __call__(self, q) -> np.ndarray:
        return self.evaluate(q)


def _isotropic_fixed_point(model, eta, weights, n, length, initial, tol, max_iterations):
    """The collocation of :func:`fixed_point` for the η-averaged gain (d ≥ 2), in NumPy:
    R(G) = (Λ/2) q D G − G + Σ_i ω_i (A_i G) ∘ (B_i G) with A_i, B_i the barycentric
    interpolation matrices to a_i q and b_i q (both in [0, Q]), Jacobian
    (Λ/2) q D − I + Σ_i ω_i [diag(B_i G) A_i + diag(A_i G) B_i], the three condition rows as
    in d = 1, and the same damped Gauss–Newton.  ``max_error`` is NaN (no closed form)."""
    p = model.p
    eta = np.asarray(eta, dtype=float)
    weights = np.asarray(weights, dtype=float)
    half_rate = p * (1.0 - p) * float(weights @ eta)  # Λ/2 with the quadrature's own ⟨η⟩
    q = chebyshev_nodes(n, length)
    D = _differentiation_matrix(q)
    A = np.stack([barycentric_matrix(q, np.sqrt(1.0 - (1.0 - (1.0 - p) ** 2) * e) * q)
                  for e in eta])
    B = np.stack([barycentric_matrix(q, p * np.sqrt(e) * q) for e in eta])
    transport = half_rate * q[:, None] * D
    D2_row0 = (D @ D)[0]
    w2 = 1.0 / float(np.max(np.abs(D2_row0)))
    conditions = np.zeros((3, n + 1))
    conditions[0, 0], conditions[1], conditions[2, -1] = 1.0, w2 * D2_row0, 1.0

    def residual(G):
        gain = np.einsum("i,ij,ij->j", weights, A @ G, B @ G)
        return np.concatenate([transport @ G - G + gain,
                               [G[0] - 1.0, w2 * (D2_row0 @ G + 1.0), G[-1]]])

    def jacobian(G):
        AG, BG = A @ G, B @ G
        J = (transport - np.eye(n + 1) + np.einsum("i,ij,ijk->jk", weights, BG, A)
             + np.einsum("i,ij,ijk->jk", weights, AG, B))
        return np.vstack([J, conditions])

    G = _start_values(initial, q)
    G, iterations, converged = _gauss_newton(G, residual, jacobian, tol, max_iterations)
    fp = FixedPoint(restitution=model.restitution, q=q, G=G,
                    residual=float(np.max(np.abs(residual(G)[: n + 1]))), check_residual=0.0,
                    iterations=iterations, max_error=math.nan, converged=converged,
                    seconds=0.0)
    fine = np.linspace(0.0, length, 4001)
    dG = barycentric_matrix(q, fine) @ (D @ G)
    gain = sum(w * fp(np.sqrt(1.0 - (1.0 - (1.0 - p) ** 2) * e) * fine) * fp(p * np.sqrt(e) * fine)
               for e, w in zip(eta, weights, strict=True))
    check = half_rate * fine * dG - fp(fine) + gain
    return replace(fp, check_residual=float(np.max(np.abs(check))))


def _start_values(initial, q) -> np.ndarray:
    """G at the nodes ``q`` from the callable ``initial`` (None: e^{−q²/2}), checked."""
    start = initial if initial is not None else (lambda x: np.exp(-0.5 * x * x))
    G = np.asarray(start(q), dtype=float)
    if G.shape != q.shape or not np.all(np.isfinite(G)):
        raise InvalidArgumentError(
            "initial", initial, "a callable giving finite values on the grid"
        )
    return G


def _gauss_newton(G, res_fn, jac_fn, tol, max_iterations):
    """Damped Gauss–Newton (least-squares steps, backtracking on the residual norm) from G:
    returns (G, iterations, converged); see :func:`fixed_point` for the stopping rule."""
    converged = False
    iterations = 0
    norm = float(np.linalg.norm(res_fn(G)))
    previous = math.inf
    for iterations in range(1, max_iterations + 1):  # noqa: B007 - reported after the loop
        J = np.asarray(jac_fn(G))
        r = np.asarray(res_fn(G))
        step = np.linalg.lstsq(J, -r, rcond=None)[0]
        # Backtracking on the residual norm: full steps near the solution, damped far from it.
        t = 1.0
        while True:
            trial = G + t * step
            trial_norm = float(np.linalg.norm(res_fn(trial)))
            if trial_norm <= norm or t < 1e-4:
                break
            t *= 0.5
        G, norm = trial, trial_norm
        size = float(np.max(np.abs(t * step)))
        # Converged when the step is below tol, or when Newton has stalled at round-off: the
        # step no longer shrinks although it is already tiny (the floor grows like n² Q).
        if size < tol or (size < 1e3 * tol and size > 0.5 * previous):
            converged = True
            break
        previous = size
    return G, iterations, converged


def stationary_residual(G: Callable, restitution: float, q) -> np.ndarray:
    """R[G](q) = λ q G'(q) − G(q) + G(pq) G((1−p)q) for a callable G and its derivative.

    ``G`` must accept ``(q, derivative)`` with derivative ∈ {0, 1}; used to check f̂ exactly.
    """
    m = MaxwellModel(restitution)
    q = np.asarray(q, dtype=float)
    return m.lam * q * G(q, 1) - G(q, 0) + G(m.p * q, 0) * G((1.0 - m.p) * q, 0)


def _operators(model: MaxwellModel, n: int, length: float):
    q = chebyshev_nodes(n, length)
    D = _differentiation_matrix(q)
    Bp = barycentric_matrix(q, model.p * q)
    Bm = barycentric_matrix(q, (1.0 - model.p) * q)
    return q, D, Bp, Bm


def _collocation_residual(G, qD, Bp, Bm, D2_row0, w2):
    """The n + 1 collocation equations and the three conditions (see :func:`fixed_point`).

    Module level and jitted with the operators as data: one compilation per n, whatever r.
    """
    eq = qD @ G - G + (Bp @ G) * (Bm @ G)
    cons = jnp.stack([G[0] - 1.0, w2 * (D2_row0 @ G + 1.0), G[-1]])
    return jnp.concatenate([eq, cons])


_residual = jax.jit(_collocation_residual)
_jacobian = jax.jit(jax.jacfwd(_collocation_residual))


def fixed_point(
    restitution: float,
    n: int | None = None,
    q_max: float = 40.0,
    *,
    initial: Callable | None = None,
    tol: float = 1e-13,
    max_iterations: int = 50,
    dimension: int = 1,
    angular: str = "uniform",
    angular_nodes: int = 16,
) -> FixedPoint:
    """Solve λ q G' − G + G(pq) G((1−p)q) = 0 with G(0) = 1, G''(0) = −1, G(q_max) = 0.

    Chebyshev collocation of degree ``n`` on [0, q_max] and damped Gauss–Newton from
    ``initial`` (a NumPy callable of q; default e^{−q²/2}), stopped when the Newton step is
    below ``tol`` in max norm.  See the module docstring for the discretisation and for why
    three conditions are imposed.  r = 1 is rejected (degenerate).  ``n`` defaults to 64 in
    d = 1 and 128 in d ≥ 2.

    ``dimension`` 2 or 3 solves the stationary form of the isotropic equation of
    :func:`maxwell_kinetics.solver.solve` (``angular`` model; the η integral is the solver's own
    quadrature with ``angular_nodes`` nodes, :meth:`maxwell_kinetics.model.AngularLaw.quadrature`):

        (Λ/2) q G' − G + Σ_i ω_i G(a_i q) G(b_i q) = 0,   a_i = √(1 − (1 − (1−p)²) η_i),
        b_i = p √η_i,   Λ/2 = p (1 − p) Σ_i ω_i η_i,

    G(q) the radial profile of the rescaled characteristic function (unit variance per
    component), with the same three conditions: the non-analytic A q^{2s*} term of the scaling
    solution plays the part of 1D's c₃ q³ (a free amplitude near q = 0 that only the decay at
    large q fixes).  The Jacobian is assembled in NumPy (:func:`_isotropic_fixed_point`; with
    the single node η = 1 it is the 1D problem, and gives the same G as the JAX path to
    round-off, tested).  That term makes the Chebyshev convergence algebraic, not spectral:
    measured (Q = 40, 16 nodes) max |G_n − G_128| = 1.6e-5, 1.7e-7, 2.7e-9 for n = 48, 64, 96
    at r = 0.5, d = 2 (s* large), and 1.2e-3, 3.2e-4, 3.8e-5 at r = 0, d = 2 (2s* = 4.29);
    against the time-dependent solve on the coarse grid at τ = 800: 3.0e-8 (d = 2, r = 0.5),
    1.9e-8 (d = 3 hard, r = 0.5), 1.4e-5 (d = 2, r = 0).
    """
    t0 = time.perf_counter()
    model = _check_restitution_below_one(restitution)
    from .model import angular_law

    angular_law(dimension, angular)  # checks both
    if dimension != 1:
        angular_nodes = check_count(angular_nodes, "angular_nodes", 1)
        n = 128 if n is None else n
    n = check_count(64 if n is None else n, "n", 8)
    length = check_positive(q_max, "q_max")
    tol = check_positive(tol, "tol")
    max_iterations = check_count(max_iterations, "max_iterations", 1)
    if dimension != 1:
        eta, weights = angular_law(dimension, angular).quadrature(angular_nodes)
        fp = _isotropic_fixed_point(model, eta, weights, n, length, initial, tol, max_iterations)
        return replace(fp, dimension=dimension, angular=angular, angular_nodes=angular_nodes,
                       seconds=time.perf_counter() - t0)

    q, D, Bp, Bm = _operators(model, n, length)
    D2_row0 = (D @ D)[0]
    lam = model.lam
    # Constraint rows are weighted like a typical collocation row: G''(0) is O(n⁴/Q²) times a
    # value, so it is divided by that scale to keep the least-squares problem balanced.
    w2 = 1.0 / float(np.max(np.abs(D2_row0)))
    # float64 for this computation only (jax.enable_x64 is thread-local and restores the
    # caller's setting): importing this module leaves JAX's global configuration alone.
    with jax.enable_x64(True):
        operators = tuple(jnp.asarray(a) for a in (lam * q[:, None] * D, Bp, Bm, D2_row0, w2))

        def res_fn(G):
            with jax.enable_x64(True):
                return np.asarray(_residual(jnp.asarray(G), *operators))

        def jac_fn(G):
            with jax.enable_x64(True):
                return np.asarray(_jacobian(jnp.asarray(G), *operators))

    G = _start_values(initial, q)

    G, iterations, converged = _gauss_newton(G, res_fn, jac_fn, tol, max_iterations)
    eq = np.asarray(res_fn(G))[: n + 1]
    fp = FixedPoint(
        restitution=model.restitution,
        q=q,
        G=G,
        residual=float(np.max(np.abs(eq))),
        check_residual=0.0,
        iterations=iterations,
        max_error=0.0,
        converged=converged,
        seconds=0.0,
    )
    fine = np.linspace(0.0, length, 4001)
    dG = barycentric_matrix(q, fine) @ (D @ G)
    check = lam * fine * dG - fp(fine) + fp(model.p * fine) * fp((1.0 - model.p) * fine)
    err = max(float(np.max(np.abs(G - f_hat(q)))), float(np.max(np.abs(fp(fine) - f_hat(fine)))))
    return replace(
        fp,
        check_residual=float(np.max(np.abs(check))),
        max_error=err,
        seconds=time.perf_counter() - t0,
    )


# --------------------------------------------------------------------------------------------
# Linearised decay rates
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class LinearRates:
    """Slowest decay rates of the linearisation around f̂ (see :func:`linear_decay_rates`).

    ``eigenvalues``: the rightmost eigenvalues μ of the discrete operator, by decreasing Re μ.
    ``rates``: the ``count`` smallest distinct decay rates −Re μ (complex pairs and the
    log-periodic copies μ + 2πikλ/ln 2 of r = 0, which share a real part, are counted once).
    ``gamma``: γ(s) for s in :data:`GAMMA_EXPONENTS`; ``s_star``, ``gamma_star``: the maximiser and
    maximum of γ on (2, 3); ``predicted_slowest`` = γ* + g''(s*) π² / (2 ln²(1/q_min)), the
    finite-domain correction of the slowest rate (a Dirichlet problem of log-length ln(1/q_min)
    around the double root s* of g(s) = −γ*).
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
    p, m = model.p, 1.0 - model.p
    curvature = p**s * math.log(p) ** 2 + (m**s * math.log(m) ** 2 if m > 0 else 0.0)
    return s, -float(res.fun), curvature


def weighted_operator(
    restitution: float, sigma: float, q_min: float, q_max: float, n: int
) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev matrix of L_σ on y = ln q ∈ [ln q_min, ln q_max] (module docstring).

    Returns ``(y, A)``; A acts on w at the nodes y_0..y_{n−1} (w(y_n = ln q_max) = 0 is the
    inflow condition and is removed).  Shifted values w(y + ln c) come from barycentric
    interpolation, and are 0 where y + ln c < ln q_min (no perturbation below q_min).
    """
    model = _check_restitution_below_one(restitution)
    p, lam = model.p, model.lam
    a, b = math.log(q_min), math.log(q_max)
    y = a + chebyshev_nodes(n, b - a)
    A = lam * _differentiation_matrix(y) + (lam * sigma - 1.0) * np.eye(n + 1)
    for c, other in ((p, 1.0 - p), (1.0 - p, p)):
        if c == 0.0:
            continue
        t = y + math.log(c)
        S = barycentric_matrix(y, np.clip(t, a, b))
        S[t < a] = 0.0
        A += c**sigma * f_hat(other * np.exp(y))[:, None] * S
    return y[:-1], A[:-1, :-1]


def linearised_operator(restitution: float, n: int = 64, q_max: float = 40.0):
    """Chebyshev matrix of L in q on [0, q_max]: ``(q, L)``, for checks of exact identities.

    L(q f̂') = 0 (scale invariance) and L(q f̂) = λ q f̂ (a velocity shift: the rescaled mean
    grows like e^{λτ}) hold exactly.  Do not read decay rates from its eigenvalues: on
    polynomials the spectrum of L is not that of admissible perturbations (module docstring);
    measured, with u(0) = u''(0) = u(q_max) = 0 imposed and r = 0.5, its leading eigenvalue
    after the shift mode λ drifts with n (−0.085, −0.053, −0.041 at n = 32, 48, 64).
    """
    model = _check_restitution_below_one(restitution)
    q, D, Bp, Bm = _operators(model, check_count(n, "n", 8), check_positive(q_max, "q_max"))
    p = model.p
    L = (model.lam * q[:, None] * D - np.eye(len(q)) + f_hat((1.0 - p) * q)[:, None] * Bp
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
    (ℓ = ln(1/q_min)) and round-off then moves the computed eigenvalues (measured: σ = 2.75,
    ln q_min = −80 gives wrong rates, below γ*, that change with n).
    """
    t0 = time.perf_counter()
    model = _check_restitution_below_one(restitution)
    s_star, g_star, curvature = _gamma_star(model)
    sigma = s_star if sigma is None else check_positive(sigma, "sigma")
    if not 2.0 < sigma < 3.0:
        raise InvalidArgumentError("sigma", sigma, "a weight exponent in (2, 3)")
    q_min = check_positive(q_min, "q_min")
    q_max = check_positive(q_max, "q_max")
    if not q_min < min(1.0, q_max):
        raise InvalidArgumentError("q_min", q_min, f"0 < q_min < min(1, q_max={q_max})")
    n = check_count(n, "n", 16)
    count = check_count(count, "count", 1)

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
