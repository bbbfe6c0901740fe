"""The command-line options of the particle models, generated from the catalogue
:mod:`particles.models`, for ``simulate MODEL`` and ``ensemble MODEL`` alike.

Every parameter of a model is an option (``Parameter.option``; a boolean also has its switch,
e.g. ``--no-constraint``).  ``simulate`` takes one value per option, ``ensemble`` a value or a
comma list (swept); each value is read by ``Parameter.parse``, so one bad value gets one message
from both commands.  The time option is ``--tau`` or ``--t``, as the engine names its time
(``engine.time_name``; the lattice takes either, and the one given must be its engine's).  The
run options that mean the same in both commands (``--json``, ``--structure-factor``,
``--checkpoint-interval``, ``--progress/--no-progress``) are added by :func:`add_run_options`.

The options are read from the catalogue when the parser is built, and the catalogue reads the
registry of kernels :data:`particles.kernels.KERNELS` then: ``--kernel`` (of ``ulam`` and
``lattice``) accepts every registered kernel the engine carries, and each parameter those kernels
declare is an option (``--exponent``), refused with any other kernel.  An alias of an option
(``--rate`` of ``--kernel``, kept for one release) means the same; an error names the option as
it was typed.
"""

from __future__ import annotations

import argparse

from particles.models import MODELS, Model
from particles.parsing import parse_name_list
from particles.validation import InvalidArgumentError

__all__ = [
    "cli_models",
    "add_model_options",
    "add_time_option",
    "add_run_options",
    "model_params",
    "time_option",
]


def cli_models() -> list[Model]:
    """The models of the catalogue whose parameters are all declared (a model registered with
    only a factory has parameters of kind ``"any"``: it is for Python, not the command line).

    Returns
    -------
    list of particles.models.Model
        Those models, in the catalogue's order.
    """
    return [m for m in MODELS.values() if all(p.kind != "any" for p in m.parameters)]


def add_model_options(parser: argparse.ArgumentParser, model: Model, *, sweep: bool) -> None:
    """One option per parameter of ``model`` (values stay strings until
    :func:`model_params`).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser of ``simulate MODEL`` or ``ensemble MODEL``.
    model : particles.models.Model
        The catalogue entry of the model.
    sweep : bool
        If true, each option accepts a comma list of values (a sweep, for ``ensemble``).
    """
    for p in model.parameters:
        text = p.describe()
        if p.example is not None:
            text += f"; e.g. {p.option} {_shown(p.example)}"
        if sweep:
            text += "; a comma list is swept"
        target = parser
        metavar = "VALUE" if not sweep else "V1,V2,..."
        if (p.kind == "flag" and p.switch) or p.aliases:
            target = parser.add_mutually_exclusive_group()
        if p.kind == "flag" and p.switch:
            target.add_argument(p.switch, dest=p.name, action="store_const",
                                const=not p.default, default=None,
                                help=f"same as {p.option} {_shown(not p.default)}")
        target.add_argument(p.option, dest=p.name, required=p.required, default=None,
                            metavar=metavar, help=text)
        for alias in p.aliases:
            target.add_argument(alias, dest=_alias_dest(p, alias), default=None, metavar=metavar,
                                help=f"alias of {p.option} (kept for one release)")


def _alias_dest(p, alias: str) -> str:
    """Where argparse keeps the text given to the alias ``alias`` of the option of ``p``."""
    return f"{p.name}__alias__{alias.lstrip('-').replace('-', '_')}"


def _given(args, p) -> tuple[object, str]:
    """(text, label) of parameter ``p`` on the command line: the text given to its option or
    to one of its aliases (None if neither), and the name errors show, the option as typed."""
    for alias in p.aliases:
        text = getattr(args, _alias_dest(p, alias), None)
        if text is not None:
            return text, alias.lstrip("-")
    return getattr(args, p.name, None), p.label


def _shown(value) -> str:
    return str(value).lower() if isinstance(value, bool) else str(value)


def add_time_option(parser: argparse.ArgumentParser, model: Model) -> None:
    """``--tau`` or ``--t`` (or both, one of them required) as the model's engines name their
    time.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser of ``simulate MODEL`` or ``ensemble MODEL``.
    model : particles.models.Model
        The catalogue entry of the model.
    """
    group = parser.add_mutually_exclusive_group(required=True)
    for name in model.time_names:
        group.add_argument(f"--{name}", dest=f"times_{name}", metavar="T1,T2,...",
                           help=f"increasing times >= 0 at which to record ({name})")


def add_run_options(parser: argparse.ArgumentParser) -> None:
    """The run options shared by ``simulate MODEL`` and ``ensemble MODEL``.

    ``--json``, ``--structure-factor``, ``--checkpoint-interval`` and ``--progress``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser of ``simulate MODEL`` or ``ensemble MODEL``.
    """
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--structure-factor", action="store_true", help="also record S(k) at the last time"
    )
    parser.add_argument("--checkpoint-interval", default="60", metavar="SECONDS",
                        help="wall-clock seconds between checkpoints (default 60)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                        help="progress on stderr (default: simulate when stderr is a terminal, "
                        "ensemble unless --json)")


def model_params(args, model: Model, *, sweep: bool) -> dict:
    """{name: value} of the parameters given on the command line (``sweep``: a list of values
    where a comma list was given), each checked by ``Parameter.parse``; the others are left to
    the factory's defaults.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options.
    model : particles.models.Model
        The catalogue entry of the model.
    sweep : bool
        If true, a comma list gives a list of values (one value stays a scalar).

    Returns
    -------
    dict
        {parameter name: parsed value or list of values} of the options given.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From the parsers it calls, for a value that is not valid for its parameter, or (sweep)
        for a list that gives one value twice, however spelled (``0,-0``; ``1000,1e3``).
    """
    params = {}
    for p in model.parameters:
        text, label = _given(args, p)
        if text is None:
            continue
        try:
            params[p.name] = _parsed(p, text, sweep)
        except InvalidArgumentError as exc:
            if label == p.label or exc.name not in (p.name, p.label):
                raise
            raise InvalidArgumentError(label, exc.value, exc.expected) from None  # --rate
    return params


def _parsed(p, text, sweep: bool):
    """The value (``sweep``: the values) of parameter ``p`` given as ``text``."""
    if isinstance(text, bool):  # the switch of a flag
        return text
    if not sweep:
        return p.parse(text)
    values = [p.parse(part) for part in parse_name_list(text, p.name, repeats=True)]
    for i, value in enumerate(values):  # "0.5,0.50" or "1e3,1000": one value twice
        if value in values[:i]:
            raise InvalidArgumentError(p.label, text, f"distinct values ({value!r} is "
                                       "given twice)")
    return values if len(values) > 1 else values[0]


def time_option(args, model: Model, time_name: str) -> tuple[str, str]:
    """(name, text) of the time option given; it must be ``time_name``, the engine's.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options.
    model : particles.models.Model
        The catalogue entry of the model.
    time_name : str
        The time the engine records at: ``"tau"`` (collisions per particle) or ``"t"``
        (physical time).

    Returns
    -------
    tuple of (str, str)
        The option's name and its text (the unparsed list of times).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If the time was given under the other name than ``time_name``, or not at all.
    """
    for name in model.time_names:
        text = getattr(args, f"times_{name}", None)
        if text is not None:
            if name != time_name:
                raise InvalidArgumentError(
                    name, text, f"times given as --{time_name} (the time of this {model.name} "
                    f"engine is {time_name})"
                )
            return name, text
    raise InvalidArgumentError(time_name, None, f"--{time_name} T1,T2,...")  # pragma: no cover
