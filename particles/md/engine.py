"""The driver interface of the hard-rod MD: :class:`MDEngine` (its data types are in
:mod:`.state`).

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

import numpy as np

from ..driver import EngineBase, initial_velocities
from ..validation import InvalidArgumentError, check_count, check_nonnegative, check_positive
from .lightcone import advance_fast
from .observables import collisions_per_particle, haff_time, rod_positions, total_momentum
from .reference import advance_reference
from .state import InelasticCollapseError, MDParams, MDState

__all__ = ["MDEngine"]

# With δ > 0: collisions of one particle with no time advance at all before a stall is reported.
_STALL_STREAK = 100_000


# ---------------------------------------------------------------------------------------------
# The engine


def collisions_per_particle_estimate(t: float, params: dict) -> float:
    """Collisions per particle by time ``t`` in the homogeneous (Haff) stage: the event
    estimate of :meth:`MDEngine.expected_events` (a rough lower bound; :mod:`particles.budget`).

    τ(t) = (2/(1 − r²)) ln(1 + t/t₀) from Haff's law at the reduced density, plus, with δ > 0,
    collisions at the rate (2/√π) n δ of a gas at temperature δ² once Haff's temperature falls
    below δ²; (2/√π) n t for r = 1.

    Parameters
    ----------
    t : float
        The time.
    params : dict
        The engine's ``to_dict()``: ``n``, ``density``, ``restitution``, ``rod_length``,
        ``delta``.

    Returns
    -------
    float
        τ(t).
    """
    n = float(params.get("n", 2))
    length = n / float(params["density"])
    reduced = length - n * float(params.get("rod_length", 0.0))
    density = n / reduced if reduced > 0 else float("inf")
    r = float(params["restitution"])
    delta = float(params.get("delta", 0.0))
    rate0 = 2.0 / math.sqrt(math.pi) * density  # dτ/dt at t = 0, unit temperature
    if r >= 1.0:
        return rate0 * t
    t0 = haff_time(r, density)
    tau = 2.0 / (1.0 - r * r) * math.log1p(t / t0)
    if delta > 0.0:
        # relative velocities below δ are not dissipated: once Haff's T falls to δ², collisions
        # go on at least at the rate of a gas at temperature δ² (a heuristic floor)
        t_delta = t0 * (1.0 / min(delta, 1.0) - 1.0)
        tau += rate0 * min(delta, 1.0) * max(0.0, t - t_delta)
    return tau


class MDEngine(EngineBase):
    """Event-driven MD of inelastic hard rods: an engine of :func:`particles.driver.simulate`.

    Driver protocol: ``name = "md"``; ``to_dict()`` is a JSON-able dict; ``initial_state(rng)``
    draws the start; ``advance(state, until, rng)`` returns the exact state at time ``until``
    (time unit t; the rng is unused, the dynamics is deterministic); ``next_stop(t)`` is the
    next point of the grid ``stop_step · m`` (m integer); ``state_from_arrays`` rebuilds a
    checkpointed :class:`MDState`; ``observe(state)`` gives τ(t) (``collisions_per_particle``)
    and the ``total_momentum`` Σ v_i (the state at the last requested time comes back as
    :attr:`particles.driver.RunResult.final_state`, e.g. for the profile v(x, t)).
    ``method`` is ``"fast"`` (light-cone scheme) or ``"reference"`` (sequential heap).

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

    Built like every engine from its parameters by keyword, ``MDEngine(n=1000, density=1.0,
    restitution=0.5)``, or, as before, from an :class:`MDParams`: ``MDEngine(MDParams(1000, 1.0,
    0.5))`` (not both).

    Parameters
    ----------
    params : particles.MDParams or None, optional
        The gas: N, density, restitution, δ, rod length, initial law (None: from the keywords
        ``n`` ... ``initial``).
    method : str, optional
        ``"fast"`` (default) or ``"reference"``.
    collapse_dt : float, optional
        Time step, in units of the initial mean free time 1/n, below which successive
        collisions of one particle count towards a collapse (default 1e-9; > 0).
    collapse_streak : int, optional
        Number of such collisions in a row that is reported as a collapse (default 200; ≥ 2).
    target_candidates : int or None, optional
        Collisions per horizon slab of the fast path (default max(256, N/8); ≥ 1).
    sequential_below : int, optional
        Fixed cost of a vectorised pass, in scalar collisions (default 64; ≥ 0).
    record : bool, optional
        Keep every processed collision in ``self.record`` (default False).
    stop_step : float, optional
        Spacing of the grid of stops in units of t (default 1; > 0).
    n, density, restitution, delta, rod_length, initial : optional
        The fields of :class:`MDParams`, when ``params`` is None (``n``, ``density`` and
        ``restitution`` required then; defaults δ = 0, σ = 0, ``"gaussian"``).

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``params`` if it is not an :class:`MDParams` (or is given together with the
        keywords), ``method`` if it is not one of the two, the field of :class:`MDParams` or
        the tuning argument that is out of its domain.
    """

    name = "md"
    time_name = "t"

    state_keys = ("time", "positions", "t_last", "velocities", "collisions")

    def __init__(
        self,
        params: MDParams | None = None,
        method: str = "fast",
        *,
        collapse_dt: float = 1e-9,
        collapse_streak: int = 200,
        target_candidates: int | None = None,
        sequential_below: int = 64,
        record: bool = False,
        stop_step: float = 1.0,
        n: int | None = None,
        density: float | None = None,
        restitution: float | None = None,
        delta: float | None = None,
        rod_length: float | None = None,
        initial: str | None = None,
    ):
        fields = {"n": n, "density": density, "restitution": restitution, "delta": delta,
                  "rod_length": rod_length, "initial": initial}
        given = {k: v for k, v in fields.items() if v is not None}
        if params is None:
            defaults = {"delta": 0.0, "rod_length": 0.0, "initial": "gaussian"}
            params = MDParams(**{**fields, **{k: v for k, v in defaults.items()
                                              if fields[k] is None}})
        elif given:
            raise InvalidArgumentError(
                "params", params, f"an MDParams or the keywords {sorted(given)}, not both"
            )
        if not isinstance(params, MDParams):
            raise InvalidArgumentError("params", params, "an MDParams")
        if method not in ("fast", "reference"):
            raise InvalidArgumentError("method", method, "'fast' or 'reference'")
        self.params = params
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

    # -- driver interface ---------------------------------------------------------------------

    def to_dict(self) -> dict:
        """The engine's parameter dict (JSON-able), recorded with every result.

        Returns
        -------
        dict
            The fields of :class:`MDParams` plus ``model`` (``"md"``), ``method`` and
            ``stop_step``.
        """
        out = self.params.to_dict()
        out["model"] = self.name
        out["method"] = self.method
        out["stop_step"] = self.stop_step
        return out

    def rebuild_state(self, arrays) -> MDState:
        """Rebuild a checkpointed state (:meth:`MDState.from_arrays` with this engine's
        parameters); :meth:`state_from_arrays` (of :class:`particles.driver.EngineBase`) calls it.

        Parameters
        ----------
        arrays : mapping
            The arrays of :meth:`MDState.to_arrays`.

        Returns
        -------
        particles.MDState
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, from :meth:`MDState.from_arrays`.
        """
        return MDState.from_arrays(arrays, self.params)

    def memory_per_particle(self) -> float:
        """Working bytes per rod: 400 (181 measured at N = 10⁶, doubled).

        Returns
        -------
        float
            400 bytes.
        """
        return 400.0

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Pair collisions to t = ``t_max``, N τ(t)/2 with τ(t) from Haff's law (a rough lower
        bound: :func:`collisions_per_particle_estimate`).

        Parameters
        ----------
        t_max : float
            The last requested t.
        n_times : int
            The number of requested times (unused).

        Returns
        -------
        tuple of (float, str)
            ``(events, "collisions (at least)")``.
        """
        params = self.to_dict()
        n = float(params.get("n", 0))
        return n * collisions_per_particle_estimate(t_max, params) / 2.0, "collisions (at least)"

    #: Recorded with each snapshot of the run driver: the rods' positions in [0, L).
    snapshot_fields = ("positions",)

    def snapshot_arrays(self, state: MDState) -> dict[str, np.ndarray]:
        """The rods' positions y_i in [0, L) at the state's time (label order).

        Parameters
        ----------
        state : particles.MDState
            The state.

        Returns
        -------
        dict of str to numpy.ndarray
            ``{"positions": y}``, y of shape ``(N,)``.
        """
        return {"positions": rod_positions(state, self.params)}

    def observe(self, state: MDState) -> dict[str, float]:
        """The scalar observables the driver records at each output time.

        Parameters
        ----------
        state : particles.MDState
            The state.

        Returns
        -------
        dict of str to float
            ``collisions_per_particle`` (τ(t) = 2 · collisions / N) and ``total_momentum`` (Σ v_i).
        """
        return {
            "collisions_per_particle": collisions_per_particle(state),
            "total_momentum": total_momentum(state),
        }

    def initial_state(self, rng: np.random.Generator) -> MDState:
        """Equilibrium hard-rod positions, velocities from the law with zero momentum, ⟨v²⟩ = 1.

        Points: N sorted uniform draws on [0, L − Nσ) (rod i at x_i + iσ).  Velocities: drawn after
        the positions by :func:`particles.driver.initial_velocities` (zero mean, ⟨v²⟩ = 1).

        Parameters
        ----------
        rng : numpy.random.Generator
            The random generator.

        Returns
        -------
        particles.MDState
            The state at t = 0 with no collisions.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``rng`` if it is not a ``numpy.random.Generator``.
        """
        if not isinstance(rng, np.random.Generator):
            raise InvalidArgumentError("rng", rng, "a numpy.random.Generator")
        p = self.params
        x = np.sort(rng.uniform(0.0, p.reduced_length, p.n))
        v = initial_velocities(p.initial, p.n, rng)
        return MDState(0.0, x, np.zeros(p.n), v, 0)

    def advance(self, state: MDState, until: float, rng: np.random.Generator | None = None):
        """Exact dynamics from ``state.time`` to ``until`` (all collisions with time ≤ until).

        Parameters
        ----------
        state : particles.MDState
            The state to advance (not modified).
        until : float
            The physical time to reach, ≥ ``state.time``.
        rng : numpy.random.Generator or None, optional
            Unused (the dynamics is deterministic); accepted for the driver protocol.

        Returns
        -------
        particles.MDState
            The state at time ``until``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``state`` if it is not an :class:`MDState` or has another N, ``until`` if it is
            negative, not finite or before the state's time.
        particles.InelasticCollapseError
            If collisions pile up in finite time (or the clock stalls).
        """
        if not isinstance(state, MDState):
            raise InvalidArgumentError("state", type(state).__name__, "an MDState")
        until = check_nonnegative(until, "until")
        if until < state.time:
            raise InvalidArgumentError("until", until, f"a time >= the state's time {state.time}")
        if state.velocities.size != self.params.n:
            raise InvalidArgumentError("state", f"N={state.velocities.size}", f"N={self.params.n}")
        run = advance_reference if self.method == "reference" else advance_fast
        x, tl, v, count = run(self, state, until)
        return MDState(float(until), x, tl, v, int(count))

    def events(self) -> np.ndarray:
        """The recorded collisions as an array of rows (time, pair), sorted (order-independent).

        Returns
        -------
        numpy.ndarray
            Float array of shape ``(collisions, 2)``, sorted by time, then pair index.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``record``, if the engine was built without ``record=True``.
        """
        if self.record is None:
            raise InvalidArgumentError("record", False, "an engine built with record=True")
        rows = np.array(self.record, dtype=float).reshape(-1, 2)
        return rows[np.lexsort((rows[:, 1], rows[:, 0]))]

    # shared helpers ------------------------------------------------------------------------

    def collapse_watch(self):
        """(dt_tiny, streak limit, message) of the collapse watch.

        With δ > 0 (or r = 1) collapse is impossible in exact arithmetic: every inelastic
        collision dissipates at least (1 − r²)δ²/4 and elastic collisions alone are finitely many
        in finite time.  Only a stall (a particle colliding again and again with no time
        advance at all) is then reported, after ``_STALL_STREAK`` collisions.

        Returns
        -------
        tuple of (float, int, str)
            The time step below which a collision counts, the streak length that is reported, and
            the description used in the error message.
        """
        if self.params.delta > 0.0 or self.params.restitution == 1.0:
            return 0.0, _STALL_STREAK, f"{_STALL_STREAK} collisions of one particle at one time"
        dt, k = self.collapse_dt, self.collapse_streak
        return dt, k, f"{k} collisions of one particle, each within {dt:g} of the previous"

    def raise_collapse(self, t, particles, collisions, detail=""):
        """Raise :class:`InelasticCollapseError` for a collapse seen by the watch.

        Parameters
        ----------
        t : float
            The physical time of the runaway.
        particles : array_like of int
            Labels of the particles involved.
        collisions : int
            Total number of collisions processed so far.
        detail : str, optional
            What the watch saw.

        Raises
        ------
        particles.InelasticCollapseError
            Always, with the run's δ and r.
        """
        raise InelasticCollapseError(
            t, particles, collisions, detail, self.params.delta, self.params.restitution
        )
