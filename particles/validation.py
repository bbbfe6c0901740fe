"""Input checks shared by both packages (NumPy only).

Every public entry point checks its arguments once, here, and a failure names the
argument and shows the value received.  ``InvalidArgumentError`` subclasses
``ValueError`` so callers may catch either.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

__all__ = [
    "InvalidArgumentError",
    "check_restitution",
    "check_times",
    "check_count",
    "check_positive",
    "check_nonnegative",
    "parse_float_list",
    "parse_name_list",
    "parse_int",
    "parse_count",
    "parse_seed",
    "check_output_file",
    "check_path",
    "check_choice",
    "check_output_dir",
]


class InvalidArgumentError(ValueError):
    """A public function received an argument outside its domain."""

    def __init__(self, name: str, value, expected: str):
        self.name = name
        self.value = value
        self.expected = expected
        super().__init__(f"argument {name!s}={value!r} is invalid: expected {expected}")


def _as_float(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, value, "a real number") from None
    if not math.isfinite(x):
        raise InvalidArgumentError(name, value, "a finite real number")
    return x


def check_restitution(r, name: str = "restitution") -> float:
    """Restitution coefficient r must be finite and lie in [0, 1]."""
    x = _as_float(name, r)
    if not 0.0 <= x <= 1.0:
        raise InvalidArgumentError(name, r, "a number in [0, 1]")
    return x


def check_positive(value, name: str) -> float:
    x = _as_float(name, value)
    if x <= 0.0:
        raise InvalidArgumentError(name, value, "a finite number > 0")
    return x


def check_nonnegative(value, name: str) -> float:
    x = _as_float(name, value)
    if x < 0.0:
        raise InvalidArgumentError(name, value, "a finite number >= 0")
    return x


def check_count(value, name: str, minimum: int) -> int:
    """An integer count (number of particles, grid points) of at least ``minimum``."""
    if isinstance(value, bool):
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}")
    try:
        as_int = int(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}") from None
    if as_int != value or as_int < minimum:
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}")
    return as_int


def check_times(times, name: str = "tau", *, strictly: bool = True) -> np.ndarray:
    """A non-empty list of finite, non-negative, increasing times.

    ``strictly=True`` demands strictly increasing values (no repeats).
    """
    if np.isscalar(times):
        times = [times]
    try:
        arr = np.asarray(times, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, times, "a list of real numbers") from None
    shown = times if not isinstance(times, np.ndarray) else times.tolist()
    if arr.ndim != 1 or arr.size == 0:
        raise InvalidArgumentError(name, shown, "a non-empty one-dimensional list of times")
    if not np.all(np.isfinite(arr)):
        raise InvalidArgumentError(name, shown, "finite times")
    if np.any(arr < 0):
        raise InvalidArgumentError(name, shown, "times >= 0")
    steps = np.diff(arr)
    if np.any(steps <= 0 if strictly else steps < 0):
        raise InvalidArgumentError(name, shown, "increasing times")
    return arr


def _split_list(text: str, name: str, what: str) -> list[str]:
    """The elements of a comma-separated list; an empty list or an empty element is refused."""
    parts = [p.strip() for p in text.split(",")]
    if not text.strip() or any(not p for p in parts):
        raise InvalidArgumentError(name, text, f"a comma-separated list of {what} with no empty "
                                   "elements")
    return parts


def parse_float_list(text: str | Sequence[float], name: str) -> list[float]:
    """Parse a comma-separated list such as ``"1,10,100"`` (for the command line).  Empty
    elements (``"1,,2"``, ``","``) and an empty list are refused."""
    if not isinstance(text, str):
        return [float(x) for x in text]
    out = []
    for part in _split_list(text, name, "numbers"):
        try:
            out.append(float(part))
        except ValueError:
            raise InvalidArgumentError(name, text, "a comma-separated list of numbers") from None
    return out


def parse_name_list(text: str, name: str) -> list[str]:
    """A comma-separated list of names (``--only a,b``): no empty elements, no repeats."""
    parts = _split_list(str(text), name, "names")
    if len(set(parts)) != len(parts):
        raise InvalidArgumentError(name, text, "a list of names without repeats")
    return parts


def parse_int(text, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """An exact integer from the command line: ``200000``, ``2e5`` or ``2.0e5`` when exactly
    integral (parsed as a decimal, never through a binary float, so 9007199254740993 stays
    itself); ``1.5`` or ``1e-3`` are refused.  Optional bounds are inclusive."""
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
    """An integer option given as ``200000`` or ``2e5`` (exactly integral); errors name the
    option and the value."""
    return parse_int(text, name, minimum)


#: Seeds are any integer in [0, 2**64 - 1], stored exactly.
SEED_MAX = 2**64 - 1


def parse_seed(text, name: str = "seed") -> int:
    """A seed: an exact integer in [0, 2**64 - 1]."""
    return parse_int(text, name, 0, SEED_MAX)


def check_path(path, name: str) -> Path:
    """A file-system path: a ``str`` (non-empty) or an ``os.PathLike``; anything else (None, a
    number, a list) is refused here instead of failing deep inside with a TypeError."""
    if isinstance(path, (str, os.PathLike)) and str(path) != "":
        return Path(path)
    raise InvalidArgumentError(name, path, "a file path (str or os.PathLike)")


def check_choice(value, name: str, choices) -> str:
    """``value`` must be one of ``choices`` (strings); unhashable values are refused cleanly."""
    if isinstance(value, str) and value in choices:
        return value
    raise InvalidArgumentError(name, value, f"one of {sorted(choices)}")


def check_output_file(path, name: str) -> Path:
    """An output file: not an existing directory, in an existing, writable directory.

    Called before any work so that a bad path fails at once and nothing else is written.
    """
    out = check_path(path, name)
    if out.is_dir():
        raise InvalidArgumentError(name, str(path), "a file path, not an existing directory")
    if not out.parent.is_dir() or not os.access(out.parent, os.W_OK):
        raise InvalidArgumentError(name, str(path), "a file in an existing, writable directory")
    return out


def check_output_dir(path, name: str) -> Path:
    """An output folder: an existing writable directory, or one that can be created (its
    nearest existing ancestor is a writable directory)."""
    out = Path(path)
    if out.exists():
        if not out.is_dir() or not os.access(out, os.W_OK):
            raise InvalidArgumentError(name, str(path), "a writable directory")
        return out
    ancestor = out.absolute().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir() or not os.access(ancestor, os.W_OK):
        raise InvalidArgumentError(
            name, str(path), "a directory that can be created (under a writable directory)"
        )
    return out
