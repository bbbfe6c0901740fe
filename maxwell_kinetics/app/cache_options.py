"""The command line's side of the compilation cache (:mod:`maxwell_kinetics.compile_cache`):
the ``--no-cache`` option of the subcommands, the check of ``JAX_PLATFORMS`` before anything is
written, and turning the cache on for one subcommand and back off when it ends.
"""

from __future__ import annotations

import os
from pathlib import Path

from .. import compile_cache

__all__ = ["add_option", "check_platforms", "from_args", "end_command"]

#: The cache state from before the running subcommand (see :func:`from_args`).
_state: dict = {}


def add_option(parser, compiles: bool = True) -> None:
    """Add ``--no-cache`` to a subcommand's parser.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand's parser.
    compiles : bool, default True
        False for a subcommand that compiles nothing (its help text says the option is
        accepted for uniformity).  The parsed arguments get ``runs_jax`` = ``compiles``.
    """
    text = ("do not use the persistent compilation cache (default: on, in "
            f"${compile_cache.ENV} or ~/.cache/maxwell-kinetics/jax)")
    if not compiles:
        text += "; this subcommand compiles nothing, the option is accepted for uniformity"
    parser.add_argument("--no-cache", action="store_true", help=text)
    # the command line checks JAX_PLATFORMS before a subcommand that runs JAX writes anything
    parser.set_defaults(runs_jax=compiles)


def check_platforms() -> None:
    """Start JAX's backend; a ``JAX_PLATFORMS`` that JAX cannot start here is bad input.

    Raises
    ------
    InvalidArgumentError
        ``JAX_PLATFORMS`` is set (e.g. to ``cuda`` on a machine without a GPU, or to an
        unknown name) and JAX cannot start any device with it; the message names the variable,
        its value (at most 200 characters) and JAX's reason, on one line.
    """
    import jax

    try:
        jax.devices()
    except Exception as exc:
        value = os.environ.get("JAX_PLATFORMS")
        if value is None:  # not the user's setting: JAX's own failure, as it is
            raise
        from particles.validation import InvalidArgumentError

        reason = " ".join(str(exc).split()) or f"{type(exc).__name__} while starting it"
        if len(reason) > 200:
            reason = reason[:200] + "..."
        shown = value if len(value) <= 200 else value[:200] + "..."
        raise InvalidArgumentError(
            "JAX_PLATFORMS", shown, "platforms that JAX can start on this machine (such as "
            f"'cpu'), or the variable unset; JAX said: {reason}") from None


def from_args(args) -> Path | None:
    """The command line's rule: the cache on unless ``--no-cache``; call it after the input
    checks, right before the first JAX computation.  It first starts JAX's backend
    (:func:`check_platforms`), so that a ``JAX_PLATFORMS`` that cannot work is reported
    before anything is written.  :func:`end_command` undoes it.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (its ``no_cache`` attribute, False when absent).

    Returns
    -------
    pathlib.Path or None
        What :func:`~maxwell_kinetics.compile_cache.enable` returns, or None with ``--no-cache``.

    Raises
    ------
    InvalidArgumentError
        From :func:`check_platforms`.
    """
    check_platforms()
    if "before_command" not in _state:
        _state["before_command"] = compile_cache.current_choice()
    if getattr(args, "no_cache", False):
        compile_cache.disable()
        return None
    return compile_cache.enable()


def end_command() -> None:
    """Put back the cache state from before :func:`from_args` (the command line calls it when
    a subcommand ends, so that a command run in-process leaves the cache as it found it)."""
    if "before_command" not in _state:
        return
    compile_cache.restore_choice(_state.pop("before_command"))
