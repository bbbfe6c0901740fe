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

import math
import time
from typing import NamedTuple

import numpy as np

from particles.initial import LAWS, InitialLaw, first_non_finite, get_law
from particles.validation import (
    InvalidArgumentError,
    check_bool,
    check_count,
    check_times,
)

from . import compile_cache, interrupt
from .deviation import reference
from .grid import INFLOW_CUT, Resolution, check_solve_budget, get_resolution
from .model import MaxwellModel
from .solution import Solution, SolverOptions, deviation_from_f_hat

__all__ = ["solve", "solve_fourier", "check_solve_arguments", "SolveArguments", "Stepper"]


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


class Stepper:
    """The scheme for one (model, law, grid, options): host-side data and the jitted calls
    that :func:`solve` drives window by window (also the handle of the benchmarks and of the
    tests of one right-hand side).

    The compiled functions live in :mod:`maxwell_kinetics._kinetic_scheme` and take r, the
    window and the stencils as traced data, so a new r reuses the compilation of the same
    (grid, law, options).  Every JAX call runs inside ``jax.enable_x64(True)``: float64 for
    this computation without changing JAX's global configuration.

    Parameters
    ----------
    model : MaxwellModel
        The collision model (r, λ, the gain's shifts).
    law : InitialLaw
        The initial velocity law.
    grid : Resolution
        The comoving grid in s = ln q.
    opts : SolverOptions
        The solver's options.
    dimension, angular, angular_nodes, angular_rule : optional
        As in :func:`solve` (d = 1: the angle plays no part).

    Attributes
    ----------
    static, dynamic :
        The scheme's compile-time and traced data; ``y0`` the initial state; ``m3`` the law's
        third moment; ``complex`` whether G is carried as (Re, Im).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``characteristic``) when the law's φ is not finite on the inflow's
        wavenumbers; (argument ``initial``) when its third moment is not finite.
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
        """The state after ``count`` windows from window ``i_start``.

        Parameters
        ----------
        y : jax.Array
            The state (as ``y0``) at the start of window ``i_start``.
        i_start : int
            Index of the first window (τ = i_start Δτ).
        count : int
            Windows to advance.

        Returns
        -------
        jax.Array
            The state at the start of window ``i_start + count`` (dispatched asynchronously:
            :meth:`wait` blocks until it is computed).
        """
        return self._step(y, i_start, count, 0.0)[0]

    def wait(self, y) -> None:
        """Block until the (asynchronously dispatched) state ``y`` is computed.

        Parameters
        ----------
        y : jax.Array
            A state returned by :meth:`advance`.
        """
        import jax

        jax.block_until_ready(y)

    def output(self, y, i_window: int, tau: float):
        """w on the fixed grid at τ.

        Parameters
        ----------
        y : jax.Array
            The state at the start of window ``i_window``.
        i_window : int
            Its window index.
        tau : float
            The time, ≥ ``i_window`` Δτ (within that window).

        Returns
        -------
        jax.Array
            w = G − g at the grid's nodes, shape (parts, n): parts 2 (Re, Im) for a complex G.
        """
        return self._step(y, i_window, 0, tau - i_window * self.dtau)[1]

    def _step(self, y, i_start: int, count: int, t: float):
        """The scheme's one compiled function (``_kinetic_scheme.step``): ``count`` windows
        from ``i_start``, then w at local time ``t`` of the window they end at."""
        with self._x64(True):
            scheme = self._scheme
            return compile_cache.call("step", scheme.step_unjitted, scheme.step, self.static,
                                      (self.dynamic, y, i_start, count, t))


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
    options : maxwell_kinetics.solution.SolverOptions
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
    force = check_bool(force, "force")
    model = MaxwellModel(restitution)
    law = get_law(initial)
    taus = check_times(tau, "tau")
    from .angular import angular_law

    angular_law(dimension, angular)  # checks both
    if dimension != 1:
        angular_nodes = check_count(angular_nodes, "angular_nodes", 1)
        from .angular_tiers import ANGULAR_RULES

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
    if options is not None and not isinstance(options, SolverOptions):
        raise InvalidArgumentError("options", options, "a SolverOptions or None")
    opts = SolverOptions() if options is None else options
    estimate = check_solve_budget(grid, float(taus[-1]), len(taus), window=opts.window,
                                  force=force, dimension=dimension, angular_rule=angular_rule,
                                  angular_nodes=angular_nodes)
    return SolveArguments(model, law, taus, grid, opts, dimension, angular, angular_nodes,
                          angular_rule, estimate)


def solve_fourier(
    restitution: float,
    initial="gaussian",
    tau=(1.0, 10.0, 100.0),
    resolution="default",
    *,
    options: SolverOptions | None = None,
    progress: bool | None = None,
    dimension: int = 1,
    angular: str = "uniform",
    angular_nodes: int = 16,
    angular_rule: str = "fast",
    force: bool = False,
) -> Solution:
    """The Fourier scheme of :func:`solve` (:class:`maxwell_kinetics.methods.FourierScheme`)
    for the Maxwell kernel of restitution r: integrate the rescaled equation from
    G(q, 0) = φ(q) and save G at the requested τ.

    G(q, τ) is the characteristic function of one Cartesian component of the rescaled velocity
    v / v₀(τ), with v₀² = ⟨v_x²⟩ = e^{−Λτ} (unit initial variance per component); τ counts
    collisions per particle.  In d = 1 (the default) it solves

        ∂τ G = λ q ∂q G − G + G(pq) G((1 − p)q),    p = (1 + r)/2,  λ = (1 − r²)/4,

    whose scaling solution is f̂(q) = (1 + |q|) e^{−|q|} for every r < 1.  In d = 2, 3 it solves
    the isotropic inelastic Maxwell model, with η = (k̂·n)² ~ Beta(1/2, (d−1)/2) ("uniform") or
    Beta(1, (d−1)/2) ("hard") and q₁ = 1 − p:

        ∂τ G = (Λ/2) q ∂q G − G + ∫₀¹ w(η) G(q √(1 − (1 − q₁²)η)) G(p q √η) dη,

    Λ = 2 p q₁ ⟨η⟩ (:meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`; Λ = 2λ in d = 1).
    The η integral is a Gauss–Jacobi quadrature whose node count grows with q: ``angular_rule``
    "fast" keeps G within 1e-8 of a converged rule; "accurate" (about 2.3× the cost) is needed
    by the tail fits of :mod:`maxwell_kinetics.scaling_tails`.  The initial law's φ is used as
    the radial profile: in d ≥ 2 it must be a d-dimensional characteristic function (the
    Gaussian is, in every d), symmetric (m₃ = 0), and r < 1.  The distances to f̂
    (:meth:`~maxwell_kinetics.solution.Solution.sup_error`,
    :meth:`~maxwell_kinetics.solution.Solution.fourier_distance`) are defined in d = 1 only.

    Called from Python, Ctrl-C raises ``KeyboardInterrupt`` as usual; the command line defers it
    to the end of the current chunk of windows (:mod:`maxwell_kinetics.interrupt`), so that it
    is neither lost nor raised inside JAX.  The method, its accuracy and its cost:
    :doc:`/guide/kinetic` and :doc:`/performance`.

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
    options : maxwell_kinetics.solution.SolverOptions, optional
        Tolerances and window length; None for the defaults.
    progress : bool or None, optional
        A progress bar over τ: None (default) a bar on a terminal or in a notebook and nothing
        otherwise, True a bar or a few plain lines, False nothing
        (:func:`particles.progress.progress_bar`).
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
    maxwell_kinetics.solution.Solution
        G and G − f̂ on the grid at the saved τ, with the settings and the wall-clock time.

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
        a finite third moment, ``characteristic`` when φ is not finite where it is sampled;
        naming ``force`` when it is not a bool, ``progress`` when it is neither a bool nor None
        (``'no'`` is not False).
    FloatingPointError
        If the integration produces a non-finite G.

    Examples
    --------
    >>> from maxwell_kinetics.solver import solve_fourier
    >>> sol = solve_fourier(0.5, "gaussian", tau=[1, 5], resolution="coarse", progress=False)
    >>> sol.sup_error().shape  # sup_q |G(q, τ) − f̂(q)| at τ = 1 and 5
    (2,)
    """
    progress = check_bool(progress, "progress", none=True)
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
    builtin = LAWS.get(law.name) is law  # a user's law is never taken for a built-in by name
    g_ref = reference(q, m3).astype(complex)
    g_minus_fhat = deviation_from_f_hat(q, m3)
    if model.lam == 0.0:
        # Elastic collisions exchange velocities: P and hence G never change.
        w0 = initial_deviation(law, q)
        saved[:] = (w0 + g_ref)[None, :]
        deviation[:] = (w0 + g_minus_fhat)[None, :]
        return Solution(model.restitution, law.name, grid, taus, saved, deviation, m3, opts,
                        time.perf_counter() - start, builtin_law=builtin)

    stepper = Stepper(model, law, grid, opts, dimension, angular, angular_nodes, angular_rule)
    interrupt.check()  # a Ctrl-C deferred by the command line while JAX was loading
    y = stepper.y0
    i_window = 0
    bar = None
    if progress is not False:  # the bar shows grid.estimate_solve until its own ETA is known
        from particles.progress import progress_bar

        from .grid import format_seconds

        cost = checked.estimate
        bar = progress_bar(float(taus[-1]), f"solve r={model.restitution:g}", "τ",
                           enabled=progress,
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
                interrupt.check()
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
                    time.perf_counter() - start, dimension, angular, angular_rule, angular_nodes,
                    builtin)


#: The keywords of :func:`solve` that configure the Fourier scheme (shorthand for the fields of
#: :class:`maxwell_kinetics.methods.FourierScheme`).
FOURIER_KEYWORDS = ("resolution", "options", "dimension", "angular", "angular_nodes",
                    "angular_rule")


def _kernel_value(kernel):
    """The kernel of :func:`solve`: a kernel as it is (or the one a model holds); a number r is
    the shorthand for the Maxwell kernel :class:`particles.kernels.ConstantRate` (its errors
    name ``restitution``, as before)."""
    from particles.kernels import ConstantRate, Kernel

    value = getattr(kernel, "kernel", kernel)
    if isinstance(value, Kernel):
        return value
    if isinstance(kernel, type) and issubclass(kernel, Kernel):
        raise InvalidArgumentError("kernel", kernel, f"a kernel value such as "
                                   f"{kernel.__name__}(restitution, ...), not the class")
    return ConstantRate(kernel)


def solve(kernel=None, initial="gaussian", times=None, method=None, *, tau=None, t=None,
          density=None, progress: bool | None = None, force: bool = False, **fourier):
    """Solve the homogeneous kinetic equation of a collision kernel from an initial law, and
    save the solution at the requested times.

    The physics is the ``kernel`` (:mod:`particles.kernels`: its post-collision map, its rate
    and the time it counts), the numerics the ``method`` (:mod:`maxwell_kinetics.methods`):

    * :class:`~maxwell_kinetics.methods.FourierScheme` (the default for kernels whose
      Fourier-space equation closes, such as the Maxwell kernel ``ConstantRate``): the rescaled
      characteristic function G(q, τ) in τ, collisions per particle, in d = 1, 2, 3
      (:func:`solve_fourier`, whose docstring states the equation and the method).  A number r
      as ``kernel`` is the shorthand for ``ConstantRate(r)``, and the keywords ``resolution``,
      ``options``, ``dimension``, ``angular``, ``angular_nodes`` and ``angular_rule`` for the
      fields of a FourierScheme, so ``solve(0.5, "gaussian", tau=[1, 5],
      resolution="coarse")`` works as it always did; a resolution as the fourth argument is
      the same as ``FourierScheme(resolution)``.
    * :class:`~maxwell_kinetics.methods.VelocitySpace` (the default for kernels of physical
      time t whose rate is homogeneous in |v − w|, such as ``RelativeVelocity``): f(v, t) on a
      velocity grid in d = 1 at density n
      (:func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`).
    * :class:`~maxwell_kinetics.methods.SphereSpectral` (the default for the hard-sphere kernels
      of :mod:`particles.sphere_kernels`, d = 3; ``dimension=2`` alone chooses it in d = 2):
      the spectral scheme of :func:`maxwell_kinetics.sphere_spectral.solve_spheres`.

    Every result satisfies one contract (:mod:`maxwell_kinetics.kinetic_result`): its time axis
    and the time's name come from the kernel.

    Parameters
    ----------
    kernel : particles.kernels.Kernel or float
        The collision kernel, or r ∈ [0, 1] for the Maxwell kernel.
    initial : str or particles.initial.InitialLaw, default "gaussian"
        The initial law (zero mean, unit variance).
    times : array_like, optional
        Increasing times ≥ 0 in the kernel's time (τ or t) at which to save the solution;
        for the Fourier scheme, default (1, 10, 100).
    method : FourierScheme or VelocitySpace or SphereSpectral or str, optional
        The method (default: :func:`maxwell_kinetics.methods.method_for`); a resolution name
        or :class:`maxwell_kinetics.grid.Resolution` means ``FourierScheme(resolution)``.
    tau, t : array_like, optional
        The times by the name of the kernel's time (instead of ``times``).
    density : float, optional
        n > 0 (default 1), for a kernel of time t: particles per unit length.
    progress : bool or None, optional
        The Fourier scheme's progress bar (:func:`solve_fourier`); the velocity-space scheme,
        one call of diffrax, shows none (Ctrl-C still stops it within 0.1 s).
    force : bool, default False
        Run a solve estimated to take more than a day anyway (:func:`solve_fourier`,
        :func:`maxwell_kinetics.inelastic_boltzmann.estimate_seconds`); the velocity-space
        scheme's reach (:func:`maxwell_kinetics.inelastic_boltzmann.check_reach`) is a limit
        of the method, which ``force`` does not lift.
    **fourier
        ``resolution``, ``options``, ``dimension``, ``angular``, ``angular_nodes``,
        ``angular_rule``: shorthand for a :class:`~maxwell_kinetics.methods.FourierScheme`.

    Returns
    -------
    maxwell_kinetics.solution.Solution or maxwell_kinetics.boltzmann_solution.BoltzmannSolution
        The solution of the method.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Before any work: naming ``kernel`` for a value that is not a kernel (``restitution``
        for a number out of [0, 1]), ``method`` for a method that does not carry the kernel
        (with the reason) or that is not a method, ``times``/``tau``/``t`` for times given twice
        or under the other time's name, ``density`` for a kernel of time τ, a Fourier keyword
        given with a method object or with a kernel the Fourier scheme does not carry; and
        everything :func:`solve_fourier` and
        :func:`~maxwell_kinetics.inelastic_boltzmann.solve_boltzmann` refuse.
    TypeError
        For a keyword that is none of the above.
    KeyboardInterrupt
        On Ctrl-C (:func:`solve_fourier`).
    FloatingPointError, RuntimeError
        If the integration fails (non-finite values, too many steps).

    Examples
    --------
    >>> from maxwell_kinetics import solve
    >>> from particles.kernels import ConstantRate
    >>> sol = solve(ConstantRate(0.5), "gaussian", [1, 5], "coarse", progress=False)
    >>> sol.time_name, sol.sup_error().shape
    ('tau', (2,))
    """
    from .methods import FourierScheme, SphereSpectral, VelocitySpace, method_for

    if "restitution" in fourier or "r" in fourier:
        raise TypeError("solve() takes the kernel first, solve(kernel, initial, times, method): "
                        "a kernel of particles.kernels or a restitution r for the Maxwell "
                        "kernel, as the first argument (not restitution= or r=)")
    unknown = sorted(set(fourier) - set(FOURIER_KEYWORDS))
    if unknown:
        raise TypeError(f"solve() got an unexpected keyword argument {unknown[0]!r}")
    value = _kernel_value(kernel)
    given = {name: v for name, v in (("times", times), ("tau", tau), ("t", t)) if v is not None}
    if len(given) > 1:
        name = "tau" if "tau" in given else "t"
        raise InvalidArgumentError(name, given[name], f"the times once (given as "
                                   f"{' and '.join(sorted(given))})")
    if "tau" in given and value.time_name != "tau" or "t" in given and value.time_name != "t":
        name = next(iter(given))
        raise InvalidArgumentError(name, given[name], f"times named {value.time_name!r}: the "
                                   f"kernel {value.name!r} counts "
                                   + ("collisions per particle tau" if value.time_name == "tau"
                                      else "physical time t"))
    chosen = next(iter(given.values()), None)
    if method is None or isinstance(method, str) or type(method).__name__ == "Resolution":
        if method is not None:
            if "resolution" in fourier:
                raise InvalidArgumentError("resolution", fourier["resolution"], "the "
                                           "resolution once (the fourth argument is one)")
            fourier = {**fourier, "resolution": method}
        elif not fourier:
            method = method_for(value)
        elif set(fourier) == {"dimension"} and SphereSpectral.refusal(value) is None:
            method = SphereSpectral(dimension=fourier.pop("dimension"))
        if fourier or method is None:
            method = FourierScheme(**fourier)
    elif fourier:
        name = sorted(fourier)[0]
        raise InvalidArgumentError(name, fourier[name], "no Fourier-scheme keyword with a "
                                   "method object (set it on the method)")
    if not isinstance(method, (FourierScheme, VelocitySpace, SphereSpectral)):
        raise InvalidArgumentError("method", method, "a method of maxwell_kinetics.methods "
                                   "(FourierScheme or VelocitySpace or SphereSpectral) or a "
                                   "resolution name")
    reason = method.refusal(value)
    if reason is not None:
        raise InvalidArgumentError("method", method, f"a method that carries the kernel: "
                                   f"{reason}")
    if isinstance(method, FourierScheme):
        if density is not None:
            raise InvalidArgumentError("density", density, f"no density with the kernel "
                                       f"{value.name!r} (its time tau counts collisions per "
                                       f"particle, whatever the density)")
        return solve_fourier(value.restitution, initial,
                             (1.0, 10.0, 100.0) if chosen is None else chosen,
                             method.resolution, options=method.options, progress=progress,
                             dimension=method.dimension, angular=method.angular,
                             angular_nodes=method.angular_nodes,
                             angular_rule=method.angular_rule, force=force)
    check_bool(progress, "progress", none=True)
    if chosen is None:
        raise InvalidArgumentError("t", None, "increasing times t >= 0 (the kernel "
                                   f"{value.name!r} has no default times)")
    if isinstance(method, SphereSpectral):
        from .sphere_spectral import solve_spheres

        return solve_spheres(value, chosen, dimension=method.dimension,
                             density=1.0 if density is None else density, initial=initial,
                             grid=method.grid, rtol=method.rtol, atol=method.atol,
                             max_steps=method.max_steps, force=force)
    from .inelastic_boltzmann import solve_boltzmann

    return solve_boltzmann(value, chosen, density=1.0 if density is None else density,
                           initial=initial, grid=method.grid, rtol=method.rtol,
                           atol=method.atol, max_steps=method.max_steps, force=force)


#: Names that lived here and moved (an import from here names the new home).
_MOVED = {"source": "maxwell_kinetics.deviation"}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"maxwell_kinetics.solver.{name} moved to {_MOVED[name]}.{name}")
    raise AttributeError(f"module 'maxwell_kinetics.solver' has no attribute {name!r}")
