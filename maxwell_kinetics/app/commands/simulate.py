"""``maxwell-kinetics simulate MODEL``: the particle models on the command line.

One sub-subcommand per model of the catalogue :mod:`particles.models`, generated from it by
:mod:`maxwell_kinetics.app.commands.model_options`: every parameter of the model is an option (with
its default, unit and help), the time option is ``--tau`` or ``--t`` as the engine names its
time, and the run options (times, seed, output, checkpointing) are added by
:func:`add_common_options`.  The handler parses and checks every value, builds the engine with
the model's factory and hands it to :func:`run_engine`, which runs it and prints the result.  A
new model or parameter is an entry of the catalogue, not an edit here; only what a model adds
to the output (``--profile`` of MD and the sticky gas) is written here.

``--json`` prints one object with keys ``tau`` (the requested times; ``t`` for the engines that
run in t: MD, the sticky gas, a kernel whose time is t), ``energy`` (⟨v²⟩ at each
time), ``kurtosis`` (⟨v⁴⟩/⟨v²⟩² at each time, of one Cartesian component in d > 1; null where
every velocity is 0), ``collisions`` (the total), ``seconds``
(wall clock), ``histogram`` (``centres``, ``density``, ``error`` of x = v/√E at the last time)
and, with ``--structure-factor``, ``k`` and ``S`` (S(k) = |v̂(k)|²/N at the last time); also
``model``, ``params`` and ``seed``, and, for ``ulam`` and ``lattice``, ``kernel`` (the collision
kernel run, :meth:`particles.kernels.Kernel.to_dict`: its name, restitution and parameters;
chosen with ``--kernel``, or ``--rate``, its alias kept for one release).  A run that ends
with every velocity 0 (possible at r = 0) is valid: ``histogram`` is then ``null`` and
``histogram_note`` says why.

``simulate md`` (time ``--t``) adds, one entry per requested time, ``collisions_per_particle``
(τ(t) = 2 · collisions / N), ``momentum`` (the total momentum Σ_i v_i) and ``collisions`` (a list:
the total at each time, where the other models give one integer); ``--structure-factor`` also
adds ``C`` (C(r) = (1/N) Σ_i v_i v_{i+r}, r = 0..⌊N/2⌋, label order) and ``--profile`` adds
``profile`` (``x``: rod positions in [0, L) sorted, ``v_x``: their velocities, ``v_i``: velocities
by particle label), all at the last time.  An inelastic collapse (δ = 0) exits with status 3 and
a message that names the time, the particles and the number of collisions.  A run whose energy
overflows float64 (e.g. a --driving far too strong) also exits with status 3, printing and saving
nothing.

Bad input raises ``InvalidArgumentError`` before anything is written,
which the top-level command turns into exit status 2.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from particles import driver
from particles import observables as obs
from particles.kernels import Kernel
from particles.md import InelasticCollapseError, profile_x
from particles.models import get_model
from particles.parsing import parse_float_list, parse_seed
from particles.sticky_observables import profile_x as sticky_profile_x
from particles.validation import InvalidArgumentError, check_nonnegative, check_times

from ..output import check_outputs, emit_json
from .model_options import (
    add_model_options,
    add_run_options,
    add_time_option,
    cli_models,
    model_params,
    time_option,
)

__all__ = ["add_parser", "add_common_options", "run_engine", "run_model"]


def add_common_options(parser: argparse.ArgumentParser) -> None:
    """The run options of ``simulate MODEL`` (the model's parameters and time are added from
    the catalogue).  Values stay strings here; they are checked by :func:`run_engine` and the
    run driver, so errors name the option and the value received.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The model's parser.
    """
    parser.add_argument("--seed", default="0", help="integer seed >= 0 (default 0)")
    add_run_options(parser)
    # simulate writes checkpoints only with --checkpoint: None tells an interval given from none
    parser.set_defaults(checkpoint_interval=None)
    parser.add_argument("--checkpoint", metavar="FILE", help="write checkpoints to FILE")
    parser.add_argument("--resume", metavar="FILE", help="continue the run saved in FILE")
    parser.add_argument("--save", metavar="FILE", help="save the full result (.npz) to FILE")
    parser.add_argument(
        "--force", action="store_true",
        help="run even when the estimated work exceeds 1e13 events",
    )


def _print_table(time_key, times, energy, count_name, counts) -> None:
    """The text output's table: time, energy and a count at each requested time."""
    print(f"{time_key:>12} {'energy':>14} {count_name:>14}")
    for t, e, c in zip(times, energy, counts, strict=True):
        print(f"{t:12.6g} {e:14.6e} {c:14d}")


def run_engine(engine, args, *, time_key: str = "tau", extend=None) -> int:
    """Run ``engine`` with the common options in ``args`` and print the result.

    ``extend(result, payload)``, if given, adds model-specific entries to the JSON payload.

    Parameters
    ----------
    engine : object
        An engine of :mod:`particles.models`.
    args : argparse.Namespace
        The parsed command line.
    time_key : str
        The time's name in the output.
    extend : callable, optional
        ``extend(result, payload)``.

    Returns
    -------
    int
        The exit status.
    """
    times = check_times(parse_float_list(args.times, time_key), time_key)
    seed = parse_seed(args.seed)
    interval = _checkpoint_interval(args)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    check_outputs(checkpoint=args.checkpoint, save=args.save, inputs={"resume": args.resume})
    try:
        result = driver.simulate(
            engine,
            times,
            seed,
            progress=progress,
            checkpoint=args.checkpoint,
            resume=args.resume,
            structure_factor="last" if args.structure_factor else False,  # only S(τ_last) printed
            checkpoint_interval=interval,
            force=args.force,
            # the per-time histograms are printed nowhere: recorded only for a file
            histograms=bool(args.save or args.checkpoint or args.resume),
        )
    except KeyboardInterrupt as exc:
        saved = getattr(exc, "checkpoint_saved", None)  # set by simulate once the file is saved
        if saved is not None:
            print(f"checkpoint saved to {saved}", file=sys.stderr)
        raise
    overflow = _overflow(result.times, result.energy, time_key)
    if overflow is not None:  # a physics failure: nothing printed or saved as if it were a result
        print(f"maxwell-kinetics simulate {engine.name}: error: {overflow}", file=sys.stderr)
        return 3
    if args.save:
        result.save(args.save)
    payload = result.summary()
    payload[time_key] = payload.pop("tau")
    payload.update({"params": result.params, "seed": result.seed})
    kernel = getattr(engine, "kernel", None)
    if isinstance(kernel, Kernel):  # the collision kernel run (its time is the run's)
        payload["kernel"] = kernel.to_dict()
    for key, values in result.extras.items():  # e.g. lattice attempts, MD τ(t)
        payload.setdefault(key, values.tolist())
    if args.structure_factor:
        payload["k"] = result.structure[0].tolist()
        payload["S"] = result.structure[1][-1].tolist()
    if extend is not None:
        extend(result, payload)
    if args.json:
        emit_json(payload)
    else:
        print(f"{engine.name}: {parameters_in_words(result.params)}, seed {seed}")
        _print_table(time_key, result.times, result.energy, "collisions", result.collisions)
        if result.histogram_note is not None:
            print(f"histogram: {result.histogram_note}")
        print(f"{result.seconds:.3f} s")
    return 0


def _overflow(times, energy, time_key: str) -> str | None:
    """Why the run is no result (velocities beyond float64: inf or NaN energy), or None."""
    bad = [i for i, e in enumerate(energy) if not np.isfinite(e)]
    if not bad:
        return None
    return (f"the energy overflowed float64 ({energy[bad[0]]} at {time_key} = "
            f"{times[bad[0]]:g}): the velocities are beyond 1e154, e.g. from a --driving too "
            "strong for these times")


def _checkpoint_interval(args) -> float:
    """``--checkpoint-interval`` checked (named as the option), and only with ``--checkpoint``;
    60 s when not given."""
    text = getattr(args, "checkpoint_interval", None)
    if text is None:
        return 60.0
    interval = check_nonnegative(text, "checkpoint-interval")
    if args.checkpoint is None:
        raise InvalidArgumentError("checkpoint-interval", text,
                                   "no --checkpoint-interval without --checkpoint FILE")
    return interval


def _md_extend(engine, args):
    """``simulate md``: τ(t), the momentum, the collisions at each time; C(r) with
    ``--structure-factor``, v(x) and v(i) with ``--profile``."""
    params = engine.params

    def extend(result, payload):
        payload["collisions_per_particle"] = result.extras["collisions_per_particle"].tolist()
        payload["momentum"] = result.extras["total_momentum"].tolist()
        payload.pop("total_momentum", None)  # the name is `momentum`; one key, not two
        payload["collisions"] = result.collisions.tolist()
        if args.structure_factor:
            half = params.n // 2 + 1
            payload["C"] = obs.correlation(result.velocities)[:half].tolist()
        if args.profile:
            state = result.final_state
            x, v_x = profile_x(state, params)
            payload["profile"] = {
                "x": x.tolist(),
                "v_x": v_x.tolist(),
                "v_i": state.velocities.tolist(),
            }

    return extend


def _sticky_extend(engine, args):
    """``simulate sticky``: the momentum, collisions and clusters at each time; C(r) with
    ``--structure-factor``, v(x) and v(i) with ``--profile``."""
    params = engine.params

    def extend(result, payload):
        payload["momentum"] = result.extras["total_momentum"].tolist()
        payload.pop("total_momentum", None)
        payload["collisions"] = result.collisions.tolist()
        payload["clusters"] = [int(c) for c in result.extras["clusters"]]
        if args.structure_factor:
            half = params.n // 2 + 1
            payload["C"] = obs.correlation(result.velocities)[:half].tolist()
        if args.profile:
            state = result.final_state
            x, v_x = sticky_profile_x(state)
            payload["profile"] = {"x": x.tolist(), "v_x": v_x.tolist(),
                                  "v_i": state.velocities.tolist()}

    return extend


#: What a model adds to the output: {model: builder of ``extend(result, payload)``}; the
#: models named here also take ``--profile``.
_EXTEND = {"md": _md_extend, "sticky": _sticky_extend}


def run_model(args) -> int:
    """The handler of ``simulate MODEL``: parameters checked, engine built, run.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit status (3: inelastic collapse, or an energy beyond float64).

    Raises
    ------
    particles.validation.InvalidArgumentError
        For any bad option, and for ``--workers`` or ``--scheduler`` without ``--chunks`` (the
        top-level command prints it and exits 2).
    """
    model = get_model(args.model)
    engine = model.build(model_params(args, model, sweep=False))
    time_name, args.times = time_option(args, model, model.time_name(engine))
    if getattr(args, "chunks", None) is not None:
        return _run_sticky_chunks(engine, args)
    for option in ("workers", "scheduler"):  # they run chunks: alone they would do nothing
        if getattr(args, option, None) is not None:
            raise InvalidArgumentError(option, getattr(args, option),
                                       f"--{option} only with --chunks K (K >= 2): "
                                       "without --chunks it would run nothing")
    extend = _EXTEND[model.name](engine, args) if model.name in _EXTEND else None
    try:
        return run_engine(engine, args, time_key=time_name, extend=extend)
    except InelasticCollapseError as exc:
        print(f"maxwell-kinetics simulate {model.name}: error: {exc}", file=sys.stderr)
        return 3


def add_parser(subparsers) -> None:
    """Add the ``simulate`` subcommand to the top-level parser's ``subparsers``: one
    sub-subcommand per model of the catalogue.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The top-level parser's subcommands.
    """
    simulate = subparsers.add_parser("simulate", help="run a particle model")
    models = simulate.add_subparsers(dest="model", required=True)
    for model in cli_models():
        parser = models.add_parser(model.name, help=model.help,
                                   description=model.description or model.help)
        add_model_options(parser, model, sweep=False)
        add_time_option(parser, model)
        add_common_options(parser)
        if model.name in _EXTEND:
            parser.add_argument("--profile", action="store_true",
                                help="also output v(x) and v(i) at the last time")
        if model.name == "sticky":
            _add_chunk_options(parser)
        parser.set_defaults(handler=run_model)


def _add_chunk_options(parser) -> None:
    """``simulate sticky --chunks K [--workers W | --scheduler ADDRESS]``."""
    parser.add_argument(
        "--chunks", default=None, metavar="K",
        help="compute the gas as K chunks of the ring, each drawn from its own child seed "
        "(K = 1: the single-process engine; K in [1, N/2]); prints energies, clusters, the "
        "mass distribution, the histogram and, with --structure-factor, S(k) and C(r) "
        "(computed in this process: 24 bytes a particle); cannot save, checkpoint or profile")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", default=None,
                       help="only with --chunks K >= 2: a local Dask cluster of W single-threaded "
                       "processes (default: the chunks run here, one after another)")
    where.add_argument("--scheduler", default=None,
                       help="only with --chunks K >= 2: the address of a running Dask scheduler")


def _run_sticky_chunks(engine, args) -> int:
    """``simulate sticky --chunks K``: :func:`particles.sticky_chunks.simulate_chunks`."""
    from particles.ensemble.cluster import check_scheduler, connect
    from particles.parsing import parse_count
    from particles.progress import progress_bar
    from particles.sticky_chunks import check_chunks, simulate_chunks
    from particles.workers import check_workers

    times = check_times(parse_float_list(args.times, "t"), "t")
    seed = parse_seed(args.seed)
    chunks = check_chunks(parse_count(args.chunks, "chunks", 1), engine.params.n)
    for option in ("checkpoint", "resume", "save", "checkpoint_interval"):
        if getattr(args, option) is not None:
            flag = option.replace("_", "-")
            raise InvalidArgumentError(flag, getattr(args, option), "no --" + flag +
                                       " with --chunks (only the outputs reach this process)")
    if args.profile:
        raise InvalidArgumentError("profile", True,
                                   "not with --chunks (the positions stay in the chunks)")
    if chunks == 1:  # the single engine, run here: workers would have nothing to do
        for option in ("workers", "scheduler"):
            if getattr(args, option) is not None:
                raise InvalidArgumentError(option, getattr(args, option),
                                           f"--{option} only with --chunks K >= 2 (K = 1 is "
                                           "the single engine, run in this process)")
    workers = None if args.workers is None else parse_count(args.workers, "workers", 1)
    workers = check_workers(workers, "workers", tasks=chunks, force=args.force)
    if args.scheduler is not None:
        check_scheduler(args.scheduler)
    client, closers = None, []
    if workers is not None or args.scheduler is not None:
        client, closers = connect("dask", workers, args.scheduler, None, None)
    show = sys.stderr.isatty() if args.progress is None else args.progress
    bar = progress_bar(len(times), "sticky chunks", "times", enabled=show)
    try:
        result = simulate_chunks(engine.params, times, seed, chunks, client=client,
                                 structure_factor=bool(args.structure_factor),
                                 progress=lambda done, total: bar.update(1))
    finally:
        bar.close()
        for close in closers:
            close()
    payload = result.to_dict()
    if args.json:
        emit_json(payload)
    else:
        print(f"sticky: {parameters_in_words(result.params)}, seed {seed}, {chunks} chunks")
        _print_table("t", result.times, result.energy, "clusters", result.clusters)
        print(f"{result.seconds:.3f} s")
    return 0


def parameters_in_words(params: dict) -> str:
    """``n=1000, restitution=0.5, initial=gaussian``: a run's parameters as the header of the
    text output shows them (the dict's repr showed quotes and braces).

    Parameters
    ----------
    params : dict
        The engine's parameters (``RunResult.params``).

    Returns
    -------
    str
        ``name=value`` pairs, comma-separated; nested dicts (a kernel) as ``name=value`` inside
        parentheses.
    """
    def word(value) -> str:
        if isinstance(value, dict):
            return "(" + parameters_in_words(value) + ")"
        return f"{value:g}" if isinstance(value, float) else str(value)

    return ", ".join(f"{key}={word(value)}" for key, value in params.items())
