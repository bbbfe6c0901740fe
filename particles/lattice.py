"""The lattice model: inelastic collisions between neighbours on a ring, vectorized.

Model.  N sites on a ring with velocities v_0..v_{N−1}; bond b joins sites b and b+1 (mod N).
Each attempt picks a bond uniformly; with the kinematic constraint (default) it collides by the
rule of :mod:`particles.collision` only if v_b > v_{b+1} (the particles approach), without it
always.  One unit of τ is N attempts.

Exact vectorized scheme.  Uniform bond choice at N attempts per unit τ is the same
process as giving every bond its own Poisson clock of rate 1: the state carries each bond's next
attempt time.  A bond whose next time is below ``until`` and below both neighbouring bonds' next
times can fire now (no earlier attempt can touch its two sites): all such bonds fire at once,
their clocks advance by fresh Exp(1) draws, and the pass repeats until every clock is ≥ ``until``.
Ties between neighbouring clocks (probability zero) go to the left bond (bond N−1 counts as
left of bond 0), so some earliest pending attempt always fires and the loop always ends.
Attempts on disjoint sites commute, so this applies exactly the updates of processing all
attempts one by one in time order (:func:`run_clocks_sequential`) — bit for bit, given the same
clock increments (:func:`run_clocks` with an explicit increment source).

Rate ∝ |Δ| (``rate="relative_velocity"``).  In hard-rod MD a neighbouring pair collides at a
rate ∝ |Δ| = |v_i − v_{i+1}|; this variant gives bond b the collision rate |Δ_b| (with the
constraint: Δ_b = v_b − v_{b+1} when it is > 0, else 0) per unit of a time t.  This is exactly
MD's rate at t = 0⁺ for Poisson positions of density 1 (a gap has density 1 at 0, so a pair
meets at rate (v_i − v_{i+1})₊), so t is the time of MD at density 1 and Haff's t₀ agrees
initially.  Collisions per particle are τ = 2·collisions/N (``state.collisions``).  It runs in
the same clock scheme by thinning: every bond's clock ticks at a common rate R ≥ max_b |Δ_b|,
and a tick collides only if U·R < Δ_b (with the constraint; < |Δ_b| without it), U uniform on
[0, 1) drawn at the tick — the accepted ticks are then a Poisson process of rate |Δ_b| (resp.
Δ_b⁺) given the velocities, which is the variant exactly.  Velocities stay in the range of the
current ones forever, so R = (max v − min v)(1 + 1e-9) taken at the start of each
:meth:`Lattice.advance` bounds every |Δ| for all later times (the factor covers round-off at the
ulp level).  When R changes between calls, the pending clocks are rescaled,
c ← t + (c − t)·R_old/R_new: by memorylessness the residual waits are independent Exp(R_old),
independent of the past, so the rescaled ones are independent Exp(R_new) (exact, no draws).
The state carries R (``attempt_rate``).  Exact initial cooling from uncorrelated Gaussian data
of variance T (derived in the tests): with the constraint dT/dt = −(2/√π)(1 − r²)T^{3/2} and
dτ/dt = 2√(T/π), so dT/dτ = −(1 − r²)T, MD's values; without it dT/dt and dτ/dt
double and dT/dτ is the same.  (Constant rate, in collisions per particle: −(1 − r²)T/2.)

Stops.  The driver stops every ``stop_step`` = 4 in τ (long windows amortise the last, sparse
passes); the passes depend on
the stop points, which are a fixed grid, so runs are reproducible and resumable bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .collision import collide_scalar, transfer_fraction
from .driver import EngineBase, initial_velocities
from .initial import get_law
from .kernels import KERNELS, ConstantRate, Kernel, RelativeVelocity, kernel_class, make_kernel
from .validation import InvalidArgumentError, check_count, check_real_array, check_restitution

__all__ = [
    "Lattice",
    "LatticeState",
    "LatticeDiscreteReference",
    "thinning_bound",
    "run_clocks",
    "run_clocks_sequential",
]

#: Clock increments for the bonds ``bonds`` (int array), in the order given.
IncrementSource = Callable[[np.ndarray], np.ndarray]

#: The kernels (:mod:`particles.kernels`) that the lattice carries: every bond at rate 1 per
#: unit τ, or at rate |Δ| (the hard-rod kernel at its default exponent 1).
CARRIED_KERNELS = (ConstantRate.name, RelativeVelocity.name)


def __getattr__(name: str):
    if name == "RATES":  # the collision-rate laws are the kernels of the registry now
        raise ImportError("particles.lattice.RATES is gone: the lattice carries the kernels "
                          "particles.lattice.CARRIED_KERNELS of particles.kernels.KERNELS")
    raise AttributeError(f"module 'particles.lattice' has no attribute {name!r}")

#: Relative margin of the thinning bound R over max v − min v (covers ulp-level round-off).
RATE_BOUND_MARGIN = 1e-9

#: The entries every lattice state's ``to_arrays`` writes (``attempt_rate`` only for rate |Δ|).
_STATE_KEYS = ("time", "velocities", "clocks", "collisions", "attempts")


@dataclass(frozen=True)
class LatticeState:
    """Lattice state at ``time``: site velocities, each bond's next attempt time, counters.

    Attributes
    ----------
    time : float
        The time of the state: τ for the constant-rate model, t for the rate-|Δ| variant.
    velocities : numpy.ndarray
        Float array of shape ``(N,)``, the site velocities.
    clocks : numpy.ndarray
        Float array of shape ``(N,)``: ``clocks[b]`` ≥ time is the next attempt time of bond
        (b, b+1).
    collisions : int
        Total number of collisions so far.
    attempts : int
        Total number of attempts (clock ticks) so far.
    attempt_rate : float or None
        The clocks' common rate R of the rate-|Δ| variant; None for the constant-rate model,
        whose clocks have rate 1.
    """

    time: float
    velocities: np.ndarray = field(repr=False)
    clocks: np.ndarray = field(repr=False)
    collisions: int = 0
    attempts: int = 0
    attempt_rate: float | None = None

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as a dict of NumPy arrays (what the driver's checkpoints store).

        Returns
        -------
        dict of str to numpy.ndarray
            ``time``, ``velocities``, ``clocks``, ``collisions``, ``attempts`` and, for the
            rate-|Δ| variant, ``attempt_rate``.
        """
        arrays = {
            "time": np.array(self.time, dtype=float),
            "velocities": self.velocities,
            "clocks": self.clocks,
            "collisions": np.array(self.collisions, dtype=np.int64),
            "attempts": np.array(self.attempts, dtype=np.int64),
        }
        if self.attempt_rate is not None:
            arrays["attempt_rate"] = np.array(self.attempt_rate, dtype=float)
        return arrays

    @classmethod
    def from_arrays(cls, arrays, n: int) -> LatticeState:
        """Rebuild a state from :meth:`to_arrays`'s dict, with consistency checks.

        Parameters
        ----------
        arrays : mapping
            The arrays, as :meth:`to_arrays` writes them.
        n : int
            The number of sites N the arrays must have.

        Returns
        -------
        particles.LatticeState
            The state (with copies of the arrays).

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint`` (a ``ValueError``, which the driver turns into its
            ``CheckpointError`` naming the file): a missing entry, velocities or clocks not of
            shape ``(n,)``, a clock not finite or before ``time``, or an ``attempt_rate`` that
            is not a finite number > 0.
        """
        missing = [k for k in _STATE_KEYS if k not in arrays]
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "a lattice state")
        v = np.asarray(arrays["velocities"], dtype=float)
        c = np.asarray(arrays["clocks"], dtype=float)
        if v.shape != (n,) or c.shape != (n,):
            raise InvalidArgumentError(
                "checkpoint", f"velocities {v.shape} / clocks {c.shape}",
                f"a lattice state, expected ({n},)",
            )
        time = float(arrays["time"])
        if not np.all(np.isfinite(c) & (c >= time)):
            # every pending attempt is at or after the state's time
            raise InvalidArgumentError(
                "checkpoint", "clocks", f"a lattice state, clocks finite and >= time={time!r}"
            )
        rate = None
        if "attempt_rate" in arrays:
            rate = float(arrays["attempt_rate"])
            if not (math.isfinite(rate) and rate > 0.0):
                raise InvalidArgumentError(
                    "checkpoint", f"attempt_rate={rate!r}", "a finite number > 0"
                )
        return cls(
            time,
            v.copy(),
            c.copy(),
            int(arrays["collisions"]),
            int(arrays["attempts"]),
            rate,
        )


def run_clocks(
    v: np.ndarray,
    clocks: np.ndarray,
    until: float,
    p: float,
    constraint: bool,
    increments: IncrementSource,
    sparse_ratio: int = 16,
    *,
    marks: IncrementSource | None = None,
    rate_bound: float = 1.0,
) -> tuple[int, int, int]:
    """Fire, in place, every bond attempt earlier than ``until`` (the vectorized scheme).

    ``v`` and ``clocks`` are float64 arrays of length N ≥ 3, modified in place;
    ``increments(bonds)`` returns the next waiting time of each bond in ``bonds`` (fresh Exp(1)
    draws in a run).  Returns ``(attempts, collisions, passes)``.

    Rate-|Δ| thinning: with ``marks`` given, a fired bond b draws ``u = marks([b])`` (uniform on
    [0, 1) in a run, drawn before the increments of the same pass) and collides iff
    ``u * rate_bound < Δ`` with the constraint, ``< |Δ|`` without it, Δ = v_b − v_{b+1}
    (the caller keeps ``rate_bound`` ≥ every |Δ| and draws the increments at that rate).

    Each pass compares every bond's clock with ``until`` and with both neighbours (contiguous
    sweeps).  Once a pass fires fewer than N/``sparse_ratio`` bonds, the bonds still pending
    (clock < ``until``) are listed and later passes only test those.  The fired set of each pass
    is the same either way, so ``sparse_ratio`` only changes speed, never the result.

    Parameters
    ----------
    v : numpy.ndarray
        Site velocities, float64 of shape ``(N,)``, N ≥ 3; modified in place.
    clocks : numpy.ndarray
        Next attempt time of each bond, float64 of shape ``(N,)``; modified in place.
    until : float
        Fire every attempt with time < ``until``.
    p : float
        The transfer fraction (1 + r)/2.
    constraint : bool
        Collide only approaching pairs (v_b > v_{b+1}).
    increments : callable
        ``increments(bonds)``: the next waiting time of each bond of the int array ``bonds``.
    sparse_ratio : int, optional
        Switch to testing the pending bonds only once a pass fires fewer than
        N/``sparse_ratio`` bonds (default 16); speed only.
    marks : callable or None, optional
        ``marks(bonds)``: uniform [0, 1) marks for rate-|Δ| thinning; None (default): every
        attempt is a collision attempt.
    rate_bound : float, optional
        The thinning bound R (default 1), used with ``marks``.

    Returns
    -------
    tuple of int
        ``(attempts, collisions, passes)``.
    """
    n = v.size
    ext = np.empty(n + 2)  # ext[1:n+1] is the clock array, with one ghost bond at each end
    ext[1 : n + 1] = clocks
    c = ext[1 : n + 1]
    left = ext[:n]
    right = ext[2:]
    fire = np.empty(n, dtype=bool)
    scratch = np.empty(n, dtype=bool)
    attempts = collisions = passes = 0
    candidates = None  # None: test every bond; else the bonds whose clock is still < until
    candidates_right = None
    while True:
        if candidates is None:
            ext[0] = c[n - 1]
            ext[n + 1] = c[0]
            np.less(c, until, out=fire)
            np.less(c, left, out=scratch)
            fire &= scratch
            np.less_equal(c, right, out=scratch)
            fire &= scratch
            bonds = np.flatnonzero(fire)
        else:
            # Few pending attempts left: test only those bonds (gathers instead of full sweeps).
            own = c[candidates]
            cfire = own < c[candidates - 1]  # index -1 wraps to bond N-1
            cfire &= own <= c[candidates_right]
            bonds = np.compress(cfire, candidates)
        if bonds.size == 0:
            break
        passes += 1
        sites = bonds + 1
        if sites[-1] == n:
            sites[-1] = 0
        va = v[bonds]
        vb = v[sites]
        d = va - vb
        if marks is not None:
            threshold = marks(bonds) * rate_bound
            accept = threshold < (d if constraint else np.abs(d))
            d *= p
            d *= accept  # exact: a rejected tick gets d = ±0, so va - d == va
            collisions += int(np.count_nonzero(accept))
        elif constraint:
            approach = d > 0
            d *= p
            d *= approach  # exact: a non-approaching pair gets d = 0, so va - d == va
            collisions += int(np.count_nonzero(approach))
        else:
            d *= p
            collisions += bonds.size
        va -= d
        vb += d
        v[bonds] = va
        v[sites] = vb
        c[bonds] += increments(bonds)
        attempts += bonds.size
        if candidates is None:
            if bonds.size * sparse_ratio < n:
                candidates = np.flatnonzero(c < until)
        else:
            candidates = np.compress(c[candidates] < until, candidates)
        if candidates is not None:
            if candidates.size == 0:
                break
            candidates_right = candidates + 1
            if candidates_right[-1] == n:
                candidates_right[-1] = 0
    clocks[:] = c
    return attempts, collisions, passes


def run_clocks_sequential(
    v: np.ndarray,
    clocks: np.ndarray,
    until: float,
    p: float,
    constraint: bool,
    increments: IncrementSource,
    *,
    marks: IncrementSource | None = None,
    rate_bound: float = 1.0,
) -> tuple[int, int]:
    """Reference for :func:`run_clocks`: the same clocks, one attempt at a time in time order
    (always the bond with the smallest next time, ties to the smaller index), in pure Python,
    with the same rate-|Δ| thinning when ``marks`` is given (one mark per attempt, then its
    increment).  Returns ``(attempts, collisions)``; modifies ``v`` and ``clocks`` in place.

    Parameters
    ----------
    v : numpy.ndarray
        Site velocities, shape ``(N,)``; modified in place.
    clocks : numpy.ndarray
        Next attempt time of each bond, shape ``(N,)``; modified in place.
    until : float
        Process every attempt with time < ``until``.
    p : float
        The transfer fraction (1 + r)/2.
    constraint : bool
        Collide only approaching pairs.
    increments : callable
        ``increments(bonds)``: the next waiting time of each bond of ``bonds``.
    marks : callable or None, optional
        Uniform marks for rate-|Δ| thinning (default None: no thinning).
    rate_bound : float, optional
        The thinning bound R (default 1), used with ``marks``.

    Returns
    -------
    tuple of int
        ``(attempts, collisions)``.
    """
    import heapq

    n = v.size
    vel = v.tolist()
    heap = [(float(t), b) for b, t in enumerate(clocks.tolist())]
    heapq.heapify(heap)
    attempts = collisions = 0
    while heap[0][0] < until:
        t, b = heapq.heappop(heap)
        a, s = b, (b + 1) % n
        if marks is not None:
            threshold = float(marks(np.array([b]))[0]) * rate_bound
            delta = vel[a] - vel[s]
            go = threshold < (delta if constraint else abs(delta))
        else:
            go = not constraint or vel[a] > vel[s]
        if go:
            vel[a], vel[s] = collide_scalar(vel[a], vel[s], p)
            collisions += 1
        attempts += 1
        heapq.heappush(heap, (t + float(increments(np.array([b]))[0]), b))
    v[:] = vel
    for t, b in heap:
        clocks[b] = t
    return attempts, collisions


@dataclass(frozen=True)
class Lattice(EngineBase):
    """Exact vectorized lattice engine: ``n`` ≥ 3 sites on a ring, restitution ``restitution``,
    initial law ``initial``, kinematic constraint on unless ``constraint=False``.

    ``rate="constant"`` (default, the paper's model): every bond attempts at rate 1, time is τ
    (N attempts per unit τ).  ``rate="relative_velocity"``: bond b collides at rate |Δ_b| (only
    approaching pairs with the constraint), time is t, MD's time at density 1; collisions per
    particle are 2·collisions/N (module docstring).

    Parameters
    ----------
    n : int
        Number of sites N ≥ 3.
    restitution : float
        Restitution coefficient r ∈ [0, 1].
    initial : str, optional
        Name of the initial velocity law (default ``"gaussian"``; one with a sampler).
    constraint : bool, optional
        Kinematic constraint: collide only approaching pairs (default True).
    rate : str or particles.kernels.Kernel, optional
        A kernel's name (:mod:`particles.kernels`): ``"constant"`` (default) or
        ``"relative_velocity"`` (:data:`CARRIED_KERNELS`), or such a kernel at this lattice's
        restitution with its default parameters (stored by its name).

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``n``, ``restitution``, ``initial`` (unknown, or without a sampler),
        ``constraint`` (not a bool) or ``rate`` (not a kernel of :data:`CARRIED_KERNELS`).
    """

    n: int
    restitution: float
    initial: str = "gaussian"
    constraint: bool = True
    rate: str = ConstantRate.name
    name: ClassVar[str] = "lattice"
    stop_step: ClassVar[float] = 4.0
    state_keys: ClassVar[tuple[str, ...]] = _STATE_KEYS

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 3))
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", law.name, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        if not isinstance(self.constraint, (bool, np.bool_)):
            raise InvalidArgumentError("constraint", self.constraint, "True or False")
        object.__setattr__(self, "constraint", bool(self.constraint))
        if isinstance(self.rate, Kernel):  # a kernel value: the lattice keeps its name
            kernel = self.rate
            kernel_class(kernel.name, "rate", among=CARRIED_KERNELS)
            if kernel.restitution != self.restitution or kernel != make_kernel(
                    kernel.name, self.restitution, "rate"):
                raise InvalidArgumentError("rate", kernel, f"the kernel {kernel.name!r} with "
                                           f"this lattice's restitution {self.restitution!r} "
                                           "and its default parameters (the lattice's bonds "
                                           "collide at rate 1 or |Δ|)")
            object.__setattr__(self, "rate", kernel.name)
        kernel_class(self.rate, "rate", among=CARRIED_KERNELS)

    @property
    def p(self) -> float:
        return transfer_fraction(self.restitution)

    @property
    def relative_velocity_rate(self) -> bool:
        return self.rate == RelativeVelocity.name

    @property
    def kernel(self) -> Kernel:
        """The collision kernel that ``rate`` names (:mod:`particles.kernels`), at this
        restitution."""
        return make_kernel(self.rate, self.restitution, "rate")

    @property
    def time_name(self) -> str:
        """The lattice's time, its kernel's ``time_name``: ``"tau"`` (attempts per site) or
        ``"t"`` (MD's time at density 1)."""
        return KERNELS[self.rate].time_name

    def to_dict(self) -> dict:
        """JSON-able parameters; ``"rate"`` appears only for the rate-|Δ| variant, so the
        checkpoints of constant-rate runs keep their identity.

        Returns
        -------
        dict
            ``n``, ``restitution``, ``initial``, ``constraint``, ``stop_step`` and, for the rate-|Δ|
            variant, ``rate``.
        """
        out = {
            "n": self.n,
            "restitution": self.restitution,
            "initial": self.initial,
            "constraint": self.constraint,
            "stop_step": self.stop_step,
        }
        if self.relative_velocity_rate:
            out["rate"] = self.rate
        return out

    def initial_state(self, rng: np.random.Generator) -> LatticeState:
        """The state at time 0: velocities from the law, fresh clocks, no attempts yet.

        Velocities come from :func:`particles.driver.initial_velocities` (zero mean, unit mean
        square); the clocks are Exp(1) draws, or Exp(R) with R = :func:`thinning_bound` for the
        rate-|Δ| variant.

        Parameters
        ----------
        rng : numpy.random.Generator
            The random generator.

        Returns
        -------
        particles.LatticeState
            The initial state.
        """
        v = initial_velocities(self.initial, self.n, rng)
        if not self.relative_velocity_rate:
            return LatticeState(0.0, v, rng.standard_exponential(self.n), 0, 0)
        bound = _thinning_bound(v)
        return LatticeState(0.0, v, rng.standard_exponential(self.n) / bound, 0, 0, bound)

    def rebuild_state(self, arrays) -> LatticeState:
        """Rebuild a checkpointed state for this engine (:meth:`state_from_arrays`, of
        :class:`particles.driver.EngineBase`, calls it).

        Parameters
        ----------
        arrays : mapping
            The arrays of :meth:`LatticeState.to_arrays`.

        Returns
        -------
        particles.LatticeState
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``: from :meth:`LatticeState.from_arrays`, or if the state has an
            ``attempt_rate`` and the engine has constant rate (or the reverse).
        """
        state = LatticeState.from_arrays(arrays, self.n)
        if (state.attempt_rate is not None) != self.relative_velocity_rate:
            raise InvalidArgumentError(
                "checkpoint", f"attempt_rate={state.attempt_rate!r}",
                f"a lattice state of rate={self.rate!r}",
            )
        return state

    def memory_per_particle(self) -> float:
        """Working bytes per site: 160 (77 measured at N = 10⁶, doubled).

        Returns
        -------
        float
            160 bytes.
        """
        return 160.0

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Attempted bond updates to ``t_max``: N per unit time; with rate |Δ| the clocks tick at
        the velocity range R, about 2√(2 ln N) at t = 0, so N t · 2√(2 ln N).

        Parameters
        ----------
        t_max : float
            The last requested time.
        n_times : int
            The number of requested times (unused).

        Returns
        -------
        tuple of (float, str)
            ``(events, "attempts")``.
        """
        n = float(self.n)
        events = n * t_max
        if self.relative_velocity_rate:
            events *= 2.0 * math.sqrt(2.0 * math.log(max(n, 2.0)))
        return events, "attempts"

    def observe(self, state: LatticeState) -> dict[str, float]:
        """The scalar observables the driver records at each output time.

        Parameters
        ----------
        state : particles.LatticeState
            The state.

        Returns
        -------
        dict of str to float
            ``{"attempts": total attempts}``.
        """
        return {"attempts": float(state.attempts)}

    def advance(self, state: LatticeState, until: float, rng: np.random.Generator) -> LatticeState:
        """Fire every attempt before ``until`` with the exact vectorized clock scheme.

        For the rate-|Δ| variant the thinning bound R is recomputed from the current velocities and
        the pending clocks are rescaled to it (module docstring).

        Parameters
        ----------
        state : particles.LatticeState
            The state to advance (not modified).
        until : float
            The time to reach (τ, or t for the rate-|Δ| variant), ≥ ``state.time``.
        rng : numpy.random.Generator
            Source of the clock increments (and thinning marks).

        Returns
        -------
        particles.LatticeState
            The state at ``until``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``until`` if it is before the state's time, or ``state`` for a rate-|Δ| run
            given a state without ``attempt_rate``.
        """
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
        v = state.velocities.copy()
        clocks = state.clocks.copy()
        if not self.relative_velocity_rate:
            attempts, collisions, _ = run_clocks(
                v,
                clocks,
                float(until),
                self.p,
                self.constraint,
                lambda bonds: rng.standard_exponential(bonds.size),
            )
            return LatticeState(
                float(until),
                v,
                clocks,
                state.collisions + collisions,
                state.attempts + attempts,
            )
        old = state.attempt_rate
        if old is None:
            raise InvalidArgumentError("state", "a state without attempt_rate", "a rate-|Δ| state")
        bound = _thinning_bound(v)
        if bound == 0.0:  # all velocities equal: no bond can ever collide again
            np.maximum(clocks, float(until), out=clocks)
            return LatticeState(float(until), v, clocks, state.collisions, state.attempts, old)
        if bound != old:
            # residual waits are independent Exp(old): rescaled, independent Exp(bound)
            clocks -= state.time
            clocks *= old / bound
            clocks += state.time
        attempts, collisions, _ = run_clocks(
            v,
            clocks,
            float(until),
            self.p,
            self.constraint,
            lambda bonds: rng.standard_exponential(bonds.size) / bound,
            marks=lambda bonds: rng.random(bonds.size),
            rate_bound=bound,
        )
        return LatticeState(
            float(until),
            v,
            clocks,
            state.collisions + collisions,
            state.attempts + attempts,
            bound,
        )


def thinning_bound(v: np.ndarray) -> float:
    """Thinning bound R = (max v − min v)(1 + ``RATE_BOUND_MARGIN``) ≥ every |v_i − v_j|, now
    and at all later times (velocities never leave their current range).

    Parameters
    ----------
    v : numpy.ndarray
        Site velocities.

    Returns
    -------
    float
        R (0 when all velocities are equal).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``v``) if ``v`` is not a non-empty one-dimensional array of finite reals.
    """
    return _thinning_bound(check_real_array(v, "v", ndim=1, min_size=1))


def _thinning_bound(v: np.ndarray) -> float:
    """:func:`thinning_bound` without the checks (the engines' own finite velocities)."""
    return float(v.max() - v.min()) * (1.0 + RATE_BOUND_MARGIN)


@dataclass(frozen=True)
class LatticeDiscreteReference(Lattice):
    """The textbook discrete-time lattice model (for distribution-level tests): a Python loop
    that picks a uniformly random bond N times per unit τ.  Its τ advances in steps of 1/N, so
    ``until`` is rounded to the nearest whole number of attempts.  The clocks are unused.

    Parameters
    ----------
    n : int
        Number of sites N ≥ 3.
    restitution : float
        Restitution coefficient r ∈ [0, 1].
    initial : str, optional
        Name of the initial velocity law (default ``"gaussian"``).
    constraint : bool, optional
        Kinematic constraint (default True).
    rate : str, optional
        Must be ``"constant"`` (the default).

    Raises
    ------
    particles.InvalidArgumentError
        As :class:`Lattice`, and naming ``rate`` for ``"relative_velocity"``.
    """

    name: ClassVar[str] = "lattice-discrete-reference"

    def __post_init__(self):
        super().__post_init__()
        if self.relative_velocity_rate:
            raise InvalidArgumentError("rate", self.rate,
                                       f"{ConstantRate.name!r} (the discrete reference)")

    def advance(self, state: LatticeState, until: float, rng: np.random.Generator) -> LatticeState:
        """Pick round(until · N) − ``state.attempts`` uniform bonds one by one and collide them.

        Parameters
        ----------
        state : particles.LatticeState
            The state to advance (not modified).
        until : float
            The τ to reach (rounded to a whole number of attempts).
        rng : numpy.random.Generator
            Source of the bond choices.

        Returns
        -------
        particles.LatticeState
            The state at ``until``, with the clocks unchanged.
        """
        n, p = self.n, self.p
        vel = state.velocities.tolist()
        total = int(round(until * n))
        steps = total - state.attempts
        collisions = 0
        for b in rng.integers(0, n, steps).tolist():
            s = b + 1 if b + 1 < n else 0
            if not self.constraint or vel[b] > vel[s]:
                vel[b], vel[s] = collide_scalar(vel[b], vel[s], p)
                collisions += 1
        return LatticeState(
            float(until), np.array(vel), state.clocks, state.collisions + collisions, total
        )
