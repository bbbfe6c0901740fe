"""Tails and multiscaling measured from the solver's d-dimensional G.

The exponents of :mod:`maxwell_kinetics.tails` come from the equation alone (the root s* of
λ(s) = s λ(1), the rates min(λ(n), n λ(1))).  This module measures the same quantities from a
:class:`maxwell_kinetics.solution.Solution` of ``solve(..., dimension=d, angular=...)``, so that the
two are independent checks of each other.

Conventions.  G(q, τ) = Φ(q / v₀(τ), τ) is the characteristic function of one Cartesian
component x = v_x / v₀ of the rescaled velocity, v₀² = e^{−Λτ} (unit initial variance per
component, Λ = λ(1) = 2pq⟨η⟩), τ = collisions per particle.  Its Taylor coefficients
G = Σ_n C_n q^{2n} are C_n = (−1)^n ⟨x^{2n}⟩/(2n)! (C_0 = 1, C_1 = −1/2 exactly).

Moments.  Put Φ(k) = Σ c_n k^{2n} into the isotropic equation of :func:`solve`; with
a = 1 − q₁², q₁ = 1 − p, the coefficient of k^{2n} gives a closed triangular hierarchy, and for
C_n = c_n e^{nΛτ}

    dC_n/dτ = (n λ(1) − λ(n)) C_n + Σ_{m=1}^{n−1} K(n, m) C_m C_{n−m},
    K(n, m) = ⟨(1 − aη)^m (p² η)^{n−m}⟩ = p^{2(n−m)} Σ_i binom(m, i) (−a)^i ⟨η^{i+n−m}⟩

(:func:`rescaled_coefficients`; the Beta moments ⟨η^j⟩ are exact).  For an isotropic law
⟨|v|^{2n}⟩ is a fixed multiple of ⟨v_x^{2n}⟩, so ⟨|v|^{2n}⟩ ∝ |C_n| e^{−nΛτ} and its local decay
rate is nΛ − d ln|C_n|/dτ, which tends to min(λ(n), nλ(1)) (:func:`moment_decay_rates`).
:func:`series_coefficients` measures C_n from the solver's G near q = 0.

Tail.  Near q = 0 the scaling solution is G = 1 − q²/2 + (analytic q⁴, q⁶, …) + A|q|^{2s*}, and
one component of it decays as x^{−1−2s*}.  :func:`tail_root_from_solution` fits the non-analytic
power of G (the primary estimator: s* to ~1e-5 for 2s* < 6 once τ ≳ 400, see
benchmarks/README.md); :func:`tail_exponent_from_solution` fits the local slope of ln P against
ln x of the solver's inverted density (:meth:`Solution.density` at given x: Gauss–Legendre, no
aliasing; resolves only the r = 0 tails).  At the resonance s* = 2 (λ(2) = 2λ(1); d = 2, r = 0,
"hard") the term is A q⁴ ln q: :func:`resonant_log_fit` against :func:`resonant_log_amplitude`.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar
from scipy.special import comb

from particles.validation import InvalidArgumentError, check_times

from .angular import angular_law
from .model import MaxwellModel
from .solution import Solution, deviation_from_f_hat
from .tails import eta_moment, growth_rate

__all__ = [
    "gain_coefficient",
    "rescaled_coefficients",
    "series_coefficients",
    "moment_decay_rates",
    "tail_exponent_from_solution",
    "tail_root_from_solution",
    "resonant_log_amplitude",
    "resonant_log_fit",
]


def gain_coefficient(dimension, restitution, n: int, m: int, angular="uniform") -> float:
    """K(n, m) = ⟨(1 − aη)^m (p²η)^{n−m}⟩, a = 1 − (1 − p)², from the exact Beta moments.

    The coefficient of C_m C_{n−m} in the moment hierarchy of the module docstring (Ernst &
    Brito, J. Stat. Phys. 2002; Krapivsky & Ben-Naim, J. Phys. A 2002).

    Parameters
    ----------
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    restitution : float
        r ∈ [0, 1]; p = (1 + r)/2.
    n, m : int
        Indices, 0 ≤ m ≤ n.
    angular : {"uniform", "hard"}
        Law of the collision direction.

    Returns
    -------
    float
        K(n, m).

    Raises
    ------
    particles.validation.InvalidArgumentError
        For a dimension, restitution or angular law out of range.
    """
    law = angular_law(dimension, angular)
    p = MaxwellModel(restitution, law.dimension, law.angular).p
    a = MaxwellModel.cross_fraction_of(p)
    total = sum(comb(m, i, exact=True) * (-a) ** i * float(eta_moment(law, i + n - m))
                for i in range(m + 1))
    return float(p ** (2 * (n - m)) * total)


def rescaled_coefficients(dimension, restitution, tau, n_max: int = 3, angular="uniform",
                          initial=None) -> np.ndarray:
    """C_n(τ), n = 0 .. n_max, of the rescaled G from the exact moment hierarchy (module
    docstring), integrated by scipy (DOP853, rtol 1e-12).  ``initial``: C_n(0) (default: the
    unit Gaussian, C_n = (−1/2)^n / n!).  Returns an array of shape (len(tau), n_max + 1).

    Parameters
    ----------
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    restitution : float
        r ∈ [0, 1]; p = (1 + r)/2.
    tau : float or array_like
        Collisions per particle τ at which to report (checked times, increasing).
    n_max : int, default 3
        Highest index n (≥ 1).
    angular : {"uniform", "hard"}
        Law of the collision direction.
    initial : array_like, optional
        C_0 .. C_{n_max} at τ = 0, starting 1, −1/2 (unit variance per component).

    Returns
    -------
    numpy.ndarray
        Shape (len(tau), n_max + 1): C_n(τ) of G(q, τ) = Σ_n C_n q^{2n}.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``tau`` for invalid times, ``n_max`` if it is not an integer ≥ 1, ``initial``
        if it has the wrong length or does not start 1, −1/2, and for a dimension,
        restitution or angular law out of range.
    """
    taus = check_times(tau, "tau")
    if isinstance(n_max, bool) or not isinstance(n_max, int) or n_max < 1:
        raise InvalidArgumentError("n_max", n_max, "an integer >= 1")
    if initial is None:
        initial = [(-0.5) ** n / math.factorial(n) for n in range(n_max + 1)]
    c0 = np.asarray(initial, dtype=float)
    if c0.shape != (n_max + 1,) or c0[0] != 1.0 or c0[1] != -0.5:
        raise InvalidArgumentError("initial", initial, f"n_max + 1 = {n_max + 1} coefficients "
                                   "starting 1, -1/2")
    lam = growth_rate(dimension, restitution, np.arange(n_max + 1), angular)
    K = np.zeros((n_max + 1, n_max + 1))
    for n in range(2, n_max + 1):
        for m in range(1, n):
            K[n, m] = gain_coefficient(dimension, restitution, n, m, angular)
    rates = np.arange(n_max + 1) * lam[1] - lam

    def rhs(_, c):
        out = rates * c
        for n in range(2, n_max + 1):
            out[n] += sum(K[n, m] * c[m] * c[n - m] for m in range(1, n))
        out[:2] = 0.0
        return out

    sol = solve_ivp(rhs, (0.0, float(taus[-1])), c0, method="DOP853", t_eval=taus,
                    rtol=1e-12, atol=1e-300)
    return sol.y.T


def _deviation_from_scaling(solution, tau_index):
    """(q, w): the solver's grid and w = G − f̂ there (real part) at output ``tau_index``."""
    k = solution.time_index(tau_index)
    q = solution.q
    return q, (solution.deviation[k] - deviation_from_f_hat(q, solution.skewness)).real


def _window_points(solution, window, tau_index, minimum: int, need: str):
    """(q, w) of :func:`_deviation_from_scaling` on the points of ``window``; at least
    ``minimum`` of them, else InvalidArgumentError naming ``window`` (expected ``need``)."""
    lo, hi = _window(window, "window")
    q, w = _deviation_from_scaling(solution, tau_index)
    sel = (q >= lo) & (q <= hi)
    if np.count_nonzero(sel) < minimum:
        raise InvalidArgumentError("window", window, need)
    return q[sel], w[sel]


def series_coefficients(solution: Solution, tau_index: int = -1, n_max: int = 3,
                        window=None, tolerance: float = 1e-6) -> np.ndarray:
    """C_2 .. C_{n_max} of G at the saved τ from the solver's values near q = 0.

    w = G − e^{−q²/2} (from the cancellation-free ``deviation``) equals
    Σ_{n≥2} (C_n − (−1/2)^n/n!) q^{2n} where G is analytic.  ``window`` None (the default): each
    C_n from the window chosen automatically between the |q|^{2s*} term and the grid's floor
    (:mod:`maxwell_kinetics.moments`; NaN where the coefficient is not resolved).  An explicit
    ``window`` (q_lo, q_hi): least squares of w/q⁴ against a polynomial in q² of degree n_max
    (two extra terms absorb the truncation) on the grid points inside it; the window is refused
    (InvalidArgumentError naming ``window``) when C_2 fitted on its lower and upper halves (in
    ln q) differ by more than ``tolerance`` relative: the non-analytic term, which builds up in
    a boundary layer that shrinks toward q = 0 in τ, is then not negligible on it.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solve of :func:`maxwell_kinetics.solver.solve` (any dimension).
    tau_index : int, default -1
        Index of the saved τ (as for :meth:`maxwell_kinetics.solution.Solution.time_index`).
    n_max : int, default 3
        Highest index n.
    window : tuple of float, optional
        (q_lo, q_hi) for an explicit fit; None chooses a window per coefficient.
    tolerance : float, default 1e-6
        Largest relative drift of C_2 between the window's halves (explicit window only).

    Returns
    -------
    numpy.ndarray
        Shape (n_max − 1,): C_2 .. C_{n_max} (NaN where not resolved, automatic window).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``window`` if it is not a pair 0 < q_lo < q_hi < inf, holds fewer than
        2 (n_max + 2) grid points, or G is not analytic enough on it.
    """
    if window is None:
        from .moments import series_estimate

        q, w = _deviation_from_scaling(solution, tau_index)
        return series_estimate(q, w, max(2, int(n_max))).values[: n_max - 1]
    qs, w = _window_points(solution, window, tau_index, 2 * (n_max + 2),
                           f"at least {2 * (n_max + 2)} grid points")
    gauss = np.array([(-0.5) ** n / math.factorial(n) for n in range(2, n_max + 1)])
    mid = np.sqrt(qs[0] * qs[-1])
    halves = [np.polynomial.polynomial.polyfit(qs[sel] ** 2, w[sel] / qs[sel] ** 4, n_max)[0]
              for sel in (qs <= mid, qs >= mid)]
    c2 = 0.5 * (halves[0] + halves[1]) + gauss[0]
    drift = abs(halves[0] - halves[1]) / abs(c2)
    if not drift <= tolerance:
        raise InvalidArgumentError(
            "window", window,
            f"a window where G is analytic: C_2 fitted on its two halves differs by {drift:.1e} "
            f"relative (> tolerance {tolerance:g}; the |q|^(2s*) term reaches it); "
            "window=None chooses one automatically")
    coef = np.polynomial.polynomial.polyfit(qs**2, w / qs**4, n_max)
    return coef[: n_max - 1] + gauss


def moment_decay_rates(solution: Solution, n: int, window=None,
                       tau_indices=None) -> tuple[np.ndarray, np.ndarray]:
    """Local decay rates of ⟨|v|^{2n}⟩ measured from the solver: nΛ − d ln|C_n|/dτ.

    C_n is :func:`series_coefficients` at the saved τ (``tau_indices``, default all; ``window``
    as there, None: chosen automatically); the
    derivative is the centred finite difference of ln|C_n| in τ between neighbours.  Returns
    (midpoints τ, rates).  Λ = 2pq⟨η⟩ is the exact energy rate of the solution's model.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solve of :func:`maxwell_kinetics.solver.solve` (any dimension).
    n : int
        Order: the moment ⟨|v|^{2n}⟩ (n ≥ 2).
    window : tuple of float, optional
        As for :func:`series_coefficients`.
    tau_indices : sequence of int, optional
        Saved times to use (default all).

    Returns
    -------
    tau : numpy.ndarray
        Midpoints between neighbouring saved τ.
    rates : numpy.ndarray
        The local decay rates there (per unit τ).
    """
    idx = list(range(len(solution.tau))) if tau_indices is None else list(tau_indices)
    c = np.array([series_coefficients(solution, k, max(n, 2), window)[n - 2] for k in idx])
    t = solution.tau[idx]
    lam1 = float(growth_rate(solution.dimension, solution.restitution, 1.0, solution.angular))
    slope = np.diff(np.log(np.abs(c))) / np.diff(t)
    return 0.5 * (t[1:] + t[:-1]), n * lam1 - slope


def tail_exponent_from_solution(solution: Solution, window=(10.0, 30.0), tau_index: int = -1,
                                points: int = 41) -> tuple[float, float]:
    """(exponent, error estimate) of the power-law tail P(x) ∝ x^{−α} of one component.

    Estimator: least-squares slope of ln P against ln x on ``points`` log-spaced x in
    ``window``, P from :meth:`Solution.density` at those x (Gauss–Legendre, no aliasing).
    Compare α with 1 + 2s* (``tail_exponent(d, r, angular).exponents["component"]``).
    The error estimate is the difference between the slopes fitted on the lower and upper
    halves of the window (in ln x): the drift of the local slope, i.e. the size of the
    corrections to pure power law that the window does not remove.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solve of :func:`maxwell_kinetics.solver.solve` (any dimension).
    window : tuple of float, default (10.0, 30.0)
        (x_lo, x_hi) in the rescaled velocity x = v_x / v₀.
    tau_index : int, default -1
        Index of the saved τ.
    points : int, default 41
        Number of log-spaced x.

    Returns
    -------
    alpha : float
        The fitted exponent α.
    error : float
        The half-window drift of the slope.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``window`` if it is not a pair 0 < lo < hi < inf or the density is not positive
        on it.
    """
    lo, hi = _window(window, "window")
    x = np.geomspace(lo, hi, int(points))
    _, P = solution.density(x, tau_index)
    if np.any(P <= 0):
        raise InvalidArgumentError("window", window, "a window where the density is positive")
    lx, lp = np.log(x), np.log(P)
    slope = np.polyfit(lx, lp, 1)[0]
    mid = x.size // 2
    low = np.polyfit(lx[: mid + 1], lp[: mid + 1], 1)[0]
    high = np.polyfit(lx[mid:], lp[mid:], 1)[0]
    return float(-slope), float(abs(high - low))


def _nonanalytic_fit(q, y, analytic_terms, beta_range):
    """min over β of the linear least squares of y against [1, q², …, q^{2(m−1)}, q^β]
    (variable projection): a grid scan of β, then bounded refinement.  Returns (β, rms)."""
    x = q / q.max()
    base = np.stack([x ** (2 * j) for j in range(analytic_terms)], axis=1)

    def rms(beta):
        A = np.concatenate([base, x[:, None] ** beta], axis=1)
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        return float(np.sqrt(np.mean((A @ coef - y) ** 2)))

    grid = np.linspace(*beta_range, 400)
    values = [rms(b) for b in grid]
    i = int(np.argmin(values))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    best = minimize_scalar(rms, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return float(best.x), float(best.fun)


def tail_root_from_solution(solution: Solution, window=(1e-4, 0.1), tau_index: int = -1,
                            analytic_terms: int = 3,
                            beta_range=(0.02, 6.0)) -> tuple[float, float]:
    """(s, error estimate): the tail root s* measured from the non-analytic term of G near q = 0.

    Estimator: near q = 0 the scaling solution is G = 1 − q²/2 + Σ_{n≥2} a_n q^{2n} + A|q|^{2s*}
    + …, so w = G − e^{−q²/2} (from the cancellation-free ``deviation``) satisfies
    w/q⁴ = b₀ + b₁q² + … + A q^β with β = 2s* − 4.  β is the minimiser, over ``beta_range``,
    of the residual of the linear least squares of w/q⁴ on the grid points in ``window``
    against ``analytic_terms`` powers q^{2j} (j = 0 .. m − 1) and q^β; s = 2 + β/2.
    The analytic terms are fitted, not assumed, so 2s* may lie above 4 (subleading to q⁴).
    Error estimate: the largest change of s when the fit is repeated on the lower and the upper
    half of the window (in ln q).  Compare with ``tail_exponent(d, r, angular).s``.

    Needs G at its fixed point on the window: at finite τ G is analytic for Gaussian data and
    the |q|^{2s*} term only forms above a crossover q that falls exponentially in τ.  The
    resonant case s* = 2 (d = 2, r = 0, "hard": A q⁴ ln q) is outside this form.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solve of :func:`maxwell_kinetics.solver.solve` (any dimension).
        In d ≥ 2 it must be solved with ``angular_rule="accurate"``.
    window : tuple of float, default (1e-4, 0.1)
        (q_lo, q_hi) of the fit.
    tau_index : int, default -1
        Index of the saved τ.
    analytic_terms : int, default 3
        Number m of analytic powers q^{2j} fitted along with q^β.
    beta_range : tuple of float, default (0.02, 6.0)
        Range of β searched.

    Returns
    -------
    s : float
        The measured tail root.
    error : float
        The half-window change of s.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``solution`` for a d ≥ 2 solve without the accurate η rule, or ``window`` if it
        is not a valid pair or holds too few grid points.
    """
    _require_accurate_rule(solution)
    lo, hi = _window(window, "window")
    q, w = _deviation_from_scaling(solution, tau_index)

    def fit(a, b):
        sel = (q >= a) & (q <= b)
        if np.count_nonzero(sel) < analytic_terms + 4:
            raise InvalidArgumentError("window", window,
                                       f"at least {2 * (analytic_terms + 4)} grid points")
        return 2.0 + 0.5 * _nonanalytic_fit(q[sel], w[sel] / q[sel] ** 4, analytic_terms,
                                            beta_range)[0]

    s = fit(lo, hi)
    mid = math.sqrt(lo * hi)
    err = max(abs(fit(lo, mid) - s), abs(fit(mid, hi) - s))
    return s, err


def resonant_log_amplitude(dimension, restitution, angular="uniform") -> float:
    """A of the q⁴ ln q term of the scaling solution when s* = 2 exactly (λ(2) = 2λ(1), e.g.
    d = 2, r = 0, "hard"): the stationary balance of the q⁴ terms gives
    A = 2 K(2, 1) C₁² / F'(2), F(s) = λ(s) − s λ(1), C₁ = −1/2 (F' by a centred difference,
    step 1e-4, relative error ~1e-8).

    Parameters
    ----------
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    restitution : float
        r ∈ [0, 1]; p = (1 + r)/2.
    angular : {"uniform", "hard"}
        Law of the collision direction.

    Returns
    -------
    float
        A (meaningful only where s* = 2 exactly).

    Raises
    ------
    particles.validation.InvalidArgumentError
        For a dimension, restitution or angular law out of range.
    """
    h = 1e-4
    lam1 = float(growth_rate(dimension, restitution, 1.0, angular))
    slope = (float(growth_rate(dimension, restitution, 2.0 + h, angular))
             - float(growth_rate(dimension, restitution, 2.0 - h, angular))) / (2 * h) - lam1
    return 2.0 * gain_coefficient(dimension, restitution, 2, 1, angular) * 0.25 / slope


def resonant_log_fit(solution: Solution, window=(1e-4, 0.1), tau_index: int = -1,
                     analytic_terms: int = 3) -> tuple[float, float, float]:
    """(A, rms of the log model, rms of the best power model) for w/q⁴ near q = 0.

    The log model is w/q⁴ = b₀ + A ln q + b₁q² + … (the resonant s* = 2 form, compare A with
    :func:`resonant_log_amplitude`); the power model is that of :func:`tail_root_from_solution`
    with β ∈ [0.02, 6].  A log-model rms far below the power model's says s* = 2 exactly.

    Parameters
    ----------
    solution : maxwell_kinetics.solution.Solution
        A solve of :func:`maxwell_kinetics.solver.solve` (any dimension).
        In d ≥ 2 it must be solved with ``angular_rule="accurate"``.
    window : tuple of float, default (1e-4, 0.1)
        (q_lo, q_hi) of the fit.
    tau_index : int, default -1
        Index of the saved τ.
    analytic_terms : int, default 3
        Number of analytic powers q^{2j} in both models.

    Returns
    -------
    tuple of float
        (A, rms of the log model, rms of the best power model).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``solution`` for a d ≥ 2 solve without the accurate η rule, or ``window`` if it
        is not a valid pair or holds too few grid points.
    """
    _require_accurate_rule(solution)
    qs, w = _window_points(solution, window, tau_index, analytic_terms + 4,
                           f"at least {analytic_terms + 4} points")
    y = w / qs**4
    x = qs / qs.max()
    basis = np.stack([np.log(qs)] + [x ** (2 * j) for j in range(analytic_terms)], axis=1)
    coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
    rms_log = float(np.sqrt(np.mean((basis @ coef - y) ** 2)))
    _, rms_power = _nonanalytic_fit(qs, y, analytic_terms, (0.02, 6.0))
    return float(coef[0]), rms_log, rms_power


def _require_accurate_rule(solution) -> None:
    """The fits of the non-analytic term need the "accurate" η rule in d ≥ 2: the "fast" one
    keeps G to 1e-8 but moves s* by ~5e-4 and the resonant amplitude by ~4e-3 relative
    (:data:`maxwell_kinetics._kinetic_scheme.ANGULAR_RULES`)."""
    if getattr(solution, "dimension", 1) != 1 and solution.angular_rule != "accurate":
        raise InvalidArgumentError(
            "solution", f"a solve with angular_rule={solution.angular_rule!r}",
            "solve(..., angular_rule='accurate') for fits of the |q|^{2s*} term (the fast "
            "rule's few η nodes at small q move that slowly relaxing term)")


def _window(window, name):
    try:
        lo, hi = (float(v) for v in window)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, window, "a pair (lo, hi)") from None
    if not (0.0 < lo < hi and math.isfinite(hi)):
        raise InvalidArgumentError(name, window, "0 < lo < hi < inf")
    return lo, hi


