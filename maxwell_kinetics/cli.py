"""The ``maxwell-kinetics`` command line.

Subcommands:

``solve``        integrate the rescaled Fourier-space equation (kinetic theory)
``fixed-point``  solve the stationary rescaled equation by Newton's method
``convergence``  error floor against resolution (writes a figure and JSON)
``reproduce``    every comparison with the paper (the main job of ``make demo``)
``simulate``     particle models (``ulam``, ``lattice``, ``md``), from :mod:`particles.cli`

Every subcommand takes ``--json`` and then prints exactly one JSON object on stdout.
Bad input exits with status 2 and a message naming the argument and the value received,
and writes no file.
"""

from __future__ import annotations

import argparse
import json
import sys

from .validation import InvalidArgumentError

__all__ = ["main", "build_parser"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="maxwell-kinetics",
        description="Velocity statistics of cooling granular gases (pseudo-Maxwell kinetics and "
        "particle models).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    from . import commands

    commands.register(sub)
    try:
        from particles.cli import register as register_particles
    except ImportError:  # pragma: no cover - particles always ships with the distribution
        register_particles = None
    if register_particles is not None:
        register_particles(sub)
    return parser


def emit_json(payload: dict) -> None:
    """Print one JSON object (the ``--json`` contract)."""
    json.dump(payload, sys.stdout, allow_nan=False)
    sys.stdout.write("\n")
    sys.stdout.flush()


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except InvalidArgumentError as exc:
        print(f"maxwell-kinetics {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("maxwell-kinetics: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
