"""Kinetic-theory subcommands of the command line (``solve``, ``fixed-point``, ...)."""

from __future__ import annotations


def register(subparsers) -> None:
    """Add the kinetic-theory subcommands."""
