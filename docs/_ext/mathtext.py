"""Typeset the TeX fragments of plain-text docstrings and help texts.

Docstrings and help texts are written to be read in a terminal: ``e^{−λτ}``, ``t^{2/3}`` and
``min_{a < b}`` are plain text there.  On the site such a fragment is typeset:
:func:`typeset` wraps each run of non-blank characters holding ``^{`` or ``_{`` (a brace group
may hold blanks: ``e^{s_min + j h}``) in a ``:math:`` role, leaving ``literals``, roles and the
punctuation around the run alone.
"""

from __future__ import annotations

import re

_LITERAL = re.compile(r"(``.*?``|:[a-z:]+:`[^`]*`|`[^`]*`)")
_MARK = re.compile(r"[\^_]\{")
_OPEN = "([\"'“‘"
_CLOSE = ")].,;:!?\"'”’"


def _end(text: str, i: int) -> int:
    """The end of the run of non-blank characters from ``i``, brace groups included; -1 when a
    brace is left open."""
    depth = 0
    while i < len(text):
        c = text[i]
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth < 0:
                return -1
        elif c.isspace() and depth == 0:
            return i
        i += 1
    return i if depth == 0 else -1


def _typeset_text(text: str) -> str:
    out, pos = [], 0
    for m in _MARK.finditer(text):
        if m.start() < pos:
            continue
        start = m.start()
        while start > pos and not text[start - 1].isspace():
            start -= 1
        end = _end(text, start)
        if end < 0 or "`" in text[start:end]:
            continue
        word = text[start:end]
        head = len(word) - len(word.lstrip(_OPEN))
        core = word[head:]
        tail = ""
        while core and core[-1] in _CLOSE:
            c = core[-1]
            # a closing bracket stays inside when the core opens it
            if c in ")]" and core.count("([" [")]".index(c)]) >= core.count(c):
                break
            core, tail = core[:-1], c + tail
        if not _MARK.search(core):
            continue
        out.append(text[pos:start] + word[:head] + f":math:`{core}`" + tail)
        pos = end
    out.append(text[pos:])
    return "".join(out)


def typeset(line: str) -> str:
    """``line`` with each run holding ``^{`` or ``_{`` outside literals and roles wrapped in a
    ``:math:`` role."""
    parts = _LITERAL.split(line)
    for j in range(0, len(parts), 2):
        parts[j] = _typeset_text(parts[j])
    return "".join(parts)
