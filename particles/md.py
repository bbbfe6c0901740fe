"""Exact event-driven molecular dynamics of inelastic hard rods on a ring (SPEC §4, §6).

Model
-----
N rods of length σ on a ring of length L = N / n fly freely between collisions.  A collision of
the left rod i with its right neighbour j = i + 1 (they collide only when approaching,
v_i > v_j) uses the rule of SPEC §1 with Δ = v_i − v_j:

    v_i' = v_i − p Δ,    v_j' = v_j + p Δ,    p = (1 + r)/2,

except that a collision with Δ < δ is elastic (p = 1, the Ben-Naim et al. regularisation); δ = 0
switches the regularisation off.  Elastic collisions (r = 1 or Δ < δ) are carried out as an exact
swap of the two velocities, so they conserve momentum and energy bit for bit.

Coordinates
-----------
Everything is done with point particles on the reduced ring of length L_r = L − N σ
(SPEC §4): the rod i sits at y_i = x_i + i σ.  Point coordinates are *unwrapped* and particle
labels never change order, so at any common time

    x_0 ≤ x_1 ≤ … ≤ x_{N−1} ≤ x_0 + L_r .

Pair b is the neighbour pair (b, b + 1); the seam pair N − 1 is (N − 1, 0) with the partner seen
at x_0 + L_r.  Each particle is stored lazily: its position ``x[i]`` at its own last-update time
``t_last[i]``; at a time t it is at x[i] + v[i] (t − t_last[i]).

Exactness
---------
Every collision is processed at its true time in causal order (no time step, no overlap
correction).  Two engines share one prediction formula and one collision formula, written once:

* ``method="reference"``: a plain sequential loop, a binary heap (``heapq``) over the N pair
  predictions with lazy invalidation, ties broken by the pair index.
* ``method="fast"``: the light-cone scheme of SPEC §6. Velocities stay in [v_min, v_max] forever
  (collisions make convex combinations), so a pending collision at (c_a, X_a) cannot influence
  anything outside the cone X_a + [v_min, v_max] (t − c_a). A prediction (c_b, X_b) is *safe* when
  it is earlier than both neighbouring pairs' predictions and no other pending collision's cone
  reaches it: v_max c_b − X_b < min_{a left of b} (v_max c_a − X_a) and X_b − v_min c_b < min_{a
  right of b} (X_a − v_min c_a), prefix and suffix minima by ``np.minimum.accumulate`` (the ring
  enters as one extra lap, + L_r). All safe collisions are processed in one NumPy pass. The
  globally earliest collision is always safe, so the scheme never stalls; so is the earliest, in
  (time, index) order, of a *tie group* (candidates within a few cone margins of each other, e.g. a
  cluster with zero gaps) that no candidate outside the group reaches, so isolated clusters each
  fire one collision per pass. Only collisions earlier than a moving horizon H are candidates; a
  later collision (c_a > H ≥ c_b) cannot reach an earlier one, so leaving it out is exact, and it
  keeps a pass at O(candidates) instead of O(N). When a pass fires only a handful of collisions (a
  clustered gas, where a few hot clusters carry long causal chains) the rest of the slab runs in
  the scalar heap loop on the same data, which is exact as well: it is the reference restricted to
  the events before H (a pass costs about as much as 100 scalar collisions). In a clustered gas
  nearly all collisions run there, and most of them in *zero-gap bursts*: a cluster collapses to
  one floating-point point, and every collision that reaches it triggers a cascade of
  collisions at one time and place.  The scalar loop runs such a cascade as a sort of the
  block's velocities (``_burst``: the heap's order, without the heap).  See
  ``benchmarks/README.md`` for the measured costs.

Both engines apply the same floating-point operations to the same data, so in non-chaotic
settings they agree bit for bit (tested).  Floating-point traps and how they are handled:

* a gap that round-off made negative is treated as zero (the pair collides at once);
* simultaneous collisions: the sequential heap orders ties by pair index, the fast scheme lets a
  pair fire only if it precedes both neighbours in (time, index) order, and within a tie group
  only the group's earliest in that order;
* repeated collisions of one pair: after an inelastic collision the pair must separate, so the
  two new velocities are clipped to the old interval and swapped if round-off left them
  approaching;
* the cone tests carry a relative round-off margin (``_CONE_MARGIN``); erring on "unsafe" costs
  only parallelism.

Runs
----
:class:`MDEngine` is an engine of the shared run driver (:func:`particles.driver.simulate`: stops,
progress bar, checkpoint / resume bit for bit, Ctrl-C, :class:`particles.driver.RunResult`).
Energy, histogram, S(k) and C(r) are those of :mod:`particles.observables` applied to the
velocities in label order (the lattice conventions); this module adds what is MD-specific: τ(t),
the total momentum, rod positions, the profiles v(x, t) and v(i, t) and Haff's law.

Inelastic collapse
------------------
With δ = 0 a group of particles can collide infinitely often in finite time.  Both engines watch
every particle: a collision whose time advance since that particle's previous collision is below
``collapse_dt`` (relative to the mean free time) extends the particle's streak, any other resets
it; a streak of ``collapse_streak`` collisions raises :class:`InelasticCollapseError`.
"""

from __future__ import annotations

import heapq
import math
import time as _time
from bisect import bisect_right
from dataclasses import asdict, dataclass
from itertools import accumulate

import numpy as np

from .collision import collide_arrays, transfer_fraction
from .driver import initial_velocities, next_grid_point
from .initial import get_law
from .validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_positive,
    check_restitution,
)

__all__ = [
    "InelasticCollapseError",
    "MDParams",
    "MDState",
    "MDEngine",
    "collisions_per_particle",
    "total_momentum",
    "rod_positions",
    "profile_x",
    "profile_i",
    "haff_energy",
    "initial_cooling_rate",
]

# Relative round-off margin of the light-cone tests (in units of the largest key magnitude).
_CONE_MARGIN = 64 * np.finfo(float).eps
# Candidates closer than this many cone margins form one tie group (see ``_advance_fast``).
_GROUP_GAP = 1024.0
# Cost model of the fast path's choice between a vectorised pass and the scalar loop, in units of
# one plain scalar collision (~1.7 µs): the cost of a pass per candidate (fitted: 0.1-0.6 µs,
# about 0.25 µs, i.e. 0.15 units) and of a collision in a zero-gap burst (0.15-0.5 µs with its
# share of the burst's fixed cost, taken as 0.15 units); the fixed cost of a pass (~80 µs,
# about 47 units) is the engine's ``sequential_below`` (default 64).  See benchmarks/README.md.
_PASS_PER_CANDIDATE = 0.15
_BURST_COST = 0.15
# With δ > 0: collisions of one particle with no time advance at all before a stall is reported.
_STALL_STREAK = 100_000
# The scalar fallback works on lazy dict views of the arrays, and on lists of the whole state
# from N / _FULL_COPY_RATIO collisions on (or at once with more than that many candidates).
_FULL_COPY_RATIO = 4


class InelasticCollapseError(RuntimeError):
    """Collisions piled up in finite time (δ = 0): the run cannot go on.

    With δ > 0 collapse is impossible in exact arithmetic, but a very small δ can still let the
    time between one particle's collisions fall below the resolution of double precision, so
    that the clock stands still (measured, N = 300-1000, r = 0.5: δ ≤ 10⁻⁷ stalls within t ≈ 20,
    δ = 10⁻⁶ runs); that stall is reported with this error too, and its message says to increase
    δ instead of to set it.

    Attributes: ``time`` (the time of the runaway), ``particles`` (labels of the particles
    involved), ``collisions`` (total number of collisions processed so far), ``delta`` (the
    run's δ).
    """

    def __init__(
        self,
        time: float,
        particles,
        collisions: int,
        detail: str = "",
        delta: float = 0.0,
        restitution: float | None = None,
    ):
        self.time = float(time)
        self.particles = np.unique(np.asarray(particles, dtype=np.int64))
        self.collisions = int(collisions)
        self.delta = float(delta)
        self.restitution = restitution
        shown = self.particles[:10].tolist()
        more = "" if self.particles.size <= 10 else f" (+{self.particles.size - 10} more)"
        if self.restitution == 1.0:
            hint = (
                "the collisions are elastic (r = 1), so delta changes nothing: the time steps "
                "fell below the resolution of double precision; check the initial state"
            )
        elif self.delta > 0.0:
            hint = (
                f"with delta = {self.delta:g} the collisions are regularised, but their time "
                "steps fell below the resolution of double precision (the time stands still); "
                "increase delta (measured at N = 1000, r = 0.5: delta <= 1e-7 stalls, 1e-6 runs)"
            )
        else:
            hint = (
                "set delta > 0 (e.g. --delta 1e-4) to regularise collisions with small relative "
                "velocity"
            )
        super().__init__(
            f"inelastic collapse at t={self.time!r} after {self.collisions} collisions, "
            f"particles {shown}{more}{': ' + detail if detail else ''}; {hint}"
        )


@dataclass(frozen=True)
class MDParams:
    """Parameters of the hard-rod gas, checked at construction.

    ``n`` particles (N ≥ 2), number ``density`` N/L > 0, ``restitution`` r ∈ [0, 1],
    regularisation ``delta`` δ ≥ 0 (0: none), ``rod_length`` σ ≥ 0 with N σ < L, and the name of
    the ``initial`` velocity law (:mod:`particles.initial`).
    """

    n: int
    density: float
    restitution: float
    delta: float = 0.0
    rod_length: float = 0.0
    initial: str = "gaussian"

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        object.__setattr__(self, "density", check_positive(self.density, "density"))
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        object.__setattr__(self, "delta", check_nonnegative(self.delta, "delta"))
        object.__setattr__(self, "rod_length", check_nonnegative(self.rod_length, "rod_length"))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", self.initial, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        if not self.reduced_length > 0.0:
            raise InvalidArgumentError(
                "rod_length",
                self.rod_length,
                f"rods that fit: n*rod_length < L = n/density = {self.length!r}",
            )

    @property
    def length(self) -> float:
        """Ring length L = N / n."""
        return self.n / self.density

    @property
    def reduced_length(self) -> float:
        """Length L − Nσ of the ring of point particles (SPEC §4)."""
        return self.length - self.n * self.rod_length

    @property
    def reduced_density(self) -> float:
        """Density N / (L − Nσ) of the equivalent point particles."""
        return self.n / self.reduced_length

    @property
    def p(self) -> float:
        """Momentum-transfer fraction p = (1 + r)/2 of an inelastic collision."""
        return transfer_fraction(self.restitution)

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True, eq=False)
class MDState:
    """A snapshot of the gas at ``time`` (everything needed to continue bit for bit).

    ``positions[i]`` is the point coordinate (reduced ring, unwrapped) of particle i at its own
    last-update time ``t_last[i]``; ``velocities[i]`` its velocity since then; ``collisions`` the
    total number of pair collisions since t = 0.
    """

    time: float
    positions: np.ndarray
    t_last: np.ndarray
    velocities: np.ndarray
    collisions: int

    def positions_at(self, t: float | None = None) -> np.ndarray:
        """Point coordinates (reduced ring, unwrapped) at time ``t`` (default: ``self.time``)."""
        t = self.time if t is None else float(t)
        return self.positions + self.velocities * (t - self.t_last)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as a dict of NumPy arrays (what the driver's checkpoints store)."""
        return {
            "time": np.array(self.time, dtype=float),
            "positions": np.array(self.positions, dtype=float),
            "t_last": np.array(self.t_last, dtype=float),
            "velocities": np.array(self.velocities, dtype=float),
            "collisions": np.array(self.collisions, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, data, params: MDParams | None = None) -> MDState:
        """Inverse of :meth:`to_arrays`, with consistency checks; a corrupt state raises
        ``InvalidArgumentError`` naming ``checkpoint`` (a ``ValueError``, which the driver turns
        into its ``CheckpointError`` naming the file)."""
        keys = ("time", "positions", "t_last", "velocities", "collisions")
        try:
            missing = [k for k in keys if k not in data]
        except TypeError:
            raise InvalidArgumentError("checkpoint", type(data).__name__, "a mapping") from None
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "an MD state")
        try:
            t = float(np.asarray(data["time"]))
            x = np.array(data["positions"], dtype=float)
            tl = np.array(data["t_last"], dtype=float)
            v = np.array(data["velocities"], dtype=float)
            count = int(np.asarray(data["collisions"]))
        except (TypeError, ValueError) as exc:
            raise InvalidArgumentError("checkpoint", str(exc), "an MD state") from None
        n = x.shape[0] if x.ndim == 1 else -1
        if x.ndim != 1 or tl.shape != x.shape or v.shape != x.shape or n < 2:
            shapes = (x.shape, tl.shape, v.shape)
            raise InvalidArgumentError("checkpoint", f"shapes {shapes}", "three arrays of length N")
        if params is not None and n != params.n:
            raise InvalidArgumentError("checkpoint", f"N={n}", f"N={params.n} as in the parameters")
        finite = all(np.all(np.isfinite(a)) for a in (x, tl, v)) and math.isfinite(t)
        if not finite or count < 0 or np.any(tl > t):
            raise InvalidArgumentError(
                "checkpoint", "non-finite values, negative count or t_last > time", "an MD state"
            )
        if params is not None:
            xt = x + v * (t - tl)
            gaps = np.diff(np.append(xt, xt[0] + params.reduced_length))
            if np.any(gaps < -1e-9 * (params.reduced_length + np.max(np.abs(xt)))):
                raise InvalidArgumentError("checkpoint", "particles out of order", "an MD state")
        return cls(t, x, tl, v, count)


# ---------------------------------------------------------------------------------------------
# MD-specific observables (energy, histogram, S(k), C(r) are those of particles.observables, on
# ``state.velocities`` in label order: the same conventions as the lattice model).


def collisions_per_particle(state: MDState) -> float:
    """τ(t) = 2 · collisions / N (each pair collision involves two particles)."""
    return 2.0 * state.collisions / state.velocities.size


def total_momentum(state: MDState) -> float:
    """Total momentum Σ_i v_i (unit masses; zero at t = 0 up to round-off)."""
    return float(np.sum(state.velocities))


def rod_positions(state: MDState, params: MDParams, t: float | None = None) -> np.ndarray:
    """Real positions y_i = x_i + i σ of the rods at time t, reduced mod L into [0, L)."""
    x = state.positions_at(t) + np.arange(params.n) * params.rod_length
    return np.mod(x, params.length)


def profile_x(state: MDState, params: MDParams, t: float | None = None):
    """The profile v(x, t): rod positions in [0, L) sorted increasingly, and their velocities."""
    y = rod_positions(state, params, t)
    order = np.argsort(y, kind="stable")
    return y[order], state.velocities[order]


def profile_i(state: MDState):
    """The profile v(i, t) against particle label i (labels keep their order on the ring)."""
    return np.arange(state.velocities.size), state.velocities.copy()


def haff_energy(t, restitution: float, density: float, t0_energy: float = 1.0):
    """Haff's law T₀ / (1 + t/t₀)², t₀ = √π / ((1 − r²) n √T₀) (SPEC §4)."""
    t = np.asarray(t, dtype=float)
    lam = (1.0 - restitution**2) * density * math.sqrt(t0_energy)
    return t0_energy / (1.0 + t * lam / math.sqrt(math.pi)) ** 2


def initial_cooling_rate(restitution: float, density: float, t0_energy: float = 1.0) -> float:
    """dT/dt at t = 0⁺ for Gaussian velocities: −(2/√π)(1 − r²) n T₀^{3/2} (SPEC §4)."""
    return -2.0 / math.sqrt(math.pi) * (1.0 - restitution**2) * density * t0_energy**1.5


# ---------------------------------------------------------------------------------------------
# The engine


class MDEngine:
    """Event-driven MD of inelastic hard rods: an engine of :func:`particles.driver.simulate`.

    Driver protocol: ``name = "md"``; ``params()`` is a JSON-able dict; ``initial_state(rng)``
    draws the start; ``advance(state, until, rng)`` returns the exact state at time ``until``
    (time unit t; the rng is unused, the dynamics is deterministic); ``next_stop(t)`` is the
    next point of the grid ``stop_step · m`` (m integer); ``state_from_arrays`` rebuilds a
    checkpointed :class:`MDState`; ``observe(state)`` gives τ(t) (``collisions_per_particle``)
    and the ``total_momentum`` Σ v_i, and remembers the state in ``last_state`` (for the
    position profile v(x, t) of the last requested time).  ``method`` is ``"fast"`` (light-cone
    scheme) or ``"reference"`` (sequential heap).

    Stopping at intermediate times changes nothing: ``advance`` never moves a particle except
    at its collisions (positions are stored lazily), so advance(advance(s, t1), t2) equals
    advance(s, t2) bit for bit, and a resumed run repeats an uninterrupted one.  ``stop_step``
    (default 1 in units of t) only sets how often the driver may checkpoint and update its
    progress bar; each stop costs O(N) (the pair predictions are rebuilt).

    ``collapse_dt`` (in units of the initial mean free time 1/n) and ``collapse_streak`` tune the
    inelastic-collapse detector (module docstring).  Tuning of the fast path (results do not
    depend on it): ``target_candidates`` collisions per horizon slab (default N/8), and
    ``sequential_below``, the fixed cost of a vectorised pass in plain scalar collisions: when the
    collisions a pass fired would have cost the scalar event loop less than a pass (this plus
    0.15 per candidate; burst collisions count 0.15, at the burst fraction seen so far), the
    rest of the slab runs in the scalar loop (same formulas, same order); 0: passes only, a
    huge value: the scalar loop after the first pass.  ``record=True`` keeps every processed
    collision as ``(time, pair)`` in ``self.record`` (for tests; see :meth:`events`).  ``stats``
    (fast path) counts vectorised ``passes``, horizon ``slabs``, collisions of the scalar loop
    (``sequential``, ``sequential_seconds``), those of them run in zero-gap bursts (``burst``),
    collisions of the passes (``vectorised``), those with no time advance for one particle
    (``vectorised_zero_dt``) and ``elastic`` collisions (|Δ| < δ).
    """

    name = "md"
    time_name = "t"

    def __init__(
        self,
        params: MDParams,
        method: str = "fast",
        *,
        collapse_dt: float = 1e-9,
        collapse_streak: int = 200,
        target_candidates: int | None = None,
        sequential_below: int = 64,
        record: bool = False,
        stop_step: float = 1.0,
    ):
        if not isinstance(params, MDParams):
            raise InvalidArgumentError("params", params, "an MDParams")
        if method not in ("fast", "reference"):
            raise InvalidArgumentError("method", method, "'fast' or 'reference'")
        self.p = params
        self.method = method
        self.collapse_dt = check_positive(collapse_dt, "collapse_dt") / params.reduced_density
        self.collapse_streak = check_count(collapse_streak, "collapse_streak", 2)
        if target_candidates is None:
            target_candidates = max(256, params.n // 8)
        self.target_candidates = check_count(target_candidates, "target_candidates", 1)
        self.sequential_below = check_count(sequential_below, "sequential_below", 0)
        self.stats = {
            "passes": 0,
            "slabs": 0,
            "sequential": 0,
            "sequential_seconds": 0.0,
            "burst": 0,
            "vectorised": 0,
            "vectorised_zero_dt": 0,
            "elastic": 0,
        }
        self.record = [] if record else None
        self.stop_step = check_positive(stop_step, "stop_step")
        self.last_state: MDState | None = None

    # -- driver interface ---------------------------------------------------------------------

    def params(self) -> dict:
        out = self.p.to_dict()
        out["model"] = self.name
        out["method"] = self.method
        out["stop_step"] = self.stop_step
        return out

    def next_stop(self, time: float) -> float:
        return next_grid_point(time, self.stop_step)

    def state_from_arrays(self, arrays) -> MDState:
        return MDState.from_arrays(arrays, self.p)

    def observe(self, state: MDState) -> dict[str, float]:
        self.last_state = state
        return {
            "collisions_per_particle": collisions_per_particle(state),
            "total_momentum": total_momentum(state),
        }

    def initial_state(self, rng: np.random.Generator) -> MDState:
        """Equilibrium hard-rod positions, velocities from the law with zero momentum, ⟨v²⟩ = 1.

        Points: N sorted uniform draws on [0, L − Nσ) (rod i at x_i + iσ).  Velocities: drawn
        after the positions by :func:`particles.driver.initial_velocities` (zero mean, ⟨v²⟩ = 1).
        """
        if not isinstance(rng, np.random.Generator):
            raise InvalidArgumentError("rng", rng, "a numpy.random.Generator")
        p = self.p
        x = np.sort(rng.uniform(0.0, p.reduced_length, p.n))
        v = initial_velocities(p.initial, p.n, rng)
        return MDState(0.0, x, np.zeros(p.n), v, 0)

    def advance(self, state: MDState, until: float, rng: np.random.Generator | None = None):
        """Exact dynamics from ``state.time`` to ``until`` (all collisions with time ≤ until)."""
        if not isinstance(state, MDState):
            raise InvalidArgumentError("state", type(state).__name__, "an MDState")
        until = check_nonnegative(until, "until")
        if until < state.time:
            raise InvalidArgumentError("until", until, f"a time >= the state's time {state.time}")
        if state.velocities.size != self.p.n:
            raise InvalidArgumentError("state", f"N={state.velocities.size}", f"N={self.p.n}")
        run = _advance_reference if self.method == "reference" else _advance_fast
        x, tl, v, count = run(self, state, until)
        return MDState(float(until), x, tl, v, int(count))

    def events(self) -> np.ndarray:
        """Recorded collisions as an array of rows (time, pair), sorted (order-independent)."""
        if self.record is None:
            raise InvalidArgumentError("record", False, "an engine built with record=True")
        rows = np.array(self.record, dtype=float).reshape(-1, 2)
        return rows[np.lexsort((rows[:, 1], rows[:, 0]))]

    # shared helpers ------------------------------------------------------------------------

    def _watch(self):
        """(dt_tiny, streak limit, message) of the collapse watch.

        With δ > 0 (or r = 1) collapse is impossible in exact arithmetic: every inelastic
        collision dissipates at least (1 − r²)δ²/4 and elastic collisions alone are finitely many
        in finite time.  Only a stall (a particle colliding again and again with no time
        advance at all) is then reported, after ``_STALL_STREAK`` collisions.
        """
        if self.p.delta > 0.0 or self.p.restitution == 1.0:
            return 0.0, _STALL_STREAK, f"{_STALL_STREAK} collisions of one particle at one time"
        dt, k = self.collapse_dt, self.collapse_streak
        return dt, k, f"{k} collisions of one particle, each within {dt:g} of the previous"

    def _collapse(self, t, particles, collisions, detail=""):
        raise InelasticCollapseError(
            t, particles, collisions, detail, self.p.delta, self.p.restitution
        )


# ---------------------------------------------------------------------------------------------
# Sequential reference: a binary heap over the N pairs (pure Python floats; IEEE double, the
# same operations in the same order as the vectorised engine).


def _advance_reference(engine: MDEngine, state: MDState, until: float):
    prm = engine.p
    n = prm.n
    lr = prm.reduced_length
    p = prm.p
    delta = prm.delta
    elastic_only = prm.restitution == 1.0
    x = state.positions.tolist()
    tl = state.t_last.tolist()
    v = state.velocities.tolist()
    count = int(state.collisions)
    inf = math.inf
    streak = [0] * n
    dt_tiny, limit, detail = engine._watch()
    record = engine.record

    def predict(b):
        i = b
        j = b + 1 if b < n - 1 else 0
        vi = v[i]
        vj = v[j]
        if not vi > vj:
            return inf
        ti = tl[i]
        tj = tl[j]
        tt = ti if ti > tj else tj
        xi = x[i] + vi * (tt - ti)
        xj = x[j] + vj * (tt - tj)
        if j == 0:
            xj = xj + lr
        g = xj - xi
        if g < 0.0:
            g = 0.0
        return tt + g / (vi - vj)

    ctime = [predict(b) for b in range(n)]
    version = [0] * n
    heap = [(c, b, 0) for b, c in enumerate(ctime) if c <= until]
    heapq.heapify(heap)
    while heap:
        c, b, ver = heapq.heappop(heap)
        if ver != version[b]:
            continue
        i = b
        j = b + 1 if b < n - 1 else 0
        # collapse watch: time advance of each particle since its previous collision
        for k in (i, j):
            if c - tl[k] <= dt_tiny:
                streak[k] += 1
            else:
                streak[k] = 0
        if streak[i] >= limit or streak[j] >= limit:
            involved = [k for k in range(n) if streak[k] > 0]
            engine._collapse(c, involved, count, detail)
        vi = v[i]
        vj = v[j]
        xc = x[i] + vi * (c - tl[i])
        x[i] = xc
        x[j] = xc - lr if j == 0 else xc
        tl[i] = c
        tl[j] = c
        d = vi - vj
        if elastic_only or d < delta:
            v[i] = vj
            v[j] = vi
        else:
            # the rule of particles.collision (collide_scalar: d = (v_i - v_j) p, then v_i - d
            # and v_j + d), inlined for speed; then the separation guard
            pd = p * d
            a = vi - pd
            e = vj + pd
            a = min(max(a, vj), vi)
            e = min(max(e, vj), vi)
            if a > e:
                a, e = e, a
            v[i] = a
            v[j] = e
        count += 1
        if record is not None:
            record.append((c, b))
        for bb in (b - 1 if b > 0 else n - 1, b, b + 1 if b < n - 1 else 0):
            cc = predict(bb)
            if cc != ctime[bb] or bb == b:
                version[bb] += 1
                ctime[bb] = cc
                if cc <= until:
                    heapq.heappush(heap, (cc, bb, version[bb]))
    return np.array(x), np.array(tl), np.array(v), count


# ---------------------------------------------------------------------------------------------
# Fast path: the light-cone scheme, vectorised.


class _Lazy(dict):
    """A dict view of a NumPy array that copies an entry to a Python scalar on first use."""

    __slots__ = ("array",)

    def __init__(self, array):
        super().__init__()
        self.array = array

    def __missing__(self, k):
        value = self.array[k].item()
        self[k] = value
        return value

    def write_back(self):
        if self:
            idx = np.fromiter(self.keys(), dtype=np.int64, count=len(self))
            self.array[idx] = np.fromiter(self.values(), dtype=self.array.dtype, count=len(self))


def _sequential_slab(engine, x, tl, v, c, streak, cand, horizon, count):
    """Process, in time order, every collision up to ``horizon`` starting from the candidate
    pairs ``cand`` (all pairs with c ≤ horizon), with scalar Python floats: the reference loop.

    The loop starts on lazy dict views of the arrays (only the particles touched are loaded:
    cheap for the sparse tail of a slab, a few collisions) and switches to plain lists of the
    whole state once it has processed N / ``_FULL_COPY_RATIO`` collisions (a hot cluster's long
    chain, where list access is about twice as fast and pays for the copy).  Either way the
    results are written back to the arrays.  Returns the number of collisions processed.
    """
    prm = engine.p
    n = prm.n
    lr = prm.reduced_length
    p = prm.p
    delta = prm.delta
    elastic_only = prm.restitution == 1.0
    dt_tiny, limit, detail = engine._watch()
    record = engine.record
    inf = math.inf
    full = cand.size * _FULL_COPY_RATIO >= n
    if full:
        X, TL, V, ST, C = x.tolist(), tl.tolist(), v.tolist(), streak.tolist(), c.tolist()
        switch_at = -1
    else:
        X, TL, V, ST, C = _Lazy(x), _Lazy(tl), _Lazy(v), _Lazy(streak), _Lazy(c)
        switch_at = n // _FULL_COPY_RATIO

    # Heap entries (time, pair); an entry is live while C[pair] still equals its time (a pair
    # re-predicted to the very same time keeps one live entry: equal keys are processed once,
    # after which C[pair] = inf).  Ties pop in pair order, as in the reference.
    heap = [(C[b], b) for b in cand.tolist()]
    heapq.heapify(heap)
    ctx = (n - 1, lr, p, delta, elastic_only, dt_tiny, limit, record, horizon)  # for _burst
    pop = heapq.heappop
    push = heapq.heappush
    last = n - 1
    done = 0
    elastic = 0
    while heap:
        if 0 <= switch_at <= done:
            for store in (X, TL, V, ST, C):
                store.write_back()
            X, TL, V, ST, C = x.tolist(), tl.tolist(), v.tolist(), streak.tolist(), c.tolist()
            full = True
            switch_at = -1
        cb, b = pop(heap)
        if cb != C[b]:
            continue
        i = b
        j = b + 1 if b < last else 0
        ti = TL[i]
        tj = TL[j]
        if ti == cb and j != 0:
            # a zero-gap burst: particle i already collided at this very time and place
            burst = _burst(ctx, X, TL, V, ST, C, heap, b, cb, False)
            if burst is not None:
                done += burst[0]
                elastic += burst[1]
                engine.stats["burst"] += burst[0]
                continue
        si = ST[i] + 1 if cb - ti <= dt_tiny else 0
        sj = ST[j] + 1 if cb - tj <= dt_tiny else 0
        ST[i] = si
        ST[j] = sj
        if si >= limit or sj >= limit:
            involved = [k for k in (range(n) if full else ST.keys()) if ST[k] > 0]
            engine._collapse(cb, involved, count + done, detail)
        vi = V[i]
        vj = V[j]
        xc = X[i] + vi * (cb - ti)
        X[i] = xc
        X[j] = xc - lr if j == 0 else xc
        TL[i] = cb
        TL[j] = cb
        d = vi - vj
        if elastic_only or d < delta:
            V[i] = vj
            V[j] = vi
            elastic += 1
            vi, vj = vj, vi
        else:
            # the rule of particles.collision (collide_scalar: d = (v_i - v_j) p, then v_i - d
            # and v_j + d), inlined for speed; then the separation guard
            pd = p * d
            a = vi - pd
            e = vj + pd
            a = min(max(a, vj), vi)
            e = min(max(e, vj), vi)
            if a > e:
                a, e = e, a
            V[i] = a
            V[j] = e
            vi = a
            vj = e
        done += 1
        if record is not None:
            record.append((cb, b))
        C[b] = inf  # the pair separates (v_i' <= v_j'); its popped entry was the live one
        # New predictions of the two neighbouring pairs: the operations of ``_predict``, inlined,
        # with the fresh data of i and j (position xc at t_last = cb).
        bb = b - 1 if b > 0 else last  # left pair (h, i), h = bb
        vh = V[bb]
        if vh > vi:
            th = TL[bb]
            tt = th if th > cb else cb
            xh = X[bb] + vh * (tt - th)
            xi = xc + vi * (tt - cb)
            if i == 0:
                xi = xi + lr
            g = xi - xh
            if g < 0.0:
                g = 0.0
            cl = tt + g / (vh - vi)
        else:
            cl = inf
        k = j + 1 if j < last else 0  # right pair (j, k), index j
        vk = V[k]
        if vj > vk:
            tk = TL[k]
            tt = tk if tk > cb else cb
            xj = X[j] + vj * (tt - cb)
            xk = X[k] + vk * (tt - tk)
            if k == 0:
                xk = xk + lr
            g = xk - xj
            if g < 0.0:
                g = 0.0
            cr = tt + g / (vj - vk)
        else:
            cr = inf
        if (cl == cb or cr == cb) and j != 0:
            # a neighbouring pair is due at this very time: a burst may follow
            burst = _burst(ctx, X, TL, V, ST, C, heap, b, cb, True)
            done += burst[0]
            elastic += burst[1]
            engine.stats["burst"] += burst[0]
            continue
        if cl != C[bb]:
            C[bb] = cl
            if cl <= horizon:
                push(heap, (cl, bb))
        if cr != C[j]:
            C[j] = cr
            if cr <= horizon:
                push(heap, (cr, j))
    if full:
        x[:] = X
        tl[:] = TL
        v[:] = V
        streak[:] = ST
        c[:] = C
    else:
        for store in (X, TL, V, ST, C):
            store.write_back()
    engine.stats["elastic"] += elastic
    return done


def _pair_time(X, TL, h, vh, k, vk, lr):
    """Predicted collision time of the pair (h, k) (k = h + 1, or k = 0 at the seam) if h and k
    had the velocities vh and vk: the operations of the scalar loops' predictions, in order."""
    if not vh > vk:
        return math.inf
    th = TL[h]
    tk = TL[k]
    tt = th if th > tk else tk
    xh = X[h] + vh * (tt - th)
    xk = X[k] + vk * (tt - tk)
    if k == 0:
        xk = xk + lr
    g = xk - xh
    if g < 0.0:
        g = 0.0
    return tt + g / (vh - vk)


def _burst(ctx, X, TL, V, ST, C, heap, b, t, fired):
    """All collisions at time ``t`` of the *block* that grows from pair ``b`` = (i, i + 1):
    consecutive particles that sit at exactly the same point at time t and have collided
    there.  Either i has collided at t already and pair b was just popped (``fired`` False), or
    the caller has just processed pair b's collision and found a neighbouring pair due at t
    (``fired`` True).  The collisions are processed in the heap loop's (time, pair) order on a
    local list of velocities, and the state and the heap are left as the heap loop would leave
    them.  ``ctx`` holds the slab's constants.  Returns (collisions, elastic ones), or None if
    it processed none and the caller still has to process pair b.

    Exactness.  For two particles at the same point, both last updated at t, the prediction
    formula gives c = t if v_i > v_j and inf otherwise, so inside the block the pending pairs at
    time t are exactly the inversions v_k > v_{k+1}.  Pair b was the smallest pending (t, pair),
    so no pair left of it is pending.  Firing the smallest pending pair k leaves none left of
    k − 1, so the next smallest is k − 1 if it became an inversion, and otherwise the first
    pending pair right of k: a gnome sort, which visits the collisions in the heap's order.  An
    elastic collision at k starts a run that the gnome would do one swap at a time: v_{k+1}
    moves left past every larger velocity of the sorted w[0..k] (each difference is at most the
    first one, so each swap is elastic too); it is done by one bisection and a slice move.
    At the ends of the block, a neighbour at the same point, last updated at t, joins without a
    collision; otherwise the boundary pair is predicted by the heap loop's formula, and if it
    is due at t it is the next pending pair when the sort reaches that end (the heap would pop
    it then too): its collision moves both particles to the left one's point, so the newcomer
    joins if that is the block's point (always on the right; on the left the burst hands back
    to the heap loop if not).  Positions and t_last of block particles do not change.
    Collisions elsewhere at time t involve other particles and commute with the block.

    The collapse watch: each burst collision is one without time advance for both particles
    (a newcomer's first one is judged by its own time advance), so a particle's streak grows by
    the number of collisions of its two pairs, counted as a difference array ``dh`` and added
    by :func:`_burst_flush`.  No streak can reach the limit while (largest streak in the block)
    + (collisions so far) stays below it; there the burst hands back to the heap loop, which
    checks every collision.
    """
    last, lr, p, delta, elastic_only, dt_tiny, limit, record, horizon = ctx
    xb = X[b]
    lo = hi = b  # the block is particles lo .. hi, w[q] the velocity of lo + q
    w = [V[b]]
    s = [ST[b]]  # streaks at entry (or at joining)
    dh = [0]  # collisions of local pair q = (lo + q, lo + q + 1): dh[0] + ... + dh[q]
    k = m = 0  # m: local pairs 0 .. m - 1
    done = 0
    elastic = 0
    tb = C[b]
    C[b] = math.inf  # its heap entry was just popped
    if fired:  # the caller has processed the collision of pair b: go on after it
        hi = b + 1
        w.append(V[hi])
        s.append(ST[hi])
        dh.append(0)
        m = 1
    budget = limit - 1 - max(s)  # collisions that certainly leave every streak below the limit

    look_left = fired  # after a collision of the block's first pair
    while True:
        if look_left:  # the block's first velocity changed: the pair on its left
            look_left = False
            h = lo - 1 if lo > 0 else last
            if h == hi:
                break
            if lo > 0 and TL[h] == t and X[h] == xb:
                sh = ST[h]  # at the block's point already: it joins without a collision
                join = False
            elif not _pair_time(X, TL, h, V[h], lo, w[0], lr) <= t:
                k = 1
                continue
            else:
                # the left boundary pair is due now, so it is the next pending pair; its
                # collision moves both particles to h's position: h joins if that is the
                # block's point
                if lo == 0:
                    break
                th = TL[h]
                if X[h] + V[h] * (t - th) != xb:
                    break
                sh = ST[h] if t - th <= dt_tiny else -1
                join = True
            if limit - 1 - sh < budget:
                budget = limit - 1 - sh
            if join:
                if done >= budget:
                    break
                X[h] = xb
                TL[h] = t
            w.insert(0, V[h])
            s.insert(0, sh)
            dh.insert(0, 0)
            lo = h
            m += 1
            # next: the new first pair if it is due (a newcomer's always is), else past the
            # pair just fired
            k = 0 if join or w[0] > w[1] else 2
            continue
        if k == m:  # at the right end: extend, join or stop
            r = hi + 1 if hi < last else 0
            if r == 0 or r == lo:
                break  # the seam (or the whole ring): the heap loop takes over if it is due
            if TL[r] == t and X[r] == xb:
                sr = ST[r]
                join = False
            elif _pair_time(X, TL, hi, w[m], r, V[r], lr) <= t:
                # the boundary pair is due now: its collision brings r to the block's point
                sr = ST[r] if t - TL[r] <= dt_tiny else -1
                join = True
            else:
                break
            if limit - 1 - sr < budget:
                budget = limit - 1 - sr
            if done >= budget:
                break
            if join:
                X[r] = xb
                TL[r] = t
            w.append(V[r])
            s.append(sr)
            dh.append(0)
            hi = r
            m += 1
            continue
        vi = w[k]
        vj = w[k + 1]
        if not vi > vj:
            k += 1
            continue
        if done >= budget:
            break
        d = vi - vj
        if elastic_only or d < delta:
            # An elastic run: vj moves left past every larger velocity of the sorted w[0..k],
            # one swap each (the gnome's next collisions, pairs k, k - 1, ..., stop, done at
            # once).  Each is elastic: w[q] - vj <= vi - vj = d < delta (IEEE subtraction is
            # monotone).
            stop = bisect_right(w, vj, 0, k)
            if done + k + 1 - stop > budget:
                # only as many as the streak budget allows: vj stops short (pair stop - 1 stays
                # an inversion) and the next check hands back to the heap loop
                stop = k + 1 - (budget - done)
            run = k + 1 - stop
            w[stop + 1 : k + 2] = w[stop : k + 1]
            w[stop] = vj
            dh[stop] += 1
            dh[k + 1] -= 1
            done += run
            elastic += run
            if record is not None:
                record.extend([(t, lo + q) for q in range(k, stop - 1, -1)])
            if done >= budget:
                break
            if stop:
                k += 1  # pairs stop .. k are sorted now
            else:
                look_left = True
            continue
        # inelastic: the rule of particles.collision and the separation guard of the heap loops
        # (min(max(a, vj), vi) written out: the same result)
        pd = p * d
        a = vi - pd
        e = vj + pd
        if vj > a:
            a = vj
        if vi < a:
            a = vi
        if vj > e:
            e = vj
        if vi < e:
            e = vi
        if a > e:
            a, e = e, a
        w[k] = a
        w[k + 1] = e
        dh[k] += 1
        dh[k + 1] -= 1
        done += 1
        if record is not None:
            record.append((t, lo + k))
        if k:
            k = k - 1 if w[k - 1] > w[k] else k + 1
        else:
            look_left = True
    # The sort is finished, or a boundary pair is due that the block cannot absorb, or a streak
    # might reach the limit: the heap loop goes on from the state written back here.
    if done == 0 and not fired:
        C[b] = tb
        return None
    _burst_flush(X, TL, V, ST, C, heap, t, horizon, lo, hi, w, s, dh, lr, last)
    return done, elastic


def _burst_flush(X, TL, V, ST, C, heap, t, horizon, lo, hi, w, s, dh, lr, last):
    """Write a burst's block back (velocities; streaks grown by the collisions of each particle's
    two pairs) and leave predictions and heap entries as the heap loop would: inner pairs
    pending at t where they are inversions (none once the sort has finished), the two boundary
    pairs predicted from the final velocities.  Returns None."""
    inf = math.inf
    push = heapq.heappush
    m = hi - lo
    hits = list(accumulate(dh))  # collisions of each local pair
    streaks = [a + b + c for a, b, c in zip(s, [0, *hits[:-1]], hits, strict=True)]
    if type(V) is list:
        V[lo : hi + 1] = w
        ST[lo : hi + 1] = streaks
    else:
        for q in range(m + 1):
            V[lo + q] = w[q]
            ST[lo + q] = streaks[q]
    for q in range(m):
        if w[q] > w[q + 1]:
            if C[lo + q] != t:
                C[lo + q] = t
                push(heap, (t, lo + q))
        else:
            C[lo + q] = inf
    h = lo - 1 if lo > 0 else last
    cc = _pair_time(X, TL, h, V[h], lo, w[0], lr)
    if cc != C[h]:
        C[h] = cc
        if cc <= horizon:
            push(heap, (cc, h))
    r = hi + 1 if hi < last else 0
    cc = _pair_time(X, TL, hi, w[m], r, V[r], lr)
    if cc != C[hi]:
        C[hi] = cc
        if cc <= horizon:
            push(heap, (cc, hi))


def _predict(x, tl, v, idx, n, lr):
    """Predicted collision times of pairs ``idx`` (inf where the pair is not approaching)."""
    i = idx
    j = idx + 1
    seam = j == n
    j[seam] = 0
    vi = v[i]
    vj = v[j]
    ti = tl[i]
    tj = tl[j]
    app = vi > vj
    tt = np.maximum(ti, tj)
    xi = x[i] + vi * (tt - ti)
    xj = x[j] + vj * (tt - tj)
    if seam.any():
        xj[seam] = xj[seam] + lr
    g = xj - xi
    np.maximum(g, 0.0, out=g)
    dv = np.where(app, vi - vj, 1.0)
    c = tt + g / dv
    c[~app] = np.inf
    return c


def _advance_fast(engine: MDEngine, state: MDState, until: float):
    prm = engine.p
    n = prm.n
    lr = prm.reduced_length
    p = prm.p
    delta = prm.delta
    elastic_only = prm.restitution == 1.0
    x = state.positions.copy()
    tl = state.t_last.copy()
    v = state.velocities.copy()
    count = int(state.collisions)
    streak = np.zeros(n, dtype=np.int64)
    dt_tiny, limit, detail = engine._watch()
    record = engine.record
    target = engine.target_candidates
    seq_below = engine.sequential_below
    stats = engine.stats

    allpairs = np.arange(n)
    c = _predict(x, tl, v, allpairs, n, lr)
    # horizon width, adapted so that about ``target`` collisions are candidates per slab
    width = None
    while True:
        cmin = c.min()
        if not cmin <= until:
            break
        vmax = float(v.max())
        vmin = float(v.min())
        if width is None:
            sample = c[np.isfinite(c)]
            k = min(target, sample.size) - 1
            width = float(np.partition(sample, k)[k] - cmin) if k > 0 else 0.0
        horizon = min(cmin + width, until)
        cand = np.flatnonzero(c <= horizon)
        stats["slabs"] += 1
        done_in_slab = 0
        while cand.size:
            stats["passes"] += 1
            cc = c[cand]
            # local minimum in (time, index) order among the neighbouring pairs
            left = cand - 1
            left[left < 0] = n - 1
            right = cand + 1
            right[right == n] = 0
            cl = c[left]
            cr = c[right]
            safe = ((cc < cl) | ((cc == cl) & (cand < left))) & (
                (cc < cr) | ((cc == cr) & (cand < right))
            )
            if cand.size > 1:
                xc = x[cand] + v[cand] * (cc - tl[cand])
                kl = vmax * cc - xc
                kr = xc - vmin * cc
                tol = _CONE_MARGIN * (
                    (abs(vmax) + abs(vmin)) * np.abs(cc).max() + np.abs(xc).max() + lr
                )
                pre = np.empty_like(kl)
                pre[0] = np.inf
                np.minimum.accumulate(kl[:-1], out=pre[1:])
                np.minimum(pre, kl.min() + lr, out=pre)
                suf = np.empty_like(kr)
                suf[-1] = np.inf
                suf[:-1] = np.minimum.accumulate(kr[:0:-1])[::-1]
                np.minimum(suf, kr.min() + lr, out=suf)
                cone = (kl < pre - tol) & (kr < suf - tol)
                # Ties: zero gaps in a cluster give several pending collisions at one time and
                # place; their keys agree within ``tol``, so the cone test blocks all of them
                # (only the global earliest used to fire: one collision per pass for the whole
                # gas).  Tie groups: runs of consecutive candidates within ``_GROUP_GAP * tol``
                # of each other.  The earliest of a group in (time, index) order is safe when
                # no candidate outside its group reaches it (the cone test against the prefix
                # minimum up to the group's start and the suffix minimum after its end): the
                # other members come later in (time, index) order, so they (and all their
                # consequences) run after it in the sequential order as well.
                brk = np.abs(np.diff(xc)) > _GROUP_GAP * tol
                if not brk.all():
                    k = cc.size
                    starts = np.flatnonzero(np.concatenate(([True], brk)))
                    gid = np.cumsum(np.concatenate(([0], brk)))
                    first = np.minimum.reduceat(
                        np.where(cc == np.minimum.reduceat(cc, starts)[gid], np.arange(k), k),
                        starts,
                    )
                    ends = np.append(starts[1:], k) - 1
                    g_ok = (kl[first] < pre[starts] - tol) & (kr[first] < suf[ends] - tol)
                    cone[first[g_ok]] = True
                safe &= cone
            safe[np.argmin(cc)] = True  # the earliest collision is always safe
            ev = cand[safe]
            tev = cc[safe]
            # -- collisions -----------------------------------------------------------
            i = ev
            j = ev + 1
            seam = j == n
            j[seam] = 0
            vi = v[i]
            vj = v[j]
            # collapse watch
            dti = tev - tl[i]
            dtj = tev - tl[j]
            stats["vectorised"] += ev.size
            stats["vectorised_zero_dt"] += int(np.count_nonzero(np.minimum(dti, dtj) <= 0.0))
            si = np.where(dti <= dt_tiny, streak[i] + 1, 0)
            sj = np.where(dtj <= dt_tiny, streak[j] + 1, 0)
            streak[i] = si
            streak[j] = sj
            if si.max() >= limit or sj.max() >= limit:
                bad = np.flatnonzero((si >= limit) | (sj >= limit))[0]
                engine._collapse(
                    tev[bad],
                    np.flatnonzero(streak > 0),
                    count + bad,
                    detail,
                )
            xcol = x[i] + vi * dti
            x[i] = xcol
            if seam.any():
                xj = xcol.copy()
                xj[seam] -= lr
                x[j] = xj
            else:
                x[j] = xcol
            tl[i] = tev
            tl[j] = tev
            d = vi - vj
            if elastic_only:
                a = vj
                e = vi
                stats["elastic"] += ev.size
            else:
                a = vi.copy()
                e = vj.copy()
                collide_arrays(a, e, p)  # the rule of particles.collision, in place
                np.minimum(np.maximum(a, vj, out=a), vi, out=a)
                np.minimum(np.maximum(e, vj, out=e), vi, out=e)
                flip = a > e
                if flip.any():
                    a, e = np.where(flip, e, a), np.where(flip, a, e)
                el = d < delta
                stats["elastic"] += int(np.count_nonzero(el))
                if el.any():
                    a = np.where(el, vj, a)
                    e = np.where(el, vi, e)
            v[i] = a
            v[j] = e
            count += ev.size
            if record is not None:
                record.extend(zip(tev.tolist(), ev.tolist(), strict=True))
            done_in_slab += ev.size
            # -- new predictions for the pairs touching changed particles ---------------
            # the pair itself now separates (v_i' <= v_j' by construction): no prediction
            c[ev] = np.inf
            aff = np.concatenate((ev - 1, ev + 1))
            aff[aff < 0] += n
            aff[aff >= n] -= n
            c[aff] = _predict(x, tl, v, aff, n, lr)
            # candidates: the unfired ones and the new predictions inside the horizon
            rest = cand[~safe]
            newc = aff[c[aff] <= horizon]
            if newc.size:
                cand = np.unique(np.concatenate((rest, newc)))
                cand = cand[c[cand] <= horizon]
            else:
                cand = rest
            # Cost model, in units of one plain scalar collision: a pass costs seq_below +
            # _PASS_PER_CANDIDATE * candidates, a collision of the scalar loop 1 if plain and
            # _BURST_COST in a zero-gap burst, at the burst fraction seen so far (in passes:
            # collisions with no time advance for one particle).  The slab goes to the scalar
            # loop once that is cheaper for the collisions this pass fired.
            burst_like = (stats["burst"] + stats["vectorised_zero_dt"]) / (
                stats["sequential"] + stats["vectorised"]
            )
            scalar = 1.0 - (1.0 - _BURST_COST) * burst_like
            pass_cost = seq_below + _PASS_PER_CANDIDATE * cand.size if seq_below else 0.0
            if ev.size * scalar < pass_cost and cand.size:
                # little parallelism left: finish the slab with the scalar event loop
                t_seq = _time.perf_counter()
                done = _sequential_slab(engine, x, tl, v, c, streak, cand, horizon, count)
                stats["sequential_seconds"] += _time.perf_counter() - t_seq
                count += done
                done_in_slab += done
                stats["sequential"] += done
                cand = cand[:0]
        # adapt the horizon width to the number of collisions that fitted in the slab
        if done_in_slab > 0 and width > 0:
            width *= min(2.0, max(0.5, target / done_in_slab))
        elif width == 0.0:
            width = None
    return x, tl, v, count
