"""The lattice model (SPEC §3): inelastic collisions between neighbours on a ring, vectorized.

Model.  N sites on a ring with velocities v_0..v_{N−1}; bond b joins sites b and b+1 (mod N).
Each attempt picks a bond uniformly; with the kinematic constraint (default) it collides by the
rule of :mod:`particles.collision` only if v_b > v_{b+1} (the particles approach), without it
always.  One unit of τ is N attempts.

Exact vectorized scheme (SPEC §6).  Uniform bond choice at N attempts per unit τ is the same
process as giving every bond its own Poisson clock of rate 1: the state carries each bond's next
attempt time.  A bond whose next time is below ``until`` and below both neighbouring bonds' next
times can fire now (no earlier attempt can touch its two sites): all such bonds fire at once,
their clocks advance by fresh Exp(1) draws, and the pass repeats until every clock is ≥ ``until``.
Ties between neighbouring clocks (probability zero) go to the left bond (bond N−1 counts as
left of bond 0), so some earliest pending attempt always fires and the loop always ends.
Attempts on disjoint sites commute, so this applies exactly the updates of processing all
attempts one by one in time order (:func:`run_clocks_sequential`) — bit for bit, given the same
clock increments (:func:`run_clocks` with an explicit increment source).

Stops.  The driver stops every ``stop_step`` = 4 in τ (long windows amortise the last, sparse
passes: measured 2.5e7 attempts/s for windows of 1, 3.5e7 for 4, N = 1e6); the passes depend on
the stop points, which are a fixed grid, so runs are reproducible and resumable bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .collision import collide_scalar, transfer_fraction
from .driver import initial_velocities, next_grid_point
from .initial import get_law
from .validation import InvalidArgumentError, check_count, check_restitution

__all__ = [
    "Lattice",
    "LatticeState",
    "LatticeDiscreteReference",
    "run_clocks",
    "run_clocks_sequential",
]

#: Clock increments for the bonds ``bonds`` (int array), in the order given.
IncrementSource = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class LatticeState:
    """Lattice state at τ = ``time``: site velocities, each bond's next attempt time
    (``clocks[b]`` ≥ time, for bond (b, b+1)), total collisions and total attempts."""

    time: float
    velocities: np.ndarray = field(repr=False)
    clocks: np.ndarray = field(repr=False)
    collisions: int = 0
    attempts: int = 0

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {
            "time": np.array(self.time, dtype=float),
            "velocities": self.velocities,
            "clocks": self.clocks,
            "collisions": np.array(self.collisions, dtype=np.int64),
            "attempts": np.array(self.attempts, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, arrays, n: int) -> LatticeState:
        v = np.asarray(arrays["velocities"], dtype=float)
        c = np.asarray(arrays["clocks"], dtype=float)
        if v.shape != (n,) or c.shape != (n,):
            raise ValueError(f"velocities {v.shape} / clocks {c.shape}, expected ({n},)")
        time = float(arrays["time"])
        if not np.all(np.isfinite(c) & (c >= time)):
            # every pending attempt is at or after the state's time
            raise ValueError(f"clocks must be finite and >= time={time!r}")
        return cls(
            time,
            v.copy(),
            c.copy(),
            int(arrays["collisions"]),
            int(arrays["attempts"]),
        )


def run_clocks(
    v: np.ndarray,
    clocks: np.ndarray,
    until: float,
    p: float,
    constraint: bool,
    increments: IncrementSource,
    sparse_ratio: int = 16,
) -> tuple[int, int, int]:
    """Fire, in place, every bond attempt earlier than ``until`` (the vectorized scheme).

    ``v`` and ``clocks`` are float64 arrays of length N ≥ 3, modified in place;
    ``increments(bonds)`` returns the next waiting time of each bond in ``bonds`` (fresh Exp(1)
    draws in a run).  Returns ``(attempts, collisions, passes)``.

    Each pass compares every bond's clock with ``until`` and with both neighbours (contiguous
    sweeps).  Once a pass fires fewer than N/``sparse_ratio`` bonds, the bonds still pending
    (clock < ``until``) are listed and later passes only test those.  The fired set of each pass
    is the same either way, so ``sparse_ratio`` only changes speed, never the result.
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
        if constraint:
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
) -> tuple[int, int]:
    """Reference for :func:`run_clocks`: the same clocks, one attempt at a time in time order
    (always the bond with the smallest next time, ties to the smaller index), in pure Python.
    Returns ``(attempts, collisions)``; modifies ``v`` and ``clocks`` in place."""
    import heapq

    n = v.size
    vel = v.tolist()
    heap = [(float(t), b) for b, t in enumerate(clocks.tolist())]
    heapq.heapify(heap)
    attempts = collisions = 0
    while heap[0][0] < until:
        t, b = heapq.heappop(heap)
        a, s = b, (b + 1) % n
        if not constraint or vel[a] > vel[s]:
            vel[a], vel[s] = collide_scalar(vel[a], vel[s], p)
            collisions += 1
        attempts += 1
        heapq.heappush(heap, (t + float(increments(np.array([b]))[0]), b))
    v[:] = vel
    for t, b in heap:
        clocks[b] = t
    return attempts, collisions


@dataclass(frozen=True)
class Lattice:
    """Exact vectorized lattice engine: ``n`` ≥ 3 sites on a ring, restitution ``restitution``,
    initial law ``initial``, kinematic constraint on unless ``constraint=False``.  Time is τ."""

    n: int
    restitution: float
    initial: str = "gaussian"
    constraint: bool = True
    name: ClassVar[str] = "lattice"
    stop_step: ClassVar[float] = 4.0

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

    @property
    def p(self) -> float:
        return transfer_fraction(self.restitution)

    def params(self) -> dict:
        return {
            "n": self.n,
            "restitution": self.restitution,
            "initial": self.initial,
            "constraint": self.constraint,
            "stop_step": self.stop_step,
        }

    def initial_state(self, rng: np.random.Generator) -> LatticeState:
        v = initial_velocities(self.initial, self.n, rng)
        return LatticeState(0.0, v, rng.standard_exponential(self.n), 0, 0)

    def next_stop(self, time: float) -> float:
        return next_grid_point(time, self.stop_step)

    def state_from_arrays(self, arrays) -> LatticeState:
        return LatticeState.from_arrays(arrays, self.n)

    def observe(self, state: LatticeState) -> dict[str, float]:
        return {"attempts": float(state.attempts)}

    def advance(self, state: LatticeState, until: float, rng: np.random.Generator) -> LatticeState:
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
        v = state.velocities.copy()
        clocks = state.clocks.copy()
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


@dataclass(frozen=True)
class LatticeDiscreteReference(Lattice):
    """The textbook discrete-time lattice model (for distribution-level tests): a Python loop
    that picks a uniformly random bond N times per unit τ.  Its τ advances in steps of 1/N, so
    ``until`` is rounded to the nearest whole number of attempts.  The clocks are unused."""

    name: ClassVar[str] = "lattice-discrete-reference"

    def advance(self, state: LatticeState, until: float, rng: np.random.Generator) -> LatticeState:
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
