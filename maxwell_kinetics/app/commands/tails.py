"""``maxwell-kinetics tail-exponent``: the power-law tail of the scaling solution of the
d-dimensional inelastic Maxwell model.

    maxwell-kinetics tail-exponent --dimension D --restitution R [--angular uniform|hard] [--json]

Prints ``s`` (s* > 1, the nontrivial root of λ(s) = s λ(1)) and ``exponents``: ``density``
(d + 2s*: the d-dimensional density decays as c^{−d−2s*}), ``speed`` and ``component``
(1 + 2s*), with the energy decay rate Λ = 2pq⟨η⟩ (:mod:`maxwell_kinetics.tails`).
"""

from __future__ import annotations

from particles.parsing import parse_int
from particles.validation import InvalidArgumentError

from .. import cache_options
from ..output import emit_json

__all__ = ["add_parser", "run"]


def add_parser(subparsers) -> None:
    """Register the ``tail-exponent`` subcommand and its options.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``add_subparsers()`` object of the top-level parser; the new parser's ``handler``
        default is :func:`run`.
    """
    p = subparsers.add_parser(
        "tail-exponent", help="tail exponents of the d-dimensional inelastic Maxwell model",
        description=__doc__.split("\n\n", 1)[1],
    )
    p.add_argument("--dimension", default="2", help="1, 2 or 3 (default 2)")
    p.add_argument("--restitution", "-r", required=True, help="restitution r in [0, 1)")
    p.add_argument("--angular", default=None,
                   help="d >= 2 only: uniform or hard (default uniform)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    cache_options.add_option(p, compiles=False)
    p.set_defaults(handler=run)


def run(args) -> int:
    """Run ``maxwell-kinetics tail-exponent`` on parsed arguments.

    Computes the tail exponent s* and the energy decay rate with
    :func:`maxwell_kinetics.tails.tail_exponent` and prints them (one JSON object with ``--json``).

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
        From the validators it calls: a bad ``--dimension``, ``--restitution`` (also one so
        close to 1 that s* cannot be resolved) or ``--angular`` (also given with
        ``--dimension 1``, where it means nothing) (exit 2).
    """
    from ...tails import tail_exponent  # scipy.optimize: imported only when it runs

    dimension = parse_int(args.dimension, "dimension")
    if args.angular is not None and dimension == 1:  # η ≡ 1 in d = 1: the option does nothing
        raise InvalidArgumentError("angular", args.angular, "--dimension 2 or 3 with it (d = 1 "
                                   "has a single collision direction)")
    tail = tail_exponent(dimension, args.restitution, args.angular or "uniform")
    payload = {"dimension": tail.dimension, "restitution": tail.restitution,
               "angular": tail.angular, "s": tail.s, "decay_rate": tail.decay_rate,
               "exponents": dict(tail.exponents)}
    if args.json:
        emit_json(payload)
    else:
        e = tail.exponents
        print(f"d = {tail.dimension}, r = {tail.restitution:g}, {tail.angular}: s* = {tail.s:.10g}"
              f"; density ~ c^-{e['density']:.6g}, speed and one component ~ "
              f"c^-{e['speed']:.6g}; energy decay rate {tail.decay_rate:.6g}")
    return 0
