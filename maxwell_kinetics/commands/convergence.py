"""``maxwell-kinetics convergence``: the solver's error floor against resolution."""

from __future__ import annotations

from pathlib import Path

from particles.validation import (
    InvalidArgumentError,
    check_output_dir,
    check_positive,
    check_restitution,
    parse_float_list,
    parse_name_list,
)

from .. import compile_cache
from ..grid import RESOLUTIONS, check_solve_budget, get_resolution
from ..output import emit_json, progress_enabled


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
    compile_cache.add_option(p)


def run(args) -> int:
    from ..convergence import convergence_study  # JAX: imported only when it runs

    rs = [check_restitution(r) for r in parse_float_list(args.restitution, "restitution")]
    names = [get_resolution(n).name for n in parse_name_list(args.resolutions, "resolutions")]
    tau_max = check_positive(args.tau_max, "tau-max")
    if tau_max < 10:
        raise InvalidArgumentError("tau-max", args.tau_max, "a final time >= 10")
    check_output_dir(args.out, "out")
    for name in names:
        check_solve_budget(get_resolution(name), tau_max, 64, name="tau-max", force=args.force)
    compile_cache.from_args(args)
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


def write_results(runs, out_dir) -> dict:
    """Write ``convergence.json`` and ``convergence.png`` into ``out_dir``; return the summary
    (:func:`maxwell_kinetics.convergence.summarize`)."""
    import json
    from pathlib import Path

    from particles import persistence

    from ..convergence import summarize
    from ..plotting import plot_convergence

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = summarize(runs)
    persistence.write_text(out / "convergence.json", json.dumps(summary, indent=1), "out")
    persistence.save_figure(plot_convergence(runs), out / "convergence.png", "out", dpi=120)
    return summary
