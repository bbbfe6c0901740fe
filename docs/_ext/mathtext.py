"""Typeset the TeX fragments of plain-text docstrings and help texts.

Docstrings and help texts are written to be read in a terminal: ``e^{−λτ}``, ``t^{2/3}`` and
``G_{free}`` are plain text there.  On the site such a fragment is typeset: :func:`typeset`
wraps each whitespace-delimited word holding ``^{`` or ``_{`` (its braces balanced) in a
``:math:`` role, leaving ``literals``, roles and the punctuation around the word alone.
"""

from __future__ import annotations

import re

_LITERAL = re.compile(r"(``.*?``|:[a-z:]+:`[^`]*`|`[^`]*`)")
_WORD = re.compile(r"\S+")
_MARK = re.compile(r"[\^_]\{")


def _wrap(word: str) -> str:
    if not _MARK.search(word) or word.count("{") != word.count("}"):
        return word
    head = re.match(r"[(\[\"'“‘]*", word).group(0)
    tail = re.search(r"[)\].,;:!?\"'”’]*$", word[len(head):]).group(0)
    core = word[len(head):len(word) - len(tail)]
    # keep a closing bracket inside when the core opens it
    while tail and tail[0] in ")]" and core.count("([" [")]".index(tail[0])]) > core.count(tail[0]):
        core, tail = core + tail[0], tail[1:]
    if not _MARK.search(core) or "`" in core:
        return word
    return f"{head}:math:`{core}`{tail}"


def typeset(line: str) -> str:
    """``line`` with each word holding ``^{`` or ``_{`` outside literals and roles wrapped in
    a ``:math:`` role."""
    parts = _LITERAL.split(line)
    for j in range(0, len(parts), 2):
        parts[j] = _WORD.sub(lambda m: _wrap(m.group(0)), parts[j])
    return "".join(parts)
