"""``maxwell-kinetics convergence``: the solver's error floor against resolution.

Writes ``convergence.json`` and ``convergence.png`` into ``--out``; both are checked before the
first solve (:func:`plan_outputs`): a directory in their place, a name too long, or a file
there that this program did not write is refused with exit status 2, naming it, and nothing is
written.  A write that fails after the work (a full disk) exits with status 3, one line naming
the file; an existing file stays as it was.
"""

from __future__ import annotations

import json
from pathlib import Path

from particles.parsing import parse_float_list, parse_name_list
from particles.validation import InvalidArgumentError, check_positive, check_restitution

from ...grid import RESOLUTIONS, check_solve_budget, get_resolution
from .. import cache_options
from ..output import (
    check_files_in,
    check_output_dir,
    emit_json,
    is_png,
    progress_enabled,
    read_json_file,
)

#: The files the command writes into ``--out``.
JSON_NAME, FIGURE_NAME = "convergence.json", "convergence.png"


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "convergence", help="error floor against resolution (figure and JSON)",
        description="Integrate from the unit Gaussian to --tau-max at each resolution and "
        "record sup_q |G − f̂|; write convergence.json and convergence.png.",
    )
    _convergence_options(p)
    p.set_defaults(handler=run)


def _convergence_options(p) -> None:
    p.add_argument("--restitution", default="0,0.5", help="comma-separated r values")
    p.add_argument("--resolutions", default=",".join(RESOLUTIONS), help="comma-separated names")
    p.add_argument("--tau-max", type=float, default=1e4, help="final τ (default 1e4)")
    p.add_argument("--out", default="results", help="output folder (default results/)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    p.add_argument("--force", action="store_true",
                   help="run even when the estimated time exceeds one day")
    cache_options.add_option(p)


def run(args) -> int:
    from ..convergence import convergence_study  # JAX: imported only when it runs

    rs = [check_restitution(r) for r in parse_float_list(args.restitution, "restitution")]
    names = [get_resolution(n).name for n in parse_name_list(args.resolutions, "resolutions")]
    tau_max = check_positive(args.tau_max, "tau-max")
    if tau_max < 10:
        raise InvalidArgumentError("tau-max", args.tau_max, "a final time >= 10")
    plan_outputs(args.out, "out")
    for name in names:
        check_solve_budget(get_resolution(name), tau_max, 64, name="tau-max", force=args.force)
    cache_options.from_args(args)
    runs = convergence_study(rs, names, tau_max, progress=progress_enabled(args))
    summary = write_results(runs, args.out)
    if args.json:
        emit_json(
            {"out": str(args.out), "table": summary["table"], "order_fit": summary["order_fit"]}
        )
    else:
        print(f"{'r':>5} {'resolution':>10} {'h':>8} {'floor':>10} {'stable':>7} {'seconds':>8}")
        for row in summary["table"]:
            print(f"{row['restitution']:>5g} {row['resolution']:>10} {row['h']:>8g} "
                  f"{row['floor']:>10.2e} {row['stable']!s:>7} {row['seconds']:>8.1f}")
        print("fitted order (slope of log floor vs log h):", summary["order_fit"])
        print(f"wrote {Path(args.out) / 'convergence.json'} and convergence.png")
    return 0


def _is_convergence_json(path) -> str | None:
    """Why ``path`` is not a ``convergence.json`` of this command (``None`` if it is one)."""
    try:
        summary = read_json_file(path)
    except ValueError as exc:
        return str(exc)
    if not (isinstance(summary, dict) and {"runs", "table", "order_fit"} <= set(summary)):
        return "it is not a JSON object with 'runs', 'table' and 'order_fit'"
    return None


def plan_outputs(out_dir, argument: str = "out") -> dict:
    """Check, before any work and writing nothing, the folder and the two files
    :func:`write_results` writes: the folder usable, each file a name the file system takes,
    a regular file or nothing, and an existing one written by this command (a
    ``convergence.json`` with ``runs``, ``table`` and ``order_fit``; a PNG image).

    Parameters
    ----------
    out_dir : str or os.PathLike
        The output folder (it need not exist yet).
    argument : str, optional
        The folder's argument name for error messages (default ``"out"``).

    Returns
    -------
    dict
        ``{file name: pathlib.Path}`` of the two files.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument`` and the path in the way.
    """
    out = check_output_dir(out_dir, argument)
    return check_files_in(out, {JSON_NAME: _is_convergence_json, FIGURE_NAME: is_png}, argument)


def write_results(runs, out_dir) -> dict:
    """Write ``convergence.json`` and ``convergence.png`` into ``out_dir`` (created if needed,
    after :func:`plan_outputs` checked both files); return the summary
    (:func:`maxwell_kinetics.app.convergence.summarize`).

    Parameters
    ----------
    runs : list of maxwell_kinetics.app.convergence.ConvergenceRun
        The runs of the study.
    out_dir : str or os.PathLike
        The output folder.

    Returns
    -------
    dict
        The summary written to ``convergence.json``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From :func:`plan_outputs` (naming ``out``); :class:`particles.persistence.WriteError`
        when a write fails (a full disk), the file that was there left as it was.
    """
    import matplotlib.pyplot as plt

    from particles import persistence

    from ..convergence import summarize
    from ..plotting import plot_convergence
    from ..reproduce import prepare_output

    paths = plan_outputs(out_dir, "out")
    prepare_output(out_dir, "out")
    summary = summarize(runs)
    persistence.write_text(paths[JSON_NAME], json.dumps(summary, indent=1), "out")
    fig = plot_convergence(runs)
    try:
        persistence.save_figure(fig, paths[FIGURE_NAME], "out", dpi=120)
    finally:
        plt.close(fig)
    return summary
