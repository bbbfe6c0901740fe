"""``maxwell-kinetics simulate {ulam,lattice,md}``: the particle models on the command line.

Each model is one sub-subcommand, added by a small ``_add_<model>`` function that declares its
own options, calls :func:`add_common_options` for the shared ones (size, restitution, initial
law, times, seed, output, checkpointing) and sets ``handler``; the handler builds the engine and
hands it to :func:`run_engine`, which runs it and prints the result.  A new model (MD) adds one
``_add_md`` function and one line in :func:`register`.

``--json`` prints one object with keys ``tau`` (the requested times; ``t`` for MD), ``energy``
(⟨v²⟩ at each time), ``collisions`` (the total), ``seconds`` (wall clock), ``histogram``
(``centres``, ``density``, ``error`` of x = v/√E at the last time) and, with
``--structure-factor``, ``k`` and ``S`` (S(k) = |v̂(k)|²/N at the last time); also ``model``,
``params`` and ``seed``.  A run that ends with every velocity 0 (possible at r = 0) is valid:
``histogram`` is then ``null`` and ``histogram_note`` says why.

``simulate md`` (time ``--t``) adds, one entry per requested time, ``collisions_per_particle``
(τ(t) = 2 · collisions / N), ``momentum`` (the total momentum Σ_i v_i) and ``collisions`` (a list:
the total at each time, where the other models give one integer); ``--structure-factor`` also
adds ``C`` (C(r) = (1/N) Σ_i v_i v_{i+r}, r = 0..⌊N/2⌋, label order) and ``--profile`` adds
``profile`` (``x``: rod positions in [0, L) sorted, ``v_x``: their velocities, ``v_i``: velocities
by particle label), all at the last time.  An inelastic collapse (δ = 0) exits with status 3 and
a message that names the time, the particles and the number of collisions.

Bad input raises ``InvalidArgumentError`` before anything is written,
which the top-level command turns into exit status 2.
"""

from __future__ import annotations

import argparse
import sys

from particles import driver
from particles import observables as obs
from particles.lattice import Lattice
from particles.md import InelasticCollapseError, MDEngine, MDParams, profile_x
from particles.sticky import StickyGas, StickyParams
from particles.sticky import profile_x as sticky_profile_x
from particles.ulam import Ulam
from particles.validation import (
    check_times,
    parse_count,
    parse_float_list,
    parse_int,
    parse_seed,
)

from ..output import check_outputs, emit_json

__all__ = ["add_parser", "add_common_options", "run_engine", "resumed_state"]


def resumed_state(path) -> dict:
    """The ``state.*`` arrays of the checkpoint at ``path`` (read through the persistence helper,
    with its checks)."""
    _, arrays = driver._read_npz(path, "resume", "checkpoint")
    return {k[len("state."):]: v for k, v in arrays.items() if k.startswith("state.")}


def add_common_options(parser: argparse.ArgumentParser, *, time_option: str = "--tau",
                       restitution: bool = True) -> None:
    """Options shared by every particle model.  Values stay strings here; they are checked by
    the engines and :func:`run_engine`, so errors name the option and the value received."""
    parser.add_argument("--n", required=True, help="number of particles / sites (e.g. 2e5)")
    if restitution:
        parser.add_argument("--restitution", required=True,
                            help="restitution coefficient r in [0, 1]")
    parser.add_argument(
        "--initial", default="gaussian", help="initial velocity law (default: gaussian)"
    )
    parser.add_argument(
        time_option,
        dest="times",
        required=True,
        metavar="T1,T2,...",
        help="increasing, non-negative times at which to record",
    )
    parser.add_argument("--seed", default="0", help="integer seed >= 0 (default 0)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--structure-factor", action="store_true", help="also output S(k) at the last time"
    )
    parser.add_argument("--checkpoint", metavar="FILE", help="write checkpoints to FILE")
    parser.add_argument("--resume", metavar="FILE", help="continue the run saved in FILE")
    parser.add_argument("--save", metavar="FILE", help="save the full result (.npz) to FILE")
    parser.add_argument(
        "--checkpoint-interval",
        default="60",
        metavar="SECONDS",
        help="wall-clock seconds between checkpoints (default 60)",
    )
    parser.add_argument(
        "--force", action="store_true",
        help="run even when the estimated work exceeds 1e13 events",
    )
    parser.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar on stderr (default: when stderr is a terminal)",
    )


def run_engine(engine, args, *, time_key: str = "tau", extend=None) -> int:
    """Run ``engine`` with the common options in ``args`` and print the result.

    ``extend(result, payload)``, if given, adds model-specific entries to the JSON payload."""
    times = check_times(parse_float_list(args.times, time_key), time_key)
    seed = parse_seed(args.seed)
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
            checkpoint_interval=args.checkpoint_interval,
            force=args.force,
        )
    except KeyboardInterrupt as exc:
        saved = getattr(exc, "checkpoint_saved", None)  # set by simulate once the file is saved
        if saved is not None:
            print(f"checkpoint saved to {saved}", file=sys.stderr)
        raise
    if args.save:
        result.save(args.save)
    payload = result.summary()
    payload[time_key] = payload.pop("tau")
    payload.update({"params": result.params, "seed": result.seed})
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
        print(f"{engine.name}: {result.params}  seed {seed}")
        print(f"{time_key:>12} {'energy':>14} {'collisions':>14}")
        for t, e, c in zip(result.times, result.energy, result.collisions, strict=True):
            print(f"{t:12.6g} {e:14.6e} {c:14d}")
        if result.histogram_note is not None:
            print(f"histogram: {result.histogram_note}")
        print(f"{result.seconds:.3f} s")
    return 0


def _run_ulam(args) -> int:
    engine = Ulam(parse_count(args.n, "n", 2), args.restitution, args.initial,
                  dimension=parse_int(args.dimension, "dimension"), angular=args.angular,
                  driving=args.driving)
    return run_engine(engine, args)


def _add_ulam(models) -> None:
    parser = models.add_parser(
        "ulam", help="mean-field pseudo-Maxwell (Ulam) model, exact continuous time in τ"
    )
    add_common_options(parser)
    parser.add_argument("--dimension", default="1",
                        help="velocity dimension d = 1, 2 or 3 (default 1; d > 1: SPEC §8)")
    parser.add_argument("--angular", default="uniform",
                        help="d > 1: collision direction uniform on the sphere ('uniform') or "
                        "weighted by |g.n| ('hard')")
    parser.add_argument("--driving", default="0",
                        help="white-noise heating strength D >= 0 (d = 1; default 0: cooling)")
    parser.set_defaults(handler=_run_ulam)


def _run_lattice(args) -> int:
    engine = Lattice(
        parse_count(args.n, "n", 3), args.restitution, args.initial, not args.no_constraint,
        rate=args.rate,
    )
    # the rate-|Δ| lattice runs in MD's time t: its JSON reports "t", as simulate md does
    return run_engine(engine, args, time_key=getattr(engine, "time_name", "tau"))


def _add_lattice(models) -> None:
    parser = models.add_parser("lattice", help="ring lattice model, τ = attempts / N")
    add_common_options(parser)
    parser.add_argument(
        "--no-constraint",
        action="store_true",
        help="collide every chosen bond (default: only approaching pairs, v_i > v_{i+1})",
    )
    parser.add_argument(
        "--rate", default="constant", choices=["constant", "relative_velocity"],
        help="bond collision rate: constant (the paper's lattice, time τ = attempts/N) or "
        "proportional to |v_i - v_{i+1}| as for MD pairs (time t of MD at density 1)",
    )
    parser.set_defaults(handler=_run_lattice)


def _run_md(args) -> int:
    params = MDParams(
        parse_count(args.n, "n", 2),
        args.density,
        args.restitution,
        delta=args.delta,
        rod_length=args.rod_length,
        initial=args.initial,
    )
    engine = MDEngine(params, args.method)

    def extend(result, payload):
        payload["collisions_per_particle"] = result.extras["collisions_per_particle"].tolist()
        payload["momentum"] = result.extras["total_momentum"].tolist()
        payload.pop("total_momentum", None)  # the name is `momentum`; one key, not two
        payload["collisions"] = result.collisions.tolist()
        if args.structure_factor:
            half = params.n // 2 + 1
            payload["C"] = obs.correlation(result.velocities)[:half].tolist()
        if args.profile:
            state = engine.last_state
            if state is None:  # a resumed run that had already finished
                state = engine.state_from_arrays(resumed_state(args.resume))
            x, v_x = profile_x(state, params)
            payload["profile"] = {
                "x": x.tolist(),
                "v_x": v_x.tolist(),
                "v_i": state.velocities.tolist(),
            }

    try:
        return run_engine(engine, args, time_key="t", extend=extend)
    except InelasticCollapseError as exc:
        print(f"maxwell-kinetics simulate md: error: {exc}", file=sys.stderr)
        return 3


def _add_md(models) -> None:
    parser = models.add_parser(
        "md",
        help="event-driven molecular dynamics of inelastic hard rods on a ring (time t)",
        description="Exact event-driven MD of N hard rods on a ring (SPEC §4).  Exit status 2: "
        "bad input (nothing written); 3: inelastic collapse (set --delta > 0, or increase "
        "a tiny one: see the message).",
    )
    add_common_options(parser, time_option="--t")
    parser.add_argument("--density", required=True, help="number density n = N/L > 0")
    parser.add_argument(
        "--delta",
        default="0",
        help="regularisation: collisions with |Δv| < δ are elastic (default 0: none)",
    )
    parser.add_argument("--rod-length", default="0", help="rod length σ >= 0 (default 0: points)")
    parser.add_argument(
        "--profile", action="store_true", help="also output v(x) and v(i) at the last time"
    )
    parser.add_argument(
        "--method",
        default="fast",
        choices=["fast", "reference"],
        help="light-cone vectorised engine (default) or the sequential heap reference",
    )
    parser.set_defaults(handler=_run_md)


def _run_sticky(args) -> int:
    params = StickyParams(parse_count(args.n, "n", 2), args.density, args.initial)
    engine = StickyGas(params)
    last = {}

    def observe(state, _observe=engine.observe):
        last["state"] = state
        return _observe(state)

    engine.observe = observe

    def extend(result, payload):
        payload["momentum"] = result.extras["total_momentum"].tolist()
        payload.pop("total_momentum", None)
        payload["collisions"] = result.collisions.tolist()
        payload["clusters"] = [int(c) for c in result.extras["clusters"]]
        if args.structure_factor:
            half = params.n // 2 + 1
            payload["C"] = obs.correlation(result.velocities)[:half].tolist()
        if args.profile:
            state = last.get("state")
            if state is None:  # a resumed run that had already finished
                state = engine.state_from_arrays(resumed_state(args.resume))
            x, v_x = sticky_profile_x(state)
            payload["profile"] = {"x": x.tolist(), "v_x": v_x.tolist(),
                                  "v_i": state.velocities.tolist()}

    return run_engine(engine, args, time_key="t", extend=extend)


def _add_sticky(models) -> None:
    parser = models.add_parser(
        "sticky",
        help="the sticky gas (r = 0), exact at any time from the convex minorant (time t)",
        description="Perfectly inelastic point particles on a ring (SPEC §7): clusters merge on "
        "contact and move with their mean velocity.  The state at each requested time is "
        "computed directly (no events); the initial state is MD's for the same --n, --density, "
        "--initial and --seed.",
    )
    add_common_options(parser, time_option="--t", restitution=False)
    parser.add_argument("--density", required=True, help="number density n = N/L > 0")
    parser.add_argument(
        "--profile", action="store_true", help="also output v(x) and v(i) at the last time"
    )
    parser.set_defaults(handler=_run_sticky)


def add_parser(subparsers) -> None:
    """Add the ``simulate`` subcommand to the top-level parser's ``subparsers``."""
    simulate = subparsers.add_parser("simulate", help="run a particle model")
    models = simulate.add_subparsers(dest="model", required=True)
    _add_ulam(models)
    _add_lattice(models)
    _add_md(models)
    _add_sticky(models)
