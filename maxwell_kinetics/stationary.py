"""The stationary rescaled equation, solved directly (its linearisation around f̂ is in
:mod:`maxwell_kinetics.linear_rates`).

Fixed point
-----------
The rescaled characteristic function G(q) (the solver's variable: the characteristic function
of the velocity in units of its thermal scale, :mod:`maxwell_kinetics.solver`) is stationary
when, for q ≥ 0,

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
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import jax
import jax.numpy as jnp
import numpy as np

from particles.validation import InvalidArgumentError, check_bool, check_count, check_positive

from .chebyshev import barycentric_matrix, chebyshev_nodes, differentiation_matrix
from .exact import f_hat
from .model import MaxwellModel, maxwell_restitution

__all__ = [
    "MAX_DEGREE_1D",
    "FixedPoint",
    "fixed_point",
    "stationary_residual",
    "isotropic_fixed_point",
    "check_inelastic",
    "collocation_operators",
]


#: Largest Chebyshev degree of the 1D collocation.  Its conditioning worsens with N (the G''(0)
#: row grows like N⁴): measured max |G − f̂| at N = 256 is <= 2e-9 for r <= 0.99, 5e-7 at
#: r = 0.995 and 1.5e-6 at r = 0.999; beyond, Gauss–Newton meets a wrong function with a small
#: residual (max error 9.6e-4 at N = 448 and r = 0.99, 2.6e-3 at N = 600 and r = 0, 0.22 at
#: N = 700 and r = 0.5), so a larger N is refused.
MAX_DEGREE_1D = 256
#: A 1D fixed point counts as converged only with a residual below this times λ (see
#: :func:`fixed_point`).
RESIDUAL_PER_LAMBDA = 1e-8


def check_inelastic(restitution) -> MaxwellModel:
    """The :class:`~maxwell_kinetics.model.MaxwellModel` of an inelastic restitution r < 1.

    At r = 1 the stationary problem is degenerate (module docstring), so it is refused.

    Parameters
    ----------
    restitution : float or particles.kernels.Kernel
        r ∈ [0, 1), or the Maxwell kernel of r (:func:`maxwell_kinetics.model.maxwell_restitution`).

    Returns
    -------
    maxwell_kinetics.model.MaxwellModel
        The model of r.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``restitution``, if it is not a finite number in [0, 1) (r = 1 included);
        ``kernel`` for a kernel whose Fourier-space equation does not close.
    """
    restitution = maxwell_restitution(restitution)
    model = MaxwellModel(restitution)  # checks finite and in [0, 1]
    if model.restitution >= 1.0:
        raise InvalidArgumentError(
            "restitution",
            restitution,
            "a number in [0, 1): at r = 1 (elastic) λ = 0 and every G with G(0) = 1 is "
            "stationary, so the fixed-point problem has no unique solution",
        )
    return model


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

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1).
    q : numpy.ndarray
        The N + 1 Chebyshev–Lobatto nodes on [0, Q] (rescaled wave numbers q = k·v0).
    G : numpy.ndarray
        G at the nodes.
    residual : float
        max_j |R[G](q_j)| over the nodes.
    check_residual : float
        max |R[G]| on 4001 equispaced points of [0, Q], through the interpolant.
    iterations : int
        Number of Gauss–Newton steps taken.
    max_error : float
        max |G − f̂| over the nodes and the fine grid (NaN in d ≥ 2).
    converged : bool
        Whether the stopping rule was met within ``max_iterations``.
    seconds : float
        Wall-clock time of the solve.
    dimension : int, default 1
        Space dimension d.
    angular : str, default "uniform"
        Angular model (d ≥ 2).
    angular_nodes : int, default 1
        Number of η quadrature nodes (d ≥ 2).
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
        """The polynomial degree N (N + 1 nodes)."""
        return len(self.q) - 1

    @property
    def q_max(self) -> float:
        """Q, the last node."""
        return float(self.q[-1])

    def evaluate(self, q) -> np.ndarray:
        """G at real q, by barycentric interpolation of the node values.

        G is taken even (G(−q) = G(q)) and zero for |q| > Q.

        Parameters
        ----------
        q : array_like
            Real rescaled wave numbers (any shape).

        Returns
        -------
        numpy.ndarray
            G(q), float, of the shape of ``q``.
        """
        q = np.asarray(q, dtype=float)
        a = np.abs(q).ravel()
        out = np.zeros_like(a)
        inside = a <= self.q_max
        if np.any(inside):
            out[inside] = barycentric_matrix(self.q, a[inside]) @ self.G
        return out.reshape(q.shape)

    def __call__(self, q) -> np.ndarray:
        return self.evaluate(q)


def isotropic_fixed_point(model, eta, weights, n, length, initial, tol, max_iterations):
    """The collocation of :func:`fixed_point` for the η-averaged gain (d ≥ 2), in NumPy:
    R(G) = (Λ/2) q D G − G + Σ_i ω_i (A_i G) ∘ (B_i G) with A_i, B_i the barycentric
    interpolation matrices to a_i q and b_i q (both in [0, Q]), Jacobian
    (Λ/2) q D − I + Σ_i ω_i [diag(B_i G) A_i + diag(A_i G) B_i], the three condition rows as
    in d = 1, and the same damped Gauss–Newton.  ``max_error`` is NaN (no closed form).
    The arguments are taken as checked: :func:`fixed_point` checks them and calls this.

    Parameters
    ----------
    model : MaxwellModel
        The collision model (p, Λ and the gain's scales per η).
    eta, weights : array_like
        The quadrature of the angular law of η (nodes, weights summing to 1).
    n : int
        Chebyshev degree.
    length : float
        The domain [0, Q] in q.
    initial : callable or None
        G at the start (None: e^{−q²/2}).
    tol : float
        Stopping tolerance of the Gauss–Newton steps.
    max_iterations : int
        At most this many steps.

    Returns
    -------
    FixedPoint
        Its ``dimension``, ``angular``, ``angular_nodes`` and ``seconds`` at their defaults:
        the caller fills them in.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``initial``) if ``initial`` does not give finite values on the nodes.
    """
    p = model.p
    eta = np.asarray(eta, dtype=float)
    weights = np.asarray(weights, dtype=float)
    half_rate = model.pair_lam * float(weights @ eta)  # Λ/2 with the quadrature's own ⟨η⟩
    q = chebyshev_nodes(n, length)
    D = differentiation_matrix(q)
    scales = [MaxwellModel.gain_scales_of(p, e) for e in eta]  # (b_i, a_i)
    A = np.stack([barycentric_matrix(q, a * q) for _, a in scales])
    B = np.stack([barycentric_matrix(q, b * q) for b, _ in scales])
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
    gain = sum(w * fp(a * fine) * fp(b * fine)
               for (b, a), w in zip(scales, weights, strict=True))
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

    Parameters
    ----------
    G : callable
        ``G(q, 0)`` the function and ``G(q, 1)`` its derivative, on arrays of q.
    restitution : float
        r ∈ [0, 1]; λ = (1 − r²)/4 and p = (1 + r)/2.
    q : array_like
        Rescaled wave numbers.

    Returns
    -------
    numpy.ndarray
        R[G](q), of the shape of ``q``; zero for f̂ at every r (up to round-off).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not in [0, 1] (from :class:`~maxwell_kinetics.model.MaxwellModel`).
    """
    m = MaxwellModel(restitution)
    q = np.asarray(q, dtype=float)
    return m.lam * q * G(q, 1) - G(q, 0) + G(m.p * q, 0) * G(m.complement * q, 0)


def collocation_operators(model: MaxwellModel, n: int, length: float):
    """The 1D collocation's nodes and matrices on [0, Q] (see the module docstring).

    Parameters
    ----------
    model : maxwell_kinetics.model.MaxwellModel
        The model (its p sets the gain arguments pq and (1 − p)q).
    n : int
        Polynomial degree N (N + 1 nodes).
    length : float
        Q, the end of the interval.

    Returns
    -------
    q : numpy.ndarray
        Shape (N + 1,): Chebyshev–Lobatto nodes.
    D : numpy.ndarray
        Shape (N + 1, N + 1): differentiation matrix.
    Bp, Bm : numpy.ndarray
        Shape (N + 1, N + 1): barycentric interpolation to p q_j and (1 − p) q_j.
    """
    q = chebyshev_nodes(n, length)
    D = differentiation_matrix(q)
    Bp = barycentric_matrix(q, model.p * q)
    Bm = barycentric_matrix(q, model.complement * q)
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


#: Estimated seconds above which :func:`fixed_point` refuses to start unless forced (one day, as
#: the time-dependent solver's :data:`maxwell_kinetics.grid.MAX_SOLVE_SECONDS`).
MAX_FIXED_POINT_SECONDS = 86400.0

#: Seconds per n³ of a d = 1 fixed point, all iterations included (measured: 49 s at n = 1024,
#: 7.3 s at n = 512 on a loaded 2-core machine); d >= 2 costs more, so this is a lower bound.
SECONDS_PER_CUBED_DEGREE = 4.5e-8


def estimate_fixed_point_seconds(n: int) -> float:
    """Estimated seconds of :func:`fixed_point` at Chebyshev degree ``n`` (dense Gauss–Newton:
    ~n³), before any work.

    Parameters
    ----------
    n : int
        The Chebyshev degree.

    Returns
    -------
    float
    """
    return SECONDS_PER_CUBED_DEGREE * float(n) ** 3


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
    force: bool = False,
) -> FixedPoint:
    """Solve λ q G' − G + G(pq) G((1−p)q) = 0 with G(0) = 1, G''(0) = −1, G(q_max) = 0.

    Chebyshev collocation of degree ``n`` on [0, q_max] and damped Gauss–Newton from
    ``initial`` (a NumPy callable of q; default e^{−q²/2}), stopped when the Newton step is
    below ``tol`` in max norm.  See the module docstring for the discretisation and for why
    three conditions are imposed.  r = 1 is rejected (degenerate).  ``n`` defaults to 64 in
    d = 1 and 128 in d ≥ 2.  The 1D residual and its Jacobian (``jax.jacfwd``) are compiled
    with JAX and evaluated in float64 inside ``jax.enable_x64(True)``.

    ``dimension`` 2 or 3 solves the stationary form of the isotropic equation of
    :func:`maxwell_kinetics.solver.solve` (``angular`` model; the η integral is the solver's own
    quadrature with ``angular_nodes`` nodes,
    :meth:`maxwell_kinetics.angular.AngularLaw.quadrature`):

        (Λ/2) q G' − G + Σ_i ω_i G(a_i q) G(b_i q) = 0,   a_i = √(1 − (1 − (1−p)²) η_i),
        b_i = p √η_i,   Λ/2 = p (1 − p) Σ_i ω_i η_i,

    G(q) the radial profile of the rescaled characteristic function (unit variance per
    component), with the same three conditions: the non-analytic A q^{2s*} term of the scaling
    solution plays the part of 1D's c₃ q³ (a free amplitude near q = 0 that only the decay at
    large q fixes).  The Jacobian is assembled in NumPy (with the single node η = 1 it is the
    1D problem, and gives the same G as the JAX path to round-off).  That term makes the
    Chebyshev convergence algebraic, not spectral: the error falls slowly with ``n`` where 2s*
    is small (r = 0), fast where it is large (the page "What is not done" of the
    documentation gives the accuracies).

    Parameters
    ----------
    restitution : float or particles.kernels.Kernel
        r ∈ [0, 1), or the Maxwell kernel of r (:func:`maxwell_kinetics.model.maxwell_restitution`).
    n : int, optional
        Polynomial degree N ≥ 8 (default 64 in d = 1, 128 in d ≥ 2); at most
        :data:`MAX_DEGREE_1D` = 256 in d = 1 (larger N is worse conditioned and less accurate).
    q_max : float, default 40.0
        Q, the end of the collocation interval (> 0), where G(Q) = 0 is imposed.
    initial : callable, optional
        Start G₀(q), a NumPy callable of an array of q; None for e^{−q²/2}.
    tol : float, default 1e-13
        Stopping threshold on the max norm of the Newton step (> 0).
    max_iterations : int, default 50
        Most Gauss–Newton steps (≥ 1).
    dimension : int, default 1
        Space dimension d ∈ {1, 2, 3}.
    angular : str, default "uniform"
        Angular model ("uniform" or "hard"), used in d ≥ 2.
    angular_nodes : int, default 16
        Gauss–Jacobi nodes of the η quadrature in d ≥ 2 (≥ 1).
    force : bool, default False
        Run even when the estimated time exceeds :data:`MAX_FIXED_POINT_SECONDS`.

    Returns
    -------
    FixedPoint
        The solution with its residuals, error against f̂ (d = 1), iteration count and a
        ``converged`` flag (not reaching ``tol`` is reported there, not raised).  In d = 1
        ``converged`` also needs a residual below :data:`RESIDUAL_PER_LAMBDA` · λ: as r → 1
        every G with G(0) = 1 has a residual O(λ), and Newton may stop on a small step far from
        f̂ (r = 1 − 1e-9: max error 0.27 at a residual of 2.4e-16).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not in [0, 1), ``dimension`` or ``angular`` is invalid, ``n``
        (above :data:`MAX_DEGREE_1D` in d = 1 included), ``max_iterations`` or
        ``angular_nodes`` is not a count in range, ``q_max`` or ``tol`` is not positive, or
        ``initial`` does not give finite values on the grid; naming ``n`` when the estimated
        time (:func:`estimate_fixed_point_seconds`, ~n³: a day near n = 12500) exceeds
        :data:`MAX_FIXED_POINT_SECONDS` and ``force`` is False; naming ``force`` when it is
        not a bool (``'no'`` is not True).
    """
    t0 = time.perf_counter()
    force = check_bool(force, "force")
    model = check_inelastic(restitution)
    from .angular import angular_law

    angular_law(dimension, angular)  # checks both
    if dimension != 1:
        angular_nodes = check_count(angular_nodes, "angular_nodes", 1)
        n = 128 if n is None else n
    n = check_count(64 if n is None else n, "n", 8)
    if dimension == 1 and n > MAX_DEGREE_1D:
        raise InvalidArgumentError(
            "n", n, f"a degree <= {MAX_DEGREE_1D} in d = 1 (beyond, the collocation is too "
            "ill-conditioned: it converges to a wrong function)")
    seconds = estimate_fixed_point_seconds(n)
    if not force and not seconds <= MAX_FIXED_POINT_SECONDS:
        from .grid import format_seconds

        raise InvalidArgumentError(
            "n", n, f"a Chebyshev degree whose Gauss-Newton solve is estimated to take at most "
            f"{format_seconds(MAX_FIXED_POINT_SECONDS)} (this one: about "
            f"{format_seconds(seconds)}, growing like n^3); force=True to run it anyway")
    length = check_positive(q_max, "q_max")
    tol = check_positive(tol, "tol")
    max_iterations = check_count(max_iterations, "max_iterations", 1)
    if dimension != 1:
        eta, weights = angular_law(dimension, angular).quadrature(angular_nodes)
        fp = isotropic_fixed_point(model, eta, weights, n, length, initial, tol, max_iterations)
        return replace(fp, dimension=dimension, angular=angular, angular_nodes=angular_nodes,
                       seconds=time.perf_counter() - t0)

    q, D, Bp, Bm = collocation_operators(model, n, length)
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
    residual = float(np.max(np.abs(eq)))
    # As r -> 1 every G with G(0) = 1 has a residual O(λ): only a residual small against λ
    # tells the solution from the rest (measured: r = 1 - 1e-9 stopped on a small step at a
    # function 0.27 from f̂ with residual 2.4e-16 = 0.5 λ; r = 0.9995 has 2.5e-16 = 1e-12 λ).
    converged = converged and residual <= RESIDUAL_PER_LAMBDA * lam
    fp = FixedPoint(
        restitution=model.restitution,
        q=q,
        G=G,
        residual=residual,
        check_residual=0.0,
        iterations=iterations,
        max_error=0.0,
        converged=converged,
        seconds=0.0,
    )
    fine = np.linspace(0.0, length, 4001)
    dG = barycentric_matrix(q, fine) @ (D @ G)
    check = lam * fine * dG - fp(fine) + fp(model.p * fine) * fp(model.complement * fine)
    err = max(float(np.max(np.abs(G - f_hat(q)))), float(np.max(np.abs(fp(fine) - f_hat(fine)))))
    return replace(
        fp,
        check_residual=float(np.max(np.abs(check))),
        max_error=err,
        seconds=time.perf_counter() - t0,
    )
