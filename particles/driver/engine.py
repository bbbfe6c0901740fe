"""The engine contract of the run driver: the :class:`Engine` protocol (every member the driver
calls, the optional hooks included) and :class:`EngineBase`, the base class of the four
engines that writes the shared code once and gives the optional hooks their neutral defaults.

Why both.  The driver checks an engine structurally (:class:`Engine`), so an object that forwards
to an engine (a wrapper, a proxy that delegates by ``__getattr__``) is an engine too; the base
class is where the code the engines share lives (the stop grid, the checks of a checkpointed
state, the defaults of the hooks).  An engine derived from :class:`EngineBase` writes only its
physics: ``name``, ``stop_step``, ``state_keys``, ``to_dict``, ``initial_state``, ``advance``,
``rebuild_state`` and its two estimates.

Adding an engine
----------------
Derive from :class:`EngineBase`; give it a ``name`` (the model's name), a ``stop_step`` (the
spacing of the driver's stops in the engine's time; default ``inf``: none between requested
times) and
the ``state_keys`` its state's ``to_arrays`` writes; write ``to_dict``, ``initial_state``,
``advance``, ``rebuild_state`` and the estimates ``memory_per_particle`` and ``expected_events``
(an engine without them is refused by :func:`particles.simulate`, naming it: its cost is never
guessed); override ``time_name``, ``observe``, ``snapshot_fields`` / ``snapshot_arrays`` where
the model has them.  Build it from its parameters by keyword (``Engine(n=..., ...)``), as the
four engines are.  Register it with :func:`particles.models.register_model` to run it in an
ensemble.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Protocol

import numpy as np

from ..validation import InvalidArgumentError

__all__ = ["ENGINE_MEMBERS", "Engine", "EngineBase", "engine_label", "next_grid_point"]


def next_grid_point(time: float, step: float) -> float:
    """The smallest ``m * step`` (m an integer) strictly greater than ``time``: the stop grid
    of the engines.

    Parameters
    ----------
    time : float
        The current time.
    step : float
        The grid's spacing, > 0.

    Returns
    -------
    float
    """
    m = math.floor(time / step) + 1
    while m * step <= time:
        m += 1
    while m > 1 and (m - 1) * step > time:
        m -= 1
    return m * step


class Engine(Protocol):  # pragma: no cover - typing only
    """Everything :func:`particles.simulate` (and the ensembles, through it) calls of a particle
    engine; it calls nothing else.  :class:`particles.Ulam`, :class:`particles.Lattice`,
    :class:`particles.MDEngine` and :class:`particles.StickyGas` derive from
    :class:`EngineBase`, which implements the optional hooks below with neutral defaults; an
    engine not derived from it must write every member out.  One member is optional for
    every engine: ``velocity_classes(state)`` (:meth:`EngineBase.velocity_classes`), read with
    ``getattr`` and not listed in :data:`ENGINE_MEMBERS`.

    A state (what ``initial_state`` and ``advance`` return) has at least ``time: float``,
    ``velocities`` (float64, shape ``(N,)``, or ``(N, d)`` in d > 1), ``collisions: int`` (the
    total so far, non-decreasing) and ``to_arrays() -> dict[str, numpy.ndarray]`` (what a
    checkpoint stores).  All randomness comes from the one generator the driver passes.

    Attributes
    ----------
    name : str
        The model's name (``"ulam"``, ``"lattice"``, ``"md"``, ``"sticky"``); it names the run
        in its files and messages.
    time_name : str
        Optional hook (default ``"tau"``): the name of the engine's time in messages and
        errors, ``"tau"`` (collisions per particle) or ``"t"`` (physical time).
    snapshot_fields : tuple of str
        Optional hook (default ``()``): the per-particle arrays :meth:`snapshot_arrays` adds to
        each snapshot (MD: ``("positions",)``).
    """

    name: str
    time_name: str
    snapshot_fields: tuple[str, ...]

    def to_dict(self) -> dict:
        """The engine's parameters, JSON-able; they name the run in its files (a checkpoint of
        other parameters is refused).

        Returns
        -------
        dict
            With ``"n"`` (the number of particles, an int ≥ 2) and, for d > 1, ``"dimension"``
            (the driver reads these two; a missing ``"dimension"`` means 1).
        """

    def initial_state(self, rng: np.random.Generator) -> Any:
        """The state at time 0.

        Parameters
        ----------
        rng : numpy.random.Generator
            The run's generator.

        Returns
        -------
        object
            The engine's state.
        """

    def advance(self, state: Any, until: float, rng: np.random.Generator) -> Any:
        """The state at time ``until``, exactly.  ``state`` is not changed (the driver keeps it
        for Ctrl-C), and the result depends on ``until`` only through the exact dynamics and the
        generator's stream, so stopping at the grid of :meth:`next_stop` changes nothing.

        Parameters
        ----------
        state : object
            The state to advance.
        until : float
            The time to reach, ≥ ``state.time``, in the engine's time.
        rng : numpy.random.Generator
            The run's generator (unused by the deterministic engines).

        Returns
        -------
        object
            The new state.
        """

    def next_stop(self, time: float) -> float:
        """The next time strictly after ``time`` at which the driver may stop (checkpoint,
        progress bar): a fixed grid of the engine's time, never the wall clock, so a resumed run
        repeats an uninterrupted one bit for bit.  ``inf``: no stop before the next requested
        time.

        Parameters
        ----------
        time : float
            The current time, in the engine's time.

        Returns
        -------
        float
        """

    def state_from_arrays(self, arrays: dict[str, np.ndarray]) -> Any:
        """Rebuild a state from the arrays a checkpoint holds (its ``to_arrays()``), checking
        them against the engine.

        Parameters
        ----------
        arrays : dict of numpy.ndarray
            The state's arrays.

        Returns
        -------
        object
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, for arrays that are missing, malformed or inconsistent (the
            driver turns it into its :class:`particles.CheckpointError` naming the file).
        """

    def observe(self, state: Any) -> dict[str, float]:
        """Optional hook (default: none): extra scalars recorded at each requested time, kept
        in :attr:`particles.RunResult.extras` (e.g. τ(t) for MD).

        Parameters
        ----------
        state : object
            The state at a requested time.

        Returns
        -------
        dict of str to float
            The same keys at every call.
        """

    def snapshot_arrays(self, state: Any) -> dict[str, np.ndarray]:
        """Optional hook (default: none): the per-particle arrays of :attr:`snapshot_fields`
        at ``state``, recorded with each snapshot (``snapshots=True``).

        Parameters
        ----------
        state : object
            The state at a requested time.

        Returns
        -------
        dict of str to numpy.ndarray
            One array of shape ``(N,)`` per name of :attr:`snapshot_fields`.
        """

    def memory_per_particle(self) -> float:
        """The engine's working memory per particle, in bytes (measured peak, doubled for
        headroom); the driver adds its records and refuses a run that does not fit.

        Returns
        -------
        float
            Bytes per particle (already times the dimension for vector velocities).
        """

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """The expected number of events of a run to ``t_max`` with ``n_times`` requested
        times, and what an event is; the driver refuses more than
        :data:`particles.budget.MAX_EVENTS` unless ``force=True``.

        Parameters
        ----------
        t_max : float
            The last requested time, in the engine's time.
        n_times : int
            The number of requested times.

        Returns
        -------
        tuple of (float, str)
            The count and its unit (``"collisions"``, ``"attempts"``, ``"hull steps"``...).
        """


#: The members of :class:`Engine`, every one of which the driver calls.
ENGINE_MEMBERS = ("name", "time_name", "snapshot_fields", "to_dict", "initial_state", "advance",
                  "next_stop", "state_from_arrays", "observe", "snapshot_arrays",
                  "memory_per_particle", "expected_events")


def engine_label(engine) -> str:
    """How an error names an engine: its class and its model name.

    Parameters
    ----------
    engine : object
        The engine (any object).

    Returns
    -------
    str
        E.g. ``"Ulam ('ulam')"``, or the class alone for an object without a string ``name``.
    """
    name = getattr(engine, "name", None)  # an object outside the contract may lack it
    cls = type(engine).__name__
    return f"{cls} ({name!r})" if isinstance(name, str) else cls


class EngineBase:
    """The base class of the particle engines: the shared code of :class:`Engine` written once.

    It gives :meth:`next_stop` (the grid ``stop_step · m``, none for an infinite ``stop_step``),
    :meth:`state_from_arrays` (the mapping and its keys checked, then :meth:`rebuild_state`;
    every failure is an :class:`~particles.InvalidArgumentError` naming ``checkpoint``), and
    the optional hooks with their neutral defaults (``time_name = "tau"``, no extra scalars, no
    snapshot fields).  The estimates have no default: an engine that does not write them out is
    refused when a run is costed, naming the engine (its cost is never guessed).

    Attributes
    ----------
    name : str
        The model's name (each engine sets it).
    time_name : str
        ``"tau"`` unless the engine sets another.
    stop_step : float
        The spacing of the stop grid in the engine's time, > 0; ``inf`` (the default): no
        stops between requested times, so checkpoints are written only there.
    state_keys : tuple of str
        The keys that the state's ``to_arrays`` always writes (each engine sets them).
    snapshot_fields : tuple of str
        ``()`` unless the engine sets others.
    """

    name: ClassVar[str] = ""
    time_name: ClassVar[str] = "tau"
    stop_step: ClassVar[float] = math.inf
    state_keys: ClassVar[tuple[str, ...]] = ("time", "velocities", "collisions")
    snapshot_fields: ClassVar[tuple[str, ...]] = ()

    def next_stop(self, time: float) -> float:
        """The next point of the stop grid ``stop_step · m`` (m an integer) after ``time``, or
        ``inf`` when ``stop_step`` is infinite (no intermediate stops).

        Parameters
        ----------
        time : float
            The current time, in the engine's time.

        Returns
        -------
        float
            The next stop.
        """
        if not math.isfinite(self.stop_step):
            return math.inf
        return next_grid_point(time, self.stop_step)

    def state_from_arrays(self, arrays) -> Any:
        """Rebuild a checkpointed state: ``arrays`` must be a mapping with every key of
        ``state_keys``; :meth:`rebuild_state` then builds and checks the state.

        Parameters
        ----------
        arrays : mapping of str to numpy.ndarray
            The state's ``to_arrays()``.

        Returns
        -------
        object
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``: not a mapping, a missing key, or anything
            :meth:`rebuild_state` refuses (its ``KeyError``, ``TypeError`` or ``ValueError``
            becomes this error, with its message).
        """
        expected = f"a state of the {self.name!r} engine"
        try:
            missing = [k for k in self.state_keys if k not in arrays]
        except TypeError:
            raise InvalidArgumentError("checkpoint", type(arrays).__name__, "a mapping") from None
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", expected)
        try:
            return self.rebuild_state(arrays)
        except InvalidArgumentError:
            raise
        except (KeyError, TypeError, ValueError) as exc:
            raise InvalidArgumentError(
                "checkpoint", f"{type(exc).__name__}: {exc}", expected
            ) from None

    def rebuild_state(self, arrays) -> Any:
        """Build and check the state from ``arrays`` (its keys are present); each engine writes
        it.

        Parameters
        ----------
        arrays : mapping of str to numpy.ndarray
            The state's ``to_arrays()``.

        Returns
        -------
        object
            The state.

        Raises
        ------
        NotImplementedError
            In the base class.
        """
        raise NotImplementedError(f"{type(self).__name__}.rebuild_state")

    def observe(self, state) -> dict[str, float]:
        """No extra scalars (the default hook).

        Parameters
        ----------
        state : object
            The state.

        Returns
        -------
        dict
            ``{}``.
        """
        return {}

    def snapshot_arrays(self, state) -> dict[str, np.ndarray]:
        """No per-particle arrays beyond the velocities (the default hook).

        Parameters
        ----------
        state : object
            The state.

        Returns
        -------
        dict
            ``{}``.
        """
        return {}

    def velocity_classes(self, state) -> tuple[np.ndarray, np.ndarray] | None:
        """Optional hook (default: None): the distinct velocities of a 1D ``state`` and how
        many particles hold each, ``(values, counts)``, when that is much shorter than the
        velocities (the sticky gas's clusters).  The driver then computes the per-time
        kurtosis and histogram over the values; they must expand to ``state.velocities``
        exactly (as a multiset).

        Parameters
        ----------
        state : object
            The state at a requested time.

        Returns
        -------
        None
            No classes: the driver reads the velocities.
        """
        return None

    def memory_per_particle(self) -> float:
        """Refuse to guess: an engine must write its own estimate.

        Returns
        -------
        float
            Never (an engine overrides it).

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``engine`` (its class and model name).
        """
        raise _no_estimate(self)

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Refuse to guess: an engine must write its own estimate.

        Parameters
        ----------
        t_max : float
            The last requested time.
        n_times : int
            The number of requested times.

        Returns
        -------
        tuple of (float, str)
            Never (an engine overrides it).

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``engine`` (its class and model name).
        """
        raise _no_estimate(self)


def _no_estimate(engine) -> InvalidArgumentError:
    return InvalidArgumentError(
        "engine", engine_label(engine),
        "an engine with its own cost estimates (memory_per_particle and expected_events): "
        "a run is never costed by guess",
    )
