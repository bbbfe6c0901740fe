"""The homogeneous 1D inelastic Boltzmann equation with collision rate n|v − w|^γ, solved in
velocity space (γ = 1: hard rods, the kinetic equation of molecular dynamics under molecular
chaos; γ = 0: the Maxwell model in physical time t, τ = n t).

Equation (weak form, any test function φ; density n, physical time t):

    d/dt ∫φ f dv = (n/2) ∫∫ |v − w|^γ f(v) f(w) [φ(v′) + φ(w′) − φ(v) − φ(w)] dv dw,

v′ = (1 − p) v + p w, w′ = (1 − p) w + p v, p = (1 + r)/2
(:class:`maxwell_kinetics.model.RelativeVelocityModel`).  Mass and momentum are conserved and
d⟨v²⟩/dt = −λ n ⟨|v − w|^{γ+2}⟩, λ = (1 − r²)/4.

Method.  The unknown is F(c, t) = s f(u + s c, t), the law of the rescaled velocity
c = (v − u)/s(t) about the conserved mean u, on a uniform grid c_i = (i − (N − 1)/2) h of
half-width L (:class:`maxwell_kinetics.velocity_grid.VelocityGrid`).  In c the equation reads

    ∂_t F = n s^γ [Q_γ(F, F) + σ′ ∂_c(c F)],    d ln s/dt = n s^γ σ′,

and σ′ = ∫c² Q_γ / (2∫c² F) keeps ∫c² F constant (= 1): the grid follows the cooling.  The
collision term is collocated at the nodes (:mod:`maxwell_kinetics._boltzmann_scheme`): the gain
at c_k is an integral over the partner that keeps the fraction 1 − p, by the trapezoid rule with
F interpolated (sixth order) at the other partner's velocity, and the generalised
Euler–Maclaurin correction at the non-smooth point v = w (0 < γ < 2); a correction
F (α + β c + δ c²) then makes the discrete mass and momentum change exactly zero and the energy
change exactly −λ Σ h² F_i F_j |c_i − c_j|^{γ+2} (the solution's own ⟨|v − w|^{γ+2}⟩).  The
dilation is an eighth-order central difference in flux form.  Time: diffrax's ``Tsit5`` with a
PID controller, from one output time to the next; the compiled solve is kept in the project's
store of compiled executables (:mod:`maxwell_kinetics._boltzmann_compiled`).

Order.  Interpolation O(h⁶); the trapezoid rule spectral for γ = 0 and 2, O(h^{γ+3}) after the
correction otherwise (γ = 1: O(h⁴)); dilation O(h⁸).  Measured (benchmarks/README.md,
``hard_rods.py``): γ = 0, r = 0.5, τ = 2, P(x) against the Fourier solver: 6.6e-6 at h = 0.25,
1.6e-7 at h = 0.125 (a factor 43, order ≈ 5.4).

Grid. The initial law is sampled at the nodes (the derivative of its CDF, sixth order), then
multiplied by 1 + a + b c + d c² with the three numbers that make the discrete mass 1, mean 0 and
⟨c²⟩ 1. A grid whose extent leaves more than
:data:`~maxwell_kinetics.velocity_grid.EXTENT_TOLERANCE` of the law's mass outside, or whose raw
moments are off by more than :data:`maxwell_kinetics.velocity_grid.RESOLUTION_TOLERANCE`, is
refused with the size needed. The grid cannot follow a tail that outgrows it (γ = 0, whose scaling
state has an |x|⁻⁴ tail): the solution records the largest mass fraction found in the two outermost
cells (:attr:`BoltzmannSolution.edge_mass`). For such tails a
:class:`maxwell_kinetics.velocity_grid.MappedGrid` c = a sinh(s) keeps the core spacing and reaches
|c| of thousands with a few hundred points (trapezoid weights g′(s) h_s, interpolation in s, the
dilation (1/g′) ∂_s(c F) in flux form, the same exact corrections with the mapped weights); the
uniform grid stays the default.

Every JAX call runs inside ``jax.enable_x64(True)`` (the caller's setting is restored).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from particles import kernels as _kernels
from particles.initial import get_law
from particles.validation import (
    InvalidArgumentError,
    check_bool,
    check_count,
    check_positive,
    check_real_array,
    check_times,
)

from . import interrupt
from . import velocity_grid as _grid
from .boltzmann_solution import BoltzmannSolution, moment_order
from .boltzmann_solution import interpolate_nodes as _interpolate
from .grid import FORCE, MAX_SOLVE_SECONDS
from .model import RelativeVelocityModel

__all__ = ["solve_boltzmann", "scaling_state", "ScalingState",
           "SCALING_GRID", "check_reach", "SMALLEST_SCALE", "STEPS_PER_TAU_AND_STIFFNESS",
           "carries", "grid_kernel", "kernel_of", "EDGE_TOLERANCE", "estimate_seconds",
           "SECONDS_PER_STEP_AND_PAIR", "relaxation_steps", "RELAXATION_MAX_STEPS"]


def carries(kernel) -> bool:
    """Whether this velocity-space solver carries a kernel (a class or an instance): one of
    physical time t, defined in d = 1, with its rate written out, whose rate depends on
    |v − w| alone and is homogeneous in it (it declares
    :attr:`particles.kernels.Kernel.homogeneity`).

    Parameters
    ----------
    kernel : type or particles.kernels.Kernel
        A kernel class or instance.

    Returns
    -------
    bool
    """
    cls = kernel if isinstance(kernel, type) else type(kernel)
    return (issubclass(cls, _kernels.Kernel) and cls.time_name == "t" and 1 in cls.dimensions
            and _kernels.defines_rate(cls)
            and cls.homogeneity is not _kernels.Kernel.homogeneity)


#: Speeds at which :func:`grid_kernel` checks that a rate is homogeneous of its declared degree.
_PROBES = np.array([0.25, 0.5, 2.0, 3.0])


def grid_kernel(kernel, argument: str = "kernel") -> _kernels.Kernel:
    """The kernel as this solver carries it, checked before any work: a
    :class:`particles.kernels.Kernel` (or a model that holds one, such as
    :class:`maxwell_kinetics.model.RelativeVelocityModel`) that :func:`carries` accepts, whose
    degree γ lies in [0, 2] and whose rate is homogeneous of that degree,
    R(v, w) = R(1, 0) |v − w|^γ with R(1, 0) > 0, at |v − w| = 0.25, 0.5, 2 and 3 (to 1e-12,
    both signs of v − w).

    Parameters
    ----------
    kernel : particles.kernels.Kernel or RelativeVelocityModel
        The kernel.
    argument : str, optional
        The argument's name in errors.

    Returns
    -------
    particles.kernels.Kernel

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument`` for anything else, with the reason.
    """
    value = getattr(kernel, "kernel", kernel)
    if not isinstance(value, _kernels.Kernel):
        raise InvalidArgumentError(argument, kernel, "a collision kernel "
                                   "(particles.kernels.Kernel)")
    if not carries(value):
        raise InvalidArgumentError(argument, kernel, "a kernel of physical time t in d = 1 whose "
                                   "rate is a power of |v - w| (it declares its homogeneity): "
                                   "the velocity-space solver follows the cooling by rescaling "
                                   "velocities")
    gamma = value.homogeneity
    if (isinstance(gamma, bool) or not isinstance(gamma, (int, float))
            or not 0.0 <= gamma <= 2.0):
        raise InvalidArgumentError(argument, kernel, f"a homogeneity in [0, 2], not {gamma!r}")
    unit = _unit_rate(value)
    for sign in (1.0, -1.0):
        got = np.asarray(value.rate(sign * _PROBES, np.zeros_like(_PROBES), np), dtype=float)
        if not (unit > 0.0 and np.all(np.isfinite(got))
                and np.allclose(got, unit * _PROBES**gamma, rtol=1e-12, atol=0.0)):
            raise InvalidArgumentError(argument, kernel, f"a rate R(1, 0) |v - w|^{gamma:g} "
                                       f"with R(1, 0) > 0, as its homogeneity {gamma:g} "
                                       f"declares (got R = {got.tolist()} at |v - w| = "
                                       f"{_PROBES.tolist()})")
    return value


def _coefficients(kernel: _kernels.Kernel) -> tuple[float, float, float]:
    """1 − p, p and λ = (1 − r²)/4 of a kernel, computed as
    :class:`~maxwell_kinetics.model.RelativeVelocityModel` computes them."""
    model = RelativeVelocityModel(kernel.restitution, exponent=0.0)
    return model.complement, model.p, model.lam


def _unit_rate(kernel: _kernels.Kernel) -> float:
    """R(1, 0): the kernel's rate at |v − w| = 1."""
    return float(kernel.rate(np.float64(1.0), np.float64(0.0), np))


#: Smallest thermal scale s(t) = √(⟨v²⟩(t)/⟨v²⟩(0)) a solve with γ > 0 may be asked to reach.
#: Measured (r = 0.5, default grid): the explicit integration stalls once s falls below about
#: 1e-18 (γ = 1: ran to s = 2.4e-19, stalled by s = 8e-20; γ = 0.5: ran to 1.5e-17, stalled by
#: 5e-19), long after the gas has reached its cooling state (:func:`scaling_state`).
SMALLEST_SCALE = 1e-15
#: Time steps per unit of τ = n t and of the grid's stiffness max |c_i|/(spacing at c_i) (the
#: dilation's stability limit); at γ = 0, r = 0.5, stiffness 200: 225 steps to τ = 10.
STEPS_PER_TAU_AND_STIFFNESS = 0.15


def _steps_per_unit_time(kernel: _kernels.Kernel, grid) -> float:
    """Time steps per unit of n t at γ = 0: :data:`STEPS_PER_TAU_AND_STIFFNESS` · R(1, 0) times
    the grid's stiffness max |c_i|/(spacing at c_i) (the dilation's stability limit)."""
    c = grid.c
    spacing = grid.weights if isinstance(grid, _grid.MappedGrid) else np.full(c.size, grid.h)
    return (STEPS_PER_TAU_AND_STIFFNESS * _unit_rate(kernel)
            * float(np.max(np.abs(c) / spacing)))


def check_reach(model: RelativeVelocityModel, density: float, t_last: float, grid,
                max_steps: int) -> None:
    """Refuse, before any work, a last time the solve cannot reach.

    γ > 0: the thermal scale s(t) predicted by Haff's law for the rate n|v − w|^γ from a
    Gaussian, s = (1 + γ λ n κ t/2)^{−1/γ} with κ = ⟨|v − w|^{γ+2}⟩/⟨v²⟩^{(γ+2)/2} =
    2^{γ+2} Γ((γ + 3)/2)/√π, must stay above :data:`SMALLEST_SCALE`.  γ = 0: the estimated
    number of time steps, :data:`STEPS_PER_TAU_AND_STIFFNESS` · n t · max |c_i|/spacing_i,
    must not pass ``max_steps`` (the solve would run that many steps and then fail).

    Parameters
    ----------
    model : maxwell_kinetics.model.RelativeVelocityModel
        The kernel (r, γ).
    density : float
        n.
    t_last : float
        The last time asked for.
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid.
    max_steps : int
        The solve's step limit.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``t``, with the largest time that can be reached.
    """
    kernel = grid_kernel(model, "model")
    gamma, lam = kernel.homogeneity, _coefficients(kernel)[2]
    if gamma > 0.0:
        kappa = 2.0 ** (gamma + 2.0) * math.gamma((gamma + 3.0) / 2.0) / math.sqrt(math.pi)
        rate = lam * density * kappa * _unit_rate(kernel) / 2.0
        # s(t) < SMALLEST_SCALE  <=>  1 + γ rate t > SMALLEST_SCALE^(−γ) = e^(γL), L = −ln S:
        # t > (e^(γL) − 1)/(γ rate) = (L/rate) expm1(γL)/(γL), written without the cancellation
        # of e^(γL) − 1 (0 in floating point for γ below ~1e-16) and without the product γ rate
        # (which underflows), so that a tiny γ reaches its limit L/rate (the Maxwell model's
        # s = e^(−rate t)) instead of t <= 0
        scaled = -gamma * math.log(SMALLEST_SCALE)
        reach = (-math.log(SMALLEST_SCALE) / rate * (math.expm1(scaled) / scaled)
                 if rate > 0.0 else math.inf)
        if t_last > reach:
            raise InvalidArgumentError(
                "t", t_last, f"a last time t <= {reach:.3g} here, where the thermal scale "
                f"sqrt(E(t)/E(0)) is still above {SMALLEST_SCALE:g} (beyond it the integration "
                "stalls; the gas has long reached its cooling state, which fixed-point --kernel "
                "relative_velocity / scaling_state gives)")
        return
    per_tau = _steps_per_unit_time(kernel, grid)
    steps = per_tau * density * t_last
    if steps > max_steps:
        raise InvalidArgumentError(
            "t", t_last, f"a last time t <= {max_steps / (per_tau * density):.3g} here (about "
            f"{per_tau:.3g} time steps per unit of n t on this grid, at most max_steps = "
            f"{max_steps} in all; raise max_steps in Python for longer solves)")


#: Seconds per time step and per pair of grid nodes (N² per step: the gain's gather and the
#: loss's matrix product, over the integrator's stages).  Measured on 401 points at γ = 0,
#: r = 0.5 (load about 5 on 2 cores): 1.7e-7 to t = 10 (225 steps, 6.1 s), 1.9e-7 to t = 40
#: (1134 steps, 34 s).
SECONDS_PER_STEP_AND_PAIR = 2e-7


def estimate_seconds(kernel, grid, density: float, t_last: float) -> float | None:
    """The estimated wall time of a velocity-space solve, before any work: for γ = 0 the
    steps of :func:`check_reach` times N² :data:`SECONDS_PER_STEP_AND_PAIR`; None for γ > 0,
    whose steps grow only slowly with t (the rescaled time n s^γ t of a cooling gas grows like
    ln t) and whose reach :func:`check_reach` bounds.

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        The kernel (:func:`grid_kernel`).
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid.
    density : float
        n.
    t_last : float
        The last time.

    Returns
    -------
    float or None
        Seconds.
    """
    kernel = grid_kernel(kernel)
    if kernel.homogeneity > 0.0:
        return None
    steps = _steps_per_unit_time(kernel, grid) * density * t_last
    return steps * grid.c.size**2 * SECONDS_PER_STEP_AND_PAIR


def _padded(times: np.ndarray) -> np.ndarray:
    """The times, the last repeated up to a multiple of 8 (one compilation for up to 8 times)."""
    size = 8 * math.ceil(times.size / 8)
    return np.concatenate([times, np.full(size - times.size, times[-1])])


class _Compiled:
    """The compiled solve, right-hand side, steady residual and Jacobian, kept in the store of
    compiled executables (:class:`maxwell_kinetics._boltzmann_compiled.Functions`)."""

    @staticmethod
    def get():
        from . import _boltzmann_compiled

        return _boltzmann_compiled.Functions.get()


def _unit(grid) -> np.ndarray:
    """The scale of the time integrator's unknown on a grid: the integrator advances unit · F,
    so that its absolute tolerance bounds each node's contribution to ⟨c⁴⟩ (ω (1 + c⁴) F in
    units of the core spacing), not F itself: on a
    :class:`maxwell_kinetics.velocity_grid.MappedGrid` a node at |c| ~ 10³ weighs ~10¹⁴ times more
    in ⟨c⁴⟩ than one in the core.  1 on the uniform grid."""
    if isinstance(grid, _grid.MappedGrid):
        c = grid.c
        return grid.weights / grid.core_spacing * (1.0 + c**4)
    return np.ones(grid.points)


def tables_for(model, grid: _grid.VelocityGrid):
    """The collision tables of a kernel on ``grid`` as JAX float64 arrays (call inside
    ``jax.enable_x64(True)``): its rate at every pair of nodes (:meth:`Kernel.rate
    <particles.kernels.Kernel.rate>`), its degree γ and the coefficient R(1, 0)·(−2ζ(−γ)) of the
    correction of the node v = w.

    Parameters
    ----------
    model : particles.kernels.Kernel or RelativeVelocityModel
        The kernel (:func:`grid_kernel`).
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid.

    Returns
    -------
    dict
        As :func:`maxwell_kinetics._boltzmann_scheme.collision_tables`, JAX arrays.
    """
    import jax.numpy as jnp
    from scipy.special import zeta

    from . import _boltzmann_scheme as scheme

    kernel = grid_kernel(model, "model")
    gamma = float(kernel.homogeneity)
    keep, p, _ = _coefficients(kernel)
    kink = 0.0 if gamma in (0.0, 2.0) else -2.0 * float(zeta(-gamma)) * _unit_rate(kernel)
    c = np.asarray(grid.c, dtype=float)
    rate = np.array(np.broadcast_to(kernel.rate(c[:, None], c[None, :], np),
                                    (c.size, c.size)), dtype=float)
    if isinstance(grid, _grid.MappedGrid):
        tables = scheme.mapped_collision_tables(c, grid.spacing, grid.position, keep, p, rate,
                                                gamma, kink)
        tables["unit"] = _unit(grid)
    else:
        tables = scheme.collision_tables(c, keep, p, rate, gamma, kink)
    return {k: jnp.asarray(v) for k, v in tables.items()}


def kernel_of(kernel, exponent=None, restitution=None, argument: str = "kernel"):
    """The kernel of a velocity-space solve from its arguments (:func:`grid_kernel`): a kernel
    as it is, or a restitution r, the shorthand for
    ``particles.kernels.RelativeVelocity(r, exponent)`` (γ = 1 by default).

    Parameters
    ----------
    kernel : particles.kernels.Kernel, RelativeVelocityModel or float
        The kernel, or r.
    exponent : float, optional
        γ, with a restitution only.
    restitution : float, optional
        r by its former keyword (instead of ``kernel``).
    argument : str, optional
        The first argument's name in errors.

    Returns
    -------
    particles.kernels.Kernel

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``restitution`` or ``exponent`` when out of range, ``exponent`` when given with a
        kernel, ``argument`` for a kernel this solver does not carry, ``restitution`` when
        given together with ``kernel``.
    """
    if restitution is not None:
        if kernel is not None:
            raise InvalidArgumentError("restitution", restitution, f"no restitution with "
                                       f"{argument}= (the kernel holds it)")
        kernel = restitution
    if isinstance(getattr(kernel, "kernel", kernel), _kernels.Kernel):
        if exponent is not None:
            raise InvalidArgumentError("exponent", exponent, "no exponent with a kernel (the "
                                       "kernel holds its own parameters)")
        return grid_kernel(kernel, argument)
    return grid_kernel(_kernels.RelativeVelocity(kernel, 1.0 if exponent is None
                                                 else exponent), argument)


def solve_boltzmann(kernel=None, t=None, *, exponent=None, density=1.0, initial="gaussian",
                    grid: _grid.VelocityGrid | None = None, rtol: float = 1e-10,
                    atol: float = 1e-13, max_steps: int = 1_000_000,
                    restitution=None, force: bool = False) -> BoltzmannSolution:
    """Solve the homogeneous 1D inelastic Boltzmann equation of a kernel whose rate is
    R(1, 0) n|v − w|^γ from an initial law to the times ``t`` (module docstring).

    Ctrl-C: the integration runs in a worker thread while the calling thread waits, so that a
    KeyboardInterrupt (or the command line's deferred Ctrl-C, :mod:`maxwell_kinetics.interrupt`)
    is raised within 0.1 s; the abandoned integration finishes in the background.

    Parameters
    ----------
    kernel : particles.kernels.Kernel or float
        A kernel this solver carries (:func:`grid_kernel`), or a restitution r ∈ [0, 1]: the
        shorthand for ``particles.kernels.RelativeVelocity(r, exponent)``.
    t : array_like
        Increasing physical times ≥ 0 at which to save the solution.
    exponent : float, optional
        With a restitution only: γ of the rate (default 1: hard rods; 0: Maxwell), in
        :data:`maxwell_kinetics.model.RATE_EXPONENTS`.
    restitution : float, optional
        The former name of the first argument, still accepted by keyword.
    density : float, default 1.0
        n > 0, particles per unit length.
    initial : str or particles.initial.InitialLaw, default "gaussian"
        The initial law (zero mean, unit variance, with a CDF): ⟨v²⟩ = 1 at t = 0.
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`), optional
        The grid of c; default :func:`maxwell_kinetics.velocity_grid.default_grid` (uniform).  A
        :class:`maxwell_kinetics.velocity_grid.MappedGrid` for γ = 0 only.
    rtol, atol : float
        Tolerances of the step-size controller (RMS norm over the grid and ln s), > 0;
        ``rtol`` < 1 too (a relative error of 1 or more controls nothing).
    max_steps : int
        Most time steps.
    force : bool, default False
        Run a solve estimated (:func:`estimate_seconds`) to take more than
        :data:`maxwell_kinetics.grid.MAX_SOLVE_SECONDS` (one day) anyway.

    Returns
    -------
    BoltzmannSolution
        f on the grid at every time, with its moments.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel`` (not a kernel this solver carries), ``restitution``, ``exponent``
        (also when given with a kernel), ``density``, ``t``, ``initial``, ``points``,
        ``half_width`` or ``core_spacing`` for bad input
        (:func:`maxwell_kinetics.velocity_grid.initial_values`), ``grid`` for a
        :class:`maxwell_kinetics.velocity_grid.MappedGrid` with γ > 0 or not a grid, ``rtol`` or
        ``atol`` if not positive (``rtol`` if not below 1), ``max_steps`` if not an integer
        >= 1.
        ``t`` for a last time beyond the solver's reach (:func:`check_reach`) or, unless
        ``force``, estimated to take more than a day, before any work; ``force`` if not a bool.
    RuntimeError
        If the time integration fails (too many steps).
    KeyboardInterrupt
        On Ctrl-C (above).
    """
    kernel = kernel_of(kernel, exponent, restitution)
    gamma = float(kernel.homogeneity)
    if t is None:
        raise InvalidArgumentError("t", t, "increasing times t >= 0")
    grid = None if grid is None else _grid.check_grid(grid)
    if isinstance(grid, _grid.MappedGrid) and gamma != 0.0:
        raise InvalidArgumentError("grid", grid, "a uniform VelocityGrid for exponent="
                                   f"{gamma:g} (the MappedGrid is for gamma = 0: at "
                                   "gamma > 0 it can grow an oscillation at its ends)")
    n = check_positive(density, "density")
    times = check_times(t, "t", strictly=True)
    if times.size == 0 or times[0] < 0:
        raise InvalidArgumentError("t", t, "increasing times t >= 0")
    if not check_positive(rtol, "rtol") < 1.0:
        raise InvalidArgumentError("rtol", rtol, "a relative tolerance in (0, 1)")
    check_positive(atol, "atol")
    max_steps = check_count(max_steps, "max_steps", 1)
    grid = _grid.default_grid(gamma) if grid is None else grid
    check_reach(kernel, n, float(times[-1]), grid, max_steps)
    force = check_bool(force, "force")
    cost = estimate_seconds(kernel, grid, n, float(times[-1]))
    if cost is not None and cost > MAX_SOLVE_SECONDS and not force:
        raise InvalidArgumentError("t", t, f"a solve estimated to take at most "
                                   f"{MAX_SOLVE_SECONDS:g} s (this one: about {cost:.3g} s); "
                                   f"fewer points or an earlier last time, or {FORCE}")
    law = get_law(initial)
    F0 = _grid.initial_values(law, grid)
    import jax.numpy as jnp

    start = time.perf_counter()
    unit = np.append(_unit(grid), 1.0)

    def integrate():  # in a worker thread: the caller stays free to take Ctrl-C
        import jax

        with jax.enable_x64(True):
            functions = _Compiled.get()
            args = (tables_for(kernel, grid), jnp.asarray(grid.c), grid.step, n, gamma,
                    _coefficients(kernel)[2])
            y0 = jnp.asarray(np.append(F0, 0.0) * unit)
            ys, ok, steps = functions.solve(y0, jnp.asarray(_padded(times)), args, rtol, atol,
                                            int(max_steps))
            ys = np.asarray(ys)[:times.size]
            if not bool(ok):
                raise RuntimeError(f"the time integration failed (steps: {int(steps)}, "
                                   f"max_steps={max_steps})")
            return ys, np.asarray(functions.rhs(jnp.asarray(ys), args)), int(steps)

    ys, rates, steps = interrupt.run_interruptibly(integrate, "velocity-space solve")
    if isinstance(grid, _grid.MappedGrid):
        ys, rates = ys / unit, rates / unit
    seconds = time.perf_counter() - start
    F, log_s = ys[:, :-1], ys[:, -1]
    s2 = np.exp(2.0 * log_s)
    if isinstance(grid, _grid.MappedGrid):
        c, w = grid.c, grid.weights
        energy_rate = s2 * (rates[:, :-1] @ (w * c * c) + 2.0 * rates[:, -1] * (F @ (w * c * c)))
        ends = [0, 1, -2, -1]
        edge = np.max(np.abs(F[:, ends]) * w[ends], axis=1)
    else:
        c, h = grid.c, grid.h
        # dE/dt = d(s² Σ h c² F)/dt = s² (Σ h c² dF/dt + 2 (d ln s/dt) Σ h c² F)
        energy_rate = s2 * (h * rates[:, :-1] @ (c * c)
                            + 2.0 * rates[:, -1] * (h * F @ (c * c)))
        edge = h * np.max(np.abs(F[:, [0, 1, -2, -1]]), axis=1)
    return BoltzmannSolution(kernel.restitution, gamma, n, law.name, grid,
                             times, F, log_s, 0.0, energy_rate, edge, int(steps), seconds)


#: The default grid of :func:`scaling_state`: the hard-rod state at r = 0.5 has a kurtosis of
#: 3.4831 and tails that reach past ±6 (121 points on ±12 and 161 on ±16 agree to 6e-8).
#: Its spacing, 0.1, does not resolve the narrow humps near r = 1: at r = 0.99 the state
#: undershoots to F ≈ −3e-4 between them and its kurtosis, 1.21439, is 2.5e-4 (relative) low.
#: Measured at r = 0.99 (benchmarks/README.md): 241 points on ±6 (spacing 0.05): kurtosis
#: 1.2146782, min F −1.6e-13 (481 on ±12 agree to 1e-11: ±6 is wide enough there); 361 on ±6
#: (0.033): 1.2146864, min F −3e-18.  Near r = 1 pass ``grid=VelocityGrid(361, 6.0)``
#: (:class:`maxwell_kinetics.velocity_grid.VelocityGrid`).
SCALING_GRID = _grid.VelocityGrid(241, 12.0)

#: Largest share of ⟨c⁴⟩ a scaling state may hold at the grid's two outermost nodes on each side
#: (:attr:`ScalingState.edge_moment`).  Measured on ±12: r = 0.5, γ = 1 (121 points): 2.4e-8,
#: whose kurtosis agrees with 161 points on ±16 to 6e-8; r = 0.9 (241 points, against 481 on
#: ±24): γ = 0.25: 6e-9, kurtoses 3.153719 and 3.153720; γ = 0.1: 1.7e-4, kurtoses 4.8136 and
#: 4.8352 (0.45 % apart); r = 0.5, γ = 0.1 (121 points): 0.12, kurtosis 9.21 (11.6 on ±24).
EDGE_TOLERANCE = 1e-6


@dataclass(frozen=True)
class ScalingState:
    """The scaling (homogeneous cooling) state of the rate |v − w|^γ: the time-independent law
    F(c) of c = (v − u)/v₀(t), v₀² = ⟨(v − u)²⟩, on the grid (∫F = 1, ⟨c⟩ = 0, ⟨c²⟩ = 1), a
    zero of Q_h(F) + σ′ ∂_c(c F) (:func:`scaling_state`).

    Attributes
    ----------
    restitution, exponent : float
        r and γ.
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid of c.
    F : numpy.ndarray
        Shape (N,): the state at the nodes.
    residual : float
        max_i |Q_h(F) + σ′ ∂_c(c F)| at the end.
    iterations : int
        Newton iterations.
    relaxation_time : float
        τ′ (collision time units n s^γ t) integrated before Newton.
    seconds : float
        Wall-clock time.
    edge_moment : float
        The share of ⟨c⁴⟩ held by the two outermost nodes on each side, Σ h |F| c⁴ there over
        ⟨c⁴⟩: a tail that the grid cuts shows here (:attr:`reaches_edges`).
    """

    restitution: float
    exponent: float
    grid: _grid.VelocityGrid
    F: np.ndarray = field(repr=False)
    residual: float = 0.0
    iterations: int = 0
    relaxation_time: float = 0.0
    seconds: float = 0.0
    edge_moment: float = 0.0

    @property
    def reaches_edges(self) -> bool:
        """Whether the state's tail reaches the grid's ends: :attr:`edge_moment` above
        :data:`EDGE_TOLERANCE` (its kurtosis then depends on the grid: widen it)."""
        return not self.edge_moment <= EDGE_TOLERANCE

    def moment(self, order: int) -> float:
        """⟨c^k⟩ of the state.

        Parameters
        ----------
        order : int
            k, an integer >= 0.

        Returns
        -------
        float
            The moment (⟨c²⟩ = 1).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``order`` when it is not an integer >= 0 (2.5, a bool, a string, NaN) or
            c^k overflows on the grid.
        """
        order = moment_order(order, "order", self.grid)
        c = self.grid.c
        return float(_grid.grid_sum(self.grid, self.F, c**order))

    @property
    def kurtosis(self) -> float:
        """⟨c⁴⟩/⟨c²⟩²."""
        return self.moment(4) / self.moment(2) ** 2

    def density(self, x) -> np.ndarray:
        """P(x) of the scaling state, x = c/√⟨c²⟩ (sixth-order interpolation, zero outside).

        Parameters
        ----------
        x : array_like
            Rescaled velocities (finite real numbers).

        Returns
        -------
        numpy.ndarray
            P(x), of the shape of ``x``.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``x`` when it is not an array of finite real numbers (NaN, ±inf, booleans,
            strings).
        """
        x = check_real_array(x, "x")
        scale = math.sqrt(self.moment(2))
        return scale * _interpolate(self.F, self.grid, x * scale)


#: Most time steps of :func:`scaling_state`'s relaxation.
RELAXATION_MAX_STEPS = 1_000_000


def relaxation_steps(kernel, grid, relaxation: float) -> float:
    """The estimated time steps of :func:`scaling_state`'s relaxation to τ′ = ``relaxation``,
    before any work: (1 + γ) τ′ times :func:`_steps_per_unit_time` (measured on its default
    grid, r = 0.5, γ = 1: 29 steps per unit of τ′, estimated 36; r = 0.9, γ = 2: 55, estimated
    54); times N² :data:`SECONDS_PER_STEP_AND_PAIR` it is the estimated wall time.

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        The kernel (:func:`grid_kernel`).
    grid : maxwell_kinetics.velocity_grid.VelocityGrid
        The grid.
    relaxation : float
        τ′ (collision time units).

    Returns
    -------
    float
        Time steps.
    """
    kernel = grid_kernel(kernel)
    return (1.0 + kernel.homogeneity) * _steps_per_unit_time(kernel, grid) * relaxation


def scaling_state(kernel=None, *, exponent=None, grid: _grid.VelocityGrid | None = None,
                  tolerance: float = 1e-11, max_iterations: int = 30,
                  relaxation: float | None = None, restitution=None,
                  force: bool = False) -> ScalingState:
    """The scaling state of the rescaled equation: relaxed in τ′ from the Gaussian, then
    Newton's method on Q_h(F) + σ′ ∂_c(c F) = 0 with ∫F = 1, ⟨c⟩ = 0 and ⟨c²⟩ = 1 (least
    squares on the N + 3 equations).

    Parameters
    ----------
    kernel : particles.kernels.Kernel or float
        A kernel this solver carries (:func:`grid_kernel`) with r < 1 and γ > 0, or r ∈ [0, 1):
        the shorthand for ``particles.kernels.RelativeVelocity(r, exponent)``.
    exponent : float, optional
        With a restitution only: γ of the rate (default 1).
    grid : maxwell_kinetics.velocity_grid.VelocityGrid, optional
        Default :data:`SCALING_GRID` (spacing 0.1: at r = 0.99 its kurtosis is 2.5e-4 low and
        F undershoots to −3e-4 between the humps; 361 points on ±6 bring both to ~1e-6 and
        −3e-18); γ = 0 has no scaling state with finite kurtosis (its tail is |x|⁻⁴) and is
        refused.
    tolerance : float, default 1e-11
        Newton stops when max|residual| ≤ tolerance.
    max_iterations : int, default 30
        Most Newton iterations.
    relaxation : float, optional
        τ′ integrated before Newton (default min(2000, 5/λ)).
    restitution : float, optional
        The former name of the first argument, still accepted by keyword.
    force : bool, default False
        Run a relaxation estimated (:func:`relaxation_steps`) to take more than
        :data:`maxwell_kinetics.grid.MAX_SOLVE_SECONDS` (one day) anyway.

    Returns
    -------
    ScalingState
        The state (check ``residual``).

    Raises
    ------
    RuntimeError
        If the relaxation before Newton fails (its integrator's steps run out).
    particles.validation.InvalidArgumentError
        Naming ``kernel`` (:func:`kernel_of`), ``restitution`` (r = 1 has no cooling state),
        ``exponent`` (γ = 0 or out of range), ``points`` or ``half_width``; ``grid`` for a
        :class:`maxwell_kinetics.velocity_grid.MappedGrid` or not a grid; ``tolerance`` or
        ``relaxation`` (not a finite number > 0), ``max_iterations`` (not an integer >= 0);
        ``relaxation`` again, before any work, for one whose estimated steps pass the
        integrator's 1000000 or (unless ``force``) whose estimated time passes a day;
        ``force`` if not a bool.
    """
    given = kernel if restitution is None else restitution
    kernel = kernel_of(kernel, exponent, restitution)
    lam = _coefficients(kernel)[2]
    if kernel.restitution == 1.0:
        raise InvalidArgumentError("restitution", getattr(given, "restitution", given),
                                   "r < 1 (an elastic gas does not cool)")
    if kernel.homogeneity == 0.0:
        raise InvalidArgumentError("exponent", 0.0 if exponent is None else exponent,
                                   "gamma > 0 (the Maxwell model's scaling state has an x^-4 "
                                   "tail and no finite kurtosis: use fixed-point --kernel "
                                   "constant)")
    grid = SCALING_GRID if grid is None else _grid.check_grid(grid)
    if isinstance(grid, _grid.MappedGrid):
        raise InvalidArgumentError("grid", grid, "a uniform VelocityGrid (the MappedGrid is "
                                   "for gamma = 0, which has no scaling state)")
    tolerance = check_positive(tolerance, "tolerance")
    max_iterations = check_count(max_iterations, "max_iterations", 0)
    if relaxation is not None:
        relaxation = check_positive(relaxation, "relaxation")
    F0 = _grid.initial_values("gaussian", grid)
    if relaxation is None:
        relaxation = min(2000.0, 5.0 / lam)
    force = check_bool(force, "force")
    steps = relaxation_steps(kernel, grid, relaxation)
    if steps > RELAXATION_MAX_STEPS:
        raise InvalidArgumentError(
            "relaxation", relaxation, f"a relaxation tau' <= "
            f"{relaxation * RELAXATION_MAX_STEPS / steps:.3g} on this grid (about {steps:.3g} "
            f"time steps estimated, at most {RELAXATION_MAX_STEPS} in all)")
    cost = steps * grid.c.size**2 * SECONDS_PER_STEP_AND_PAIR
    if cost > MAX_SOLVE_SECONDS and not force:
        raise InvalidArgumentError(
            "relaxation", relaxation, f"a relaxation estimated to take at most "
            f"{MAX_SOLVE_SECONDS:g} s (this one: about {cost:.3g} s); a shorter relaxation or "
            f"fewer points, or {FORCE}")
    import jax
    import jax.numpy as jnp

    start = time.perf_counter()
    c, h = grid.c, grid.step
    with jax.enable_x64(True):
        functions = _Compiled.get()
        tables = tables_for(kernel, grid)
        cj = jnp.asarray(c)
        args = (tables, cj, h, 1.0, 0.0, lam)  # s^γ ≡ 1: time is τ′
        ys, ok, steps = functions.solve(jnp.asarray(np.append(F0, 0.0)),
                                        jnp.asarray(_padded(np.array([float(relaxation)]))),
                                        args, 1e-8, 1e-12, RELAXATION_MAX_STEPS)
        if not bool(ok):  # Newton from a half-relaxed state could "converge" elsewhere
            raise RuntimeError(f"the relaxation to tau' = {relaxation:g} failed (steps: "
                               f"{int(steps)} of at most {RELAXATION_MAX_STEPS}); pass a shorter "
                               "relaxation")
        F = np.asarray(ys[-1, :-1])
        constraints = h * np.array([np.ones_like(c), c, c * c])
        iterations = 0
        residual = np.asarray(functions.steady(jnp.asarray(F), tables, cj, h, lam))
        while np.max(np.abs(residual)) > tolerance and iterations < max_iterations:
            J = np.asarray(functions.jacobian(jnp.asarray(F), tables, cj, h, lam))
            A = np.vstack([J, constraints])
            b = -np.concatenate([residual, constraints @ F - np.array([1.0, 0.0, 1.0])])
            F = F + np.linalg.lstsq(A, b, rcond=None)[0]
            residual = np.asarray(functions.steady(jnp.asarray(F), tables, cj, h, lam))
            iterations += 1
    ends = [0, 1, -2, -1]
    fourth = _grid.grid_sum(grid, F, c**4)
    edge = float(h * np.sum(np.abs(F[ends]) * c[ends] ** 4) / fourth)
    return ScalingState(kernel.restitution, float(kernel.homogeneity), grid, F,
                        float(np.max(np.abs(residual))), iterations, float(relaxation),
                        time.perf_counter() - start, edge)


#: Names that moved to :mod:`maxwell_kinetics.velocity_grid` (an import from here says so).
_MOVED = ("VelocityGrid", "MappedGrid", "default_grid", "initial_values", "EXTENT_TOLERANCE",
          "RESOLUTION_TOLERANCE", "MAX_SPACING", "MAX_POINTS")


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"maxwell_kinetics.inelastic_boltzmann.{name} moved to "
                          f"maxwell_kinetics.velocity_grid.{name}")
    raise AttributeError(f"module 'maxwell_kinetics.inelastic_boltzmann' has no attribute "
                         f"{name!r}")
