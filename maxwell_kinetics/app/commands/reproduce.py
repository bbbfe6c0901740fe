"""``maxwell-kinetics reproduce``: run every comparison, write PNG figures and ``summary.json``.

    maxwell-kinetics reproduce [--out results] [--full | --small] [--only NAME,...] [--json]
                               [--no-progress] [--workers N]

Every file the run writes into ``--out`` is checked before the first comparison runs
(:func:`maxwell_kinetics.app.reproduce.plan_outputs`), so a bad ``--out``, a directory where a
figure, an ``.npz`` or ``summary.json`` goes, a ``summary.json`` that is not ours or one made
at another size (which ``--only`` would mix with) fails at once with exit status 2, naming
the file, and nothing written.  ``--only`` merges its comparisons into the ``summary.json``
already there.  A write that fails after the work (a full disk) exits with status 3, one
line naming the file; no partial file is left and an existing file stays as it was.

The run ends with the verdict table of the comparisons it ran, one line per claim of the
paper (or of this project) with its status ``agrees``, ``disagrees``, ``explained`` (holds once
a named measurement artefact is removed, shown by an independent check), ``refuted`` (the
paper's claim is false and the run shows its cause) or ``not measured`` (this size does not
resolve it; the table names the size that does) (:mod:`maxwell_kinetics.app.comparisons.verdicts`);
``--json`` carries the verdicts instead.  When a claim that this size resolves fails (a
``disagrees``), the exit status is 3, after every file is written; ``not measured`` and
``refuted`` (a documented finding about the paper, not a failure of the code) exit 0.
"""

from __future__ import annotations

from particles.parsing import parse_count, parse_name_list
from particles.validation import InvalidArgumentError
from particles.workers import check_workers

from .. import cache_options
from ..output import emit_json, progress_enabled

__all__ = ["add_parser", "run", "exit_status"]


def add_parser(subparsers) -> None:
    """Register the ``reproduce`` subcommand and its options.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``add_subparsers()`` object of the top-level parser; the new parser's ``handler``
        default is :func:`run`.
    """
    p = subparsers.add_parser(
        "reproduce", help="reproduce the paper's figures and the kinetic-vs-particle comparisons",
        description="Run every comparison and write <out>/<name>.png, <out>/<name>.npz (data for "
        "Comparison.load) and <out>/summary.json, then print the verdict table: one line per "
        "claim tested, agrees, disagrees, explained (holds once a named measurement artefact "
        "is removed), refuted (the paper's claim is false; the run shows the cause) or not "
        "measured (this size does not resolve it; the table names the size that does).",
        epilog="Exit status: 0 no claim disagrees (agrees, explained, refuted or not measured); "
        "2 bad input (nothing written); 3 a claim that this size resolves disagrees (every "
        "file is written; see the table or --json), or a write failed after the work (one "
        "line naming the file).",
    )
    p.add_argument("--out", default="results", help="output folder (default results/)")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--full", action="store_true", help="the paper's sizes (hours)")
    size.add_argument("--small", action="store_true", help="the tests' size (a minute)")
    p.add_argument("--only", default=None, help="comma-separated comparison names")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object (with the verdicts) instead of the table")
    p.add_argument("--no-progress", action="store_true", help="no progress lines or bars")
    p.add_argument("--workers", default=None,
                   help="run the particle runs on N dask processes through the ensemble engine "
                   "(task files in <out>/runs; --full does this with one process per core); "
                   "at most 4 x the CPUs unless --force")
    p.add_argument("--force", action="store_true",
                   help="allow more than 4 x the CPUs as --workers, and replace the results "
                   "of another size in --out (refused without it)")
    cache_options.add_option(p)
    p.set_defaults(handler=run)


def run(args) -> int:
    """Run ``maxwell-kinetics reproduce`` on parsed arguments.

    Runs the selected comparisons at the chosen size through
    :func:`maxwell_kinetics.app.reproduce.run_all`, which writes a PNG and an ``.npz`` per
    comparison and merges their numbers into ``summary.json`` in ``--out``; prints a one-line
    summary and the verdict table of the comparisons run now (or one JSON object: ``out``,
    ``size``, ``seconds``, ``comparisons`` the names run now, ``in_summary`` every name
    ``summary.json`` holds, ``verdicts`` ``{name: [verdict record]}`` of the comparisons run
    now, ``disagrees`` the number of verdicts with that status and ``statuses`` the count of
    each status).

    Parameters
    ----------
    args : argparse.Namespace
        The options registered by :func:`add_parser`.

    Returns
    -------
    int
        The exit status: 0 on success (every verdict ``agrees``, ``explained``, ``refuted``
        or ``not measured``), 3 when a verdict of the comparisons run is ``disagrees``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``--only`` names a comparison that does not exist, or (from the validators it calls)
        for a bad ``--workers`` (not a count, or above 4 x the CPUs without ``--force``), an
        unusable ``--out`` folder or a file in it that may not be replaced; every output is
        checked before anything runs.  :class:`particles.persistence.WriteError` (exit 3) for
        a write that fails after the work.
    """
    from ..comparisons import COMPARISONS
    from ..comparisons.verdicts import disagreeing, status_counts, verdict_table
    from ..reproduce import plan_outputs, run_all

    only = None
    if args.only is not None:
        only = parse_name_list(args.only, "only")
        bad = [n for n in only if n not in COMPARISONS]
        if bad:
            raise InvalidArgumentError("only", args.only, "names among " + ", ".join(COMPARISONS))
    workers = None if args.workers is None else parse_count(args.workers, "workers", 1)
    check_workers(workers, "workers", force=args.force)
    size = "full" if args.full else "small" if args.small else "default"
    names = list(COMPARISONS) if only is None else only
    plan_outputs(args.out, names, size, "out", force=args.force)  # every output, before any work
    out = args.out
    cache_options.from_args(args)
    summary = run_all(out, size, only, progress=progress_enabled(args), workers=workers,
                      force=args.force)
    ran = {n: summary["comparisons"][n] for n in COMPARISONS if n in names}
    failed = disagreeing(ran)
    if args.json:
        emit_json({"out": str(out), "size": size, "seconds": summary["seconds"],
                   "comparisons": sorted(names), "in_summary": sorted(summary["comparisons"]),
                   "verdicts": {n: s.get("verdicts", []) for n, s in ran.items()},
                   "disagrees": len(failed), "statuses": status_counts(ran)})
    else:
        held = len(summary["comparisons"])
        print(f"wrote {len(names)} comparison{'s' * (len(names) != 1)} (figure and .npz) and "
              f"{out}/summary.json, which holds {held} comparison{'s' * (held != 1)} at size "
              f"{size}, in {summary['seconds']:.0f} s")
        print()
        print(verdict_table(ran))
    return exit_status(ran)


def exit_status(summaries: dict) -> int:
    """The exit status of ``reproduce`` for the summaries of the comparisons run: 3 when a
    verdict disagrees (a claim that this size resolves failed), else 0 (``not measured`` and
    ``refuted`` verdicts do not fail).

    Parameters
    ----------
    summaries : dict
        ``{comparison name: summary}`` with their ``verdicts``.

    Returns
    -------
    int
        0 or 3.
    """
    from ..comparisons.verdicts import disagreeing

    return 3 if disagreeing(summaries) else 0
