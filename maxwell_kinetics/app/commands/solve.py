"""``maxwell-kinetics solve``: integrate the rescaled Fourier-space equation (kinetic theory).

Every input, output paths included, is checked before any work, so bad input writes no file.
Ctrl-C (SIGINT) is deferred for the whole run (:mod:`maxwell_kinetics.interrupt`): the solver
stops at the end of its current chunk of windows, nothing is written, and the command line
prints "interrupted" and exits with status 130.
"""

from __future__ import annotations

import os
import sys

import numpy as np

from particles import persistence
from particles.kernels import ConstantRate
from particles.parsing import parse_float_list, parse_int
from particles.validation import InvalidArgumentError

from ... import interrupt
from ...grid import FORCE, MAX_SOLVE_SECONDS, RESOLUTIONS, format_seconds
from .. import cache_options
from ..output import check_outputs, emit_json, progress_enabled
from .kernel_options import add_kernel_options, chosen_kernel, kernel_from_args
from .kernel_options import solvable as _solvable

#: Seconds per quadrature node of the speed density at one τ (G interpolated there; measured:
#: 36 s for 1.7e7 nodes, 5 speeds, d = 3), and per node and speed (the kernel).
SECONDS_PER_SPEED_NODE = 2e-6
SECONDS_PER_SPEED_NODE_VALUE = 1e-8


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "solve", help="integrate the rescaled Fourier-space equation",
        description="Integrate dG/dτ = λ q G' − G + G(pq) G((1−p)q) from the initial law and "
        "report G at the requested τ and q (and, with --speed, the density of the speed "
        "|v|/v0 in d = 1, 2, 3), with the kurtosis and the even moments read from G near "
        "q = 0.",
    )
    p.add_argument("--restitution", "-r", required=True, help="restitution coefficient r in [0, 1]")
    p.add_argument("--initial", default="gaussian", help="initial law (gaussian, uniform, ...)")
    add_kernel_options(p, _solvable, ConstantRate.name,
                       "a kernel of time tau is solved in Fourier space, one of time t on a "
                       "velocity grid")
    p.add_argument("--tau", default=None,
                   help="a kernel of time tau: comma-separated increasing times, e.g. 10,50,100")
    p.add_argument("--t", default=None,
                   help="a kernel of time t: comma-separated increasing physical times")
    p.add_argument("--density", default=None,
                   help="a kernel of time t: particles per unit length n > 0 (default 1)")
    p.add_argument("--points", default=None,
                   help="a kernel of time t: velocity grid points (default 201, 401 for "
                   "gamma = 0)")
    p.add_argument("--half-width", default=None,
                   help="a kernel of time t: grid half-width in units of the standard "
                   "deviation (default 6, 40 for gamma = 0)")
    p.add_argument("--core-spacing", default=None,
                   help="a kernel of time t: a mapped grid c = a sinh(s), fine in the "
                   "core and wide in the tails: its spacing at c = 0 (below the uniform "
                   "spacing 2 half-width/(points - 1)); with --exponent 0 only, whose "
                   "|x|^-4 tail outgrows a uniform grid")
    p.add_argument("--grid", default=None,
                   help="--kernel hard_spheres or variable_hard_spheres: the spectral grid, "
                   "coarse, default or fine (maxwell_kinetics.sphere_grid.GRIDS)")
    p.add_argument("--q", default="0.5,1,2,5", help="comma-separated q at which to report G")
    p.add_argument("--speed", default=None,
                   help="comma-separated speeds |v|/v0 >= 0 at which to report the density of "
                   "the speed (d-dimensional radial inverse transform of G)")
    p.add_argument("--resolution", default="default", help="one of " + ", ".join(RESOLUTIONS))
    p.add_argument("--dimension", default="1",
                   help="velocity dimension d = 1, 2 or 3 (isotropic inelastic Maxwell model)")
    p.add_argument("--angular", default=None,
                   help="d > 1 only: collision directions uniform on the sphere ('uniform', "
                   "the default) or weighted by |g.n| ('hard')")
    p.add_argument("--angular-rule", default=None,
                   help="d > 1 only: the η quadrature, 'fast' (default; G to ~1e-8) or "
                   "'accurate' (needed for fits of the |q|^{2s*} term, ~2.3x the cost)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE", help="write a PNG: G and |G − f̂| for a kernel of "
                   "time tau, P(x) at every --t for one of time t")
    p.add_argument("--save", metavar="FILE", help="save the solution (.npz; "
                   "maxwell_kinetics.Solution.load, or BoltzmannSolution.load for a kernel of "
                   "time t)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.add_argument("--force", action="store_true",
                   help="run even when the estimated time (the solve and the speed density) "
                   "exceeds one day")
    cache_options.add_option(p)
    p.set_defaults(handler=run)


def run(args) -> int:
    """Run ``maxwell-kinetics solve`` on parsed arguments, with Ctrl-C deferred (module
    docstring): an interrupt raises KeyboardInterrupt from the solver's loop or before any
    file is written, and files written when it arrives during the writing are removed."""
    with interrupt.deferred_sigint():
        written = []
        try:
            return _run(args, written)
        except KeyboardInterrupt:
            for path in written:  # an interrupt while writing: leave no output behind
                try:
                    os.unlink(path)
                except OSError:
                    pass
            raise


#: The command line's option for each argument of :func:`maxwell_kinetics.solver.solve` whose
#: name differs from it.
OPTIONS = {"angular_rule": "angular-rule", "angular_nodes": "angular-nodes"}


def _library_error(exc: InvalidArgumentError, typed: dict) -> InvalidArgumentError:
    """The library's refusal, naming the option as typed (``--angular-rule``, not
    ``angular_rule``), with the text typed when the library saw its parsed value, and
    ``--force`` for ``force=True``."""
    name = OPTIONS.get(exc.name, exc.name)
    value = typed.get(exc.name, (None, exc.value))
    value = value[1] if value[0] is exc.value else exc.value
    return InvalidArgumentError(name, value, exc.expected.replace(FORCE, "--force"))


#: The options of the velocity-space method alone (a kernel of time t).
RELATIVE_VELOCITY_OPTIONS = ("t", "density", "points", "half_width", "core_spacing")


def _run(args, written: list) -> int:
    from ...solver import check_solve_arguments, solve_fourier  # JAX: only when a solve runs
    from .sphere_commands import is_sphere_kernel, run_solve

    cls = chosen_kernel(args, _solvable)
    if is_sphere_kernel(cls):
        return run_solve(args, written)
    if args.grid is not None:
        raise InvalidArgumentError("grid", args.grid, "--grid with --kernel hard_spheres or "
                                   "variable_hard_spheres only (the spectral hard-sphere grid)")
    if not cls.fourier_closed:
        return _run_relative_velocity(args, written)
    kernel_from_args(args, _solvable, 0.0)  # a parameter of another kernel, refused by name
    for name in RELATIVE_VELOCITY_OPTIONS:
        if getattr(args, name) is not None:
            option = name.replace("_", "-")
            raise InvalidArgumentError(option, getattr(args, name),
                                       f"no --{option} with --kernel {cls.name} (it belongs "
                                       "to the kernels of time t, solved on a velocity grid)")
    if args.tau is None:
        raise InvalidArgumentError("tau", None, f"--tau T1,T2,... with --kernel {cls.name}")
    tau = parse_float_list(args.tau, "tau")
    dimension = parse_int(args.dimension, "dimension")
    for option, value in (("angular", args.angular), ("angular-rule", args.angular_rule)):
        if value is not None and dimension == 1:  # d = 1 has η ≡ 1: the option would do nothing
            raise InvalidArgumentError(option, value, "--dimension 2 or 3 with it (d = 1 has "
                                       "a single collision direction)")
    arguments = {"restitution": args.restitution, "initial": args.initial, "tau": tau,
                 "resolution": args.resolution, "dimension": dimension,
                 "angular": args.angular or "uniform",
                 "angular_rule": args.angular_rule or "fast", "force": args.force}
    typed = {"tau": (tau, args.tau), "dimension": (dimension, args.dimension)}
    try:  # the library's checks (the solve-time budget included), before anything is written
        checked = check_solve_arguments(**arguments)
    except InvalidArgumentError as exc:
        raise _library_error(exc, typed) from None
    model, law, taus, grid = checked.model, checked.law, checked.tau, checked.grid
    angular, cost = checked.angular, checked.estimate
    q = np.asarray(parse_float_list(args.q, "q"))
    if np.any(~np.isfinite(q)) or np.any(np.abs(q) > grid.q_max):
        raise InvalidArgumentError(
            "q", args.q, f"values with |q| <= q_max={grid.q_max:.6g} of resolution {grid.name!r}"
        )
    if len(np.unique(q)) < q.size:  # 1,1.0 or 0,-0: the same q twice
        raise InvalidArgumentError("q", args.q, "distinct values of q")
    speeds = None
    if args.speed is not None:
        speeds = np.asarray(parse_float_list(args.speed, "speed"))
        if np.any(~np.isfinite(speeds)) or np.any(speeds < 0):
            raise InvalidArgumentError("speed", args.speed, "finite speeds |v|/v0 >= 0")
        if len(np.unique(speeds)) < speeds.size:  # 1,1.0 or 0,-0: the same speed twice
            raise InvalidArgumentError("speed", args.speed, "distinct speeds")
        from ...velocity import check_quadrature  # refuse a transform too large, before the solve

        speed_nodes = check_quadrature(grid.q_max, speeds, "speed", radial=True,
                                       shown=args.speed)
    check_outputs(save=args.save, images={"plot": args.plot})
    if speeds is not None:  # the speed density at every τ: its quadrature costs too
        speed_seconds = len(taus) * speed_nodes * (SECONDS_PER_SPEED_NODE
                                                   + speeds.size * SECONDS_PER_SPEED_NODE_VALUE)
        cost = {**cost, "seconds": cost["seconds"] + speed_seconds}
        if not args.force and not cost["seconds"] <= MAX_SOLVE_SECONDS:
            raise InvalidArgumentError(
                "speed", args.speed,
                f"a solve estimated to take at most {format_seconds(MAX_SOLVE_SECONDS)} (the "
                f"speed density at {len(taus)} times on {speed_nodes:.3g} quadrature nodes: "
                f"about {format_seconds(speed_seconds)}); fewer or smaller speeds or times, or "
                "pass --force to run it anyway")
    cache_options.from_args(args)
    try:
        arguments["tau"] = taus
        sol = solve_fourier(**arguments, progress=progress_enabled(args))
    except InvalidArgumentError as exc:  # checked above: kept for the option names
        raise _library_error(exc, typed) from None
    seconds = sol.seconds
    # The distance to f̂ is defined in d = 1 only (f̂ is the 1D scaling solution): null for d > 1.
    sup = sol.sup_error() if dimension == 1 else None
    values = np.array([sol.evaluate(q, k) for k in range(len(taus))])
    moments = sol.moments(orders=(2, 4, 6))
    kurtosis = moments.kurtosis()
    speed_density = None
    if speeds is not None:
        speed_density = np.array([sol.speed_density(speeds, k)[1] for k in range(len(taus))])
    interrupt.check()  # a Ctrl-C since the solve: write nothing
    if args.plot:
        from ...figures import plot_solution

        figure = plot_solution(sol)
        interrupt.check()
        written.append(args.plot)
        persistence.save_figure(figure, args.plot, "plot", dpi=120)
    if args.save:
        written.append(args.save)
        sol.save(args.save)
    interrupt.check()  # a Ctrl-C while writing: the files are removed
    if args.json:
        extra = {}
        if speeds is not None:
            extra = {"speed": speeds.tolist(), "speed_density": speed_density.tolist()}
        emit_json({
            "restitution": model.restitution,
            "dimension": dimension,
            "angular": angular if dimension > 1 else None,  # d = 1 has no angles (η ≡ 1)
            "angular_rule": sol.angular_rule if dimension > 1 else None,
            "initial": law.name,
            "resolution": grid.name,
            "tau": taus.tolist(),
            "sup_error": None if sup is None else sup.tolist(),
            "kurtosis": [float(k) if np.isfinite(k) else None for k in kurtosis],
            "moments": moments.to_dict(),
            "q": q.tolist(),
            "G_real": values.real.tolist(),
            "G_imag": values.imag.tolist(),
            **extra,
            "seconds": seconds,
            "estimate_seconds": cost["seconds"],
        })
    else:
        print(f"r = {model.restitution:g}, initial {law.name}, resolution {grid.name} "
              f"({grid.n} points), {seconds:.2f} s")
        if sup is not None:
            for tau, err, kurt in zip(taus, sup, kurtosis, strict=True):
                print(f"  tau = {tau:<10g} sup_q |G - f_hat| = {err:.3e}   kurtosis {kurt:.10g}")
        else:
            print(f"  dimension {dimension} ({angular}): no distance to f_hat "
                  "(the one-dimensional scaling solution)")
            for tau, kurt in zip(taus, kurtosis, strict=True):
                print(f"  tau = {tau:<10g} kurtosis <|v|^4>/<|v|^2>^2 = {kurt:.10g}")
        if speeds is not None:
            print("  speed density P(s) at s = " + ", ".join(f"{v:g}" for v in speeds))
            for tau, row in zip(taus, speed_density, strict=True):
                print(f"  tau = {tau:<10g} " + " ".join(f"{v:.6e}" for v in row))
    return 0




def _run_relative_velocity(args, written: list) -> int:
    """``solve --kernel NAME`` for a kernel of time t: the velocity-space method
    (:class:`maxwell_kinetics.methods.VelocitySpace`), every input checked before the solve."""
    from particles.parsing import parse_int
    from particles.validation import check_real

    from ...inelastic_boltzmann import estimate_seconds
    from ...methods import VelocitySpace
    from ...solver import solve
    from ...velocity_grid import MappedGrid, VelocityGrid, default_grid, initial_values

    name = args.kernel
    if args.tau is not None:
        raise InvalidArgumentError("tau", args.tau, f"--t T1,T2,... with --kernel {name} "
                                   "(its time is the physical time t, not collisions per "
                                   "particle)")
    for dest in ("q", "speed", "angular", "angular_rule"):
        value = getattr(args, dest)
        default = {"q": "0.5,1,2,5"}.get(dest)
        if value is not None and value != default:
            option = dest.replace("_", "-")
            raise InvalidArgumentError(option, value, f"no --{option} with --kernel "
                                       f"{name} (a Fourier-solver option)")
    if args.resolution != "default" or args.dimension != "1":
        option, value = (("resolution", args.resolution) if args.resolution != "default"
                         else ("dimension", args.dimension))
        raise InvalidArgumentError(option, value, f"no --{option} with --kernel {name} "
                                   "(one dimension; the grid is --points and --half-width)")
    if args.t is None:
        raise InvalidArgumentError("t", None, f"--t T1,T2,... with --kernel {name}")
    times = parse_float_list(args.t, "t")
    # Every number is read from its text as typed, by the rules of every other option
    # (particles.validation.check_real: no digit-group underscores, no non-zero number that
    # reads as 0); the library's refusals below show that text, not the value read.
    typed: dict[str, tuple[float, str]] = {}

    def number(name: str) -> float:
        text = getattr(args, name)
        value = check_real(text, name.replace("_", "-"))
        typed[name] = (value, text)
        return value

    density = 1.0 if args.density is None else number("density")
    if not density > 0:
        raise InvalidArgumentError("density", args.density, "a finite density n > 0")
    restitution = number("restitution")
    try:
        kernel = kernel_from_args(args, _solvable, restitution, typed)
        gamma = float(kernel.homogeneity)
        grid = default_grid(gamma)
        points = grid.points if args.points is None else parse_int(args.points, "points")
        half_width = grid.half_width if args.half_width is None else number("half_width")
        core = None if args.core_spacing is None else number("core_spacing")
        if core is not None and gamma != 0.0:
            raise InvalidArgumentError("core-spacing", args.core_spacing,
                                       "--core-spacing (a mapped grid) with a rate of degree "
                                       f"gamma = 0 only (here gamma = {gamma:g}: use the "
                                       "uniform grid)")
        grid = (VelocityGrid(points, half_width) if core is None
                else MappedGrid(points, half_width, core))
        initial_values(args.initial, grid)  # the grid against the law, before the solve
    except InvalidArgumentError as exc:
        raise _typed_error(exc, typed) from None
    typed["t"] = (times[-1], args.t)  # the reach check names the last time
    check_outputs(save=args.save, images={"plot": args.plot})
    cost = estimate_seconds(kernel, grid, density, float(times[-1]))
    if cost is not None and cost > 60.0 and not args.json:
        print(f"maxwell-kinetics solve: estimated ~{format_seconds(cost)} (Ctrl-C stops it)",
              file=sys.stderr)
    cache_options.from_args(args)  # the store of compiled executables, unless --no-cache
    try:
        sol = solve(kernel, args.initial, times, VelocitySpace(grid=grid), density=density,
                    force=args.force)
    except InvalidArgumentError as exc:
        raise _typed_error(exc, typed) from None
    interrupt.check()
    if args.plot:  # the result contract's plot: P(x, t) at every saved t
        import matplotlib.figure

        figure = matplotlib.figure.Figure(figsize=(6.4, 4.4))
        sol.plot(figure.add_subplot())
        interrupt.check()
        written.append(args.plot)
        persistence.save_figure(figure, args.plot, "plot", dpi=120)
    if args.save:
        written.append(args.save)
        sol.save(args.save)
    interrupt.check()  # a Ctrl-C while writing: the files are removed
    kurtosis = sol.kurtosis
    if args.json:
        emit_json({
            "rate": kernel.name,
            "kernel": kernel.to_dict(),
            "restitution": kernel.restitution,
            "exponent": gamma,
            "density": density,
            "initial": sol.initial,
            "points": grid.points,
            "half_width": grid.half_width,
            "core_spacing": None if core is None else grid.core_spacing,
            "t": sol.t.tolist(),
            "energy": sol.energy.tolist(),
            "kurtosis": kurtosis.tolist(),
            "moments": {str(k): col.tolist()
                        for k, col in zip((2, 4, 6), sol.moments((2, 4, 6)).raw().T,
                                          strict=True)},
            "edge_mass": sol.edge_mass.tolist(),
            "seconds": sol.seconds,
        })
        return 0
    print(f"r = {kernel.restitution:g}, kernel {kernel.name}, rate of degree {gamma:g} in "
          f"|v - w|, n = {density:g}, "
          f"initial {sol.initial}, grid {grid.points} points on +-{grid.half_width:g}"
          + ("" if core is None else f" (mapped, core spacing {grid.core_spacing:g})")
          + f", {sol.seconds:.2f} s")
    for t, energy, kurt in zip(sol.t, sol.energy, kurtosis, strict=True):
        print(f"  t = {t:<10g} <v^2> = {energy:.10g}   kurtosis {kurt:.10g}")
    return 0


def _typed_error(exc: InvalidArgumentError, typed: dict) -> InvalidArgumentError:
    """The library's refusal of a velocity-space solve's input, naming the option as
    typed (``half-width``, not ``half_width``) and showing the text typed when the library saw
    the value read from it (``typed``: name -> (value read, text))."""
    name = {"half_width": "half-width", "core_spacing": "core-spacing"}.get(exc.name, exc.name)
    value = exc.value
    read = typed.get(exc.name, typed.get(name.replace("-", "_")))
    if read is not None and isinstance(value, float) and value == read[0]:
        value = read[1]
    return InvalidArgumentError(name, value, exc.expected.replace(
        "half_width >=", "--half-width >=").replace(FORCE, "--force"))
