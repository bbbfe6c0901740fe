"""Exact parsing of command-line text into typed values: lists of numbers and of names,
integers and counts (as decimals, never through a binary float) and seeds.

The command line only turns text into values here; every rule on the values themselves lives
once, in :mod:`particles.validation`.  A failure raises
:class:`particles.validation.InvalidArgumentError` naming the option and showing the text.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .validation import InvalidArgumentError, check_seed, number_text_problem

__all__ = [
    "parse_float_list",
    "parse_name_list",
    "parse_int",
    "parse_count",
    "parse_seed",
]


def _split_list(text: str, name: str, what: str) -> list[str]:
    """The elements of a comma-separated list; an empty list or an empty element is refused."""
    parts = [p.strip() for p in text.split(",")]
    if not text.strip() or any(not p for p in parts):
        raise InvalidArgumentError(name, text, f"a comma-separated list of {what} with no empty "
                                   "elements")
    return parts


def parse_float_list(text: str | Sequence[float], name: str) -> list[float]:
    """Parse a comma-separated list of numbers such as ``"1,10,100"`` (for the command line).

    Empty elements (``"1,,2"``, ``","``) and an empty list are refused, and so are non-finite
    values (``nan``, ``inf``, ``1e400``) and repeated values: equal numbers spelled differently
    (``0,-0`` or ``1000,1000.0``) are repeats.  A sequence that is not a string is checked the
    same way element by element (booleans and complex numbers are refused).

    Parameters
    ----------
    text : str or sequence of float
        The list as text, or already as numbers.
    name : str
        The option name shown in the error.

    Returns
    -------
    list of float
        The numbers, in order.

    Raises
    ------
    particles.InvalidArgumentError
        If the text is empty, has an empty element, an element is not a finite number, or a
        value is repeated (naming ``name``).
    """
    if isinstance(text, str):
        parts = _split_list(text, name, "numbers")
    else:
        try:
            parts = list(text)
        except TypeError:
            raise InvalidArgumentError(name, text, "a list of numbers") from None
        if not parts:
            raise InvalidArgumentError(name, text, "a non-empty list of numbers")
    out = []
    for part in parts:
        if isinstance(part, (bool, np.bool_, complex, np.complexfloating)) or not isinstance(
                part, (str, int, float, np.integer, np.floating)):
            raise InvalidArgumentError(name, text, "a list of real numbers")
        try:
            value = float(part)
        except (ValueError, OverflowError):
            raise InvalidArgumentError(name, text, "a comma-separated list of numbers") from None
        if not math.isfinite(value):
            raise InvalidArgumentError(name, text, f"finite numbers (got {part!s})")
        if isinstance(part, str):
            problem = number_text_problem(part, value)
            if problem:
                raise InvalidArgumentError(name, text, f"{problem} (got {part})")
        out.append(value + 0.0)  # "-0" is 0.0
    seen: set[float] = set()
    for value in out:  # 0.0 == -0.0, so "0,-0" is a repeat
        if value in seen:
            raise InvalidArgumentError(name, text, f"distinct values ({value + 0.0:g} is repeated)")
        seen.add(value)
    return out


def parse_name_list(text: str, name: str, *, repeats: bool = False) -> list[str]:
    """Parse a comma-separated list of names (``--only a,b``).

    Parameters
    ----------
    text : str
        The list as text; surrounding spaces of each element are stripped.
    name : str
        The option name shown in the error.
    repeats : bool, default False
        Let a name repeat (for a caller that refuses repeats itself, once the elements are
        parsed into values: ``0.3,0.3`` is then a repeated value, not a repeated name).

    Returns
    -------
    list of str
        The names, in the order given.

    Raises
    ------
    particles.InvalidArgumentError
        If the list is empty, has an empty element, or repeats a name (unless ``repeats``;
        naming ``name``).
    """
    parts = _split_list(str(text), name, "names")
    if not repeats and len(set(parts)) != len(parts):
        raise InvalidArgumentError(name, text, "a list of names without repeats")
    return parts


def parse_int(text, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """Parse an exact integer from the command line.

    ``200000``, ``2e5`` and ``2.0e5`` are accepted when exactly integral; the text is parsed as a
    decimal, never through a binary float, so 9007199254740993 stays itself.  ``1.5`` or ``1e-3``
    are refused, and so are exponents beyond 4000 in magnitude.  An ``int`` is taken as it is.

    Parameters
    ----------
    text : str or int
        The value.
    name : str
        The option name shown in the error.
    minimum, maximum : int or None, optional
        Inclusive bounds; None (default) leaves that side open.

    Returns
    -------
    int
        The integer.

    Raises
    ------
    particles.InvalidArgumentError
        If ``text`` is a bool, not a decimal number, not integral, or out of bounds (naming
        ``name``).
    """
    from decimal import Decimal, InvalidOperation

    expected = "an integer"
    if minimum is not None:
        expected += f" >= {minimum}"
    if maximum is not None:
        expected += f" and <= {maximum}" if minimum is not None else f" <= {maximum}"
    if isinstance(text, bool):
        raise InvalidArgumentError(name, text, expected)
    if isinstance(text, int):
        value = text
    else:
        raw = str(text).strip()
        if "_" in raw:
            raise InvalidArgumentError(name, text, expected + " written without underscores")
        try:
            d = Decimal(raw)
        except InvalidOperation:
            raise InvalidArgumentError(name, text, expected) from None
        if not d.is_finite() or d != d.to_integral_value() or abs(d.adjusted()) > 4000:
            raise InvalidArgumentError(name, text, expected)
        value = int(d)
    if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
        raise InvalidArgumentError(name, text, expected)
    return value


def parse_count(text, name: str, minimum: int) -> int:
    """Parse an integer option given as ``200000`` or ``2e5`` (exactly integral), ``>= minimum``.

    The same as :func:`parse_int` with only a lower bound.

    Parameters
    ----------
    text : str or int
        The value.
    name : str
        The option name shown in the error.
    minimum : int
        The smallest accepted value (inclusive).

    Returns
    -------
    int
        The count.

    Raises
    ------
    particles.InvalidArgumentError
        From :func:`parse_int`, if the value is not an integer ``>= minimum``.
    """
    return parse_int(text, name, minimum)


def parse_seed(text, name: str = "seed") -> int:
    """Parse a random seed: an exact integer in [0, 2**64 - 1]
    (:func:`particles.validation.check_seed`).

    Parameters
    ----------
    text : str or int
        The seed.
    name : str, optional
        The option name shown in the error (default ``"seed"``).

    Returns
    -------
    int
        The seed, stored exactly.

    Raises
    ------
    particles.InvalidArgumentError
        From :func:`parse_int`, if the value is not an integer in that range.
    """
    value = parse_int(text, name)
    try:
        return check_seed(value, name)
    except InvalidArgumentError:
        raise InvalidArgumentError(name, text, "an integer in [0, 2**64 - 1]") from None
