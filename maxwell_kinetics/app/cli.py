"""The ``maxwell-kinetics`` command line.

Subcommands:

``solve``        integrate the rescaled Fourier-space equation (kinetic theory)
``fixed-point``  solve the stationary rescaled equation by Newton's method
``tail-exponent`` tail exponents of the d-dimensional inelastic Maxwell model
``steady``       steady state of the driven (heated) 1D model
``convergence``  error floor against resolution (writes a figure and JSON)
``reproduce``    every comparison with the paper (the main job of ``make demo``)
``simulate``     particle models (``ulam``, ``lattice``, ``md``, ``sticky``)
``ensemble``     many seeds and parameter sweeps of a particle model, on dask
``kernels``      the registered collision kernels, their parameters and what carries them

One module per subcommand in :mod:`maxwell_kinetics.app.commands`, each with ``add_parser`` and a
handler; they share :mod:`maxwell_kinetics.app.output` and never import this module.

Every subcommand takes ``--json`` and then prints exactly one JSON object on stdout.
Bad input exits with status 2 and a message naming the argument and the value received,
and writes no file.  Numeric values that start with '-' may follow their option after a space
(``--tau -1,2``, ``-r -0.5``): :func:`join_negative_values` passes them on as ``--tau=-1,2``,
for every subcommand, so that the validation (not argparse) reports them.
"""

from __future__ import annotations

import os
import sys

# Ctrl-C during the imports below (~0.3 s) when run as the program: one line and status 130.
# The handler records the signal because an interrupt inside a C extension's import (NumPy's)
# may surface as an ImportError instead of a KeyboardInterrupt.
_PROGRAM = os.path.basename(getattr(sys.modules.get("__main__"), "__file__", "") or "") in (
    "maxwell-kinetics", "cli.py")
_START_SIGNALS: list = []


def _start_handler(signum, frame):
    _START_SIGNALS.append(signum)
    raise KeyboardInterrupt


if _PROGRAM:
    import _signal

    _signal.signal(_signal.SIGINT, _start_handler)
try:
    import argparse

    from particles.validation import InvalidArgumentError

    from .. import interrupt
    from . import cache_options
    from .commands import (
        convergence,
        ensemble,
        fixed_point,
        kernels,
        reproduce,
        simulate,
        solve,
        steady,
        tails,
    )
    from .output import emit_json
except BaseException:
    if not (_PROGRAM and _START_SIGNALS):
        raise  # imported by Python code (the caller's KeyboardInterrupt), or a real error
    print("maxwell-kinetics: interrupted", file=sys.stderr)
    raise SystemExit(130) from None
finally:
    if _PROGRAM:
        _signal.signal(_signal.SIGINT, _signal.default_int_handler)
if _PROGRAM and _START_SIGNALS:
    # The imports went on: the KeyboardInterrupt was swallowed on the way (a library's bare
    # ``except`` around an optional import, seen on a loaded machine), but Ctrl-C was pressed.
    print("maxwell-kinetics: interrupted", file=sys.stderr)
    raise SystemExit(130)

__all__ = ["main", "build_parser", "emit_json", "join_negative_values", "refuse_repeated_options"]

#: The subcommands in the order of ``--help``.
COMMANDS = (solve, fixed_point, tails, steady, convergence, reproduce, simulate, ensemble,
            kernels)


def build_parser() -> argparse.ArgumentParser:
    """The parser of every subcommand (the CLI reference of the site is generated from it).

    Returns
    -------
    argparse.ArgumentParser
    """
    parser = argparse.ArgumentParser(
        prog="maxwell-kinetics",
        description="Velocity statistics of cooling granular gases (pseudo-Maxwell kinetics and "
        "particle models).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def _looks_numeric(token: str) -> bool:
    """True for a value such as ``-1``, ``-0.5``, ``-inf``, ``-1e3`` or ``-1,2`` (a list whose
    first entry is a negative number): argparse would take it for an option."""
    if not token.startswith("-") or token.startswith("--"):
        return False
    try:
        float(token.split(",", 1)[0].strip())
    except ValueError:
        return False
    return True


def _takes_one_value(parser: argparse.ArgumentParser, option: str, optional: bool = True) -> bool:
    """True when ``option`` (exact, or an unambiguous ``--`` prefix) takes one value; with
    ``optional=False``, only when the value is required (``nargs="?"`` may take none, so the
    next token is not skipped as its value unless it was joined)."""
    action = _option_action(parser, option)
    return action is not None and action.nargs in ((None, 1, "?") if optional else (None, 1))


def _option_action(parser: argparse.ArgumentParser, option: str):
    """The action of ``option`` (exact, or an unambiguous ``--`` prefix), else None."""
    actions = parser._option_string_actions
    if option in actions:
        return actions[option]
    if option.startswith("--") and parser.allow_abbrev:
        found = {action for name, action in actions.items() if name.startswith(option)}
        if len(found) == 1:
            return found.pop()
    return None


def _subcommands(parser: argparse.ArgumentParser) -> dict:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return {}


def join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """Rewrite ``--opt -x`` as ``--opt=-x`` when ``--opt`` takes a value and ``-x`` is numeric.

    argparse reads a token such as ``-1,2`` or ``-inf`` after ``--tau`` as an option and fails
    with "expected one argument", which hides the value; joined, the value reaches the
    validation, whose message names the argument and the value.  The walk follows the
    subcommands (``solve``, ``simulate ulam``, ...) so that each option is looked up in the
    parser that defines it; everything after ``--`` is left alone.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser.
    argv : list of str
        The arguments.

    Returns
    -------
    list of str
    """
    out: list[str] = []
    i = 0
    while i < len(argv):
        token = argv[i]
        if token == "--":
            out.extend(argv[i:])
            break
        subcommands = _subcommands(parser)
        if token in subcommands:
            parser = subcommands[token]
        elif token.startswith("-") and "=" not in token and _takes_one_value(parser, token):
            if i + 1 < len(argv) and _looks_numeric(argv[i + 1]):  # joined: skip both
                out.append(f"{token}={argv[i + 1]}")
                i += 2
                continue
            if i + 1 < len(argv) and _takes_one_value(parser, token, optional=False):
                out.extend([token, argv[i + 1]])  # its value, whatever it is: skip both
                i += 2
                continue
        out.append(token)
        i += 1
    return out


def _value_action(parser: argparse.ArgumentParser, option: str):
    """The action of ``option`` (exact, or an unambiguous ``--`` prefix) when it always takes
    one value, else None."""
    action = _option_action(parser, option)
    return action if action is not None and action.nargs in (None, 1) else None


def refuse_repeated_options(parser: argparse.ArgumentParser, argv: list[str]) -> None:
    """Refuse an option that takes a value given twice (``--restitution 5 --restitution 0.5``,
    or ``-r`` and ``--restitution``): argparse keeps the last value, so the first would be
    ignored without being checked.  ``argv`` is :func:`join_negative_values`'s output (each
    value joined as ``--opt=value`` or following its option).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser.
    argv : list of str
        The arguments.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the option and its first value, with the second.
    """
    given: dict = {}
    i = 0
    while i < len(argv):
        token = argv[i]
        if token == "--":
            break
        subcommands = _subcommands(parser)
        if token in subcommands:
            parser = subcommands[token]
        elif token.startswith("-"):
            option, joined, value = token.partition("=")
            action = _value_action(parser, option)
            if action is not None:
                if not joined:
                    value = argv[i + 1] if i + 1 < len(argv) else None
                    i += 1
                key = (id(parser), action.dest)
                if key in given:
                    first_option, first = given[key]
                    name = action.dest.replace("_", "-")
                    again = "" if option == first_option else f" as {option}"
                    raise InvalidArgumentError(
                        name, first, f"--{name} once (it is given again{again}, as {value!r}: "
                        "only one value can be used)")
                given[key] = (option, value)
        i += 1


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 success, 2 bad input, 3 a failure of
    the physics such as inelastic collapse or a claim that ``reproduce`` finds to disagree, or
    of a write such as a full disk, 130 interrupted,
    141 when the reader of the output went away, as in ``| head``: no traceback).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
    """
    command = "maxwell-kinetics"
    try:
        parser = build_parser()
        argv = list(sys.argv[1:] if argv is None else argv)
        argv = join_negative_values(parser, argv)
        refuse_repeated_options(parser, argv)
        args = parser.parse_args(argv)
        command = f"maxwell-kinetics {args.command}"
        if getattr(args, "runs_jax", False) and "JAX_PLATFORMS" in os.environ:
            cache_options.check_platforms()  # one line, exit 2, before anything is written
        return int(args.handler(args) or 0)
    except InvalidArgumentError as exc:  # a failed write (a full disk) carries exit status 3
        print(f"{command}: error: {exc}", file=sys.stderr)
        return getattr(exc, "exit_status", 2)
    except KeyboardInterrupt:  # at any moment, start-up included: one line, no traceback
        print(f"{command}: interrupted", file=sys.stderr)
        if _PROGRAM and interrupt.abandoned():
            # a solve's worker thread still runs inside JAX: the interpreter's shutdown would
            # abort the process (status 134), so leave now, with the streams flushed
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(130)
        return 130
    except BrokenPipeError:  # stdout closed by its reader: stop quietly, as a shell tool does
        try:  # Python flushes stdout at exit; point it at /dev/null so that this cannot fail
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 128 + 13  # 128 + SIGPIPE
    finally:
        cache_options.end_command()  # an in-process run leaves JAX's cache settings as they were


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
