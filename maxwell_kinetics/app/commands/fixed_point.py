"""``maxwell-kinetics fixed-point``: the stationary rescaled equation by Newton's method, and the
linear decay rates around it."""

from __future__ import annotations

import sys
import time

from particles.kernels import ConstantRate
from particles.parsing import parse_count
from particles.validation import InvalidArgumentError

from .. import cache_options
from ..output import emit_json
from .kernel_options import add_kernel_options, chosen_kernel, kernel_from_args
from .kernel_options import solvable as _solvable

#: Dense matrices of the Chebyshev collocation: about 12 of (n + 1)² doubles at once.
_MATRICES = 12


def check_fixed_point_budget(n: int) -> None:
    """Refuse a Chebyshev degree whose dense operators cannot fit in the memory available."""
    from particles.budget import available_memory, format_bytes

    need = _MATRICES * 8.0 * (n + 1) ** 2
    available = available_memory()
    if not need <= available:
        raise InvalidArgumentError(
            "n", n, f"a degree whose dense operators fit in the {format_bytes(available)} "
            f"available (estimate {format_bytes(need)})",
        )

#: Largest residual max_j |R[G](q_j)| of a converged fixed point (converged solves reach ~1e-15).
RESIDUAL_TOLERANCE = 1e-8


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "fixed-point",
        help="solve the stationary rescaled equation directly and compute linear decay rates",
        description="Solve λ q G' − G + G(pq) G((1−p)q) = 0 with G(0) = 1, G''(0) = −1 by "
        "Chebyshev collocation and Gauss–Newton, report the max error to f̂ = (1+q)e^{−q}, and "
        "the slowest decay rates of the equation linearised around f̂ next to γ(s).  With "
        "--dimension 2 or 3: the stationary isotropic equation (η-averaged gain); no closed "
        "form and no decay rates there.",
    )
    p.add_argument("--restitution", "-r", required=True, help="restitution r in [0, 1)")
    add_kernel_options(p, _solvable, ConstantRate.name,
                       "a kernel of time tau: the Fourier-space fixed point; one of time t: "
                       "the scaling state in velocity space, its kurtosis, <c^6> and P(c)")
    p.add_argument("--points", default=None,
                   help="a kernel of time t: velocity grid points (default 241)")
    p.add_argument("--half-width", default=None,
                   help="a kernel of time t: grid half-width in units of the standard "
                   "deviation (default 12)")
    p.add_argument("--grid", default=None,
                   help="--kernel hard_spheres or variable_hard_spheres (--dimension 2 or 3): "
                   "the spectral grid of the cooling state, coarse, default or fine")
    p.add_argument("--n", default=None, help="Chebyshev degree (default 64 in 1D, 128 in 2D/3D; "
                   "at most 256 in 1D, where a larger degree is ill-conditioned)")
    p.add_argument("--dimension", default="1",
                   help="velocity dimension d in {1, 2, 3} (d >= 2: the isotropic model)")
    p.add_argument("--angular", default=None,
                   help="angular model, only with --dimension 2 or 3: uniform (default) or hard")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--force", action="store_true",
                   help="run even when the Gauss-Newton solve (with a kernel of time t: the "
                   "relaxation before it) is estimated to take more than one day")
    cache_options.add_option(p)
    p.set_defaults(handler=run)




def run(args) -> int:
    from .sphere_commands import is_sphere_kernel, run_fixed_point

    cls = chosen_kernel(args, _solvable)
    if is_sphere_kernel(cls):
        return run_fixed_point(args)
    if args.grid is not None:
        raise InvalidArgumentError("grid", args.grid, "--grid with --kernel hard_spheres or "
                                   "variable_hard_spheres only (the spectral hard-sphere grid)")
    if not cls.fourier_closed:
        return _run_relative_velocity(args)
    kernel_from_args(args, _solvable, 0.0)  # a parameter of another kernel, refused by name
    for name in ("points", "half_width"):
        if getattr(args, name) is not None:
            option = name.replace("_", "-")
            raise InvalidArgumentError(option, getattr(args, name), f"no --{option} with "
                                       f"--kernel {cls.name} (it belongs to the kernels of "
                                       "time t, whose scaling state is solved on a velocity "
                                       "grid)")
    return _run_constant(args)


def _number(text, name: str) -> float:
    """A finite real number from the command line's text, read as typed by the rules of every
    other option (:func:`particles.validation.check_real`: no digit-group underscores, no
    non-zero number that reads as 0), or an error naming ``name`` and showing the text."""
    from particles.validation import check_real

    return check_real(text, name)


def _run_relative_velocity(args) -> int:
    """``fixed-point --kernel NAME`` for a kernel of time t: the scaling state of
    :func:`maxwell_kinetics.inelastic_boltzmann.scaling_state`."""
    from particles.parsing import parse_int

    from ...inelastic_boltzmann import SCALING_GRID, scaling_state
    from ...velocity_grid import VelocityGrid, initial_values

    for name in ("n", "angular"):
        if getattr(args, name) is not None:
            raise InvalidArgumentError(name, getattr(args, name), f"no --{name} with --kernel "
                                       f"{args.kernel} (a Fourier fixed-point option)")
    if args.dimension != "1":
        raise InvalidArgumentError("dimension", args.dimension, "no --dimension with --kernel "
                                   f"{args.kernel} (one dimension)")
    restitution = _number(args.restitution, "restitution")
    grid = SCALING_GRID
    points = grid.points if args.points is None else parse_int(args.points, "points")
    half_width = (grid.half_width if args.half_width is None
                  else _number(args.half_width, "half-width"))
    # the library's refusals show the text typed, not the value read from it
    typed = {"restitution": (restitution, args.restitution),
             "half_width": (half_width, args.half_width)}
    try:
        kernel = kernel_from_args(args, _solvable, restitution, typed)  # r and its parameters
        grid = VelocityGrid(points, half_width)
        initial_values("gaussian", grid)  # the starting law must fit the grid
        cache_options.from_args(args)  # the store of compiled executables, unless --no-cache
        state = scaling_state(kernel, grid=grid, force=args.force)
    except InvalidArgumentError as exc:
        if exc.name == "relaxation":  # its default, set by the kernel: the grid is the choice
            raise InvalidArgumentError("points", points if args.points is None else args.points,
                                       f"fewer points: {exc.expected}") from None
        value = exc.value
        read, text = typed.get(exc.name, (None, None))
        if text is not None and isinstance(value, float) and value == read:
            value = text
        raise InvalidArgumentError({"half_width": "half-width"}.get(exc.name, exc.name),
                                   value, exc.expected.replace(
                                       "half_width >=", "--half-width >=")) from None
    from ...inelastic_boltzmann import EDGE_TOLERANCE

    converged = state.residual <= RESIDUAL_TOLERANCE and not state.reaches_edges
    x = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0]
    payload = {
        "rate": kernel.name,
        "kernel": kernel.to_dict(),
        "restitution": state.restitution,
        "exponent": state.exponent,
        "points": grid.points,
        "half_width": grid.half_width,
        "kurtosis": state.kurtosis,
        "moment_6": state.moment(6),
        "x": x,
        "density": state.density(x).tolist(),
        "residual": state.residual,
        "iterations": state.iterations,
        "edge_moment": state.edge_moment,
        "converged": converged,
        "seconds": state.seconds,
    }
    status = 0
    if state.residual > RESIDUAL_TOLERANCE:
        print(f"maxwell-kinetics fixed-point: warning: Newton did not converge (residual "
              f"{state.residual:.3e} against {RESIDUAL_TOLERANCE:g}); the result is not a "
              "scaling state", file=sys.stderr)
        status = 3
    if state.reaches_edges:
        print(f"maxwell-kinetics fixed-point: warning: the state's tail reaches the grid's ends "
              f"(they hold {state.edge_moment:.2e} of <c^4>, above {EDGE_TOLERANCE:g}): its "
              f"kurtosis depends on the grid; widen --half-width (now {grid.half_width:g}) and "
              "raise --points with it", file=sys.stderr)
        status = 3
    if args.json:
        emit_json(payload)
        return status
    print(f"scaling state, r = {state.restitution:g}, kernel {kernel.name}, rate of degree "
          f"{state.exponent:g} in |v - w|: grid "
          f"{grid.points} points on +-{grid.half_width:g}")
    print(f"  kurtosis = {state.kurtosis:.10g}   <c^6> = {state.moment(6):.10g}   "
          f"residual = {state.residual:.3e}   Newton iterations = {state.iterations}")
    print("  P(c) at c = " + ", ".join(f"{v:g}" for v in x) + ": "
          + " ".join(f"{v:.6e}" for v in payload["density"]))
    print(f"  ({state.seconds:.2f} s)")
    return status


def _run_constant(args) -> int:
    from ...linear_rates import linear_decay_rates
    from ...stationary import (  # JAX: imported only when it runs
        MAX_DEGREE_1D,
        RESIDUAL_PER_LAMBDA,
        fixed_point,
    )

    start = time.perf_counter()
    from ...angular import angular_law

    dimension = parse_count(args.dimension, "dimension", 1)
    angular = "uniform" if args.angular is None else args.angular
    angular_law(dimension, angular)  # checks both, before any work
    if dimension == 1 and args.angular is not None:
        raise InvalidArgumentError("angular", args.angular,
                                   "no --angular without --dimension 2 or 3 (in d = 1 there is "
                                   "no collision direction to choose)")
    n = parse_count(args.n, "n", 8) if args.n is not None else (64 if dimension == 1 else 128)
    check_fixed_point_budget(n)
    if dimension == 1 and n > MAX_DEGREE_1D:
        # measured: beyond, Gauss-Newton meets a wrong function with a small residual
        # (max |G - f_hat| = 0.22 at --n 800, r = 0.5); see stationary.MAX_DEGREE_1D
        raise InvalidArgumentError("n", args.n, f"a Chebyshev degree --n <= {MAX_DEGREE_1D} in "
                                   "d = 1 (a larger one is too ill-conditioned: it converges to "
                                   "a wrong function)")
    cache_options.from_args(args)
    try:
        fp = fixed_point(args.restitution, n=n, dimension=dimension, angular=angular,
                         force=args.force)
    except InvalidArgumentError as exc:  # the library's refusal, with the option to force it
        if "force=True" not in exc.expected:
            raise
        raise InvalidArgumentError(exc.name, exc.value, exc.expected.replace(
            "force=True", "pass --force")) from None
    # Newton may stop on a small step at a non-solution (n = 8, r = 0.99: residual 4.8e-3):
    # a fixed point counts as converged only when its residual is small too
    converged = bool(fp.converged) and fp.residual <= RESIDUAL_TOLERANCE
    # The linearisation is around f̂, the one-dimensional scaling solution: d = 1 only.
    rates = linear_decay_rates(fp.restitution) if dimension == 1 else None
    payload = {
        "restitution": fp.restitution,
        "dimension": dimension,
        "angular": angular if dimension > 1 else None,
        "max_error": fp.max_error if dimension == 1 else None,
        "residual": fp.residual,
        "iterations": fp.iterations,
        "converged": converged,
        "decay_rates": list(rates.rates) if rates else None,
        "gamma": {str(s): g for s, g in rates.gamma.items()} if rates else None,
        "gamma_star": rates.gamma_star if rates else None,
        "s_star": rates.s_star if rates else None,
        "q_min": rates.q_min if rates else None,
        "seconds": time.perf_counter() - start,
    }
    status = 0
    if not converged:  # never a silent success: a warning and exit status 3
        against = f"{RESIDUAL_TOLERANCE:g}"
        if dimension == 1:  # and 1e-8 λ: see stationary.RESIDUAL_PER_LAMBDA
            from ...model import MaxwellModel

            against += f" and {RESIDUAL_PER_LAMBDA:g} lambda = " + \
                f"{RESIDUAL_PER_LAMBDA * MaxwellModel(fp.restitution).lam:.1e}"
        print(f"maxwell-kinetics fixed-point: warning: Gauss-Newton did not converge in "
              f"{fp.iterations} iterations (residual {fp.residual:.3e} against "
              f"{against}); the result is not a fixed point", file=sys.stderr)
        status = 3
    if args.json:
        emit_json(payload)
        return status
    model = "" if dimension == 1 else f", d = {dimension} ({angular})"
    print(f"fixed point, r = {fp.restitution:g}{model}: Chebyshev n = {fp.n} on "
          f"[0, {fp.q_max:g}]")
    if rates is None:
        print(f"  residual = {fp.residual:.3e}   Gauss-Newton iterations = {fp.iterations}")
        print(f"  ({payload['seconds']:.2f} s)")
        return status
    print(f"  max |G - f_hat| = {fp.max_error:.3e}   residual = {fp.residual:.3e}   "
          f"Gauss-Newton iterations = {fp.iterations}")
    print(f"  slowest linear decay rates (q >= q_min = {rates.q_min:.3g}): "
          + ", ".join(f"{x:.6g}" for x in rates.rates))
    print(f"  max gamma(s) on (2, 3) = {rates.gamma_star:.6g} at s* = {rates.s_star:.4f}; "
          + ", ".join(f"gamma({s}) = {g:.6g}" for s, g in rates.gamma.items()))
    print(f"  ({payload['seconds']:.2f} s)")
    return status


