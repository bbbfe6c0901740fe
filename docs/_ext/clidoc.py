"""The real parser of ``maxwell-kinetics``, its help texts escaped for reStructuredText.

The help strings are plain text written for a terminal (``|v|`` is an absolute value, not a
substitution); sphinx-argparse renders them as reStructuredText, so this module builds the
parser with :func:`maxwell_kinetics.app.cli.build_parser` and escapes what reStructuredText would
misread.  Options, defaults and choices are those of the real parser.
"""

from __future__ import annotations

import argparse
import re

from mathtext import typeset

from maxwell_kinetics.app.cli import build_parser

_LITERAL = re.compile(r"(``.*?``|:math:`[^`]*`)", re.S)


def _escape(text):
    if not text:
        return text
    text = re.sub(r":[a-z:]+:`~?\.?([^`]*)`", r"``\1``", text)
    text = "\n".join(typeset(line) for line in text.split("\n"))
    parts = _LITERAL.split(text)
    for j in range(0, len(parts), 2):
        parts[j] = re.sub(r"([|`*])", r"\\\1", parts[j])
    return "".join(parts)


def _walk(parser: argparse.ArgumentParser) -> None:
    parser.description = _escape(parser.description)
    parser.epilog = _escape(parser.epilog)
    for action in parser._actions:
        action.help = _escape(action.help)
        if isinstance(action, argparse._SubParsersAction):
            for choice in action._choices_actions:
                choice.help = _escape(choice.help)
            for sub in action.choices.values():
                _walk(sub)


def parser() -> argparse.ArgumentParser:
    """The command line's parser, help texts escaped for reStructuredText."""
    p = build_parser()
    _walk(p)
    return p
