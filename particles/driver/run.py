"""The run loop: initial velocities and :func:`simulate` (progress bar, checkpoints, Ctrl-C, the
final histogram).  It calls nothing of an engine outside :class:`particles.driver.Engine`."""

from __future__ import annotations

import inspect
import math
import time as _time

import numpy as np

from .. import budget
from .. import observables as obs
from ..initial import get_law
from ..paths import check_output_file, check_path
from ..progress import progress_bar
from ..validation import (
    InvalidArgumentError,
    check_bool,
    check_count,
    check_nonnegative,
    check_seed,
    check_times,
    shown,
)
from .checkpoint import (
    CheckpointLock,
    Records,
    load_checkpoint,
    run_identity,
    save_checkpoint,
    seed_record,
    seed_source,
)
from .engine import ENGINE_MEMBERS, Engine, engine_label, next_grid_point  # noqa: F401 (were here)
from .result import RunResult


def initial_velocities(law, n: int, rng: np.random.Generator) -> np.ndarray:
    """Draw ``n`` velocities from ``law`` (a name or an ``InitialLaw``), then subtract their mean
    and rescale them so that the mean is 0 and ⟨v²⟩ = 1 up to round-off.

    Parameters
    ----------
    law : str or particles.initial.InitialLaw
        The initial law.
    n : int
        Number of particles.
    rng : numpy.random.Generator
        The source of randomness (the run's seed).

    Returns
    -------
    numpy.ndarray
        ``n`` velocities, float64.

    Raises
    ------
    InvalidArgumentError
        Naming ``n`` (not an integer ≥ 2), ``rng`` (not a ``numpy.random.Generator``) or
        ``initial`` (an unknown law or one of zero variance).
    """
    n = check_count(n, "n", 2)
    if not isinstance(rng, np.random.Generator):
        raise InvalidArgumentError("rng", rng, "a numpy.random.Generator (default_rng(seed))")
    v = get_law(law).sample(rng, n)
    v = v - v.mean()
    e = float(np.mean(v * v))
    if not e > 0.0:
        raise InvalidArgumentError(
            "initial", getattr(law, "name", law), "a law with non-zero variance"
        )
    v *= 1.0 / math.sqrt(e)
    return v


def _structure_mode(value) -> str | None:
    """``structure_factor`` option: False → None, True or ``"all"`` → ``"all"``, ``"last"``."""
    if value is False or value is None:
        return None
    if value is True or value == "all":
        return "all"
    if value == "last":
        return "last"
    raise InvalidArgumentError("structure_factor", value, "False, True, 'all' or 'last'")


def _final_histogram(v: np.ndarray, edges) -> tuple[obs.Histogram | None, str | None]:
    """The rescaled histogram of the final velocities (of one Cartesian component in d > 1), or
    ``(None, reason)`` where it is undefined.

    A state with every velocity 0 (energy 0) is a valid end of a run, not bad input: r = 0 makes
    colliding velocities equal, so N = 2 reaches it after one collision.  x = v/√E has no meaning
    there, so no histogram is made (``rescaled_histogram`` would raise, and a raise after the
    run would turn a valid run into exit status 2)."""
    if v.ndim == 2:
        v = np.ascontiguousarray(v[:, 0])
    if not np.any(v):
        return None, "every velocity is 0 at the last time (energy 0): x = v/sqrt(E) is undefined"
    return obs.rescaled_histogram(v, edges), None


def simulate(
    engine,
    times,
    seed,
    *,
    progress: bool | None = None,
    checkpoint=None,
    resume=None,
    bins=None,
    structure_factor: bool = False,
    snapshots: bool = False,
    checkpoint_interval: float = 60.0,
    force: bool = False,
    histograms: bool = True,
) -> RunResult:
    """Run ``engine`` from its initial state through the requested ``times`` and record it.

    At every requested time the run records the energy ⟨v²⟩, the mean velocity and the total
    number of collisions, and, on request, the structure factor and the velocities; at the last
    time it records the rescaled histogram of the velocities.  A run is a function of its
    engine, times and seed: the same arguments give the same records bit for bit, and so does a
    run resumed from a checkpoint.  Before anything is drawn, the run's memory and work are
    estimated (:mod:`particles.budget`).

    Parameters
    ----------
    engine : particles.driver.Engine
        A model's engine (:class:`~particles.Ulam`, :class:`~particles.Lattice`,
        :class:`~particles.MDEngine`, :class:`~particles.StickyGas`, or any object with every
        member of the contract :class:`particles.driver.Engine`).
    times : sequence of float
        Increasing times ≥ 0, in the engine's own time (the collision time τ for Ulam and the
        lattice, the physical time t for MD and the sticky gas).
    seed : int or numpy.random.SeedSequence
        The run's seed: an integer in [0, 2⁶⁴ − 1] (:data:`particles.validation.SEED_MAX`, the
        bound of the command line and the ensembles too), or a ``SeedSequence`` (e.g. a child
        of ``SeedSequence(s).spawn(k)`` for independent runs).  It seeds the one
        ``numpy.random.default_rng`` of the run.  ``SeedSequence(s)`` of an integer s is the
        run of seed s, bit for bit, and is recorded as s; any other is recorded
        (``RunResult.seed``, checkpoints) as ``{"entropy", "spawn_key", "pool_size"}``.
    progress : bool or None, optional
        None (default): a bar on a terminal or in a notebook, nothing otherwise; True: a bar,
        or a few plain lines where no bar can be drawn; False: nothing
        (:func:`particles.progress.progress_bar`).
    checkpoint : str or path, optional
        A file to which the state, the RNG state and the records so far are written every
        ``checkpoint_interval`` seconds of wall-clock time (at the engine's stops), at the end,
        and on Ctrl-C before the ``KeyboardInterrupt`` propagates; that exception then carries
        the path as ``checkpoint_saved`` (absent if nothing was saved, e.g. when it came before
        the run loop).  While the run writes it, it holds a lock on ``<checkpoint>.lock``.
    resume : str or path, optional
        A checkpoint to continue from; it must have been written by this same run (model,
        parameters, times, seed and options).
    bins : array_like, optional
        Edges of the final histogram in the rescaled velocity x = v/√E (one Cartesian component
        in d > 1); default :data:`particles.observables.DEFAULT_EDGES`.
    structure_factor : bool or {"all", "last"}, optional
        Record S(k) (d = 1 only): True or ``"all"`` at every time, ``"last"`` at the last time
        only (one row of N/2 + 1 floats), False (default) not at all.
    snapshots : bool, optional
        Record the velocities at every time (d = 1 only).  Default False.
    histograms : bool, optional
        Record the rescaled histogram at every time (``RunResult.histograms``; default True);
        False records only the last time's (``RunResult.histogram``), which saves a pass
        over the velocities at each time (the command line asks for them only when the
        result is saved or checkpointed).
    checkpoint_interval : float, optional
        Seconds of wall-clock time between checkpoint writes (≥ 0; default 60).
    force : bool, optional
        Run even when the estimated work exceeds 10¹³ events, or the engine's stop grid
        (``stop_step``) makes more than :data:`MAX_STOPS` stops.  Default False.

    Returns
    -------
    particles.RunResult
        The records at every requested time.

    Raises
    ------
    particles.InvalidArgumentError
        For a bad argument (``engine`` lacking a member of the contract, naming the engine and
        the members; a ``seed`` that is a ``numpy.random.Generator``; ``structure_factor`` or
        ``snapshots`` in d > 1; a ``force`` that is not a bool, or a ``progress`` that is
        neither a bool nor None), or a run refused by its estimates: one that cannot fit in the
        memory available, or one of more than 10¹³ events without ``force=True`` (an engine
        without the estimates is refused, naming it), or one whose ``stop_step`` makes more
        than :data:`MAX_STOPS` stops up to the last time (naming ``stop_step`` where it is a
        keyword of the engine, as MD's, and ``times`` where the model fixes it); and an
        engine that breaks the contract of ``advance`` during the run, naming it, before the
        offending state is recorded or saved: a state past the stop it was asked for, or one
        whose time does not move forward (or is not a number), refused at the first such step.
    particles.CheckpointError
        For a ``resume`` file written by another run, or a ``checkpoint`` locked by a running
        process.

    Examples
    --------
    >>> from particles import Ulam, simulate
    >>> result = simulate(Ulam(n=1000, restitution=0.5), [0.0, 1.0, 2.0], seed=1, progress=False)
    >>> result.energy.shape
    (3,)
    """
    _check_engine(engine)
    given_times, given_structure, given_snapshots = times, structure_factor, snapshots
    times = check_times(times, "times")  # the keyword typed (the command line checks --tau/--t)
    seed = _run_seed(seed)
    progress = check_bool(progress, "progress", none=True)
    force = check_bool(force, "force")
    hist_edges = obs.rescaled_histogram(np.array([1.0, -1.0]), bins).edges  # validates bins
    checkpoint_interval = check_nonnegative(checkpoint_interval, "checkpoint_interval")
    structure_factor = _structure_mode(structure_factor)
    snapshots = bool(snapshots)
    histograms = check_bool(histograms, "histograms")
    if checkpoint is not None:
        checkpoint = check_output_file(checkpoint, "checkpoint")
    if int(engine.to_dict().get("dimension", 1)) != 1 and (structure_factor or snapshots):
        name, value, option = (("structure_factor", given_structure, "--structure-factor")
                               if structure_factor else ("snapshots", given_snapshots, None))
        raise InvalidArgumentError(
            name, value, f"{name}=False{f' (no {option})' if option else ''} for a model of "
            "dimension > 1 (S(k) and snapshots are recorded in d = 1 only)",
        )
    identity = run_identity(engine, times, seed, hist_edges, structure_factor, snapshots,
                            histograms)
    estimate = budget.check_budget(
        budget.estimate_run(engine, float(times[-1]), n_times=len(times),
                            structure=structure_factor, snapshots=snapshots),
        force=force, time_name=engine.time_name,
    )
    _check_stops(engine, float(times[-1]), given_times, force)
    n = int(engine.to_dict()["n"])
    with CheckpointLock(checkpoint):
        fields = tuple(engine.snapshot_fields) if snapshots else ()
        records = Records(len(times), n, structure_factor, snapshots, fields,
                          hist_edges if histograms else None)
        if resume is not None:
            state, rng = load_checkpoint(check_path(resume, "resume"), engine, identity,
                                          records)
        else:
            rng = np.random.default_rng(seed_source(seed))
            state = engine.initial_state(rng)
        return _run(engine, times, seed, identity, state, rng, records, progress, checkpoint,
                    checkpoint_interval, hist_edges, estimate)


#: The most stops of an engine's stop grid (``stop_step · m``) that a run makes without
#: ``force``: each is one call of ``advance`` with its Python overhead (tens of µs at least),
#: so 10⁷ stops are minutes before any physics; a step so small that a stop does not move the
#: time would never end.
MAX_STOPS = 1e7


def _check_stops(engine, last: float, given_times, force: bool) -> None:
    """Refuse a stop grid of more than :data:`MAX_STOPS` stops up to ``last`` (unless
    ``force``), naming what the user typed: ``stop_step`` (``--stop-step``) where it is a
    keyword of the engine (MD, the sticky gas), otherwise ``times`` (``--tau``/``--t``), with
    the times received (Ulam's and the lattice's stop grid follow from the model)."""
    step = float(engine.stop_step)
    if math.isfinite(step) and step <= 0.0:  # an engine's own grid: 0 would divide by zero
        raise InvalidArgumentError("engine", engine_label(engine), "an engine whose stop_step "
                                   f"is > 0 or inf (it is {shown(engine.stop_step)})")
    stops = last / step if math.isfinite(step) else 0.0  # not finite: no stops (next_stop)
    if force or stops <= MAX_STOPS:
        return
    time, most = engine.time_name, f"{MAX_STOPS:.0e}"
    if _stop_step_is_a_keyword(engine):
        raise InvalidArgumentError(
            "stop_step", engine.stop_step,
            f"a stop_step (--stop-step) that makes at most {most} stops up to {time} = "
            f"{last:g} (this one makes {stops:.3g}); pass force=True (--force) to run it anyway")
    if isinstance(given_times, np.ndarray):  # the command line's parsed --tau: shown as a list
        given_times = given_times.tolist()
    raise InvalidArgumentError(
        "times", given_times,
        f"times (--{time}) up to {MAX_STOPS * step:g}: {engine.name} stops every {step:g} of "
        f"{time} (its own stop grid), so {time} = {last:g} makes {stops:.3g} stops, more than "
        f"{most}; pass force=True (--force) to run it anyway")


def _stop_step_is_a_keyword(engine) -> bool:
    """Whether ``stop_step`` is a keyword of the engine's constructor (the user chose it)."""
    try:
        return "stop_step" in inspect.signature(type(engine)).parameters
    except (TypeError, ValueError):  # no signature to read
        return False


_SEED_EXPECTED = "an integer in [0, 2**64 - 1] or a numpy.random.SeedSequence"


def _run_seed(seed):
    """The seed of a run as recorded (:func:`particles.driver.checkpoint.seed_record`): an int
    (checked by :func:`particles.validation.check_seed`), a root ``SeedSequence`` of such an
    int turned into that int (``default_rng`` draws the same stream from both), or the record
    of any other ``SeedSequence``.  A ``Generator`` is refused: its state moves as it is drawn
    from, so a run seeded by it could be neither repeated nor resumed from its seed."""
    if isinstance(seed, np.random.Generator):
        raise InvalidArgumentError(
            "seed", f"a numpy.random.Generator ({type(seed.bit_generator).__name__})",
            _SEED_EXPECTED + "; a Generator's state moves as it is drawn from, so the run could "
            "be neither repeated nor resumed from it (pass generator.bit_generator.seed_seq, or "
            "a child of SeedSequence.spawn)")
    if isinstance(seed, np.random.BitGenerator):
        raise InvalidArgumentError("seed", f"a numpy.random.{type(seed).__name__}",
                                   _SEED_EXPECTED + " (pass its seed_seq)")
    if isinstance(seed, np.random.SeedSequence):
        if type(seed) is not np.random.SeedSequence:
            raise InvalidArgumentError("seed", type(seed).__name__, _SEED_EXPECTED)
        record = seed_record(seed)
        entropy = record["entropy"]
        if (not record["spawn_key"] and record["pool_size"] == 4 and isinstance(entropy, int)
                and 0 <= entropy < 2**64):
            return entropy
        return record
    return check_seed(seed)


def _check_engine(engine) -> None:
    """The engine contract (:class:`particles.driver.Engine`), checked at the boundary: a wrong
    object is bad input naming the engine, not an AttributeError deep inside (an engine
    derived from :class:`particles.driver.EngineBase` has every member but perhaps the two
    estimates, which :func:`particles.budget.estimate_run` refuses by name)."""
    if isinstance(engine, type):
        raise InvalidArgumentError("engine", engine.__name__, "an engine object, not its class")
    missing = [name for name in ENGINE_MEMBERS if not hasattr(engine, name)]
    if missing:
        raise InvalidArgumentError(
            "engine", engine_label(engine),
            f"an engine of the driver contract particles.driver.Engine (missing {missing})",
        )
    if not (isinstance(engine.name, str) and engine.name):
        raise InvalidArgumentError("engine", engine_label(engine), "an engine with a name")
    if not (isinstance(engine.time_name, str) and engine.time_name):
        raise InvalidArgumentError(
            "engine", engine_label(engine), "an engine whose time_name is a non-empty string"
        )


def _check_step(engine, time, stop, new) -> None:
    """The contract of ``advance`` (:meth:`particles.driver.Engine.advance`), checked at every
    step before the new state is kept: its time moves forward (a state whose time does not move
    would make the run loop forever) and does not pass the stop (a state past a requested time
    would be recorded as the state at that time).  A time that is not a number is refused too.
    Raises :class:`~particles.InvalidArgumentError` naming the engine."""
    got = getattr(new, "time", None)
    try:
        ok = time < got <= stop
    except (TypeError, ValueError):  # not a number, or an array
        ok = False
    if not ok:
        raise InvalidArgumentError(
            "engine", engine_label(engine),
            f"an engine whose advance(state, stop, rng) returns the state at the stop, later "
            f"than the state's time (its time went from {float(time)!r} to {shown(got)}, "
            f"stop {stop!r})")


def _run(engine, times, seed, identity, state, rng, records, progress, checkpoint,
         checkpoint_interval, hist_edges, estimate) -> RunResult:
    """The run loop of :func:`simulate` (arguments checked, lock held)."""
    rng_state = rng.bit_generator.state

    started = _time.perf_counter()
    seconds_before = records.seconds
    last_save = _time.monotonic()
    bar = None
    if progress is not False:
        bar = progress_bar(float(times[-1]), engine.name, engine.time_name, enabled=progress,
                           initial=float(state.time), postfix=f"estimate {estimate.describe()}")
    try:
        while records.done < len(times):
            target = float(times[records.done])
            while state.time < target:
                stop = min(float(engine.next_stop(state.time)), target)
                new = engine.advance(state, stop, rng)
                _check_step(engine, state.time, stop, new)
                new_rng_state = rng.bit_generator.state
                step = new.time - state.time
                # One statement: Ctrl-C cannot separate the state from its RNG state.  The old
                # state is dropped here, before the next advance (a large state counts twice
                # while it is computed, not three times).
                state, rng_state = new, new_rng_state
                del new
                if bar is not None:
                    bar.update(step)
                if checkpoint is not None and _time.monotonic() - last_save >= checkpoint_interval:
                    records.seconds = seconds_before + _time.perf_counter() - started
                    save_checkpoint(checkpoint, identity, state, rng_state, records)
                    last_save = _time.monotonic()
            records.record(engine, state, len(times))
    except KeyboardInterrupt as exc:
        if checkpoint is not None:
            records.seconds = seconds_before + _time.perf_counter() - started
            save_checkpoint(checkpoint, identity, state, rng_state, records)
            exc.checkpoint_saved = str(checkpoint)  # only once the file is in place
        raise
    finally:
        if bar is not None:
            bar.close()
    records.seconds = seconds_before + _time.perf_counter() - started
    v = state.velocities
    histogram, histogram_note = _final_histogram(v, hist_edges)  # before anything is written
    if checkpoint is not None:
        save_checkpoint(checkpoint, identity, state, rng_state, records)

    structure = None
    if records.structure is not None:
        structure = (obs.wavenumbers(v.size), records.structure)
    return RunResult(
        model=engine.name,
        params=identity["params"],
        seed=seed,
        times=times,
        energy=records.energy,
        momentum=records.momentum,
        collisions=records.collisions,
        kurtosis=records.kurtosis,
        velocities=v,
        histogram=histogram,
        seconds=records.seconds,
        structure=structure,
        snapshots=records.snapshots,
        snapshot_extras=records.snapshot_extras,
        extras=records.extras,
        histogram_note=histogram_note,
        final_state=state,
        histogram_edges=hist_edges,
        histogram_counts=records.hist_count,
        histogram_scales=records.hist_v0,
        time_name=engine.time_name,
    )
