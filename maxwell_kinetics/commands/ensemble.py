"""``maxwell-kinetics ensemble MODEL``: many runs of a particle model on dask (issue 16).

    maxwell-kinetics ensemble MODEL [the options of simulate MODEL] --seeds 1-16
        [--workers N | --scheduler ADDRESS | --cluster slurm|pbs --config FILE | --serial]
        --out DIR [--json] [--no-progress]

Models: ``ulam``, ``lattice``, ``md``, ``sticky``.  A parameter given as a comma list
(``--restitution 0.3,0.5,0.9``) is swept; ``--seeds`` takes ranges and lists (``1-16,20``).
Each task writes its result to its own file in ``--out`` (named by a hash of the model, the
parameters, the seed, the times and the format version); a rerun skips the finished tasks, so an
interrupted ensemble resumes where it stopped.  The aggregate (mean and standard error over
seeds per parameter set) is saved as ``<out>/ensemble.npz`` and printed with ``--json``.

Exit status: 0 all tasks finished; 3 some task failed (listed with its parameters); 2 bad input
(nothing written; an unreachable ``--scheduler`` fails after 10 s); 130 interrupted.
"""

from __future__ import annotations

from particles.ensemble import EnsembleSpec, parse_seeds, run_ensemble
from particles.validation import (
    InvalidArgumentError,
    check_times,
    check_workers,
    parse_count,
    parse_float_list,
    parse_name_list,
)

from ..output import emit_json, progress_enabled

__all__ = ["add_parser", "run"]

#: Per model: (option, parameter, kind) where kind is "int", "float", "name" or "flag".
_OPTIONS = {
    "ulam": [("--n", "n", "int"), ("--restitution", "restitution", "float"),
             ("--initial", "initial", "name")],
    "lattice": [("--n", "n", "int"), ("--restitution", "restitution", "float"),
                ("--initial", "initial", "name"), ("--no-constraint", "constraint", "flag")],
    "md": [("--n", "n", "int"), ("--density", "density", "float"),
           ("--restitution", "restitution", "float"), ("--delta", "delta", "float"),
           ("--rod-length", "rod_length", "float"), ("--initial", "initial", "name"),
           ("--method", "method", "name")],
    "sticky": [("--n", "n", "int"), ("--density", "density", "float"),
               ("--initial", "initial", "name")],
}
_REQUIRED = {"n", "restitution", "density"}
_TIME = {"ulam": "--tau", "lattice": "--tau", "md": "--t", "sticky": "--t"}


def add_parser(subparsers) -> None:
    ensemble = subparsers.add_parser(
        "ensemble", help="many seeds and a parameter sweep of a particle model, on dask",
        description=__doc__.split("\n\n", 1)[1],
    )
    models = ensemble.add_subparsers(dest="model", required=True)
    for model, options in _OPTIONS.items():
        p = models.add_parser(model, help=f"an ensemble of simulate {model}")
        for option, name, kind in options:
            if kind == "flag":
                p.add_argument(option, action="store_true", help="as in simulate " + model)
            else:
                p.add_argument(option, dest=name, required=name in _REQUIRED,
                               default=None, help="a value or a comma list (swept)")
        p.add_argument(_TIME[model], dest="times", required=True, metavar="T1,T2,...",
                       help="increasing, non-negative times at which to record")
        p.add_argument("--seeds", required=True, help="seeds: ranges and lists, e.g. 1-16,20")
        p.add_argument("--structure-factor", action="store_true",
                       help="also record S(k) at the last time")
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
        p.add_argument("--json", action="store_true", help="print one JSON object")
        p.add_argument("--no-progress", action="store_true", help="no progress bar or lines")
        p.set_defaults(handler=run)


def _values(text: str, name: str, kind: str) -> list:
    if kind == "int":
        return [parse_count(part, name, 2) for part in parse_name_list(text, name)]
    if kind == "float":
        values = parse_float_list(text, name)
        if len(set(values)) != len(values):
            raise InvalidArgumentError(name, text, "a list without repeats")
        return values
    return parse_name_list(text, name)


def spec_from_args(args) -> EnsembleSpec:
    """The :class:`EnsembleSpec` of the command line (checked: nothing runs if it is bad)."""
    params = {}
    for option, name, kind in _OPTIONS[args.model]:
        value = getattr(args, name if kind != "flag" else option.lstrip("-").replace("-", "_"))
        if kind == "flag":
            if value:
                params[name] = False  # --no-constraint
            continue
        if value is not None:
            values = _values(value, name, kind)
            params[name] = values if len(values) > 1 else values[0]
    time_name = _TIME[args.model].lstrip("-")
    times = check_times(parse_float_list(args.times, time_name), time_name)
    options = {"structure_factor": "last"} if args.structure_factor else {}
    return EnsembleSpec(args.model, params, parse_seeds(args.seeds), tuple(times), options)


def run(args) -> int:
    spec = spec_from_args(args)
    if args.config is not None and args.cluster is None:
        raise InvalidArgumentError("config", args.config, "--cluster slurm|pbs with it")
    workers = None if args.workers is None else parse_count(args.workers, "workers", 1)
    check_workers(workers, "workers", force=args.force)
    report = run_ensemble(
        spec, args.out, workers=workers, scheduler=args.scheduler, cluster=args.cluster,
        config=args.config, progress=progress_enabled(args),
        executor="serial" if args.serial else "dask", force=args.force,
    )
    payload = report.to_json()
    if args.json:
        emit_json(payload)
    else:
        print(f"ensemble {spec.model}: {len(spec.expand())} tasks, ran {len(report.ran)}, "
              f"skipped {len(report.skipped)} (finished before), "
              f"recomputed {len(report.recomputed)}, failed {len(report.failed)}; "
              f"aggregate in {report.aggregate_path}")
        for failure in report.failed:
            print(f"  failed: {failure['params']} seed {failure['seed']}: {failure['error']}")
    return 3 if report.failed else 0
