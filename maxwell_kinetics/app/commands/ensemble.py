"""``maxwell-kinetics ensemble MODEL``: many runs of a particle model on dask.

    maxwell-kinetics ensemble MODEL [the model options of simulate MODEL] --tau|--t T1,T2
        --seeds 1-16 [--structure-factor] [--checkpoint-interval S]
        [--workers N | --scheduler ADDRESS | --cluster slurm|pbs --config FILE | --serial]
        --out DIR [--json] [--no-progress]

Models: those of the catalogue :mod:`particles.models` (``ulam``, ``lattice``, ``md``,
``sticky``), with the options of ``simulate MODEL`` generated from it alike: every parameter,
the time (``--tau`` or ``--t``), ``--structure-factor``, ``--checkpoint-interval``,
``--progress/--no-progress``, ``--json``.  Any parameter given as a comma list
(``--restitution 0.3,0.5,0.9``, ``--constraint true,false``) is swept; ``--seeds`` takes
ranges and lists (``1-16,20``).
Each task writes its result to its own file in ``--out`` (named by a hash of the model, the
parameters, the seed, the times and the format version); a rerun skips the finished tasks, so an
interrupted ensemble resumes where it stopped.  The aggregate (mean and standard error over
seeds per parameter set) is saved as ``<out>/ensemble.npz`` and printed with ``--json``;
printed, each parameter set of an engine with a collision kernel (``ulam``, ``lattice``: chosen
with ``--kernel``, or ``--rate``, its alias kept for one release) also has ``kernel``
(:meth:`particles.kernels.Kernel.to_dict`).

Exit status: 0 all tasks finished; 3 some task failed (listed with its parameters); 2 bad input
(nothing written; an unreachable ``--scheduler`` fails after 10 s); 130 interrupted.
"""

from __future__ import annotations

from particles.ensemble import EnsembleSpec, run_ensemble
from particles.ensemble.spec import MAX_TASKS
from particles.kernels import Kernel
from particles.models import get_model
from particles.parsing import parse_count, parse_float_list
from particles.validation import InvalidArgumentError, check_times
from particles.workers import check_workers

from ..output import emit_json
from .model_options import (
    add_model_options,
    add_run_options,
    add_time_option,
    cli_models,
    model_params,
    time_option,
)

__all__ = ["add_parser", "run", "spec_from_args"]


def add_parser(subparsers) -> None:
    """Register ``ensemble MODEL`` with one sub-subcommand per model of the catalogue.

    Each model's parser has that model's parameter options (comma lists sweep them), the time
    option its engines use, ``--seeds``, the shared run options, where to run (``--workers``,
    ``--scheduler``, ``--cluster`` with ``--config``, or ``--serial``) and ``--out``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``add_subparsers()`` object of the top-level parser; each model parser's
        ``handler`` default is :func:`run`.
    """
    ensemble = subparsers.add_parser(
        "ensemble", help="many seeds and a parameter sweep of a particle model, on dask",
        description=__doc__.split("\n\n", 1)[1],
    )
    models = ensemble.add_subparsers(dest="model", required=True)
    for model in cli_models():
        p = models.add_parser(model.name, help=f"an ensemble of simulate {model.name}",
                              description=model.description or model.help)
        add_model_options(p, model, sweep=True)
        add_time_option(p, model)
        p.add_argument("--seeds", required=True,
                       help="seeds: ranges and lists, e.g. 1-16,20 (at most "
                       f"{MAX_TASKS} tasks, seeds x parameter sets, in one ensemble)")
        add_run_options(p)
        where = p.add_mutually_exclusive_group()
        where.add_argument("--workers", default=None,
                           help="local cluster of N single-threaded processes (default: cores; "
                           "never more than the tasks; at most 4 x the CPUs unless --force)")
        where.add_argument("--scheduler", default=None, help="address of a running scheduler")
        where.add_argument("--cluster", choices=["slurm", "pbs"], default=None,
                           help="a batch system through dask-jobqueue (needs --config)")
        where.add_argument("--serial", action="store_true",
                           help="run the tasks one after another in this process (no dask)")
        p.add_argument("--config", default=None, help="TOML file of the batch cluster")
        p.add_argument("--force", action="store_true",
                       help="allow more than 4 x the CPUs as --workers")
        p.add_argument("--out", required=True, help="output folder (task files, aggregate)")
        p.set_defaults(handler=run)


def spec_from_args(args) -> EnsembleSpec:
    """The ensemble specification of the command line, checked before anything runs.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``ensemble MODEL``.

    Returns
    -------
    particles.ensemble.EnsembleSpec
        The model, its parameters (lists for the swept ones), the seeds, the record times and
        the run options (checkpoint interval, structure factor).

    Raises
    ------
    particles.validation.InvalidArgumentError
        From the validators it calls: a bad parameter value, seed list or time list, or a time
        option that is not the one the model's engines use.
    """
    model = get_model(args.model)
    params = model_params(args, model, sweep=True)
    given = [name for name in model.time_names if getattr(args, f"times_{name}") is not None]
    name = given[0]
    text = getattr(args, f"times_{name}")
    times = check_times(parse_float_list(text, name), name)
    options = {"checkpoint_interval": args.checkpoint_interval}
    if args.structure_factor:
        options["structure_factor"] = "last"
    # the seeds as typed: the spec counts its tasks (seeds x parameter sets) from the ranges'
    # bounds and refuses more than particles.ensemble.spec.MAX_TASKS before listing any seed
    spec = EnsembleSpec(args.model, params, args.seeds, tuple(times), options)
    time_option(args, model, spec.time_name)  # the option given names the engines' time
    return spec


def _with_kernels(payload: dict, model) -> dict:
    """``payload`` with ``kernel`` (the kernel's ``to_dict()``) added to each parameter set of
    its aggregate whose engine has a collision kernel (the engines are built again: cheap, the
    specification built them all)."""
    aggregate = payload.get("aggregate")
    if not isinstance(aggregate, dict) or not aggregate.get("sets"):
        return payload
    sets = []
    for entry in aggregate["sets"]:
        kernel = getattr(model.build(entry["params"]), "kernel", None)
        sets.append({**entry, "kernel": kernel.to_dict()} if isinstance(kernel, Kernel)
                    else entry)
    return {**payload, "aggregate": {**aggregate, "sets": sets}}


def _progress(args) -> bool:
    """``--progress/--no-progress`` as given; by default on unless ``--json``."""
    return (not args.json) if args.progress is None else args.progress


def run(args) -> int:
    """Run ``maxwell-kinetics ensemble MODEL``: every (parameter point, seed) task of the
    specification, on dask or serially, with task files and the aggregate in ``--out``.

    Finished tasks are skipped on a rerun.  Prints a summary line and each failure (or one JSON
    object with ``--json``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``ensemble MODEL``.

    Returns
    -------
    int
        The exit status: 0 if every task succeeded, 3 if any failed.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``--config`` is given without ``--cluster`` (or ``--cluster`` without
        ``--config``), or ``--force`` without ``--workers``;
        also, from the validators it calls, a
        bad specification (see :func:`spec_from_args`) or ``--workers``.
    """
    spec = spec_from_args(args)
    if args.config is not None and args.cluster is None:
        raise InvalidArgumentError("config", args.config, "--cluster slurm|pbs with it")
    if args.cluster is not None and args.config is None:  # the option, not the library's None
        raise InvalidArgumentError("cluster", args.cluster,
                                   "--config FILE with it (the batch cluster's TOML file)")
    if args.force and args.workers is None:  # it only lifts the bound on --workers
        raise InvalidArgumentError("force", True, "--workers N with it (--force allows more "
                                   "than 4 x the CPUs as --workers)")
    workers = None if args.workers is None else parse_count(args.workers, "workers", 1)
    check_workers(workers, "workers", force=args.force)
    report = run_ensemble(
        spec, args.out, workers=workers, scheduler=args.scheduler, cluster=args.cluster,
        config=args.config, progress=_progress(args),
        executor="serial" if args.serial else "dask", force=args.force,
    )
    payload = _with_kernels(report.to_json(), get_model(spec.model))
    if args.json:
        emit_json(payload)
    else:
        print(f"ensemble {spec.model}: {report.tasks} tasks, ran {len(report.ran)}, "
              f"skipped {len(report.skipped)} (finished before), "
              f"recomputed {len(report.recomputed)}, failed {len(report.failed)}; "
              f"aggregate in {report.aggregate_path}")
        for failure in report.failed:
            print(f"  failed: {failure['params']} seed {failure['seed']}: {failure['error']}")
        print_means(payload["aggregate"])
    return 3 if report.failed else 0


def print_means(summary: dict) -> None:
    """The aggregate's energy and kurtosis, mean ± standard error over the seeds, one line per
    parameter set and time (what ``--json`` prints in full).

    Parameters
    ----------
    summary : dict
        The aggregate's JSON summary (:func:`particles.ensemble.aggregate`).
    """
    time_name = next(k for k in ("tau", "t") if k in summary)
    for entry in summary["sets"]:
        params = ", ".join(f"{k}={v}" for k, v in entry["params"].items())
        print(f"set {entry['index']}: {params} ({entry['n_seeds']} seeds)")
        if not entry["n_seeds"]:
            continue
        print(f"  {time_name:>10}  {'energy':>25}  {'kurtosis':>25}")
        columns = [entry["observables"].get(name) for name in ("energy", "kurtosis")]
        for i, time in enumerate(summary[time_name]):
            cells = []
            for column in columns:
                if column is None:
                    cells.append(f"{'-':>25}")
                    continue
                sem = column["sem"][i]
                error = "-" if sem is None else f"{sem:.2g}"  # one seed: no standard error
                cells.append(f"{column['mean'][i]:>12.6g} ± {error:<10}")
            print(f"  {time:>10g}  " + "  ".join(cells).rstrip())
