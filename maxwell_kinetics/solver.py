"""Time-dependent solver of the rescaled pseudo-Maxwell equation in Fourier space.

Equation.  With P̂(k, τ) = ∫ e^{ikv} P(v, τ) dv (τ = collisions per particle) and the
rescaled characteristic function G(q, τ) = P̂(q / v0(τ), τ), v0² = ⟨v²⟩ = e^{−2λτ} for unit
initial variance,

    ∂τ G = λ q ∂q G − G + G(p q) G((1 − p) q),        p = (1 + r)/2,  λ = p(1 − p),

for q ≥ 0; G(−q) = conj G(q).  G(0) = 1 and G''(0) = −1 are conserved, and every solution with
finite variance tends to the scaling solution f̂(q) = (1 + |q|) e^{−|q|}.

Method: semi-Lagrangian in s = ln q, for the deviation w = G − g from the reference

    g(q) = e^{−q²/2} (1 − i m₃ q³/6),        m₃ = ⟨x³⟩ (conserved; 0 for symmetric laws),

which has the same small-q expansion as G to O(q³).  Storing w instead of G matters near q = 0:
there G ≈ 1 and a round-off error δ at q₀ is a variance error δ/q₀² that the dynamics keeps
(the q² mode is neutral), whereas w = O(q³) is stored to relative precision.  The
source g(pq)g((1−p)q) − g + λ q g' is evaluated in closed form (:func:`source`, with the
series of e^x − 1 − x for small x = λq²), so no O(1) terms cancel.

In s the transport term λ ∂s G is a shift at constant speed λ toward small q, so along the
characteristics (the comoving points s + λ(τ − τ_w)) the equation is the unscaled one,
∂τ u = −u + u(s + ln p) u(s + ln(1 − p)), whose shifts of w are fixed stencils on the uniform s
grid (:mod:`maxwell_kinetics.grid`) while g is evaluated exactly.  The solver integrates that
ODE with diffrax (Dopri8, adaptive PID steps, tolerances ``rtol``/``atol`` in diffrax's RMS
norm) over windows of length Δτ = m h / λ, after which the comoving grid has moved by exactly
m cells: the values are shifted by m (no interpolation), m points leave through the outflow end
q_min and m enter at the inflow end q_max.  Transport is therefore exact, the ODE is not stiff
(its rates are O(1), independent of h), and the only spatial error is the Lagrange
interpolation of w, of order ``resolution.order``, in the gain term.  Outputs between window
ends are interpolated from the comoving grid back to the fixed grid with stencils of twice that
order (they do not feed back into the dynamics).

Boundaries: below q_min (default e^{−24}) the gain terms see w continued as
w(q_0) (q/q_0)³ from the first node q_0, its leading small-q behaviour (the |q|³/3 of f̂ builds
up there; for laws with a finite fourth moment w starts as O(q⁴), and the continuation errs by
O(q_min⁴), far below round-off).
Setting w = 0 there instead, a variance error of order q_min/3 at the cut, looks negligible
but is not: the gain terms sample ever smaller q, and over ~100–300 τ such a cut pins the late
state at f̂((1 + ε) q) with ε ≈ 0.21 q_min, which would be the whole error floor of the finest
grids (benchmarks/README.md).  Above q_max the free-streaming value e^{−τ} φ(q e^{λτ}) of the
initial law φ enters (zero for user laws that JAX cannot trace, and for τ > 40 where it is
below 4e-18).

For r = 1 (elastic, λ = 0) collisions only exchange velocities: G(q, τ) = φ(q) for all τ.

References: the model and its moment hierarchy, Ben-Naim & Krapivsky (Phys. Rev. E 2000); the
d-dimensional isotropic models, Ernst & Brito (J. Stat. Phys. 2002) and Krapivsky & Ben-Naim
(J. Phys. A 2002); the contraction toward f̂ in the metrics d_s, Bobylev, Cercignani & Toscani
(J. Stat. Phys. 2003).  The ODE solver is diffrax's ``Dopri8`` with a ``PIDController``.

Compilation and precision: the scheme's jitted functions (:mod:`maxwell_kinetics._kinetic_scheme`)
are module-level and take r (with p, λ, the window and the gain stencils) and the output times as
traced data; the grid, the law and the options are their static argument.  A sweep over r at one
resolution and law therefore compiles once.  Every JAX call of the solver runs inside
``jax.enable_x64(True)`` (a thread-local context that restores the caller's setting): the solver
computes in float64 whatever JAX's global configuration, and does not change it.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from particles import persistence
from particles.initial import InitialLaw, first_non_finite, get_law
from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_positive,
    check_times,
)

from . import _interrupt, compile_cache
from .deviation import reference
from .exact import f_hat
from .grid import INFLOW_CUT, Resolution, check_solve_budget, get_resolution
from .model import MaxwellModel

__all__ = ["solve", "check_solve_arguments", "SolveArguments", "Solution", "SolverOptions"]


@dataclass(frozen=True)
class SolverOptions:
    """Time-integration settings of :func:`solve`.

    Attributes
    ----------
    rtol, atol : float, default 1e-11 and 1e-13
        Relative and absolute tolerances of diffrax's PID step-size controller (RMS norm over
        the grid), > 0.
    window : float, default 2.0
        Target length in τ of one semi-Lagrangian window (rounded so that the grid moves by a
        whole number of cells), > 0.
    max_steps_per_window : int, default 100000
        Most ODE steps diffrax may take in one window.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``rtol``, ``atol`` or ``window`` is not a positive number.
    """

    rtol: float = 1e-11
    atol: float = 1e-13
    window: float = 2.0
    max_steps_per_window: int = 100_000

    def __post_init__(self):
        check_positive(self.rtol, "rtol")
        check_positive(self.atol, "atol")
        check_positive(self.window, "window")


#: Version of the saved Solution format (2: particles.persistence, hashed; 1 still loads).
_SOLUTION_VERSION = 2


def _check_skewness_finite(law: InitialLaw) -> float:
    m3 = float(law.skewness)
    if not math.isfinite(m3):
        raise InvalidArgumentError("initial", law.name, "a law with a finite third moment")
    return m3


def _checked_phi(law: InitialLaw, k: np.ndarray, where: str) -> np.ndarray:
    """φ(k) by NumPy, or InvalidArgumentError naming ``characteristic`` and the first bad k."""
    values = np.broadcast_to(law.phi(k), np.shape(k))
    bad = first_non_finite(k, values)
    if bad is not None:
        raise InvalidArgumentError(
            "characteristic", f"phi({bad[0]:.6g}) = {bad[1]} (law {law.name!r})",
            f"finite values of the characteristic function on {where}",
        )
    return np.asarray(values)


def inflow_wavenumbers(model: MaxwellModel, grid: Resolution, opts: SolverOptions) -> np.ndarray:
    """k = q e^{λτ} at which the free-streaming inflow evaluates φ, sampled log-uniformly.

    The inflow (right ghost) nodes sit at ln q ∈ [ln q_max + h, ln q_max + (cells + cells_max +
    5 order/2) h] with cells h ≤ λ·window + h/2 and cells_max h ≤ window/4 + h/2
    (:mod:`maxwell_kinetics._kinetic_scheme`), and φ is taken at k = q e^{λ min(τ, 40)}
    (:data:`maxwell_kinetics.grid.INFLOW_CUT`).  The sampled range is wider on both sides,
    ln k ∈ [ln q_max − window − h, ln q_max + window + 4 order h + 40λ], with 64 points per
    unit of ln k.  Empty for λ = 0 (no inflow).
    """
    lam = model.lam
    if lam == 0.0:
        return np.empty(0)
    lo = math.log(grid.q_max) - opts.window - grid.h
    hi = math.log(grid.q_max) + opts.window + 4 * grid.order * grid.h + lam * INFLOW_CUT
    return np.exp(np.linspace(lo, hi, max(2, math.ceil(64 * (hi - lo)))))


def initial_deviation(law: InitialLaw, q: np.ndarray, q_fit: float = 2e-3) -> np.ndarray:
    """w(q, 0) = φ(q) − g(q), accurate to relative round-off also where both are ≈ 1.

    For q ≥ q_fit the difference is taken directly (absolute error ~1e-16, i.e. a variance
    error below 1e-16 / q_fit² ≈ 3e-11).  Below q_fit, w is the least-squares series
    c₃q³ + … + c₇q⁷ fitted on q ∈ [q_fit, 8 q_fit] (c₃ is zero for laws with a finite
    third absolute moment; a heavy x⁻⁴ tail, as in f̂ itself, gives the real |q|³ term).
    """
    m3 = law.skewness
    q = np.asarray(q, dtype=float)
    w = _checked_phi(law, q, "the solver's q grid") - reference(q, m3).astype(complex)
    small = q < q_fit
    if np.any(small):
        qf = np.geomspace(q_fit, 8 * q_fit, 64)
        wf = _checked_phi(law, qf, "the small-q fit") - reference(qf, m3).astype(complex)
        powers = np.arange(3, 8)
        basis = (qf[:, None] / q_fit) ** powers
        coef, *_ = np.linalg.lstsq(basis.astype(complex), wf, rcond=None)
        w[small] = ((q[small, None] / q_fit) ** powers) @ coef
    return w


def deviation_from_f_hat(q: np.ndarray, m3: float) -> np.ndarray:
    """g(q) − f̂(q) without cancellation at small q (Taylor series of e^{−q²/2} − f̂ below 0.05)."""
    q = np.asarray(q, dtype=float)
    out = reference(q, m3).astype(complex) - f_hat(q)
    small = q < 0.05
    if np.any(small):
        nmax = 20
        # Taylor coefficients of e^{−q²/2} − (1 + q) e^{−q}; those of f̂ are (−1)^n (1 − n)/n!.
        diff = np.array([(-1) ** n * (n - 1) / math.factorial(n) for n in range(nmax)])
        for m in range(nmax // 2):
            diff[2 * m] += (-0.5) ** m / math.factorial(m)
        diff[:3] = 0.0  # identical through q²
        qs = q[small]
        out[small] = np.polynomial.polynomial.polyval(qs, diff) - 1j * (m3 / 6.0) * qs**3 * np.exp(
            -0.5 * qs * qs
        )
    return out


class _Stepper:
    """The scheme for one (model, law, grid, options): host-side data and the jitted calls.

    The compiled functions live in :mod:`maxwell_kinetics._kinetic_scheme` and take r, the
    window and the stencils as traced data, so a new r reuses the compilation of the same
    (grid, law, options).  Every JAX call runs inside ``jax.enable_x64(True)``: float64 for
    this computation without changing JAX's global configuration.
    """

    def __init__(self, model: MaxwellModel, law: InitialLaw, grid: Resolution, opts: SolverOptions,
                 dimension: int = 1, angular: str = "uniform", angular_nodes: int = 1,
                 angular_rule: str = "accurate"):
        import jax

        from . import _kinetic_scheme as scheme

        self.model, self.law, self.grid, self.opts = model, law, grid, opts
        tiers = scheme.angular_tiers(dimension, angular, angular_nodes, grid, angular_rule)
        if law.traceable:  # the inflow evaluates φ (in JAX) far beyond q_max: check it first
            _checked_phi(law, inflow_wavenumbers(model, grid, opts), "the inflow's k = q e^{λτ}")
        self.m3 = m3 = _check_skewness_finite(law)
        self.complex = m3 != 0.0 or not law.symmetric
        self.static = scheme.Static(
            grid, law, opts, self.complex, m3, dimension, angular,
            sum(t.eta.size for t in tiers),
            tuple((t.first, t.eta.size) for t in tiers) if dimension != 1 else ())
        self.speed = scheme.transport_speed(model, tiers[0].eta, tiers[0].weights)
        self.cells, self.dtau = scheme.window_cells(self.speed, grid, opts)
        w0 = initial_deviation(law, np.exp(grid.s_min + grid.h * np.arange(grid.n + self.cells)))
        self._scheme, self._x64 = scheme, jax.enable_x64
        with jax.enable_x64(True):
            self.dynamic = scheme.dynamic(model, grid, opts, tiers)
            self.y0 = scheme.initial_state(self.static, w0)

    def advance(self, y, i_start: int, count: int):
        """The state after ``count`` windows from window ``i_start``."""
        with self._x64(True):
            scheme = self._scheme
            return compile_cache.call("advance", scheme.advance_unjitted, scheme.advance,
                                      self.static, (self.dynamic, y, i_start, count))

    def wait(self, y) -> None:
        """Block until the (asynchronously dispatched) state ``y`` is computed."""
        import jax

        jax.block_until_ready(y)

    def output(self, y, i_window: int, tau: float):
        """w on the fixed grid at τ (≥ i_window Δτ) as a (parts, n) array."""
        with self._x64(True):
            scheme = self._scheme
            return compile_cache.call("output", scheme.output_unjitted, scheme.output,
                                      self.static, (self.dynamic, y, i_window, tau))


class SolveArguments(NamedTuple):
    """The arguments of :func:`solve`, checked and typed by :func:`check_solve_arguments`.

    Parameters
    ----------
    model : maxwell_kinetics.model.MaxwellModel
        The model of the restitution coefficient.
    law : particles.initial.InitialLaw
        The initial law.
    tau : numpy.ndarray
        The output times, increasing and non-negative.
    grid : maxwell_kinetics.grid.Resolution
        The q grid.
    options : SolverOptions
        The time-integration settings.
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    angular, angular_rule : str
        Angular model and η rule ("uniform" and "accurate" in d = 1, where they are unused).
    angular_nodes : int
        Scale of the η quadrature (1 in d = 1).
    estimate : dict
        The cost :func:`maxwell_kinetics.grid.estimate_solve` estimated (``seconds``,
        ``memory``, ``windows``).
    """

    model: MaxwellModel
    law: InitialLaw
    tau: np.ndarray
    grid: Resolution
    options: SolverOptions
    dimension: int
    angular: str
    angular_nodes: int
    angular_rule: str
    estimate: dict


def check_solve_arguments(
    restitution: float,
    initial="gaussian",
    tau=(1.0, 10.0, 100.0),
    resolution="default",
    *,
    options: SolverOptions | None = None,
    dimension: int = 1,
    angular: str = "uniform",
    angular_nodes: int = 16,
    angular_rule: str = "fast",
    force: bool = False,
) -> SolveArguments:
    """Every check of :func:`solve` on its arguments (the same names and defaults), before
    any work and without JAX: :func:`solve` calls it first, and a caller may call it to refuse
    bad input before preparing anything else (the command line does, before it writes).

    Parameters
    ----------
    restitution, initial, tau, resolution, options, dimension, angular, angular_nodes, \
angular_rule, force
        As for :func:`solve`.

    Returns
    -------
    SolveArguments
        The checked values: the model, the law, the times as an array, the grid, the options,
        the angular settings (in d = 1: "uniform", 1 node and rule "accurate", which d = 1
        does not use) and the cost :func:`maxwell_kinetics.grid.estimate_solve` estimated.

    Raises
    ------
    particles.validation.InvalidArgumentError
        As listed under :func:`solve`.
    """
    model = MaxwellModel(restitution)
    law = get_law(initial)
    taus = check_times(tau, "tau")
    from .model import angular_law

    angular_law(dimension, angular)  # checks both
    if dimension != 1:
        angular_nodes = check_count(angular_nodes, "angular_nodes", 1)
        from ._kinetic_scheme import ANGULAR_RULES

        if angular_rule not in ANGULAR_RULES:
            raise InvalidArgumentError("angular_rule", angular_rule,
                                       "one of " + ", ".join(ANGULAR_RULES))
        if model.restitution >= 1.0:
            raise InvalidArgumentError("restitution", restitution, "r < 1 when dimension >= 2")
        if law.skewness != 0.0 or not law.symmetric:
            raise InvalidArgumentError("initial", law.name,
                                       "a symmetric law (real Φ) when dimension >= 2")
    else:
        angular, angular_nodes, angular_rule = "uniform", 1, "accurate"
    grid = get_resolution(resolution)
    opts = options or SolverOptions()
    estimate = check_solve_budget(grid, float(taus[-1]), len(taus), window=opts.window,
                                  force=force, dimension=dimension, angular_rule=angular_rule)
    return SolveArguments(model, law, taus, grid, opts, dimension, angular, angular_nodes,
                          angular_rule, estimate)


def solve(
    restitution: float,
    initial="gaussian",
    tau=(1.0, 10.0, 100.0),
    resolution="default",
    *,
    options: SolverOptions | None = None,
    progress: bool = False,
    dimension: int = 1,
    angular: str = "uniform",
    angular_nodes: int = 16,
    angular_rule: str = "fast",
    force: bool = False,
) -> Solution:
    """Integrate the rescaled equation from G(q, 0) = φ(q) and save G at the requested τ.

    ``dimension`` d ∈ {1, 2, 3} and ``angular`` ∈ {"uniform", "hard"} select the isotropic
    inelastic Maxwell model in d dimensions (d = 1, the default, is the equation of the module
    docstring; ``angular`` is then irrelevant).  With isotropic data φ(k) = Φ(|k|) and
    η = (k̂·n)² ~ Beta(1/2, (d−1)/2) ("uniform") or Beta(1, (d−1)/2) ("hard"), q₁ = 1 − p:

        ∂τ Φ(k) + Φ(k) = ∫₀¹ w(η) Φ(k √(1 − (1 − q₁²) η)) Φ(p k √η) dη,

    and ⟨|v|²⟩ ∝ e^{−Λτ}, Λ = 2 p q₁ ⟨η⟩
    (:meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`; d = 1: η ≡ 1, Λ = 2λ).
    Rescaled by the decaying per-component variance, G(q, τ) = Φ(q / v₀(τ), τ)
    with v₀² = e^{−Λτ} (unit initial variance per component) solves

        ∂τ G = (Λ/2) q ∂q G − G + ∫₀¹ w(η) G(q √(1 − (1 − q₁²)η)) G(p q √η) dη,

    the d = 1 equation with transport speed Λ/2 in place of λ and the gain averaged over η.
    The η integral is Gauss–Jacobi quadrature with a node count that grows with q
    (:func:`maxwell_kinetics._kinetic_scheme.angular_tiers`; each node is one pair of shifted
    stencils on its range of q).  ``angular_rule`` "fast" (the default): 2, 3, 4, 6, 8, 12, 16,
    12 nodes from q = 0, 1e-3, 1e-2, 0.05, 0.15, 0.35, 0.6, 10 (4.76 per grid point; G within
    1.0e-8 of 32 nodes at every q, measured on the coarse grid for d = 2, 3, both angular
    models, r = 0, 0.5, 0.9).  "accurate": 2 nodes below q = 1e-6, 16 up to q = 10 and 12 above
    (10.7 per grid point, about 2.3× the cost): the fewer nodes of "fast" at small q keep G to
    1e-8 but move the slowly relaxing |q|^{2s*} term that :mod:`maxwell_kinetics.scaling_tails`
    fits (s* by 5e-4), so those fits require "accurate".  ``angular_nodes`` (16) scales every
    range of either rule (32 doubles them; at least 2 nodes).  Measured (coarse
    grid, r = 0.5, G at τ = 30 and 300 against 32 nodes at every q): 16 nodes at every q differ
    by 3.1e-9 (d = 2) and 2.7e-9 (d = 3).  Λ/2 is taken as p q₁ Σ ω_i η_i with the quadrature's
    own ⟨η⟩ (exact in every range) so that G''(0) = −1 is kept exactly.  G(0) = 1, and G is the
    characteristic function of one Cartesian component of v / v₀ along any axis, so
    :meth:`Solution.density` gives the density of one component and
    :meth:`Solution.speed_density` that of the speed |v| / v₀.  The initial law's φ is used
    as the radial profile Φ: it must be a d-dimensional characteristic function (the Gaussian
    is, in every d); d ≥ 2 needs a symmetric law with m₃ = 0 and r < 1 (at r = 1 the d ≥ 2
    equation still relaxes, and Λ = 0 leaves the scheme no transport).  The distances to f̂
    (:meth:`Solution.sup_error`, :meth:`Solution.fourier_distance`) are defined for d = 1 only
    and raise for d ≥ 2: f̂ is the one-dimensional scaling solution, and none is known in closed
    form for d ≥ 2.  The stored array ``deviation`` = G − f̂ is then only the
    representation :meth:`Solution.evaluate` interpolates, not a distance to anything.

    Parameters
    ----------
    restitution : float
        Restitution coefficient r ∈ [0, 1] (p = (1 + r)/2, λ = (1 − r²)/4); r < 1 in d ≥ 2.
    initial : str or particles.initial.InitialLaw, default "gaussian"
        A law name of :mod:`particles.initial` or a law; its characteristic function φ(k) =
        ∫ e^{ikv} P(v) dv, with unit variance, is G(q, 0).
    tau : array_like, default (1.0, 10.0, 100.0)
        Increasing, non-negative times τ (collisions per particle, not physical time) at which
        G is saved.
    resolution : str or maxwell_kinetics.grid.Resolution, default "default"
        A name in :data:`maxwell_kinetics.grid.RESOLUTIONS` or a grid.
    options : SolverOptions, optional
        Tolerances and window length; None for the defaults.
    progress : bool, default False
        Show a tqdm progress bar over τ.
    dimension : int, default 1
        Space dimension d ∈ {1, 2, 3}.
    angular : str, default "uniform"
        Angular model ("uniform" or "hard"), used in d ≥ 2.
    angular_nodes : int, default 16
        Scale of the η quadrature's node counts in d ≥ 2 (≥ 1).
    angular_rule : str, default "fast"
        The η rule in d ≥ 2, "fast" or "accurate" (d = 1 has η ≡ 1).
    force : bool, default False
        Run a solve estimated (:func:`maxwell_kinetics.grid.estimate_solve`) to take more than
        :data:`maxwell_kinetics.grid.MAX_SOLVE_SECONDS` (one day) anyway; without it such a
        solve is refused before any work.  The memory check applies either way.

    Returns
    -------
    Solution
        G and G − f̂ on the grid at the saved τ, with the settings and the wall-clock time.

    Ctrl-C: called from Python, an interrupt raises KeyboardInterrupt as usual (Python's own
    SIGINT handler).  The command line instead defers it (:mod:`maxwell_kinetics._interrupt`):
    the loop waits for each chunk of windows (1/200 of the run) and raises KeyboardInterrupt
    between chunks, so that it is neither lost nor raised inside JAX.

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C (see above).
    particles.validation.InvalidArgumentError
        For an invalid restitution, law, time list, resolution, dimension, angular model,
        ``angular_nodes`` or ``angular_rule``; naming ``tau`` for a solve that cannot fit in
        the memory available or (unless ``force``) is estimated to take more than one day, the
        estimate in the message; in d ≥ 2 for r = 1 (naming ``restitution``) or
        a law that is not symmetric (naming ``initial``); naming ``initial`` for a law without
        a finite third moment, ``characteristic`` when φ is not finite where it is sampled.
    FloatingPointError
        If the integration produces a non-finite G.
    """
    checked = check_solve_arguments(restitution, initial, tau, resolution, options=options,
                                    dimension=dimension, angular=angular,
                                    angular_nodes=angular_nodes, angular_rule=angular_rule,
                                    force=force)
    model, law, taus, grid, opts = (checked.model, checked.law, checked.tau, checked.grid,
                                    checked.options)
    angular, angular_nodes, angular_rule = (checked.angular, checked.angular_nodes,
                                            checked.angular_rule)
    start = time.perf_counter()
    q = grid.q
    saved = np.empty((taus.size, grid.n), dtype=complex)
    deviation = np.empty_like(saved)
    m3 = _check_skewness_finite(law)
    g_ref = reference(q, m3).astype(complex)
    g_minus_fhat = deviation_from_f_hat(q, m3)
    if model.lam == 0.0:
        # Elastic collisions exchange velocities: P and hence G never change.
        w0 = initial_deviation(law, q)
        saved[:] = (w0 + g_ref)[None, :]
        deviation[:] = (w0 + g_minus_fhat)[None, :]
        return Solution(model.restitution, law.name, grid, taus, saved, deviation, m3, opts,
                        time.perf_counter() - start)

    stepper = _Stepper(model, law, grid, opts, dimension, angular, angular_nodes, angular_rule)
    _interrupt.check()  # a Ctrl-C deferred by the command line while JAX was loading
    y = stepper.y0
    i_window = 0
    bar = None
    if progress:  # the bar shows the estimate of grid.estimate_solve until its own ETA is known
        from particles.progress import progress_bar

        from .grid import estimate_solve, format_seconds

        cost = estimate_solve(grid, float(taus[-1]), len(taus), dimension=dimension,
                              angular_rule=angular_rule, window=opts.window)
        bar = progress_bar(float(taus[-1]), f"solve r={model.restitution:g}", "τ",
                           postfix=f"estimate ~{format_seconds(cost['seconds'])} after compile")
    chunk = max(1, int(math.ceil(taus[-1] / stepper.dtau / 200)))
    try:
        for k, target in enumerate(taus):
            n_full = int(math.floor(target / stepper.dtau + 1e-12)) - i_window
            while n_full > 0:
                step = min(chunk, n_full)
                y = stepper.advance(y, i_window, step)
                # JAX dispatches asynchronously: wait for this chunk, so that the command
                # line's deferred Ctrl-C is seen within one chunk (1/200 of the run) and raised
                # here, with no JAX computation in flight
                stepper.wait(y)
                _interrupt.check()
                i_window += step
                n_full -= step
                if bar is not None:
                    bar.update(i_window * stepper.dtau - bar.n)
            out = np.asarray(stepper.output(y, i_window, float(target)))
            w = out[0] + 1j * out[1] if stepper.complex else out[0]
            deviation[k] = w + g_minus_fhat
            saved[k] = w + g_ref
            if not np.all(np.isfinite(saved[k])):
                raise FloatingPointError(f"solver produced non-finite G at tau={target}")
    finally:
        if bar is not None:
            bar.update(float(taus[-1]) - bar.n)
            bar.close()
    return Solution(model.restitution, law.name, grid, taus, saved, deviation, m3, opts,
                    time.perf_counter() - start, dimension, angular, angular_rule, angular_nodes)


@dataclass(frozen=True)
class Solution:
    """G(q, τ) on the grid at the saved τ, with evaluation and diagnostics.

    ``G[k, j]`` is G(q_j, tau[k]) for the grid q_j = e^{s_min + j h} (q ≥ 0; G(−q) = conj G(q)).
    ``deviation[k, j]`` is G − f̂ at the same points, computed without the cancellation of
    G − f̂ ≈ (1 − q²/2) − (1 − q²/2) at small q (it is what :meth:`evaluate` interpolates and,
    for ``dimension`` 1, what the distances to f̂ use; they refuse ``dimension`` ≥ 2).
    G(q, τ) = P̂(q / v0(τ), τ) with P̂(k) = ∫ e^{ikv} P(v) dv, q = k·v0(τ); the properties
    ``q`` (the grid) and ``model`` (the :class:`~maxwell_kinetics.model.MaxwellModel`) are
    derived.  Returned by :func:`solve`; saved and loaded with :meth:`save` and :meth:`load`.

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1].
    initial : str
        Name of the initial law.
    resolution : maxwell_kinetics.grid.Resolution
        The q grid.
    tau : numpy.ndarray
        Saved collisions per particle τ, shape (T,).
    G : numpy.ndarray
        Complex, shape (T, n): G on the grid.
    deviation : numpy.ndarray
        Complex, shape (T, n): G − f̂ on the grid.
    skewness : float, default 0.0
        m₃ = ⟨x³⟩ of the initial law (conserved).
    options : SolverOptions
        The time-integration settings used.
    seconds : float, default 0.0
        Wall-clock time of the solve.
    dimension : int, default 1
        Space dimension d.
    angular : str, default "uniform"
        Angular model (d ≥ 2).
    angular_rule : str, default "accurate"
        The η rule of the solve (d = 1: exact, η ≡ 1).
    angular_nodes : int, default 1
        The ``angular_nodes`` of the solve, the scale of its η rule (d = 1: 1, η ≡ 1).
    """

    restitution: float
    initial: str
    resolution: Resolution
    tau: np.ndarray
    G: np.ndarray = field(repr=False)
    deviation: np.ndarray = field(repr=False)
    skewness: float = 0.0
    options: SolverOptions = field(default_factory=SolverOptions)
    seconds: float = 0.0
    dimension: int = 1
    angular: str = "uniform"
    angular_rule: str = "accurate"  # the η rule of solve (d = 1: exact, η ≡ 1)
    angular_nodes: int = 1  # the scale of the η rule of solve (d = 1: 1, η ≡ 1)

    @property
    def q(self) -> np.ndarray:
        """The grid's rescaled wave numbers q_j (``resolution.q``)."""
        return self.resolution.q

    @property
    def model(self) -> MaxwellModel:
        """The :class:`~maxwell_kinetics.model.MaxwellModel` of ``restitution``."""
        return MaxwellModel(self.restitution)

    def time_index(self, tau_index: int) -> int:
        """The non-negative index of saved time ``tau_index`` (negative counts from the end, as
        in Python); :class:`~particles.validation.InvalidArgumentError` naming ``tau_index``
        when there is no such saved time.

        Parameters
        ----------
        tau_index : int
            Index into the saved times, −T ≤ tau_index < T.

        Returns
        -------
        int
            The index in [0, T).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``tau_index``, when it is out of range.
        """
        n = len(self.tau)
        if not -n <= tau_index < n:
            raise InvalidArgumentError("tau_index", tau_index, f"an index into {n} saved times")
        return tau_index % n

    def evaluate(self, q, tau_index: int = -1) -> np.ndarray:
        """G(q) at arbitrary real q, |q| ≤ q_max, by Lagrange interpolation in s = ln|q|.

        Inside the grid G = f̂ + (G − f̂), the deviation interpolated at O(h^order) accuracy;
        below q_min, G = g (the reference, exact to O(q³)).

        Parameters
        ----------
        q : array_like
            Real rescaled wave numbers q = k·v0(τ) with |q| ≤ q_max (any shape; negative q
            gives conj G(|q|)).
        tau_index : int, default -1
            Index of the saved τ (negative counts from the end).

        Returns
        -------
        numpy.ndarray
            Complex G(q), of the shape of ``q``.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``q`` if a value is not finite or beyond the grid's end, or ``tau_index`` if
            it is out of range.
        """
        grid = self.resolution
        q = np.asarray(q, dtype=float)
        a = np.abs(q)
        if np.any(~np.isfinite(a)) or np.any(a > grid.q_max * (1 + 1e-12)):
            bad = q[~(np.isfinite(a) & (a <= grid.q_max * (1 + 1e-12)))].ravel()[:3]
            raise InvalidArgumentError(
                "q", bad.tolist(), f"|q| <= q_max={grid.q_max:.6g} (the grid's end)"
            )
        out = np.array(reference(a, self.skewness), dtype=complex)  # G = g below q_min
        inside = a >= grid.q_min
        dev = self.deviation[self.time_index(tau_index)]
        out[inside] = f_hat(a[inside]) + self._interpolate(dev, a[inside])
        return np.where(q < 0, np.conj(out), out)

    def _interpolate(self, values: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Lagrange interpolation in s = ln q of grid ``values`` at q_min ≤ q ≤ q_max."""
        grid = self.resolution
        order = grid.order
        pos = (np.log(q) - grid.s_min) / grid.h
        first = np.clip(np.floor(pos) - order // 2 + 1, 0, grid.n - order).astype(int)
        x = pos - first  # position within the stencil, in cells
        out = np.zeros(x.shape, dtype=complex)
        for k in range(order):
            wk = np.ones_like(x)
            for m in range(order):
                if m != k:
                    wk *= (x - m) / (k - m)
            out += wk * values[first + k]
        return out

    def _require_one_dimension(self, what: str) -> None:
        if self.dimension != 1:
            raise InvalidArgumentError(
                "dimension", self.dimension,
                f"dimension 1 for {what}: f̂ = (1 + |q|) e^{{−|q|}} is the scaling solution of "
                "the one-dimensional equation only (none is known in closed form for d >= 2)",
            )

    def sup_error(self, tau_index: int | None = None) -> np.ndarray | float:
        """sup over q ≥ 0 of |G(q, τ) − f̂(q)|: on the grid, refined 16× around the maximum.

        Only for ``dimension`` 1 (InvalidArgumentError naming ``dimension`` otherwise): f̂ is
        the scaling solution of the one-dimensional equation, and in d ≥ 2 the distance to it
        does not tend to zero.

        Parameters
        ----------
        tau_index : int, optional
            One saved time; None for all.

        Returns
        -------
        float or numpy.ndarray
            The sup at that time, or shape (T,) for all times.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``dimension`` when d ≥ 2, or ``tau_index`` when out of range.
        """
        self._require_one_dimension("sup_error")
        if tau_index is None:
            return np.array([self.sup_error(k) for k in range(len(self.tau))])
        return self._weighted_sup(self.time_index(tau_index), 0.0, self.resolution.q_min)

    def fourier_distance(self, s: float, tau_index: int | None = None, q_low: float | None = None):
        """d_s(G, f̂) = sup_q |G − f̂| / q^s over q ∈ [q_low, q_max] (default q_low = q_min).

        Restricting the sup to q ≥ q_low gives a lower bound of the full metric, so it obeys the
        contraction bound too; small q_low makes the value sensitive to round-off (|ΔG| ~ 1e-16
        divided by q_low^s) and to the grid's cut at q_min.  Only for ``dimension`` 1,
        as :meth:`sup_error`.  The contraction bound d_s(G(τ), f̂) ≤ e^{−γ(s)τ} d_s(G(0), f̂)
        for s ∈ (2, 3) is that of Bobylev, Cercignani & Toscani (J. Stat. Phys. 2003).

        Parameters
        ----------
        s : float
            Exponent of the metric.
        tau_index : int, optional
            One saved time; None for all.
        q_low : float, optional
            Lower end of the sup; None for the grid's q_min.

        Returns
        -------
        float or numpy.ndarray
            d_s at that time, or shape (T,) for all times.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``dimension`` when d ≥ 2, or ``tau_index`` when out of range.
        """
        self._require_one_dimension("fourier_distance")
        if tau_index is None:
            return np.array([self.fourier_distance(s, k, q_low) for k in range(len(self.tau))])
        q_low = self.resolution.q_min if q_low is None else q_low
        return self._weighted_sup(self.time_index(tau_index), s, q_low)

    def _weighted_sup(self, k: int, s: float, q_low: float) -> float:
        q = self.q
        keep = q >= q_low
        diff = np.abs(self.deviation[k][keep]) / q[keep] ** s
        j = int(np.argmax(diff))
        qk = q[keep]
        lo, hi = qk[max(j - 1, 0)], qk[min(j + 1, qk.size - 1)]
        fine = np.exp(np.linspace(np.log(lo), np.log(hi), 33))
        fine_diff = np.abs(self._interpolate(self.deviation[k], fine)) / fine**s
        return float(max(diff[j], fine_diff.max()))

    def density(self, x=None, tau_index: int = -1):
        """Velocity-space density P(x, τ) of the rescaled velocity x = v / v0: returns ``(x, P)``.

        Units: x = v / v0(τ) with v0² = ⟨v²⟩ = e^{−2λτ} (unit initial variance), so P has unit
        variance; the density of v itself is P(v / v0) / v0.  For ``dimension`` d ≥ 2, x is one
        Cartesian component and v0² = e^{−Λτ} its variance
        (:meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`).

        Sign and normalisation: the characteristic function is P̂(k) = ∫ e^{ikv} P(v) dv
        (so G(q) = E[e^{iqx}]), and its inverse carries e^{−iqx} and 1/(2π):

            P(x) = (1/2π) ∫_{−∞}^{∞} e^{−iqx} G(q) dq = (1/π) Re ∫_0^{q_max} e^{−iqx} G(q) dq,

        using G(−q) = conj G(q) and cutting G at the grid's end q_max.

        ``x=None``: the pyfftw grid of :func:`maxwell_kinetics.velocity.inverse_transform`, the
        trapezoid sum P(x_k) = (dq/2π) Σ_j e^{−2πijk/M} G(q_j), q_j = j dq, j = −M/2 .. M/2:
        pyfftw's ``irfft`` (numpy's normalisation, (1/M) Σ_j X_j e^{+2πijk/M}) of the half
        spectrum X_j = conj G(q_j), multiplied by M dq/2π; x_k = k L/M, k = −M/2 .. M/2 − 1,
        with period L = 2π/dq = 1000 and M the smallest power of two with M dq/2 ≥ q_max.
        Given x, P is computed there by Gauss–Legendre quadrature (no aliasing).  Error sources
        (aliasing of the x⁻⁴ tail, the cut at q_max): :mod:`maxwell_kinetics.velocity`.

        Parameters
        ----------
        x : array_like, optional
            Rescaled velocities at which to evaluate P; None for the FFT grid.
        tau_index : int, default -1
            Index of the saved τ (negative counts from the end).

        Returns
        -------
        x, P : numpy.ndarray
            The velocities and the density there.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``x`` if it is not an array of finite real numbers, or so large that the
            quadrature would exceed :data:`maxwell_kinetics.velocity.MAX_QUADRATURE_NODES` nodes
            or the memory available (panels of width π / max|x|: |x| up to about 9e4; the
            check runs before any work); naming ``tau_index`` if it is out of range.
        """
        from .velocity import invert

        return invert(self._truncated(tau_index), q_max=self.resolution.q_max, x=x)

    def _truncated(self, tau_index: int):
        """G(q) at saved time ``tau_index`` as a callable, zero beyond the grid's end q_max
        (|G| < 1e-13 there once near the scaling solution)."""
        q_max = self.resolution.q_max
        k = self.time_index(tau_index)

        def G(q):
            q = np.asarray(q, dtype=float)
            out = np.zeros(q.shape, dtype=complex)
            inside = np.abs(q) <= q_max
            out[inside] = self.evaluate(q[inside], k)
            return out

        return G

    def speed_density(self, s, tau_index: int = -1):
        """Density of the rescaled speed |v| / v0 in d = ``dimension``: returns ``(s, P)``.

        Units: v0² = e^{−Λτ} is the variance of one component (unit initial variance per
        component, Λ = :meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`; d = 1:
        Λ = 2λ), so ⟨s²⟩ = d and ∫_0^∞ P ds = 1; the density of |v| itself is P(|v| / v0) / v0.

        G(q) is the radial profile Φ(|k|) of the isotropic characteristic function
        E[e^{ik·v/v0}] (the project's sign and normalisation), and P(s) = S_d s^{d−1} f(s) with
        the radial inverse transform f (:func:`maxwell_kinetics.velocity.speed_density_at`,
        where the formulas and the errors are): d = 3, P(s) = (2/π) s ∫_0^{q_max} k sin(ks)
        G(k) dk; d = 2, P(s) = s ∫_0^{q_max} k J₀(ks) G(k) dk; d = 1, P(s) = (2/π) ∫_0^{q_max}
        cos(ks) Re G(k) dk (the density of |x|), G cut at the grid's end q_max as in
        :meth:`density`.  Gauss–Legendre panels, no aliasing.  ``s``: finite speeds ≥ 0
        (InvalidArgumentError naming ``s`` otherwise).

        Parameters
        ----------
        s : array_like
            Rescaled speeds |v| / v0 ≥ 0, finite.
        tau_index : int, default -1
            Index of the saved τ (negative counts from the end).

        Returns
        -------
        s, P : numpy.ndarray
            The speeds (as a float array) and the speed density there.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``s`` for a negative, non-finite, boolean or complex speed or one so large
            that the quadrature would exceed
            :data:`maxwell_kinetics.velocity.MAX_QUADRATURE_NODES` nodes or the memory
            available (about 9e4; checked before any work), or ``tau_index`` when out of range.
        """
        from .velocity import check_speeds, speed_density_at

        s = check_speeds(s, "s")
        G = self._truncated(tau_index)
        return s, speed_density_at(G, s, self.dimension, q_max=self.resolution.q_max)

    def moments(self, orders=(2, 4, 6), tau_index: int | None = None):
        """Even moments at the saved τ, read from G near q = 0: a
        :class:`~maxwell_kinetics.moments.Moments`.

        ``values[k, j]`` is ⟨|v|^n⟩/v₀^n for n = ``orders[j]`` at ``tau[k]`` (d = 1: ⟨x^n⟩ of the
        rescaled velocity x = v/v₀), ``component`` the moments of one Cartesian component,
        ``errors`` their error estimates.  v₀² is the variance of one component, so the order-2
        values are 1 (d = 1) and d.  The q window is chosen per moment and per τ between the
        non-analytic |q|^{2s*} term and the grid's floor (method, and the cases returned as NaN
        with a reason: :mod:`maxwell_kinetics.moments`).  ``orders``: even positive integers
        (InvalidArgumentError naming ``orders`` otherwise); ``tau_index``: one saved time, or
        None for all.

        Parameters
        ----------
        orders : sequence of int, default (2, 4, 6)
            Even positive orders n.
        tau_index : int, optional
            One saved time; None for all.

        Returns
        -------
        maxwell_kinetics.moments.Moments
            One row per selected time.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``orders`` or ``tau_index`` when invalid.
        """
        from .moments import moments_of

        idx = range(len(self.tau)) if tau_index is None else [self.time_index(tau_index)]
        q = self.q
        ref = deviation_from_f_hat(q, self.skewness)
        rows = [(self.deviation[k] - ref).real for k in idx]
        return moments_of(q, rows, self.tau[list(idx)], self.dimension, orders)

    def kurtosis(self) -> np.ndarray:
        """⟨|v|⁴⟩/⟨|v|²⟩² at each saved τ (d = 1: ⟨x⁴⟩/⟨x²⟩², 3 for a Gaussian; d = 2: 2;
        d = 3: 5/3), from :meth:`moments`; NaN where the fourth moment is not resolved.

        Returns
        -------
        numpy.ndarray
            Shape (T,).
        """
        return self.moments(orders=(2, 4)).kurtosis()

    # -- persistence --------------------------------------------------------------------
    def to_record(self) -> tuple[dict, dict[str, np.ndarray]]:
        """(meta, arrays): the JSON-able parameters and the arrays ``tau``, ``G``, ``deviation``
        (what :meth:`save` writes, also used when a comparison saves a solution inside it).

        Returns
        -------
        meta : dict
            restitution, initial, resolution and options (as dicts), skewness, seconds,
            dimension, angular, angular_rule, angular_nodes.
        arrays : dict of str to numpy.ndarray
            ``tau``, ``G`` and ``deviation``.
        """
        meta = {
            "restitution": self.restitution,
            "initial": self.initial,
            "resolution": dataclasses.asdict(self.resolution),
            "skewness": self.skewness,
            "options": dataclasses.asdict(self.options),
            "seconds": self.seconds,
            "dimension": self.dimension,
            "angular": self.angular,
            "angular_rule": self.angular_rule,
            "angular_nodes": self.angular_nodes,
        }
        return meta, {"tau": self.tau, "G": self.G, "deviation": self.deviation}

    @classmethod
    def from_record(cls, meta: dict, arrays: dict, path="solution") -> Solution:
        """Inverse of :meth:`to_record`; a malformed record raises
        :class:`particles.persistence.FileFormatError` naming ``path``.

        Parameters
        ----------
        meta : dict
            The parameters, as :meth:`to_record` writes them (``dimension``, ``angular``,
            ``angular_rule`` and ``angular_nodes`` may be missing: older records; a missing
            ``angular_nodes`` reads as the default 16 in d >= 2, 1 in d = 1).
        arrays : dict
            ``tau``, ``G`` and ``deviation``.
        path : str or os.PathLike, default "solution"
            Name of the source, for the error message.

        Returns
        -------
        Solution
            The rebuilt solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If a key is missing or a value has the wrong type.
        """
        try:
            return cls(
                float(meta["restitution"]),
                str(meta["initial"]),
                Resolution(**meta["resolution"]),
                np.asarray(arrays["tau"]),
                np.asarray(arrays["G"]),
                np.asarray(arrays["deviation"]),
                float(meta["skewness"]),
                SolverOptions(**meta["options"]),
                float(meta["seconds"]),
                int(meta.get("dimension", 1)),
                str(meta.get("angular", "uniform")),
                # files written before the rule existed used the 16-node ("accurate") rule
                str(meta.get("angular_rule", "accurate")),
                int(meta.get("angular_nodes", 16 if int(meta.get("dimension", 1)) > 1 else 1)),
            )
        except (KeyError, ValueError, TypeError) as exc:
            raise persistence.FileFormatError(
                path, f"{type(exc).__name__}: {exc}", "path", "a saved Solution"
            ) from None

    def save(self, path) -> None:
        """Save to ``path`` through :mod:`particles.persistence` (kind ``"solution"``: arrays
        ``tau``, ``G``, ``deviation`` and the parameters as JSON); reload with
        :meth:`Solution.load`.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        """
        meta, arrays = self.to_record()
        persistence.save(path, "solution", _SOLUTION_VERSION, arrays, meta)

    @classmethod
    def load(cls, path) -> Solution:
        """Read a file written by :meth:`save` (also of version 0.1.0); anything else raises
        :class:`particles.persistence.FileFormatError` naming ``path`` and the reason.

        Parameters
        ----------
        path : str or os.PathLike
            The file to read.

        Returns
        -------
        Solution
            The saved solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If the file is not a saved Solution of a known version.
        """
        loaded = persistence.load(path, "solution", (1, _SOLUTION_VERSION),
                                  expected="a saved Solution")
        return cls.from_record(loaded.meta, loaded.arrays, path)
