"""Kinetic-theory subcommands of the command line (``solve``, ``fixed-point``, ``convergence``).

Every handler validates all of its input before computing or writing anything, so bad input
writes no file.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from particles.validation import InvalidArgumentError, parse_float_list


def register(subparsers) -> None:
    """Add the kinetic-theory subcommands."""
    _add_solve(subparsers)
    _register_fixed_point(subparsers)
    _add_convergence(subparsers)
    from .reproduce import register as _register_reproduce

    _register_reproduce(subparsers)


# -- solve --------------------------------------------------------------------------------
def _add_solve(subparsers) -> None:
    from .grid import RESOLUTIONS

    p = subparsers.add_parser(
        "solve", help="integrate the rescaled Fourier-space equation",
        description="Integrate dG/dτ = λ q G' − G + G(pq) G((1−p)q) from the initial law and "
        "report G at the requested τ and q.",
    )
    p.add_argument("--restitution", "-r", required=True, help="restitution coefficient r in [0, 1]")
    p.add_argument("--initial", default="gaussian", help="initial law (gaussian, uniform, ...)")
    p.add_argument("--tau", required=True, help="comma-separated increasing times, e.g. 10,50,100")
    p.add_argument("--q", default="0.5,1,2,5", help="comma-separated q at which to report G")
    p.add_argument("--resolution", default="default", help="one of " + ", ".join(RESOLUTIONS))
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE", help="write a PNG of G and |G − f̂|")
    p.add_argument("--save", metavar="FILE", help="save the Solution (.npz)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.set_defaults(handler=_run_solve)


def _run_solve(args) -> int:
    from particles.initial import get_law
    from particles.validation import check_output_file, check_times

    from .cli import emit_json
    from .grid import get_resolution
    from .model import MaxwellModel

    model = MaxwellModel(args.restitution)
    law = get_law(args.initial)
    try:
        taus = check_times(parse_float_list(args.tau, "tau"), "tau")
    except InvalidArgumentError as exc:  # show the text received, not the parsed list
        raise InvalidArgumentError("tau", args.tau, exc.expected) from None
    grid = get_resolution(args.resolution)
    q = np.asarray(parse_float_list(args.q, "q"))
    if np.any(~np.isfinite(q)) or np.any(np.abs(q) > grid.q_max):
        raise InvalidArgumentError(
            "q", args.q, f"values with |q| <= q_max={grid.q_max:.6g} of resolution {grid.name!r}"
        )
    outputs = {name: check_output_file(path, name)
               for name, path in (("plot", args.plot), ("save", args.save)) if path is not None}
    if len(outputs) == 2 and outputs["plot"].resolve() == outputs["save"].resolve():
        raise InvalidArgumentError("save", args.save, "a different file from --plot")

    from .solver import solve

    start = time.perf_counter()
    sol = solve(model.restitution, law, taus, grid, progress=not args.no_progress and not args.json)
    seconds = time.perf_counter() - start
    sup = sol.sup_error()
    values = np.array([sol.evaluate(q, k) for k in range(len(taus))])
    if args.plot:
        from .plotting import plot_solution

        plot_solution(sol).savefig(args.plot, dpi=120)
    if args.save:
        sol.save(args.save)
    if args.json:
        emit_json({
            "restitution": model.restitution,
            "initial": law.name,
            "resolution": grid.name,
            "tau": taus.tolist(),
            "sup_error": sup.tolist(),
            "q": q.tolist(),
            "G_real": values.real.tolist(),
            "G_imag": values.imag.tolist(),
            "seconds": seconds,
        })
    else:
        print(f"r = {model.restitution:g}, initial {law.name}, resolution {grid.name} "
              f"({grid.n} points), {seconds:.2f} s")
        for tau, err in zip(taus, sup, strict=True):
            print(f"  tau = {tau:<10g} sup_q |G - f_hat| = {err:.3e}")
    return 0


# -- fixed-point ------------------------------------------------------------------------------


def _register_fixed_point(subparsers) -> None:
    p = subparsers.add_parser(
        "fixed-point",
        help="solve the stationary rescaled equation directly and compute linear decay rates",
        description="Solve λ q G' − G + G(pq) G((1−p)q) = 0 with G(0) = 1, G''(0) = −1 by "
        "Chebyshev collocation and Gauss–Newton, report the max error to f̂ = (1+q)e^{−q}, and "
        "the slowest decay rates of the equation linearised around f̂ next to γ(s).",
    )
    p.add_argument("--restitution", "-r", required=True, help="restitution r in [0, 1)")
    p.add_argument("--n", type=int, default=64, help="Chebyshev degree of the fixed point")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=_fixed_point)


def _fixed_point(args) -> int:
    import time

    from particles.validation import check_count

    from .cli import emit_json
    from .stationary import fixed_point, linear_decay_rates

    start = time.perf_counter()
    n = check_count(args.n, "n", 8)
    fp = fixed_point(args.restitution, n=n)
    rates = linear_decay_rates(fp.restitution)
    payload = {
        "restitution": fp.restitution,
        "max_error": fp.max_error,
        "residual": fp.residual,
        "iterations": fp.iterations,
        "decay_rates": list(rates.rates),
        "gamma": {str(s): g for s, g in rates.gamma.items()},
        "gamma_star": rates.gamma_star,
        "s_star": rates.s_star,
        "q_min": rates.q_min,
        "seconds": time.perf_counter() - start,
    }
    if args.json:
        emit_json(payload)
        return 0
    print(f"fixed point, r = {fp.restitution:g}: Chebyshev n = {fp.n} on [0, {fp.q_max:g}]")
    print(f"  max |G - f_hat| = {fp.max_error:.3e}   residual = {fp.residual:.3e}   "
          f"Gauss-Newton iterations = {fp.iterations}")
    print(f"  slowest linear decay rates (q >= q_min = {rates.q_min:.3g}): "
          + ", ".join(f"{x:.6g}" for x in rates.rates))
    print(f"  max gamma(s) on (2, 3) = {rates.gamma_star:.6g} at s* = {rates.s_star:.4f}; "
          + ", ".join(f"gamma({s}) = {g:.6g}" for s, g in rates.gamma.items()))
    print(f"  ({payload['seconds']:.2f} s)")
    return 0


# -- convergence --------------------------------------------------------------------------
def _add_convergence(subparsers) -> None:
    p = subparsers.add_parser(
        "convergence", help="error floor against resolution (figure and JSON)",
        description="Integrate from the unit Gaussian to --tau-max at each resolution and "
        "record sup_q |G − f̂|; write convergence.json and convergence.png.",
    )
    _convergence_options(p)
    p.set_defaults(handler=_run_convergence)


def _convergence_options(p) -> None:
    from .grid import RESOLUTIONS

    p.add_argument("--restitution", default="0,0.5", help="comma-separated r values")
    p.add_argument("--resolutions", default=",".join(RESOLUTIONS), help="comma-separated names")
    p.add_argument("--tau-max", type=float, default=1e4, help="final τ (default 1e4)")
    p.add_argument("--out", default="results", help="output folder (default results/)")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _run_convergence(args) -> int:
    from particles.validation import check_output_dir, check_positive, check_restitution

    from .cli import emit_json
    from .convergence import convergence_study, write_results
    from .grid import get_resolution

    rs = [check_restitution(r) for r in parse_float_list(args.restitution, "restitution")]
    names = [get_resolution(n.strip()).name for n in args.resolutions.split(",") if n.strip()]
    tau_max = check_positive(args.tau_max, "tau-max")
    if tau_max < 10:
        raise InvalidArgumentError("tau-max", args.tau_max, "a final time >= 10")
    check_output_dir(args.out, "out")
    runs = convergence_study(rs, names, tau_max, progress=not args.json)
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
