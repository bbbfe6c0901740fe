"""The Ulam (mean-field pseudo-Maxwell) model: exact continuous-time dynamics, vectorized.

Model (SPEC §2).  N particles; pair collisions form a Poisson process of rate N/2 in τ, each
collision picks a uniformly random pair i ≠ j and applies the rule of :mod:`particles.collision`.
Each particle thus collides at rate 1 and τ counts collisions per particle.  This is *not* a
synchronous sweep over all pairs.

Exact vectorized scheme (SPEC §6).  τ is cut into windows on a fixed grid of step ``window``
(a power of two, so grid points are exact floats) and at the requested times.  For a window of
length Δτ we draw the number of events K ~ Poisson(N Δτ / 2) and the K pairs; event times inside
a window are never needed, only their order.  The events are then fired in rounds: in each round
every remaining event that is the earliest remaining event of *both* its particles fires (all
such events touch disjoint particles, and no earlier event can touch them), and is removed.  This
applies exactly the updates of a sequential loop over the same events, in an order that differs
only by swapping events on disjoint particles, so the velocities agree bit for bit
(:func:`collide_in_order` against :func:`collide_sequential`).

"Earliest remaining event of each particle" is a scatter-max of the occurrence index: the events
are stored in *reverse* time order as an interleaved int32 array ``[a_0, b_0, a_1, b_1, ...]``
and a single fancy assignment ``first[pairs] = arange(2K)`` leaves, for each particle, the
largest occurrence index written to it.  NumPy applies repeated indices in order in practice, but
does not promise it, so the result is checked (every occurrence must see an index ≥ its own) and
recomputed with ``np.maximum.at`` if the check ever fails.

Momentum round-off.  Collisions conserve the total momentum only up to round-off, and that
residue does not decay while the velocities decay like e^{−λτ}: for λτ ≳ 30 every velocity would
approach the round-off mean (measured before this correction: r = 0.9, N = 2·10⁴, τ = 1200, all
velocities of a run equal).  The collision rule is Galilean invariant (it depends only on the
difference of the two velocities), so subtracting the mean velocity from every particle commutes
with the dynamics and is exact up to round-off.  Both engines do it (:func:`recentre`) at the
same deterministic points: the multiples of ``stop_step`` in τ, after every event before that
point and before every event after it.  They are window boundaries of the fast path (``stop_step``
is a multiple of ``window``), so the fast path and the sequential loop still agree bit for bit on
the same events (:func:`collide_sequential` followed by :func:`recentre`).  The momentum recorded
at a grid point is therefore ~0 by construction and says nothing about conservation; the
collisions' own drift shows at times between grid points, and the tests bound it there.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .collision import collide_arrays, collide_scalar, transfer_fraction
from .driver import initial_velocities, next_grid_point
from .initial import get_law
from .validation import InvalidArgumentError, check_count, check_restitution

__all__ = [
    "Ulam",
    "UlamReference",
    "UlamState",
    "draw_pairs",
    "collide_in_order",
    "collide_sequential",
    "recentre",
]

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
    """Ulam state at time ``time`` (τ): velocities and the total number of pair collisions."""

    time: float
    velocities: np.ndarray = field(repr=False)
    collisions: int = 0

    def to_arrays(self) -> dict[str, np.ndarray]:
        return {
            "time": np.array(self.time, dtype=float),
            "velocities": self.velocities,
            "collisions": np.array(self.collisions, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, arrays, n: int) -> UlamState:
        v = np.asarray(arrays["velocities"], dtype=float)
        if v.shape != (n,):
            raise ValueError(f"velocities of shape {v.shape}, expected ({n},)")
        return cls(float(arrays["time"]), v.copy(), int(arrays["collisions"]))


def draw_pairs(rng: np.random.Generator, n: int, k: int) -> np.ndarray:
    """``k`` independent uniformly random ordered pairs (i, j), i ≠ j, of ``n`` particles, as an
    int32 array of shape (k, 2)."""
    pairs = np.empty((k, 2), dtype=np.int32)
    pairs[:, 0] = rng.integers(0, n, k, dtype=np.int32)
    second = rng.integers(0, n - 1, k, dtype=np.int32)
    second += second >= pairs[:, 0]
    pairs[:, 1] = second
    return pairs


def _largest_occurrence(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """For each entry of ``flat`` (particle ids), the largest ``occ`` among the entries with the
    same particle.  One fancy assignment (the last write wins), verified; exact fallback."""
    first[flat] = occ
    own = first[flat]
    if not np.all(own >= occ):  # pragma: no cover - NumPy did not write in order
        own = _largest_occurrence_ufunc(first, flat, occ)
    return own


def _largest_occurrence_ufunc(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """The same with ``np.maximum.at`` (order-independent, ~10x slower)."""
    first[flat] = -1
    np.maximum.at(first, flat, occ)
    return first[flat]


def _fire_rounds(
    v: np.ndarray, reversed_pairs: np.ndarray, p: float, first: np.ndarray, occurrence: np.ndarray
) -> int:
    """Apply the events of ``reversed_pairs`` ((K, 2) int32, C-contiguous, **last event first**)
    to ``v`` in place, round by round.  ``first`` is int32 scratch of size N, ``occurrence`` is
    ``arange(≥ 2K, dtype=int32)``.  Returns the number of rounds."""
    packed = reversed_pairs.view(np.int64).reshape(-1)  # one int64 per event: cheap compaction
    rounds = 0
    while packed.size:
        m = packed.size
        # a_0, b_0, a_1, b_1, ... (reverse time order); intp indices index ~2x faster than int32
        flat = packed.view(np.int32).astype(np.intp)
        occ = occurrence[: 2 * m]
        own = _largest_occurrence(first, flat, occ)
        # Event r (occurrences 2r, 2r+1) fires iff it is the earliest of both its particles.
        own_is_first = own == occ
        fire = own_is_first[0::2]
        fire &= own_is_first[1::2]
        # np.compress, not packed[fire]: boolean indexing is ~5x slower on random masks.
        fired = np.compress(fire, packed).view(np.int32).astype(np.intp)
        vv = v[fired]
        vv2 = vv.reshape(-1, 2)
        collide_arrays(vv2[:, 0], vv2[:, 1], p)
        v[fired] = vv
        np.logical_not(fire, out=fire)
        packed = np.compress(fire, packed)
        rounds += 1
    return rounds


def recentre(v: np.ndarray) -> None:
    """Subtract the mean velocity from ``v`` in place (exact by Galilean invariance of the
    collision rule; removes the non-decaying round-off of the total momentum)."""
    v -= v.mean()


def _is_grid_point(t: float, step: float) -> bool:
    return t > 0.0 and t % step == 0.0


def _check_events(v, pairs, restitution):
    p = transfer_fraction(restitution)
    v = np.array(v, dtype=float)  # a copy
    pairs = np.asarray(pairs)
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise InvalidArgumentError("pairs", f"array of shape {pairs.shape}", "shape (K, 2)")
    if pairs.size and (
        pairs.min() < 0 or pairs.max() >= v.size or np.any(pairs[:, 0] == pairs[:, 1])
    ):
        raise InvalidArgumentError(
            "pairs", "out-of-range or i == j entries", f"pairs of 0..{v.size - 1}, i != j"
        )
    return v, pairs, p


def collide_in_order(v, pairs, restitution) -> np.ndarray:
    """Fast path: apply the collisions ``pairs[0], pairs[1], …`` (time order) to a copy of ``v``
    with the round-parallel scheme; returns the new velocities."""
    v, pairs, p = _check_events(v, pairs, restitution)
    reversed_pairs = np.ascontiguousarray(pairs[::-1], dtype=np.int32)
    first = np.empty(v.size, dtype=np.int32)
    occurrence = np.arange(2 * len(pairs), dtype=np.int32)
    _fire_rounds(v, reversed_pairs, p, first, occurrence)
    return v


def collide_sequential(v, pairs, restitution) -> np.ndarray:
    """Reference: a plain Python loop over ``pairs`` in time order, on a copy of ``v``."""
    v, pairs, p = _check_events(v, pairs, restitution)
    out = v.tolist()
    for a, b in pairs.tolist():
        out[a], out[b] = collide_scalar(out[a], out[b], p)
    return np.array(out, dtype=float)


@dataclass(frozen=True)
class Ulam:
    """Exact vectorized Ulam engine with ``n`` ≥ 2 particles, restitution ``restitution`` ∈ [0, 1],
    initial law ``initial`` (a name of :mod:`particles.initial`).  Time is τ."""

    n: int
    restitution: float
    initial: str = "gaussian"
    name: ClassVar[str] = "ulam"

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        if self.n > 2**31 - 1:  # particle ids are int32 in the event arrays
            raise InvalidArgumentError("n", self.n, "an integer <= 2**31 - 1")
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", law.name, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)

    @property
    def p(self) -> float:
        return transfer_fraction(self.restitution)

    @property
    def window(self) -> float:
        """τ-length of an event window (a power of two): about 2.5e4 events per window."""
        return _window_for(self.n)

    @property
    def stop_step(self) -> float:
        """Driver stops (progress, checkpoints) every max(4, window) in τ (a power of two).  Each
        ``advance`` copies the velocities (the previous state must survive Ctrl-C); stops 4 apart
        keep that copy below ~3% of the run time at N = 1e6."""
        return max(4.0, self.window)

    def params(self) -> dict:
        return {
            "n": self.n,
            "restitution": self.restitution,
            "initial": self.initial,
            "window": self.window,
        }

    def initial_state(self, rng: np.random.Generator) -> UlamState:
        return UlamState(0.0, initial_velocities(self.initial, self.n, rng), 0)

    def next_stop(self, time: float) -> float:
        return next_grid_point(time, self.stop_step)

    def state_from_arrays(self, arrays) -> UlamState:
        return UlamState.from_arrays(arrays, self.n)

    def windows(self, start: float, until: float) -> list[tuple[float, float]]:
        """The event windows covering (start, until]: cut at multiples of ``window``."""
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
        """Exact dynamics from ``state.time`` to ``until`` (window by window)."""
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
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
                _fire_rounds(v, draw_pairs(rng, self.n, k), p, first, occurrence)
                collisions += k
            if _is_grid_point(b, self.stop_step):
                recentre(v)
        return UlamState(float(until), v, collisions)


@dataclass(frozen=True)
class UlamReference(Ulam):
    """Sequential reference of the same model (for tests): a Python loop drawing exponential
    waiting times of rate N/2 and one random pair per collision.  Memorylessness makes stopping
    at ``until`` and redrawing the next waiting time exact."""

    name: ClassVar[str] = "ulam-reference"

    def advance(self, state: UlamState, until: float, rng: np.random.Generator) -> UlamState:
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
