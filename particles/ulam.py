"""The Ulam (mean-field pseudo-Maxwell) model: exact continuous-time dynamics, vectorized.

Model.  N particles; pair collisions form a Poisson process of rate N/2 in τ, each
collision picks a uniformly random pair i ≠ j and applies the rule of :mod:`particles.collision`.
Each particle thus collides at rate 1 and τ counts collisions per particle.  This is *not* a
synchronous sweep over all pairs.

Momentum round-off.  Collisions conserve the total momentum only up to round-off, and that
residue does not decay while the velocities decay like e^{−λτ}: for λτ ≳ 30 every velocity would
approach the round-off mean (measured before this correction: r = 0.9, N = 2·10⁴, τ = 1200, all
velocities of a run equal).  The collision rule is Galilean invariant (it depends only on the
difference of the two velocities), so subtracting the mean velocity from every particle commutes
with the dynamics and is exact up to round-off.  Both engines do it (:func:`recentre`) at the
same deterministic points: the multiples of ``stop_step`` in τ, after every event before that
point and before every event after it.  They are window boundaries of the fast path (``stop_step``
is a multiple of ``window``), so the fast path and the sequential loop still agree bit for bit on
the same events (:func:`~particles.pair_schedule.collide_sequential` followed by
:func:`recentre`).  The momentum recorded at a grid point is therefore ~0 by construction and
says nothing about conservation; the collisions' own drift shows at times between grid points,
and the tests bound it there.

Throughput: ``benchmarks/ulam_dimensions.py`` (table in benchmarks/README.md): 2D uniform runs
about 2 times slower than 1D, 2D hard about 1.6 and 3D about 4-5 (the 2D cost is the gather and
scatter, the round schedule and, for "uniform", the cosine of the draws).

Initial velocities in d dimensions: each Cartesian component is an independent draw of the
initial law, centred and scaled to unit variance (so ⟨|v|²⟩ = d at τ = 0).  Recentring subtracts
the mean velocity vector.  Expected energy: ⟨|v|²⟩(τ) = ⟨|v|²⟩(0) e^{−Λτ N/(N−1)} with
Λ = 2pq⟨η⟩, ⟨η⟩ = 1/d (uniform) or 2/(d + 1) (hard) (derivation in :class:`Ulam`).  The run
driver (:func:`particles.driver.simulate`) takes d ≥ 2 too (S(k) only in 1D).

Driven 1D model (``driving`` = D > 0).  Between its collision events every particle feels white
noise of strength D (Fokker–Planck term D ∂²_v P), i.e. a Gaussian kick of variance 2DΔτ over a
time Δτ.  Exact scheme: the events of a window get explicit times (K sorted uniform times in the
window, which is the law of the event times of a Poisson process given K) and two standard
normals each, drawn in advance; when an event fires, each of its two particles first receives
the kick for the time since its previous kick (``last``), then the collision is applied.  At the
end of ``advance`` and at each recentring point every particle is kicked up to that time (N more
normals).  Since the noise is additive and independent of the velocities, recentring still
commutes with the dynamics; it removes the random walk of the centre of mass (variance 2Dτ/N),
and with zero total momentum the steady energy is ⟨v²⟩ = (D/pq)(1 − 1/N)² (derivation in
:class:`Ulam`).

Rate ∝ |v_i − v_j| (``rate="relative_velocity"``): DSMC of the hard-rod Boltzmann equation in
time t at density n, by thinning under the velocity-hull bound (:class:`Ulam`).

Modules.  The engines; the pair scheduler (pairs, round schedule, fast and reference loops over
events) is in :mod:`particles.pair_schedule`, the kinematics of d = 2, 3 in
:mod:`particles.ulam_kinematics`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .collision import collide_arrays, collide_scalar, transfer_fraction
from .driver import EngineBase, initial_velocities, next_grid_point
from .initial import get_law
from .kernels import ConstantRate, Kernel, RelativeVelocity, kernel_class, make_kernel
from .pair_schedule import (
    BLOCK_WINDOWS,
    draw_pairs_unchecked,
    fire_rounds,
    fire_rounds_plane,
    fire_rounds_thinned,
    fire_rounds_with_rows,
    hull_bound,
    kernel_bound,
    power_of_two_near,
    thin_sequential,
    thinned_windows,
)
from .ulam_kinematics import (
    as_complex,
    check_angular,
    collide_pairs_vectors,
    subset_draws,
)
from .ulam_kinematics import draw_angles as _draw_angles
from .ulam_kinematics import plane_transfer as _plane_transfer
from .validation import (
    InvalidArgumentError,
    check_count,
    check_dimension,
    check_nonnegative,
    check_positive,
    check_restitution,
)

__all__ = [
    "Ulam",
    "UlamReference",
    "UlamState",
    "recentre",
]

#: Names that lived here before and have one home elsewhere now: a deep import of one of them
#: from this module raises an ImportError naming that home.
_MOVED = {
    **{name: "particles.pair_schedule" for name in (
        "draw_pairs", "collide_in_order", "collide_sequential", "collide_in_order_vectors",
        "collide_sequential_vectors", "largest_occurrence",
        "largest_occurrence_ufunc", "_rounds")},
    **{name: "particles.ulam_kinematics" for name in (
        "AngularDraws", "ANGULAR_MODELS", "draw_angles", "collision_directions",
        "collide_vectors", "collide_complex", "plane_transfer")},
}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"particles.ulam.{name} moved to {_MOVED[name]}.{name}")
    if name == "RATES":  # the collision-rate laws are the kernels of the registry now
        raise ImportError("particles.ulam.RATES is gone: the rate laws are the registered "
                          "kernels, tuple(particles.kernels.KERNELS)")
    raise AttributeError(f"module 'particles.ulam' has no attribute {name!r}")


#: Events per window aimed at: large enough to amortise NumPy call overhead, small enough that
#: a particle has few events per window (few rounds).  Measured best near 2.5e4 at N = 1e6
#: (2.3e7 events/s, against 1.9e7 with 1e5 and 1.1e7 with 2e5).
TARGET_EVENTS = 25_000


def _window_for(n: int) -> float:
    """Window length in τ: the power of two nearest to 2·TARGET_EVENTS/N, clipped to [2⁻¹², 2]."""
    exponent = int(np.clip(np.round(np.log2(2.0 * TARGET_EVENTS / n)), -12, 1))
    return 2.0**exponent


@dataclass(frozen=True)
class UlamState:
    """Ulam state at time ``time`` (τ): velocities and the total number of pair collisions.

    Attributes
    ----------
    time : float
        τ, collisions per particle (N/2 pair collisions per unit on average).
    velocities : numpy.ndarray
        Shape ``(N,)`` in 1D, ``(N, d)`` otherwise.
    collisions : int
        Total number of pair collisions so far.
    """

    time: float
    velocities: np.ndarray = field(repr=False)
    collisions: int = 0

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as a dict of NumPy arrays (what the driver's checkpoints store).

        Returns
        -------
        dict of str to numpy.ndarray
            ``time``, ``velocities`` and ``collisions``.
        """
        return {
            "time": np.array(self.time, dtype=float),
            "velocities": self.velocities,
            "collisions": np.array(self.collisions, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, arrays, n: int, dimension: int = 1) -> UlamState:
        """Rebuild a state from :meth:`to_arrays`'s dict.

        Parameters
        ----------
        arrays : mapping
            The arrays, as :meth:`to_arrays` writes them.
        n : int
            The number of particles N.
        dimension : int, optional
            The dimension d (default 1).

        Returns
        -------
        particles.UlamState
            The state (with a copy of the velocities).

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint`` (a ``ValueError``, which the driver turns into its
            ``CheckpointError`` naming the file): a missing entry, or velocities not of shape
            ``(n,)`` (1D) or ``(n, dimension)``.
        """
        missing = [k for k in ("time", "velocities", "collisions") if k not in arrays]
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "an Ulam state")
        v = np.asarray(arrays["velocities"], dtype=float)
        shape = (n,) if dimension == 1 else (n, dimension)
        if v.shape != shape:
            raise InvalidArgumentError(
                "checkpoint", f"velocities of shape {v.shape}", f"an Ulam state, expected {shape}"
            )
        return cls(float(arrays["time"]), v.copy(), int(arrays["collisions"]))


def recentre(v: np.ndarray) -> None:
    """Subtract the mean velocity from ``v`` in place (exact by Galilean invariance of the
    collision rule; removes the non-decaying round-off of the total momentum).  ``v`` of shape
    (N,) or (N, d).

    Parameters
    ----------
    v : numpy.ndarray
        Velocities, modified in place.
    """
    v -= v.mean() if v.ndim == 1 else v.mean(axis=0)


def _is_grid_point(t: float, step: float) -> bool:
    return t > 0.0 and t % step == 0.0


@dataclass(frozen=True)
class Ulam(EngineBase):
    """Exact vectorized Ulam engine with ``n`` ≥ 2 particles, restitution ``restitution`` ∈ [0, 1],
    initial law ``initial`` (a name of :mod:`particles.initial`).

    Two collision-rate laws (``rate``):

    * ``"constant"`` (default; the pseudo-Maxwell model): every pair collides at the same rate;
      time is τ, collisions per particle (N/2 pair collisions per unit τ).
    * another kernel of :mod:`particles.kernels` (DSMC by thinning with its ``rate`` and
      ``rate_bound``; below, hard rods |v − w|): time t at n = ``density``; a given
      particle i collides with a given other particle j at rate (n/N)|v_i − v_j|, so particle i
      collides at rate (n/N)Σ_j |v_i − v_j| → n⟨|v − w|⟩ (2n√(T/π) per particle for a Gaussian
      of temperature T = ⟨v²⟩) and the one-particle law f obeys, as N → ∞,
      d/dt ∫φ f = (n/2) ∫∫ |v − w| f(v) f(w) [φ(v') + φ(w') − φ(v) − φ(w)] dv dw.
      Finite-N identities (expectations, given the velocities): the total collision rate is
      (n/N)Σ_{i<j}|v_i − v_j| and dE/dt = −(1 − r²)/4 · n · (1/N²)Σ_{i≠j}|v_i − v_j|³ with
      E = (1/N)Σ v_i² (→ −(1 − r²)/4 · n⟨|v − w|³⟩).  Exact scheme: candidate pairs (uniform,
      i ≠ j) at the uniformized rate n(N − 1)B/2 with the bound B =
      :func:`~particles.pair_schedule.hull_bound` (≥ every
      |v_i − v_j| now and later: collisions keep velocities in their pair's hull), each accepted
      with probability |v_i − v_j|/B through a uniform mark U drawn with it (accept iff
      U·B < |v_i − v_j| at the candidate's turn).  B is recomputed from the velocities every
      ``BLOCK_WINDOWS`` sub-windows (tightened as the gas cools; the thinning stays exact since
      B bounds every later |g|; :func:`~particles.pair_schedule.thinned_windows`).  Each
      block's sub-window length is the power of two h with
      n(N − 1)B h/2 ≈ ``TARGET_EVENTS`` candidates, on the grid of multiples of h; the driver
      stops (recentring, checkpoints) every ``stop_step`` in t, the power of two nearest 4/n.
      ``collisions`` counts the accepted candidates.

    ``dimension`` ∈ {1, 2, 3} (velocities (N,) in 1D, (N, d) otherwise), ``angular`` ∈
    {"uniform", "hard"} (the law of the collision direction n; irrelevant in 1D), ``driving``
    = D ≥ 0 (white-noise heating, 1D only).  With the defaults this is the 1D Ulam engine,
    unchanged.

    Finite-N identities (expectations, zero total momentum, which recentring keeps).  With
    Σ_i v_i = 0, the mean of |v_i − v_j|² over the N(N − 1) ordered pairs i ≠ j is
    2N/(N − 1) · E, E = (1/N)Σ|v_i|².  A collision changes Σ|v|² by
    −2δ·g + 2|δ|² = −2p(g·n)² + 2p²(g·n)² = −2pq (g·n)² (δ = p(g·n)n), and
    ⟨(g·n)²⟩ = ⟨η⟩|g|² for both angular models (η = (ĝ·n)²).  At N/2 collisions per unit τ:
    dE/dτ = −(N/2)(1/N) 2pq⟨η⟩ · 2N/(N − 1) · E = −Λ N/(N − 1) E, Λ = 2pq⟨η⟩.
    Driven 1D: the noise adds 2D(1 − 1/N) per unit τ to the centred energy, so the steady
    centred energy is D (N − 1)²/(pq N²).

    Parameters
    ----------
    n : int
        Number of particles N, 2 ≤ N ≤ 2³¹ − 1.
    restitution : float
        Restitution coefficient r ∈ [0, 1].
    initial : str, optional
        Name of the initial velocity law (default ``"gaussian"``; one with a sampler).
    dimension : int, optional
        1 (default), 2 or 3.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``.
    driving : float, optional
        White-noise heating D ≥ 0 (default 0; 1D only).
    rate : str or particles.kernels.Kernel, optional
        A kernel or its name: ``"constant"`` (default, τ), any other one (t; 1D, no driving).
    density : float, optional
        The number density n > 0 of the rate (n/N)|v_i − v_j| (default 1; a value other than 1
        only with ``rate="relative_velocity"``), in 1/length: t is in length/velocity.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``n``, ``restitution``, ``initial`` (unknown, or without a sampler),
        ``dimension``, ``angular``, ``driving`` (negative, or non-zero with dimension > 1),
        ``rate`` (not a registered kernel, one of another restitution, or not ``"constant"`` with
        dimension > 1 or driving) or ``density`` (not finite, ≤ 0, or not 1 with the constant).
    """

    n: int
    restitution: float
    initial: str = "gaussian"
    dimension: int = 1
    angular: str = "uniform"
    driving: float = 0.0
    rate: str | Kernel = ConstantRate.name
    density: float = 1.0
    name: ClassVar[str] = "ulam"
    #: The collision kernel (:mod:`particles.kernels`) that ``rate`` names or is.
    kernel: Kernel = field(init=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        if self.n > 2**31 - 1:  # particle ids are int32 in the event arrays
            raise InvalidArgumentError("n", self.n, "an integer <= 2**31 - 1")
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", law.name, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        object.__setattr__(self, "dimension", check_dimension(self.dimension))
        check_angular(self.angular)
        driving = check_nonnegative(self.driving, "driving")
        if driving > 0.0 and self.dimension != 1:
            raise InvalidArgumentError("driving", self.driving, "0 when dimension > 1")
        object.__setattr__(self, "driving", driving)
        if isinstance(self.rate, Kernel):
            kernel = self.rate
            if kernel.restitution != self.restitution:
                raise InvalidArgumentError(
                    "rate", kernel, f"a kernel of the engine's restitution {self.restitution}")
        else:
            kernel = make_kernel(kernel_class(self.rate, "rate").name, self.restitution, "rate")
        rate = kernel.name
        object.__setattr__(self, "rate", rate)
        object.__setattr__(self, "kernel", kernel)
        density = check_positive(self.density, "density")
        if 1 not in kernel.dimensions:
            raise InvalidArgumentError("rate", rate, "a kernel defined in d = 1")
        if rate != ConstantRate.name:
            if self.dimension != 1:
                raise InvalidArgumentError("rate", rate,
                                           f"{ConstantRate.name!r} when dimension > 1")
            if driving != 0.0:
                raise InvalidArgumentError("rate", rate, f"{ConstantRate.name!r} with driving > 0")
        elif density != 1.0:
            raise InvalidArgumentError(
                "density", self.density, f"1 with rate {ConstantRate.name!r} (the density sets the "
                f"rate (n/N)|v_i - v_j| of rate {RelativeVelocity.name!r} only)")
        object.__setattr__(self, "density", density)

    @property
    def p(self) -> float:
        return transfer_fraction(self.restitution)

    @property
    def relative_velocity_rate(self) -> bool:
        """True for a velocity-dependent rate (the DSMC by thinning, time t), False for τ."""
        return self.rate != ConstantRate.name

    @property
    def time_name(self) -> str:
        """The model's time, its kernel's ``time_name``: ``"tau"`` (collisions per particle,
        constant rate) or ``"t"`` (physical time at density n, e.g. the relative velocity)."""
        return self.kernel.time_name

    @property
    def window(self) -> float:
        """τ-length of an event window (a power of two): about 2.5e4 events per window."""
        return _window_for(self.n)

    @property
    def stop_step(self) -> float:
        """Driver stops (progress, checkpoints) every max(4, window) in τ (a power of two).  Each
        ``advance`` copies the velocities (the previous state must survive Ctrl-C); stops 4 apart
        keep that copy below ~3% of the run time at N = 1e6.  ``rate="relative_velocity"``: the
        power of two nearest to 4/n in t (about 4.5 collisions per particle for a Gaussian of
        T = 1, fewer as the gas cools)."""
        if self.relative_velocity_rate:
            return power_of_two_near(4.0 / self.density)
        return max(4.0, self.window)

    def to_dict(self) -> dict:
        """JSON-able parameters, recorded with every result.

        ``dimension``/``angular`` and ``driving`` appear only where they differ from the 1D
        defaults,
        so that the checkpoints of 1D runs keep their identity.

        Returns
        -------
        dict
            ``n``, ``restitution``, ``initial``, ``window`` and those optional keys.
        """
        out = {
            "n": self.n,
            "restitution": self.restitution,
            "initial": self.initial,
            "window": self.window,
        }
        # Only where they differ from the 1D defaults, so checkpoints of 0.1 runs still match.
        if self.dimension != 1:
            out.update(dimension=self.dimension, angular=self.angular)
        if self.driving != 0.0:
            out["driving"] = self.driving
        if self.relative_velocity_rate:  # adaptive sub-windows: no fixed window
            del out["window"]
            out.update(rate=self.rate, density=self.density,
                       target_events=min(TARGET_EVENTS, self.n),
                       block_windows=BLOCK_WINDOWS)
            # the kernel's parameters that differ from their defaults (hard rods: as before)
            for parameter in self.kernel.parameters:
                value = getattr(self.kernel, parameter.name)
                if value != parameter.default:
                    out[parameter.name] = value
        return out

    def initial_state(self, rng: np.random.Generator) -> UlamState:
        """The state at τ = 0: velocities from the law, each component drawn by
        :func:`particles.driver.initial_velocities`.

        Parameters
        ----------
        rng : numpy.random.Generator
            The random generator.

        Returns
        -------
        particles.UlamState
            The initial state, with no collisions.
        """
        if self.dimension == 1:
            return UlamState(0.0, initial_velocities(self.initial, self.n, rng), 0)
        columns = [initial_velocities(self.initial, self.n, rng) for _ in range(self.dimension)]
        return UlamState(0.0, np.stack(columns, axis=1), 0)

    def rebuild_state(self, arrays) -> UlamState:
        """Rebuild a checkpointed state (:meth:`UlamState.from_arrays` with this engine's N and d);
        :meth:`state_from_arrays` (of :class:`particles.driver.EngineBase`) calls it.

        Parameters
        ----------
        arrays : mapping
            The arrays of :meth:`UlamState.to_arrays`.

        Returns
        -------
        particles.UlamState
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, from :meth:`UlamState.from_arrays`.
        """
        return UlamState.from_arrays(arrays, self.n, self.dimension)

    def memory_per_particle(self) -> float:
        """Working bytes per particle: 64 per velocity component (31 measured at N = 10⁶ in 1D,
        doubled).

        Returns
        -------
        float
            64 · d bytes.
        """
        return 64.0 * self.dimension

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Pair collisions to τ = ``t_max``: N/2 per unit τ.  ``rate="relative_velocity"``: an
        upper bound on the candidates to t = ``t_max``, n(N − 1)B t/2 with B = 2√2·6 (six
        standard deviations of each unit-energy velocity; the real count is far smaller as the
        gas cools).

        Parameters
        ----------
        t_max : float
            The last requested τ.
        n_times : int
            The number of requested times (unused).

        Returns
        -------
        tuple of (float, str)
            ``(N t_max / 2, "collisions")``.
        """
        if self.relative_velocity_rate:
            bound = kernel_bound(self.kernel, 12.0 * math.sqrt(2.0))
            return 0.5 * self.density * (self.n - 1) * bound * t_max, "candidates"
        return float(self.n) * t_max / 2.0, "collisions"

    def windows(self, start: float, until: float) -> list[tuple[float, float]]:
        """The event windows covering (start, until]: cut at multiples of ``window``.

        Parameters
        ----------
        start, until : float
            The τ interval.

        Returns
        -------
        list of tuple of float
            The consecutive windows ``(a, b)``, from ``start`` to ``until``.
        """
        cuts = [start]
        t = start
        while True:
            t = next_grid_point(t, self.window)
            if t >= until:
                break
            cuts.append(t)
        cuts.append(until)
        return list(zip(cuts[:-1], cuts[1:], strict=True))

    def advance(self, state: UlamState, until: float, rng: np.random.Generator) -> UlamState:
        """Exact dynamics from ``state.time`` to ``until`` (window by window).

        Parameters
        ----------
        state : particles.UlamState
            The state to advance (not modified).
        until : float
            The τ to reach, ≥ ``state.time``.
        rng : numpy.random.Generator
            Source of the event counts, pairs and angles.

        Returns
        -------
        particles.UlamState
            The state at ``until``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``until`` if it is before the state's time.
        """
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
        return self._advance(state, until, rng)

    def _advance(self, state: UlamState, until: float, rng) -> UlamState:
        """The dynamics of :meth:`advance`, after its check of ``until``."""
        if self.relative_velocity_rate:
            return self._advance_thinned(state, until, rng)
        if self.dimension != 1:
            return self._advance_vectors(state, until, rng)
        if self.driving != 0.0:
            return self._advance_driven(state, until, rng)
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p = self.p
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                if occurrence.size < 2 * k:
                    occurrence = np.arange(
                        max(2 * k, int(1.25 * self.n * self.window) + 16), dtype=np.int32
                    )
                # The drawn pairs, read from last to first, are the window's events in order.
                fire_rounds(v, draw_pairs_unchecked(rng, self.n, k), p, first, occurrence)
                collisions += k
            if _is_grid_point(b, self.stop_step):
                recentre(v)
        return UlamState(float(until), v, collisions)

    def thinned_windows(self, start: float, until: float, bound: float):
        """The sub-windows of the thinning block from ``start`` with bound ``bound`` (rate
        ``"relative_velocity"``; :func:`~particles.pair_schedule.thinned_windows` at this
        engine's candidate rate per unit bound n(N − 1)/2 and ``stop_step``).

        Parameters
        ----------
        start, until : float
            The block's start and the time to reach (t).
        bound : float
            The thinning bound B ≥ 0 at ``start``.

        Returns
        -------
        list of tuple of float
            The consecutive sub-windows ``(a, b)``.
        """
        return thinned_windows(start, until, 0.5 * self.density * (self.n - 1) * bound,
                               self.stop_step, min(TARGET_EVENTS, self.n))

    def _advance_thinned(self, state: UlamState, until: float, rng, sequential=False):
        """``rate="relative_velocity"``: block by block the bound B (:func:`hull_bound`), then
        per sub-window the Poisson count of candidates (mean n(N − 1)B Δt/2), the pairs
        (:func:`~particles.pair_schedule.draw_pairs_unchecked`, last candidate first) and one
        uniform mark per candidate; fired in rounds (or, ``sequential``, one by one by
        :meth:`_thin_window`).  Recentred at the multiples of ``stop_step``."""
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p = self.p
        kernel = self.kernel
        half_rate = 0.5 * self.density * (self.n - 1)
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        s = float(state.time)
        target = float(until)
        while s < target:
            bound = kernel_bound(kernel, hull_bound(v))  # ≥ every pair's rate, now and later
            windows = self.thinned_windows(s, target, bound)
            for a, b in windows:
                k = int(rng.poisson(half_rate * bound * (b - a))) if bound > 0.0 else 0
                if k:
                    pairs = draw_pairs_unchecked(rng, self.n, k)  # row 0: the last candidate
                    marks = rng.random(k)
                    if sequential:
                        collisions += self._thin_window(v, pairs, marks, bound, p, kernel)
                    else:
                        if occurrence.size < 2 * k:
                            occurrence = np.arange(max(2 * k, 4 * TARGET_EVENTS),
                                                   dtype=np.int32)
                        collisions += fire_rounds_thinned(v, pairs, marks, bound, p, first,
                                                          occurrence, kernel.rate)
            s = windows[-1][1]
            if _is_grid_point(s, self.stop_step):
                recentre(v)
        return UlamState(target, v, collisions)

    def _thin_window(self, v, pairs, marks, bound, p, kernel) -> int:
        """The reference's loop over one sub-window (:func:`thin_sequential`): accepted count."""
        return thin_sequential(v, pairs, marks, bound, p, kernel.rate)[0]

    def _occurrences(self, occurrence: np.ndarray, k: int) -> np.ndarray:
        if occurrence.size < 2 * k:
            occurrence = np.arange(
                max(2 * k, int(1.25 * self.n * self.window) + 16), dtype=np.int32
            )
        return occurrence

    def _advance_vectors(self, state: UlamState, until: float, rng) -> UlamState:
        """d ≥ 2: per window the Poisson count, the pairs, then the angular draws."""
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p, angular = self.p, self.angular
        plane = as_complex(v) if self.dimension == 2 else None  # a view: v changes with it
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                occurrence = self._occurrences(occurrence, k)
                pairs = draw_pairs_unchecked(rng, self.n, k)  # row 0 is the window's last event
                draws = _draw_angles(rng, k, self.dimension, angular)
                if plane is not None:
                    transfer = _plane_transfer(draws.sine, p)
                    fire_rounds_plane(plane, pairs, transfer, first, occurrence)
                else:

                    def collide(w, fired, rows, draws=draws):
                        collide_pairs_vectors(w, fired, subset_draws(draws, rows), angular, p)

                    fire_rounds_with_rows(v, pairs, first, occurrence, collide)
                collisions += k
            if _is_grid_point(b, self.stop_step):
                recentre(v)
        return UlamState(float(until), v, collisions)

    def _advance_driven(self, state: UlamState, until: float, rng) -> UlamState:
        """Driven 1D: per window the Poisson count, the pairs, the sorted event times, two
        normals per event; kicks of variance 2DΔτ since each particle's previous kick."""
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p = self.p
        two_d = 2.0 * self.driving
        last = np.full(self.n, float(state.time))
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                occurrence = self._occurrences(occurrence, k)
                pairs = draw_pairs_unchecked(rng, self.n, k)  # row 0 is the window's last event
                times = np.sort(rng.uniform(a, b, k))[::-1]  # row order: latest first
                kicks = rng.standard_normal((k, 2))

                def collide(w, fired, rows, times=times, kicks=kicks):
                    ia, ib = fired[0::2], fired[1::2]
                    t = times[rows]
                    va = w[ia] + np.sqrt(two_d * (t - last[ia])) * kicks[rows, 0]
                    vb = w[ib] + np.sqrt(two_d * (t - last[ib])) * kicks[rows, 1]
                    last[ia] = t
                    last[ib] = t
                    collide_arrays(va, vb, p)
                    w[ia] = va
                    w[ib] = vb

                fire_rounds_with_rows(v, pairs, first, occurrence, collide)
                collisions += k
            if _is_grid_point(b, self.stop_step):  # bring every particle to b, then recentre
                v += np.sqrt(two_d * (b - last)) * rng.standard_normal(self.n)
                last[:] = b
                recentre(v)
        if np.any(last < until):
            v += np.sqrt(two_d * (float(until) - last)) * rng.standard_normal(self.n)
        return UlamState(float(until), v, collisions)


@dataclass(frozen=True)
class UlamReference(Ulam):
    """Sequential reference of the same model (for tests): a Python loop drawing exponential
    waiting times of rate N/2 and one random pair per collision.  Memorylessness makes stopping
    at ``until`` and redrawing the next waiting time exact.

    ``rate="relative_velocity"``: the same draws as :class:`Ulam` (blocks, bounds, candidate
    counts, pairs, marks), the candidates applied one at a time in time order by a Python loop
    (:func:`~particles.pair_schedule.thin_sequential`), so the two agree bit for bit.

    Parameters
    ----------
    n, restitution, initial, dimension, angular, driving, rate, density
        As for :class:`Ulam`.
    """

    name: ClassVar[str] = "ulam-reference"

    def _advance(self, state: UlamState, until: float, rng) -> UlamState:
        """One collision at a time, at exponential waiting times of rate N/2 (τ units)."""
        if self.relative_velocity_rate:
            return self._advance_thinned(state, until, rng, sequential=True)
        if self.dimension != 1 or self.driving != 0.0:
            return self._advance_general(state, until, rng)
        v = state.velocities.tolist()
        n, p = self.n, self.p
        t = state.time
        collisions = int(state.collisions)
        mean_wait = 2.0 / n
        step = self.stop_step
        grid = next_grid_point(t, step)  # the next recentring point after the start

        def recentre_list(values):
            arr = np.array(values)
            recentre(arr)
            return arr.tolist()

        while True:
            t += rng.exponential(mean_wait)
            while grid <= until and grid <= t:  # recentre before the events after a grid point
                v = recentre_list(v)
                grid = next_grid_point(grid, step)
            if t >= until:
                break
            i = int(rng.integers(n))
            j = int(rng.integers(n - 1))
            j += j >= i
            v[i], v[j] = collide_scalar(v[i], v[j], p)
            collisions += 1
        return UlamState(float(until), np.array(v), collisions)

    def _advance_general(self, state: UlamState, until: float, rng) -> UlamState:
        """Independent reference for d ≥ 2 and for driving: one event at a time; "hard"
        directions by rejection (n uniform, accepted with probability |ĝ·n|); the noise is
        applied to every particle over each waiting time (kicks of variance 2DΔτ)."""
        n, p = self.n, self.p
        v = np.array(state.velocities, dtype=float, copy=True)
        vector = v.ndim == 2
        t = float(state.time)
        collisions = int(state.collisions)
        step = self.stop_step
        grid = next_grid_point(t, step)
        sigma2 = 2.0 * self.driving

        def heat(dt):
            if sigma2 > 0.0 and dt > 0.0:
                v[:] += math.sqrt(sigma2 * dt) * rng.standard_normal(v.shape)

        while True:
            event = t + rng.exponential(2.0 / n)
            target = min(event, until)
            while grid <= target:
                heat(grid - t)
                t = grid
                recentre(v)
                grid = next_grid_point(grid, step)
            heat(target - t)
            t = target
            if t >= until:
                break
            i = int(rng.integers(n))
            j = int(rng.integers(n - 1))
            j += j >= i
            if not vector:
                v[i], v[j] = collide_scalar(float(v[i]), float(v[j]), p)
            else:
                g = v[i] - v[j]
                while True:
                    direction = rng.standard_normal(self.dimension)
                    direction /= np.linalg.norm(direction)
                    g_norm = np.linalg.norm(g)
                    if self.angular == "uniform" or g_norm == 0.0:
                        break
                    if rng.random() < abs(g @ direction) / g_norm:
                        break
                delta = p * (g @ direction) * direction
                v[i] -= delta
                v[j] += delta
            collisions += 1
        return UlamState(float(until), v, collisions)
