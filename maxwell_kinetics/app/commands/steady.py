"""``maxwell-kinetics steady``: the non-equilibrium steady state of the driven 1D Maxwell model
(white-noise heating of strength D).

    maxwell-kinetics steady --restitution R --driving D [--json] [--plot FILE]

Prints the steady ``variance`` D/(pq), the ``kurtosis`` 3 + 6pq/(2 − pq), the first
``cumulants`` and the ``density`` (``x`` and ``P``: P(v) on a uniform grid of [−H, H),
H = √D max(60, 15/√(pq)),
from the exact characteristic function by FFT, with round-off of ~1e-16 far out;
:mod:`maxwell_kinetics.driven`).  There is no steady state for
D = 0 (the gas cools to rest) or r = 1 with D > 0 (the heating is never dissipated): both exit 2.
"""

from __future__ import annotations

import numpy as np

from particles import persistence

from ...driven import steady_state
from .. import cache_options
from ..output import check_outputs, emit_json

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    """Register the ``steady`` subcommand and its options.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``add_subparsers()`` object of the top-level parser; the new parser's ``handler``
        default is :func:`run`.
    """
    p = subparsers.add_parser(
        "steady", help="the steady state of the driven (heated) 1D Maxwell model",
        description=__doc__.split("\n\n", 1)[1],
    )
    p.add_argument("--restitution", "-r", required=True, help="restitution r in [0, 1)")
    p.add_argument("--driving", "-D", required=True, help="heating strength D > 0")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE", help="write a PNG of ln P(v) with the Gaussian")
    cache_options.add_option(p, compiles=False)
    p.set_defaults(handler=run)


def run(args) -> int:
    """Run ``maxwell-kinetics steady`` on parsed arguments.

    Computes the steady state of the driven model
    (:func:`maxwell_kinetics.driven.steady_state`) and prints it, as one JSON object with
    ``--json``; ``--plot`` writes a PNG of the density beside the Gaussian of the same variance.

    Parameters
    ----------
    args : argparse.Namespace
        The options registered by :func:`add_parser`.

    Returns
    -------
    int
        The exit status, 0 on success.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From the validators it calls: a bad ``--restitution`` or ``--driving``
        (no steady state for D = 0 or r = 1), or an unwritable ``--plot`` path (exit 2).
    """
    check_outputs(images={"plot": args.plot})
    state = steady_state(args.restitution, args.driving)
    payload = {"restitution": state.restitution, "driving": state.driving,
               "variance": state.variance, "kurtosis": state.kurtosis,
               "cumulants": np.asarray(state.cumulants).tolist(),
               "density": {"x": state.velocity.tolist(), "P": state.density.tolist()}}
    if args.plot:
        from ...figures import plot_density

        fig = plot_density(state.velocity, state.density, state.variance,
                     title=f"driven steady state, r = {state.restitution:g}, "
                           f"D = {state.driving:g}")
        persistence.save_figure(fig, args.plot, "plot", dpi=120)
    if args.json:
        emit_json(payload)
    else:
        print(f"r = {state.restitution:g}, D = {state.driving:g}: variance {state.variance:.10g}, "
              f"kurtosis {state.kurtosis:.10g}; tail P ~ exp(-|v|/sqrt(D))")
    return 0
