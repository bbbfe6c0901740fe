"""``maxwell-kinetics simulate {ulam,lattice,md}``: the particle models on the command line."""

from __future__ import annotations


def register(subparsers) -> None:
    """Add the ``simulate`` subcommand to the top-level parser's ``subparsers``."""
    simulate = subparsers.add_parser("simulate", help="run a particle model")
    models = simulate.add_subparsers(dest="model", required=True)
    del models  # the models register themselves here as they land
