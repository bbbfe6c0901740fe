"""``solve`` and ``fixed-point`` for the hard-sphere kernels of :mod:`particles.sphere_kernels`
(``--kernel hard_spheres`` or ``variable_hard_spheres``, ``--dimension 2`` or ``3``): the spectral
solver of :mod:`maxwell_kinetics.sphere_spectral`.  Every option is checked before any work; the
options of the other methods are refused by name.
"""

from __future__ import annotations

from particles import persistence
from particles.parsing import parse_float_list, parse_int
from particles.validation import InvalidArgumentError, check_real

from ... import interrupt
from ..output import check_outputs, emit_json
from .kernel_options import kernel_from_args
from .kernel_options import solvable as _solvable

__all__ = ["is_sphere_kernel", "run_solve", "run_fixed_point"]


def is_sphere_kernel(cls) -> bool:
    """Whether the spectral hard-sphere method carries a kernel class.

    Parameters
    ----------
    cls : type
        A kernel class.

    Returns
    -------
    bool
    """
    from ...methods import SphereSpectral

    return SphereSpectral.refusal(cls) is None


def _refuse(args, names: dict, kernel: str) -> None:
    """Refuse each option of ``names`` (attribute → value it has when not given) that was given."""
    for name, unset in names.items():
        value = getattr(args, name, unset)
        if value != unset:
            option = name.replace("_", "-")
            raise InvalidArgumentError(option, value, f"no --{option} with --kernel {kernel} "
                                       "(the spectral hard-sphere solver takes --t, "
                                       "--dimension 2 or 3, --density, --grid)")


def _common(args):
    """The kernel, d and grid name from the options (checked)."""
    from ...sphere_grid import sphere_grid

    restitution = check_real(args.restitution, "restitution")
    kernel = kernel_from_args(args, _solvable, restitution)
    dimension = parse_int(args.dimension, "dimension")
    if dimension not in (2, 3):
        raise InvalidArgumentError("dimension", args.dimension, f"--dimension 2 or 3 with "
                                   f"--kernel {kernel.name}")
    grid_name = "default" if args.grid is None else args.grid
    try:
        grid = sphere_grid(grid_name, dimension)
    except InvalidArgumentError as exc:
        raise InvalidArgumentError("grid", args.grid, exc.expected) from None
    return kernel, dimension, grid_name, grid


def run_solve(args, written: list) -> int:
    """``solve --kernel hard_spheres``: T, a₂, a₃ at each ``--t``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``solve``.
    written : list
        Filled with the paths written (removed on Ctrl-C).

    Returns
    -------
    int
        The exit status, 0.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For an option out of range or one of another method.
    """
    from ...methods import SphereSpectral
    from ...solver import solve

    _refuse(args, {"tau": None, "speed": None, "angular": None, "angular_rule": None,
                   "points": None, "half_width": None, "core_spacing": None,
                   "q": "0.5,1,2,5", "resolution": "default"}, args.kernel)
    kernel, dimension, grid_name, grid = _common(args)
    if args.t is None:
        raise InvalidArgumentError("t", None, f"--t T1,T2,... with --kernel {kernel.name}")
    times = parse_float_list(args.t, "t")
    density = 1.0 if args.density is None else check_real(args.density, "density")
    if not density > 0:
        raise InvalidArgumentError("density", args.density, "a finite density n > 0")
    if args.initial != "gaussian":
        raise InvalidArgumentError("initial", args.initial, "gaussian (the Maxwellian of T = 1) "
                                   f"with --kernel {kernel.name}")
    check_outputs(save=args.save, images={"plot": args.plot})
    sol = solve(kernel, "gaussian", times, SphereSpectral(dimension=dimension, grid=grid),
                density=density, force=args.force)
    interrupt.check()
    if args.plot:
        import matplotlib.figure

        figure = matplotlib.figure.Figure(figsize=(6.4, 4.4))
        sol.plot(figure.add_subplot())
        written.append(args.plot)
        persistence.save_figure(figure, args.plot, "plot", dpi=120)
    if args.save:
        written.append(args.save)
        sol.save(args.save)
    interrupt.check()
    sonine = sol.sonine()
    if args.json:
        emit_json({"kernel": kernel.to_dict(), "restitution": kernel.restitution,
                   "dimension": dimension, "density": density, "initial": "gaussian",
                   "grid": grid_name, "grid_parameters": grid.to_dict(),
                   "t": sol.times.tolist(), "temperature": sol.temperature.tolist(),
                   "a2": sonine[:, 0].tolist(), "a3": sonine[:, 1].tolist(),
                   "cooling_rate": sol.cooling_rate.tolist(),
                   "kurtosis": sol.kurtosis.tolist(), "steps": sol.steps,
                   "seconds": sol.seconds})
        return 0
    print(f"kernel {kernel.name}, alpha = {kernel.restitution:g}, d = {dimension}, "
          f"n = {density:g}, grid {grid_name} ({grid.points}^{dimension} modes), "
          f"{sol.seconds:.1f} s")
    for t, T, (a2, a3) in zip(sol.times, sol.temperature, sonine, strict=True):
        print(f"  t = {t:<10g} T = {T:.10g}   a2 = {a2:.6g}   a3 = {a3:.6g}")
    return 0


def run_fixed_point(args) -> int:
    """``fixed-point --kernel hard_spheres``: the homogeneous cooling state's a₂ and a₃.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``fixed-point``.

    Returns
    -------
    int
        The exit status, 0.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For an option out of range or one of another method.
    """
    from ...sphere_spectral import cooling_state

    _refuse(args, {"n": None, "angular": None, "points": None, "half_width": None},
            args.kernel)
    kernel, dimension, grid_name, grid = _common(args)
    if kernel.restitution >= 1.0:
        raise InvalidArgumentError("restitution", args.restitution, "r < 1 (elastic spheres do "
                                   "not cool: every Maxwellian is stationary)")
    state = cooling_state(kernel, dimension=dimension, grid=grid)
    if args.json:
        emit_json({"kernel": kernel.to_dict(), "restitution": kernel.restitution,
                   "dimension": dimension, "grid": grid_name,
                   "grid_parameters": grid.to_dict(), "a2": state.a2, "a3": state.a3,
                   "cooling_rate": state.cooling_rate, "residual": state.residual,
                   "tau": state.tau, "steps": state.steps, "seconds": state.seconds})
        return 0
    print(f"homogeneous cooling state, kernel {kernel.name}, alpha = {kernel.restitution:g}, "
          f"d = {dimension}, grid {grid_name}: a2 = {state.a2:.6g}, a3 = {state.a3:.6g}, "
          f"cooling rate {state.cooling_rate:.6g} (residual {state.residual:.2e} at "
          f"tau = {state.tau:g}, {state.seconds:.1f} s)")
    return 0
