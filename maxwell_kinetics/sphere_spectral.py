"""A deterministic spectral solver of the homogeneous inelastic Boltzmann equation of smooth hard
spheres (d = 3) and hard disks (d = 2), and of variable hard spheres, in JAX.

Equation (m = 1, f normalised to 1, density n, physical time t):

    ∂f/∂t = Q(f, f),
    Q(f, f)(v) = ∫ dw ∫_{S^{d−1}} dn |g·n| [ α⁻² f(v*) f(w*) − f(v) f(w) ],   g = v − w,

n over the whole unit sphere (no step function), post-collision v′ = v − (1+α)/2 (g·n) n,
w′ = w + (1+α)/2 (g·n) n; weak form d/dt ∫ψ f = ∫∫ f(v) f(w) ∫ dn |g·n| [ψ(v′) − ψ(v)]
(:class:`particles.sphere_kernels.HardSpheres`; the right side is multiplied by n).
T = ⟨|v − u|²⟩/d, c = v/√(2T), a₂ = d/(d+2)·⟨c⁴⟩/⟨c²⟩² − 1,
a₃ = 1 + 3a₂ − d²/((d+2)(d+4))·⟨c⁶⟩/⟨c²⟩³
(:func:`particles.sphere_observables.sonine_coefficients`).
:class:`particles.sphere_kernels.VariableHardSpheres` is the same equation with |g·n| replaced by
B(g, n) = |g|^γ |ĝ·n|^{d−2}/(2π) (isotropic scattering at rate |g|^γ).

Scaled equation.  The unknown is F(c, t) = s^d f(u + s c, t) on a fixed grid of c, u the
conserved mean and s(t) the thermal scale (⟨|c|²⟩ = d is held: unit variance per component).
For a kernel homogeneous of degree γ in g,

    ∂F/∂t = n s^γ [Q(F, F) + σ′ ∇·(c F)],   d ln s/dt = n s^γ σ′,

with σ′ = −∫|c|² Q / ∫|c|² ∇·(cF) computed from Q itself, so the grid follows the cooling and
the homogeneous cooling state (HCS) is a steady F: :func:`cooling_state` marches the scaled
equation in τ (dτ = n s^γ dt) until it is stationary.  T(t) = s(t)²; the cooling rate
ζ = −d ln T/dt = −2 n s^γ σ′.

Method: Fourier–Galerkin on the periodic box [−L, L]^d with N modes per axis (Pareschi–Russo,
Mouhot–Pareschi), the collision kernel truncated to a cylinder about each n: |g·n| ≤ R,
|g − (g·n)n| ≤ R.  From the weak form with ψ = e^{−ik·v}, writing w = v − g,
g = s n + g⊥ (s = g·n), and β = (1 + α)/2 (the Jacobian α⁻² never appears: the weak form moves
the test function to v′ instead):

    Q̂⁺_k = Σ_{l+m=k} f̂_l f̂_m ∫_{S^{d−1}} dn ∫_{−R}^{R} ds e^{i s [β l·n − (1−β) m·n]} Φ(s, |m⊥|),

Φ(s, p) = ∫_{|g⊥|≤R} B(s, |g⊥|) e^{−i g⊥·m⊥} dg⊥ (hard spheres: |s| Ψ(p), Ψ = 2πR J₁(Rp)/p in
d = 3, 2 sin(Rp)/p in d = 2).  The exponential factors into a function of l times one of m,
so each quadrature node (n, s) is a product in velocity space:
F(c + βsn) × IFFT(F̂ e^{−is(1−β)m·n} Φ)(c), 2 FFTs per node
(:mod:`maxwell_kinetics._sphere_spectral_scheme`); the pairs (n, s) and (−n, −s) are one
point, so the n-rule covers the whole sphere and s runs over [0, R] (twice the weight).  The
sphere rule is Lebedev's (d = 3) or equally spaced angles (d = 2), s is Gauss–Legendre: both
converge spectrally for smooth F (the errors of the grids of
:data:`maxwell_kinetics.sphere_grid.GRIDS` are measured in benchmarks/README.md, "Spectral
hard spheres").  The loss is F × IFFT(F̂ L(|k|)), L the Fourier transform of the
truncated rate, by a one-dimensional radial quadrature.  Cost O(M_n M_s N^d log N) per
right-hand side (M_n sphere nodes, M_s radial nodes).

Conservation: Q is replaced by Q − F (λ₀ + λ·c + λ_e|c|²) with the λ that make the discrete
mass and momentum changes zero and keep the discrete energy change (a least-squares correction
in the norm ∫X²/F, in the spirit of Gamba–Tharkabhushanam and Pareschi–Rey); the dilation
∇·(cF) = dF + c·∇F (spectral derivatives, advective form) is corrected alike, its energy
change set to the exact −2Σ|c|²F, and σ′ then holds Σ|c|²F fixed: mass, momentum and
⟨|c|²⟩ are conserved to round-off, and d⟨|v|²⟩/dt is the collisions' Σ|c|² Q alone.

Edge layer: the dilation carries F outward, and on the periodic box the flows of the two sides
meet at its faces, where the truncated kernel (relative speeds ≤ √2 R) no longer damps F; an
instability grows there (measured, d = 2, N = 32: from τ ≈ 2).  An absorbing term −κ(c)F,
κ = 0 inside the cube |c_a| ≤ R and rising smoothly to the full rate at |g| = R on the faces,
removes it (:func:`maxwell_kinetics._sphere_spectral_scheme.sponge`); it acts where F is
below ~1e-12 of its peak on the default grids, and the mass it takes is restored by the
projection, which keeps the collisions' energy change, not the layer's.

Order: spectral in N (for smooth F; the HCS tail e^{−A|c|} is smooth), spectral in the sphere
and s rules; the truncation errors in L and R are exponentially small once F is negligible at
the box edge and at relative speeds beyond R; L ≳ 1.4 R keeps the periodic images apart.
Time: diffrax's Tsit5 (order 5, embedded order 4) with a PID step-size controller.  Every JAX
call runs in ``jax.enable_x64(True)``; the right-hand side has no host callback and runs
unchanged on a GPU.
"""

from __future__ import annotations

import math
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from particles import kernels as _kernels
from particles.validation import (
    InvalidArgumentError,
    check_bool,
    check_count,
    check_nonnegative,
    check_positive,
    check_times,
)

from . import _sphere_spectral_scheme as _scheme
from . import interrupt
from .grid import FORCE, MAX_SOLVE_SECONDS
from .sphere_grid import SphereGrid, sphere_grid
from .sphere_solution import SphereSolution, sonine

__all__ = ["carries", "kernel_form", "SphereOperator", "clear_operator_cache", "estimate_solve",
           "solve_spheres", "cooling_state", "CoolingState"]


def carries(kernel) -> bool:
    """Whether this solver carries a kernel (class or instance): a kernel of
    :mod:`particles.sphere_kernels` (``direction_law`` "hard": hard spheres, "isotropic":
    variable hard spheres), of physical time t, defined in d = 2 and 3.

    Parameters
    ----------
    kernel : type or particles.kernels.Kernel
        The kernel.

    Returns
    -------
    bool
    """
    cls = kernel if isinstance(kernel, type) else type(kernel)
    return (issubclass(cls, _kernels.Kernel) and cls.time_name == "t"
            and getattr(cls, "direction_law", None) in ("hard", "isotropic")
            and {2, 3} <= set(cls.dimensions))


def kernel_form(kernel, dimension: int) -> _scheme.KernelForm:
    """The collision kernel B(g, n) = C |g|^{γ−a} |g·n|^a of a carried kernel in d dimensions,
    checked against the kernel's own rate: ∫ dn B = R(v, w) at |g| = 0.5, 1, 2 (to 1e-12).

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        A kernel :func:`carries` accepts.
    dimension : int
        d, 2 or 3.

    Returns
    -------
    maxwell_kinetics._sphere_spectral_scheme.KernelForm

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel`` when it is not carried or its rate is not the one its law implies,
        ``dimension`` when it is not 2 or 3.
    """
    if dimension not in (2, 3) or isinstance(dimension, bool):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    if not isinstance(kernel, _kernels.Kernel) or not carries(kernel):
        raise InvalidArgumentError("kernel", kernel, "a kernel of particles.sphere_kernels "
                                   "(hard_spheres or variable_hard_spheres)")
    gamma = float(kernel.homogeneity)
    if kernel.direction_law == "hard":
        form = _scheme.KernelForm(1.0, gamma, 1)
    else:
        form = _scheme.KernelForm(1.0 / (2.0 * math.pi), gamma, dimension - 2)
    probes = np.array([0.5, 1.0, 2.0])
    v = np.zeros((3, dimension))
    v[:, 0] = probes
    got = np.asarray(kernel.rate(v, np.zeros_like(v), np), dtype=float)
    a = form.angular
    full = form.constant * (4.0 * math.pi / (a + 1) if dimension == 3
                            else (4.0 if a == 1 else 2.0 * math.pi))
    if not (0.0 <= gamma <= 1.0 and np.allclose(got, full * probes**gamma, rtol=1e-12, atol=0)):
        raise InvalidArgumentError("kernel", kernel, f"a rate {full:.6g} |g|^{gamma:g} as its "
                                   f"direction law implies in d = {dimension} (got {got})")
    return form


#: How many operators' tables :class:`SphereOperator` keeps (least recently used first out):
#: a process that solves a few (kernel, d, grid) again and again builds each once.
OPERATOR_CACHE_SIZE = 6
_TABLE_CACHE: OrderedDict = OrderedDict()
_CACHE_LOCK = threading.RLock()


def _shared_tables(dimension: int, grid: SphereGrid, form, transfer: float) -> dict:
    """The tables, nodes and moment basis of one (d, grid, kernel form, β), built by
    :func:`maxwell_kinetics._sphere_spectral_scheme.build_tables` on the first call and
    taken from a bounded cache (:data:`OPERATOR_CACHE_SIZE`) afterwards: the key holds every
    argument the tables depend on (the grid's five fields, C, γ and a of the form, β)."""
    key = (dimension, grid, form, transfer)
    with _CACHE_LOCK:
        if key in _TABLE_CACHE:
            _TABLE_CACHE.move_to_end(key)
            return _TABLE_CACHE[key]
    g = grid
    tables = _scheme.build_tables(dimension, g.points, g.half_width, g.cutoff, g.sphere_order,
                                  g.radial_nodes, form, transfer)
    c = tables.c
    entry = {"tables": tables,
             "nodes": np.stack(np.meshgrid(*([c] * dimension), indexing="ij"), axis=-1),
             "basis": _scheme.moment_basis(c, dimension)}
    for array in (entry["nodes"], entry["basis"]):
        array.setflags(write=False)
    with _CACHE_LOCK:
        entry = _TABLE_CACHE.setdefault(key, entry)
        _TABLE_CACHE.move_to_end(key)
        while len(_TABLE_CACHE) > OPERATOR_CACHE_SIZE:
            _TABLE_CACHE.popitem(last=False)
    return entry


def clear_operator_cache() -> None:
    """Forget every cached operator table (:data:`OPERATOR_CACHE_SIZE`); the next
    :class:`SphereOperator` of each kind builds its tables again."""
    with _CACHE_LOCK:
        _TABLE_CACHE.clear()


class SphereOperator:
    """The collision operator of one (kernel, d, grid) on the grid's nodes, with its jitted
    right-hand sides (the handle of :func:`solve_spheres`, :func:`cooling_state` and the
    tests).

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        A carried kernel (:func:`kernel_form`).
    dimension : int
        d.
    grid : str or SphereGrid, optional
        The grid (:func:`sphere_grid`).

    Attributes
    ----------
    grid : SphereGrid
    nodes : numpy.ndarray
        c at the nodes, shape (N,)*d + (d,).
    form : maxwell_kinetics._sphere_spectral_scheme.KernelForm
    tables : maxwell_kinetics._sphere_spectral_scheme.Tables
    basis : numpy.ndarray
        The collision invariants 1, c, |c|² at the nodes, shape (d + 2,) + (N,)*d (shared,
        read-only).

    Raises
    ------
    particles.validation.InvalidArgumentError
        As :func:`kernel_form` and :func:`sphere_grid`.

    Notes
    -----
    The tables (about a second on the default grids) are built once per (d, grid, kernel
    form, β = (1 + α)/2) in a process and shared, read-only, by every operator of the same
    key (:data:`OPERATOR_CACHE_SIZE` keys, least recently used dropped first;
    :func:`clear_operator_cache`); any other grid field, α or kernel builds its own.
    """

    _compiled: dict = {}

    def __init__(self, kernel, dimension: int, grid=None):
        self.form = kernel_form(kernel, dimension)
        self.kernel, self.dimension = kernel, dimension
        self.grid = g = sphere_grid(grid, dimension)
        self._shared = _shared_tables(dimension, g, self.form, float(kernel.p))
        self.tables, self.nodes, self.basis = (self._shared[k] for k in
                                                ("tables", "nodes", "basis"))
        self.weight = g.spacing**dimension
        self._key = (dimension, self.form.separable())

    def device_arguments(self):
        """The operator's tables, its basis of the collision invariants and the grid's axes as
        JAX arrays: what the compiled right-hand sides take.  Made once per cached entry of the
        tables; call it inside ``jax.enable_x64(True)``.

        Returns
        -------
        tables : dict
            The tables (:attr:`tables`) as JAX arrays.
        basis : jax.Array
            :attr:`basis`.
        grids : tuple of jax.Array
            The d components of c at the nodes.
        """
        return self._args()

    def _args(self):
        # the device copies, made once per cached entry (every caller runs in enable_x64)
        with _CACHE_LOCK:
            if "args" not in self._shared:
                self._shared["args"] = self._device_args()
            return self._shared["args"]

    def _device_args(self):
        import jax.numpy as jnp

        t = self.tables
        tables = {"axes_k": tuple(jnp.asarray(k) for k in t.axes_k),
                  "mask": jnp.asarray(t.mask), "directions": jnp.asarray(t.directions),
                  "weights": jnp.asarray(t.weights), "s": jnp.asarray(t.s),
                  "s_weights": jnp.asarray(t.s_weights), "cross": jnp.asarray(t.cross),
                  "loss": jnp.asarray(t.loss), "beta": jnp.asarray(t.beta),
                  "sponge": jnp.asarray(t.sponge)}
        grids = tuple(jnp.asarray(self.nodes[..., a]) for a in range(self.dimension))
        return tables, jnp.asarray(self.basis), grids

    def _functions(self):
        if self._key not in SphereOperator._compiled:
            SphereOperator._compiled[self._key] = _Functions(*self._key)
        return SphereOperator._compiled[self._key]

    def collision(self, F) -> tuple[np.ndarray, np.ndarray]:
        """The gain and loss of F at the nodes, before the conservative projection.

        Parameters
        ----------
        F : array_like
            F at the nodes, shape (N,)*d.

        Returns
        -------
        gain, loss : numpy.ndarray
        """
        import jax

        with jax.enable_x64(True):
            tables, _, _ = self._args()
            gain, loss = self._functions().collision(jax.numpy.asarray(F, dtype=float), tables)
            return np.asarray(gain), np.asarray(loss)

    def scaled_rhs(self, F) -> tuple[np.ndarray, float]:
        """dF/dτ of the scaled equation and σ′ = d ln s/dτ (module docstring).

        Parameters
        ----------
        F : array_like
            Shape (N,)*d.

        Returns
        -------
        rhs : numpy.ndarray
        sigma : float
        """
        import jax

        with jax.enable_x64(True):
            rhs, sigma = self._functions().rhs(jax.numpy.asarray(F, dtype=float), *self._args())
            return np.asarray(rhs), float(sigma)

    def initial(self, initial="gaussian") -> tuple[np.ndarray, float, np.ndarray]:
        """F(c, 0) at the nodes with mass 1, mean 0 and ⟨|c|²⟩ = d exactly on the grid (the
        sampled law times 1 + a + b·c + e|c|²), and the scale s(0) and mean u of f(v, 0).

        Parameters
        ----------
        initial : str or callable
            "gaussian" (the Maxwellian of T = 1) or a density f(v) of d-vectors (last axis),
            vectorised, with finite mass, mean and temperature on the grid.

        Returns
        -------
        F : numpy.ndarray
        scale : float
            s(0) = √T(0).
        mean : numpy.ndarray
            u, shape (d,).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``initial`` for another name, or a density that is not finite and positive
            in mass and temperature on the grid.
        """
        d, c = self.dimension, self.nodes
        if isinstance(initial, str):
            if initial != "gaussian":
                raise InvalidArgumentError("initial", initial, "'gaussian' (the Maxwellian "
                                           "of T = 1) or a density f(v) of d-vectors")
            scale, mean = 1.0, np.zeros(d)
            F = np.exp(-0.5 * np.sum(c * c, axis=-1)) / (2.0 * math.pi) ** (d / 2)
        elif callable(initial):
            raw = np.asarray(initial(c), dtype=float)
            mass = raw.sum() * self.weight
            if raw.shape != c.shape[:-1] or not (np.all(np.isfinite(raw)) and mass > 0):
                raise InvalidArgumentError("initial", initial, "a density f(v) that returns "
                                           "finite values of positive mass on the grid")
            mean = np.tensordot(raw, c, axes=d) * self.weight / mass
            temp = np.sum(raw * np.sum((c - mean) ** 2, axis=-1)) * self.weight / (mass * d)
            if not temp > 0:
                raise InvalidArgumentError("initial", initial, "a density of positive "
                                           "temperature")
            scale = math.sqrt(temp)
            F = np.asarray(initial(mean + scale * c), dtype=float) * scale**d / mass
        else:
            raise InvalidArgumentError("initial", initial, "'gaussian' or a density f(v)")
        basis = self.basis.reshape(d + 2, -1)
        target = np.zeros(d + 2)
        target[0], target[-1] = 1.0, float(d)
        gram = (basis * F.reshape(1, -1)) @ basis.T * self.weight
        lam = np.linalg.solve(gram, target - basis @ F.reshape(-1) * self.weight)
        return F * (1.0 + (lam @ basis).reshape(F.shape)), scale, mean

    def integrate(self, F, log_scale: float, times, density: float, rtol: float, atol: float,
                  max_steps: int, gamma: float | None = None, interruptible: bool = True):
        """diffrax's Tsit5 from (F, ln s) at t = 0 over ``times`` (module docstring).

        Parameters
        ----------
        F : array_like
            F at t = 0, shape (N,)*d.
        log_scale : float
            ln s at t = 0.
        times : array_like
            The save times.
        density : float
            n.
        rtol, atol : float
            The step-size controller's tolerances.
        max_steps : int
            Most steps.
        gamma : float, optional
            The degree γ in the factor n s^γ (default the kernel's; 0 marches in τ).
        interruptible : bool, default True
            Run in a worker thread, so that Ctrl-C reaches the caller at once
            (:func:`maxwell_kinetics.interrupt.run_interruptibly`); False runs in the calling
            thread (a caller that is itself such a worker).

        Returns
        -------
        F : numpy.ndarray
            Shape (T,) + (N,)*d.
        log_scale : numpy.ndarray
            Shape (T,).
        ok : bool
            Whether diffrax finished.
        steps : int
            Steps taken.

        Raises
        ------
        KeyboardInterrupt
            On Ctrl-C, within about 0.1 s (:func:`maxwell_kinetics.interrupt.run_interruptibly`).
        """
        import jax
        import jax.numpy as jnp

        gamma = self.form.exponent if gamma is None else gamma

        def work():
            with jax.enable_x64(True):
                tables, basis, grids = self._args()
                args = (tables, basis, grids, jnp.asarray(density), jnp.asarray(gamma))
                y0 = (jnp.asarray(F, dtype=float), jnp.asarray(log_scale, dtype=float))
                ys, ok, steps = self._functions().solve(y0, jnp.asarray(times, dtype=float),
                                                        args, rtol, atol, max_steps)
                return np.asarray(ys[0]), np.asarray(ys[1]), bool(ok), int(steps)

        if not interruptible:
            return work()
        return interrupt.run_interruptibly(work, "spectral hard-sphere solve")


class _Functions:
    """The jitted functions of one (d, separable) (compiled once per grid shape)."""

    def __init__(self, dimension: int, separable: bool):
        import diffrax
        import jax
        import jax.numpy as jnp

        scheme, d, sep = _scheme, dimension, separable

        def rhs(F, tables, basis, grids):
            return scheme.scaled_rhs(F, tables, d, sep, basis, grids)

        def field(t, y, args):
            F, log_scale = y
            tables, basis, grids, density, gamma = args
            dF, sigma = rhs(F, tables, basis, grids)
            rate = density * jnp.exp(gamma * log_scale)
            return rate * dF, rate * sigma

        def solve(y0, times, args, rtol, atol, max_steps):
            out = diffrax.diffeqsolve(
                diffrax.ODETerm(field), diffrax.Tsit5(), 0.0, times[-1], None, y0, args=args,
                saveat=diffrax.SaveAt(ts=times),
                stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
                max_steps=max_steps, throw=False)
            return out.ys, out.result == diffrax.RESULTS.successful, out.stats["num_steps"]

        self.collision = jax.jit(lambda F, tables: scheme.collision(F, tables, d, sep))
        self.rhs = jax.jit(rhs)
        self.solve = jax.jit(solve, static_argnums=(5,))


#: Time steps per unit of the integrator's time τ = ∫ n s^γ dt (s the thermal scale), as
#: a + b γ: measured from the Maxwellian at α = 0.5 (2026-11-29, load 1-2 on 2 cores): hard
#: spheres and disks (γ = 1) 21-36 steps per unit τ beyond 10-15 steps of start ("coarse"
#: d = 2: 59 steps at τ = 2.0, 137 at 5.4; d = 3: 65 at 1.65, 154 at 4.23; "default" d = 2:
#: 82 at 2.0, 217 at 5.4), the Maxwell kernel (γ = 0) 4-5 (27, 24 and 21 steps at τ = 5).
STEPS_PER_TAU = (5.0, 35.0)
#: Steps before the first unit of τ (the controller's start).
STEPS_AT_START = 15.0
#: Seconds per step and per unit of work W = (directions × radial nodes) × N^d log₂ N^d:
#: measured 7e-9 to 1.3e-8 on the three grids above (0.028 s, 0.25 s and 0.50 s per step on
#: "coarse" d = 2, "default" d = 2 and "coarse" d = 3); the larger, rounded up.
SECONDS_PER_STEP_AND_WORK = 1.5e-8


def estimate_solve(operator: SphereOperator, F0, density: float, t_last: float) -> dict:
    """The estimated steps and wall time of a solve from ``F0`` to ``t_last``, before it runs.

    The integrator's time is τ = ∫ n s^γ dt.  From the initial cooling, d ln s/dt = n s^γ σ₀
    (σ₀ = :meth:`SphereOperator.scaled_rhs`'s rate at ``F0``, < 0 when the gas cools), so
    τ = ln(1 + γ|σ₀| n t)/(γ|σ₀|) for γ > 0 (n t when γ|σ₀| n t is small) and τ = n t for
    γ = 0; the steps are :data:`STEPS_AT_START` + (a + b γ) τ (:data:`STEPS_PER_TAU`), each
    costing :data:`SECONDS_PER_STEP_AND_WORK` per unit of the grid's work.  A hotter gas
    (σ₀ > 0, a heated start) is counted at σ₀ = 0.

    Parameters
    ----------
    operator : SphereOperator
        The operator of the solve.
    F0 : numpy.ndarray
        The initial scaled law on the operator's grid.
    density : float
        n.
    t_last : float
        The last time t.

    Returns
    -------
    dict
        ``tau``, ``steps`` and ``seconds`` (floats).
    """
    gamma = float(operator.form.exponent)
    sigma = max(0.0, -float(operator.scaled_rhs(F0)[1]))
    x = gamma * sigma * density * t_last
    tau = density * t_last if x < 1e-12 else math.log1p(x) / (gamma * sigma)
    steps = STEPS_AT_START + (STEPS_PER_TAU[0] + STEPS_PER_TAU[1] * gamma) * tau
    grid, d = operator.grid, operator.dimension
    directions = len(_scheme.sphere_rule(d, grid.sphere_order)[1])
    modes = grid.points**d
    work = directions * grid.radial_nodes * modes * math.log2(modes)
    return {"tau": tau, "steps": steps, "seconds": steps * work * SECONDS_PER_STEP_AND_WORK}


def solve_spheres(kernel, t, *, dimension: int = 3, density: float = 1.0, initial="gaussian",
                  grid=None, rtol: float = 1e-9, atol: float = 1e-12,
                  max_steps: int = 100_000, force: bool = False) -> SphereSolution:
    """Solve ∂f/∂t = n Q(f, f) for hard spheres or variable hard spheres in d = 2, 3 (module
    docstring) and save the scaled F(c, t) at the times ``t``.

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        :class:`particles.sphere_kernels.HardSpheres` or
        :class:`~particles.sphere_kernels.VariableHardSpheres`.
    t : array_like
        Increasing times t ≥ 0 (0 allowed: the initial law).
    dimension : int, default 3
        d, 2 or 3.
    density : float, default 1
        n > 0.
    initial : str or callable, default "gaussian"
        The initial law (:meth:`SphereOperator.initial`).
    grid : str or SphereGrid, optional
        The grid (:data:`GRIDS`; default "default").
    rtol, atol : float
        Tolerances of diffrax's PID controller on F (values ~ (2π)^{−d/2} at the peak);
        1e-7 leaves a noise of ~1e-5 in dF/dτ, 1e-9 (the default) takes as many steps (their
        number is set by the stability of the dilation and the loss at the box's edge).
    max_steps : int
        Most time steps.
    force : bool, default False
        Run a solve estimated (:func:`estimate_solve`) to take more than
        :data:`maxwell_kinetics.grid.MAX_SOLVE_SECONDS` (one day) anyway.

    Returns
    -------
    SphereSolution

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel``, ``dimension``, ``grid``, ``initial``, ``t``, ``density``,
        ``rtol``, ``atol`` or ``max_steps`` when out of range.
    RuntimeError
        When the integration fails (too many steps, non-finite values).
    particles.validation.InvalidArgumentError
        Naming ``t`` before the integration when the estimated steps (:func:`estimate_solve`)
        exceed ``max_steps``, or (unless ``force``) its estimated time exceeds one day.
    KeyboardInterrupt
        On Ctrl-C, within about 0.1 s (the integration runs in a worker thread).
    """
    times = check_times(t, "t", strictly=False)
    force = check_bool(force, "force")
    density = check_positive(density, "density")
    rtol, atol = check_positive(rtol, "rtol"), check_positive(atol, "atol")
    max_steps = check_count(max_steps, "max_steps", 1)
    start = time.perf_counter()

    def work():  # the operator's tables take seconds too: all of it where Ctrl-C can wait
        operator = SphereOperator(kernel, dimension, grid)
        F0, scale, mean = operator.initial(initial)
        cost = estimate_solve(operator, F0, density, float(times[-1]) if times.size else 0.0)
        if cost["steps"] > max_steps:
            raise InvalidArgumentError(
                "t", float(times[-1]), f"a last time the integrator reaches in max_steps = "
                f"{max_steps} steps (this one: about {cost['steps']:.3g} steps; raise "
                "max_steps in Python for longer solves)")
        if cost["seconds"] > MAX_SOLVE_SECONDS and not force:
            raise InvalidArgumentError(
                "t", float(times[-1]), f"a solve estimated to take at most "
                f"{MAX_SOLVE_SECONDS:g} s (this one: about {cost['seconds']:.3g} s); a coarser "
                f"grid or an earlier last time, or {FORCE}")
        return operator, mean, *operator.integrate(F0, math.log(scale), times, density, rtol,
                                                   atol, max_steps, interruptible=False)

    operator, mean, F, log_scale, ok, steps = interrupt.run_interruptibly(
        work, "spectral hard-sphere solve")
    if not ok or not np.all(np.isfinite(F)):
        raise RuntimeError(f"the spectral hard-sphere solve failed after {steps} steps "
                           f"(max_steps = {max_steps}, or non-finite values)")
    sigma = np.array([operator.scaled_rhs(row)[1] for row in F])
    rate = density * np.exp(operator.form.exponent * log_scale)
    return SphereSolution(kernel.name, float(kernel.restitution), float(operator.form.exponent),
                          dimension, density, initial if isinstance(initial, str) else "custom",
                          operator.grid, times, F, log_scale, mean, -2.0 * rate * sigma, steps,
                          time.perf_counter() - start)


@dataclass(frozen=True)
class CoolingState:
    """The homogeneous cooling state of :func:`cooling_state`: the stationary F(c) of the scaled
    equation (⟨|c|²⟩ = d) and its Sonine coefficients.

    Attributes
    ----------
    kernel : str
        The kernel's name.
    restitution : float
        α.
    dimension : int
        d.
    grid : SphereGrid
        The grid.
    F : numpy.ndarray
        F at the nodes, shape (N,)*d.
    a2, a3 : float
        The Sonine coefficients of F.
    cooling_rate : float
        ζ* = −2σ′: −d ln T/dτ with dτ = n s^γ dt (for hard spheres ζ = ζ* n √T).
    residual : float
        max |dF/dτ| / max F at the end (with "newton", or the largest error of the d + 2
        conserved moments if larger).
    tau : float
        The scaled time marched (before Newton, with "newton").
    steps : int
        Time steps taken.
    seconds : float
        Wall-clock time.
    history : numpy.ndarray
        Rows (τ, a₂, a₃, residual) at the end of each chunk ("march"), or at the end of the
        march and after Newton ("newton").
    method : str
        "newton" or "march" (:func:`cooling_state`).
    newton_steps, krylov_steps : int
        Newton steps and Jacobian-vector products ("newton"; 0 for "march").
    """

    kernel: str
    restitution: float
    dimension: int
    grid: SphereGrid
    F: np.ndarray = field(repr=False)
    a2: float
    a3: float
    cooling_rate: float
    residual: float
    tau: float
    steps: int
    seconds: float
    history: np.ndarray = field(repr=False)
    method: str = "march"
    newton_steps: int = 0
    krylov_steps: int = 0


def cooling_state(kernel, *, dimension: int = 3, grid=None, method: str = "newton",
                  tolerance: float | None = None, chunk: float = 0.25, max_tau: float = 40.0,
                  march_tau: float | None = None, rtol: float = 1e-9, atol: float = 1e-12,
                  start=None) -> CoolingState:
    """The homogeneous cooling state: the steady F of the scaled equation ∂F/∂τ = Q̃ + σ′ D̃,
    from the Maxwellian (or ``start``).

    ``method="newton"`` (the default) marches τ = ``march_tau`` and then solves the steady
    equation by Newton–Krylov (:func:`maxwell_kinetics.sphere_steady.steady_state`) to the
    residual max |dF/dτ| / max F < ``tolerance`` (default 1e-10); ``method="march"`` marches
    in chunks of τ until the residual is below ``tolerance`` (default 1e-6).  Both reach the
    same state on the same grid: measured on "coarse", d = 2, α = 0.5, the march stopped at
    1e-6 leaves a₂ 1.0e-7 from Newton's, one stopped at 1e-8 1.2e-9 (a₃: 1.8e-7, 3.7e-9).
    From the Maxwellian, Newton after τ = 0.5 reaches the state of τ = 1; the default march
    is the cheaper of the two (:func:`maxwell_kinetics.sphere_steady.default_march_tau`).

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        A carried kernel (:func:`kernel_form`), α < 1.
    dimension : int, default 3
        d.
    grid : str or SphereGrid, optional
        The grid.
    method : {"newton", "march"}, default "newton"
        The steady solve after a short march, or the march alone.
    tolerance : float, optional
        The residual at which to stop (default 1e-10 for "newton", 1e-6 for "march").
    chunk : float, default 0.25
        τ between residual checks of the march ("march").
    max_tau : float, default 40
        Give up (RuntimeError) past this τ ("march").
    march_tau : float, optional
        τ marched before Newton ("newton"; 0: Newton from ``start`` itself); default 1 for
        α ≤ 0.3, 0.5 above.
    rtol, atol : float
        The step-size controller's tolerances.
    start : numpy.ndarray, optional
        F to start from (on this grid; default the Maxwellian).

    Returns
    -------
    CoolingState

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``kernel`` (not carried, or elastic: the Maxwellian is already steady),
        ``dimension``, ``grid``, ``method``, ``tolerance``, ``chunk``, ``max_tau``,
        ``march_tau`` or ``start``.
    maxwell_kinetics.sphere_steady.SteadyStateError
        ("newton", a RuntimeError) When Newton–Krylov does not reach ``tolerance``; the
        message names the residual reached.
    RuntimeError
        ("march") When the residual is not reached by ``max_tau``, or the integration fails.
    KeyboardInterrupt
        On Ctrl-C, within about 0.1 s (each march and the Newton solve run in a worker
        thread).
    """
    if method not in ("newton", "march"):
        raise InvalidArgumentError("method", method, "'newton' or 'march'")
    if tolerance is None:
        tolerance = 1e-10 if method == "newton" else 1e-6
    tolerance = check_positive(tolerance, "tolerance")
    chunk, max_tau = check_positive(chunk, "chunk"), check_positive(max_tau, "max_tau")
    if march_tau is None:
        from .sphere_steady import default_march_tau

        march_tau = default_march_tau(kernel.restitution)
    march_tau = check_nonnegative(march_tau, "march_tau")
    begin = time.perf_counter()
    operator = interrupt.run_interruptibly(lambda: SphereOperator(kernel, dimension, grid),
                                           "spectral operator")
    if kernel.restitution == 1.0:
        raise InvalidArgumentError("kernel", kernel, "a restitution below 1 (elastic spheres "
                                   "do not cool: every Maxwellian is stationary)")
    F = operator.initial("gaussian")[0] if start is None else np.asarray(start, dtype=float)
    if F.shape != operator.nodes.shape[:-1]:
        raise InvalidArgumentError("start", f"an array of shape {F.shape}",
                                   f"F on the grid, shape {operator.nodes.shape[:-1]}")
    tau, steps, history = 0.0, 0, []
    c = operator.nodes

    def march(F, length):
        # a march in τ: the field's factor n s^γ is 1 with n = 1 and γ = 0
        out, _, ok, n = operator.integrate(F, 0.0, [length], 1.0, rtol, atol, 100_000,
                                           gamma=0.0)
        if not ok or not np.all(np.isfinite(out)):
            raise RuntimeError(f"the cooling-state march failed at tau = {tau:g}")
        return out[0], n

    newton = krylov = 0
    if method == "newton":
        from .sphere_steady import steady_state

        if march_tau > 0:
            F, steps = march(F, march_tau)
            tau = march_tau
        solved = interrupt.run_interruptibly(
            lambda: steady_state(operator, F, tolerance=tolerance), "spectral steady solve")
        F, sigma, residual = solved.F, solved.sigma, solved.residual
        newton, krylov = solved.newton_steps, solved.krylov_steps
        a2, a3 = sonine(F, c, operator.weight)
        history = [(tau, *sonine(F, c, operator.weight), solved.history[0]),
                   (tau, a2, a3, residual)]
    else:
        while True:
            rhs, sigma = operator.scaled_rhs(F)
            residual = float(np.max(np.abs(rhs)) / np.max(F))
            a2, a3 = sonine(F, c, operator.weight)
            history.append((tau, a2, a3, residual))
            if residual < tolerance:
                break
            if tau >= max_tau:
                raise RuntimeError(f"no cooling state within tau = {max_tau:g}: the residual "
                                   f"is {residual:.3g} > {tolerance:g}")
            F, n = march(F, chunk)
            tau, steps = tau + chunk, steps + n
    return CoolingState(kernel.name, float(kernel.restitution), dimension, operator.grid, F,
                        a2, a3, -2.0 * sigma, residual, tau, steps, time.perf_counter() - begin,
                        np.array(history), method, newton, krylov)
