"""The driver interface of the hard-rod MD: parameters, state, engine and the collapse error.

:class:`MDEngine` is an engine of the shared run driver (:func:`particles.driver.simulate`: stops,
progress bar, checkpoint / resume bit for bit, Ctrl-C, :class:`particles.driver.RunResult`).  It
runs one of the two exact event loops, :func:`particles.md.reference.advance_reference` (the
sequential heap) or :func:`particles.md.lightcone.advance_fast` (the light-cone scheme); both use
the pair prediction and the collision of :mod:`particles.md.kernel`.

Inelastic collapse
------------------
With δ = 0 a group of particles can collide infinitely often in finite time.  Both engines watch
every particle: a collision whose time advance since that particle's previous collision is below
``collapse_dt`` (relative to the mean free time) extends the particle's streak, any other resets
it; a streak of ``collapse_streak`` collisions raises :class:`InelasticCollapseError`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..collision import transfer_fraction
from ..driver import initial_velocities, next_grid_point
from ..initial import get_law
from ..validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_positive,
    check_restitution,
)
from .lightcone import advance_fast
from .observables import collisions_per_particle, total_momentum
from .reference import advance_reference

__all__ = ["InelasticCollapseError", "MDParams", "MDState", "MDEngine"]

# With δ > 0: collisions of one particle with no time advance at all before a stall is reported.
_STALL_STREAK = 100_000


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
        run = advance_reference if self.method == "reference" else advance_fast
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
