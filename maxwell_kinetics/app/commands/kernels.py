"""``maxwell-kinetics kernels``: the registered collision kernels, read from the registry.

    maxwell-kinetics kernels [--json]

One row per kernel of :data:`particles.kernels.KERNELS`: its name, the time it counts (``tau``,
collisions per particle, or ``t``, physical time at density n), its parameters with their
ranges and defaults, and what carries it: the kinetic solvers (``fourier``: the Fourier-space
scheme of ``solve``, for kernels whose Fourier equation closes; ``velocity_grid``: the
velocity-space solver, for kernels of time t whose rate is a power of |v − w|; see
:mod:`maxwell_kinetics.methods`) and the particle engines (``ulam``,
``lattice``), each asked whether it carries the kernel.  A kernel registered by the user's own
code before the command runs is listed the same way.
"""

from __future__ import annotations

from ..output import emit_json

__all__ = ["add_parser", "run", "kernel_rows"]


def add_parser(subparsers) -> None:
    """Register the ``kernels`` subcommand.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``add_subparsers()`` object of the top-level parser; the new parser's ``handler``
        default is :func:`run`.
    """
    p = subparsers.add_parser("kernels", help="the registered collision kernels",
                              description=__doc__.split("\n\n", 2)[2])
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=run)


def kernel_rows() -> list[dict]:
    """Every registered kernel (:func:`particles.kernels.describe_kernels`) with ``methods``
    and ``engines``: the names of the solvers and particle engines that carry it.

    Returns
    -------
    list of dict
    """
    from particles.kernels import KERNELS, describe_kernels
    from particles.lattice import CARRIED_KERNELS as LATTICE_KERNELS
    from particles.pair_schedule import ulam_carries

    from ...methods import carrying_methods

    rows = []
    for row in describe_kernels():
        cls = KERNELS[row["name"]]
        methods = carrying_methods(cls)
        engines = [name for name, carried in (("ulam", ulam_carries(cls)),
                                              ("lattice", cls.name in LATTICE_KERNELS))
                   if carried]
        rows.append({**row, "methods": methods, "engines": engines})
    return rows


def run(args) -> int:
    """Run ``maxwell-kinetics kernels``: print the rows of :func:`kernel_rows` (one JSON
    object ``{"kernels": [...]}`` with ``--json``, a table otherwise).

    Parameters
    ----------
    args : argparse.Namespace
        The options registered by :func:`add_parser`.

    Returns
    -------
    int
        0.
    """
    rows = kernel_rows()
    if args.json:
        emit_json({"kernels": rows})
        return 0
    for row in rows:
        params = ", ".join(
            p["name"] if p["default"] is None
            else f"{p['name']} in [{p['low']:g}, {p['high']:g}] (default {p['default']:g})"
            for p in row["parameters"])
        print(f"{row['name']}  (time {row['time']}; d = "
              f"{', '.join(map(str, row['dimensions']))})")
        print(f"  {row['summary']}")
        print(f"  parameters: {params}")
        print(f"  solvers: {', '.join(row['methods']) or 'none'};  "
              f"engines: {', '.join(row['engines']) or 'none'}")
    return 0
