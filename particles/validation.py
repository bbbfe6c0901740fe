"""Input checks shared by both packages (NumPy only).

Every public entry point checks its arguments once, here, and a failure names the
argument and shows the value received.  ``InvalidArgumentError`` subclasses
``ValueError`` so callers may catch either.
"""

from __future__ import annotations

import math
import os
import stat
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
    "output_target",
    "file_kind",
    "check_workers",
    "max_workers",
    "check_path",
    "check_choice",
    "check_output_dir",
]


class InvalidArgumentError(ValueError):
    """A public function received an argument outside its domain.

    Its message is ``argument NAME=VALUE is invalid: expected EXPECTED``; the command line
    prints it and exits with status 2.

    Parameters
    ----------
    name : str
        The argument's name.
    value : object
        The value received.
    expected : str
        What the argument accepts.
    """

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
    """Restitution coefficient r must be finite and lie in [0, 1].

    Parameters
    ----------
    r : float
        The value.
    name : str
        The argument's name, for the message.

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    x = _as_float(name, r)
    if not 0.0 <= x <= 1.0:
        raise InvalidArgumentError(name, r, "a number in [0, 1]")
    return x


def check_positive(value, name: str) -> float:
    """A finite number > 0.

    Parameters
    ----------
    value : float
        The value.
    name : str
        The argument's name, for the message.

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    x = _as_float(name, value)
    if x <= 0.0:
        raise InvalidArgumentError(name, value, "a finite number > 0")
    return x


def check_nonnegative(value, name: str) -> float:
    """A finite number ≥ 0.

    Parameters
    ----------
    value : float
        The value.
    name : str
        The argument's name, for the message.

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    x = _as_float(name, value)
    if x < 0.0:
        raise InvalidArgumentError(name, value, "a finite number >= 0")
    return x


def check_count(value, name: str, minimum: int) -> int:
    """An integer count (number of particles, grid points) of at least ``minimum``.

    Parameters
    ----------
    value : int
        The value (an exact integer; ``True`` and floats are refused).
    name : str
        The argument's name, for the message.
    minimum : int
        The smallest value accepted.

    Returns
    -------
    int

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
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

    Parameters
    ----------
    times : array_like
        The times.
    name : str
        The argument's name, for the message.
    strictly : bool
        Refuse repeated values.

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
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
    elements (``"1,,2"``, ``","``) and an empty list are refused.

    Parameters
    ----------
    text : str or sequence of float
        The list.
    name : str
        The argument's name, for the message.

    Returns
    -------
    list of float

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
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
    """A comma-separated list of names (``--only a,b``): no empty elements, no repeats.

    Parameters
    ----------
    text : str
        The list.
    name : str
        The argument's name, for the message.

    Returns
    -------
    list of str

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    parts = _split_list(str(text), name, "names")
    if len(set(parts)) != len(parts):
        raise InvalidArgumentError(name, text, "a list of names without repeats")
    return parts


def parse_int(text, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """An exact integer from the command line: ``200000``, ``2e5`` or ``2.0e5`` when exactly
    integral (parsed as a decimal, never through a binary float, so 9007199254740993 stays
    itself); ``1.5`` or ``1e-3`` are refused.  Optional bounds are inclusive.

    Parameters
    ----------
    text : str or int
        The text.
    name : str
        The argument's name, for the message.
    minimum, maximum : int, optional
        Inclusive bounds.

    Returns
    -------
    int

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
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
    option and the value.

    Parameters
    ----------
    text : str or int
        The text.
    name : str
        The argument's name, for the message.
    minimum : int
        The smallest value accepted.

    Returns
    -------
    int
    """
    return parse_int(text, name, minimum)


#: Seeds are any integer in [0, 2**64 - 1], stored exactly.
SEED_MAX = 2**64 - 1


def parse_seed(text, name: str = "seed") -> int:
    """A seed: an exact integer in [0, 2**64 - 1].

    Parameters
    ----------
    text : str or int
        The text.
    name : str
        The argument's name, for the message.

    Returns
    -------
    int
    """
    return parse_int(text, name, 0, SEED_MAX)


def check_path(path, name: str) -> Path:
    """A file-system path: a ``str`` (non-empty) or an ``os.PathLike``; anything else (None, a
    number, a list) is refused here instead of failing deep inside with a TypeError.

    Parameters
    ----------
    path : str or os.PathLike
        The path.
    name : str
        The argument's name, for the message.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    if isinstance(path, (str, os.PathLike)) and str(path) != "":
        return Path(path)
    raise InvalidArgumentError(name, path, "a file path (str or os.PathLike)")


def check_choice(value, name: str, choices) -> str:
    """``value`` must be one of ``choices`` (strings); unhashable values are refused cleanly.

    Parameters
    ----------
    value : str
        The value.
    name : str
        The argument's name, for the message.
    choices : sequence of str
        The values accepted.

    Returns
    -------
    str

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    if isinstance(value, str) and value in choices:
        return value
    raise InvalidArgumentError(name, value, f"one of {sorted(choices)}")


def file_kind(path) -> str | None:
    """What exists at ``path`` without following a final symlink: ``None`` (nothing),
    ``"regular file"``, ``"directory"``, ``"symlink"``, ``"character device"``,
    ``"block device"``, ``"FIFO"``, ``"socket"`` or ``"special file"``.

    Parameters
    ----------
    path : str or os.PathLike
        The path.

    Returns
    -------
    str or None
    """
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None
    except OSError:  # e.g. a component that is a file: nothing can exist there
        return None
    for test, kind in ((stat.S_ISREG, "regular file"), (stat.S_ISDIR, "directory"),
                       (stat.S_ISLNK, "symlink"), (stat.S_ISCHR, "character device"),
                       (stat.S_ISBLK, "block device"), (stat.S_ISFIFO, "FIFO"),
                       (stat.S_ISSOCK, "socket")):
        if test(mode):
            return kind
    return "special file"


def output_target(path, name: str) -> Path:
    """The file an output written to ``path`` replaces: ``path`` itself, or the file a symlink
    (or a chain of them) points to, so that a link stays a link and its target is written.

    Refused (:class:`InvalidArgumentError` naming ``name``, the path and what it is): an
    existing directory (or a link to one), and anything that is not a regular file: a character
    or block device (``/dev/null`` included), a FIFO, a socket.  Writing replaces the file by a
    rename, which would turn such an object into a regular file (as root, ``/dev/null`` itself);
    to discard an output, leave the option out.  A dangling link is resolved to the file it
    names, which is then created.

    Parameters
    ----------
    path : str or os.PathLike
        The path.
    name : str
        The argument's name, for the message.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    out = check_path(path, name)
    target = Path(os.path.realpath(out)) if file_kind(out) == "symlink" else out
    kind = file_kind(target)
    if kind == "directory":
        shown = "a symlink to a directory" if target != out else "an existing directory"
        raise InvalidArgumentError(name, str(path), f"a file path, not {shown}")
    if kind not in (None, "regular file"):
        via = f" (through the symlink to {target})" if target != out else ""
        raise InvalidArgumentError(
            name, str(path),
            f"a regular file or a new path, not a {kind}{via}: output is written to a new file "
            "and renamed into place, which would replace it",
        )
    return target


def check_output_file(path, name: str) -> Path:
    """An output file: a regular file or a new path (:func:`output_target`: never a device, a
    FIFO, a socket or a directory; a symlink is followed), in an existing, writable directory.

    Called before any work so that a bad path fails at once and nothing else is written.

    Parameters
    ----------
    path : str or os.PathLike
        The path.
    name : str
        The argument's name, for the message.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    out = check_path(path, name)
    target = output_target(out, name)
    if not target.parent.is_dir() or not os.access(target.parent, os.W_OK):
        raise InvalidArgumentError(name, str(path), "a file in an existing, writable directory")
    return out


def check_output_dir(path, name: str) -> Path:
    """An output folder: an existing writable directory (or a symlink to one), or one that can
    be created (its nearest existing ancestor is a writable directory).  Anything else that
    exists there (a file, a device, a FIFO, a socket) is refused, naming what it is.

    Parameters
    ----------
    path : str or os.PathLike
        The folder.
    name : str
        The argument's name, for the message.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    out = check_path(path, name)
    if out.exists() or file_kind(out) is not None:
        if not out.is_dir():
            kind = file_kind(Path(os.path.realpath(out))) or "dangling symlink"
            raise InvalidArgumentError(name, str(path), f"a writable directory, not a {kind}")
        if not os.access(out, os.W_OK):
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


def max_workers() -> int:
    """The largest worker count accepted without ``force``: 4 × the CPUs of this machine.

    More processes than that only compete for the same cores (each worker is a process with
    its own interpreter and imports, about a second and 100 MB to start); a bigger number is
    almost always a typo (``--workers 64`` for ``4``).

    Returns
    -------
    int
    """
    return 4 * (os.cpu_count() or 1)


def check_workers(workers, name: str = "workers", *, tasks: int | None = None,
                  force: bool = False) -> int | None:
    """A worker count: an integer ≥ 1, at most :func:`max_workers` unless ``force``, and
    never more than ``tasks`` (the count is lowered to it: idle workers cost start-up time and
    memory and do nothing).  ``None`` stays ``None`` (the caller's default).

    Parameters
    ----------
    workers : int or None
        The count asked for.
    name : str
        The argument's name, for the message.
    tasks : int, optional
        The number of tasks (the count is lowered to it).
    force : bool
        Allow more than :func:`max_workers`.

    Returns
    -------
    int or None

    Raises
    ------
    InvalidArgumentError
        Naming ``name`` and the value received.
    """
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise InvalidArgumentError(name, workers, "an integer >= 1")
    workers = int(workers)
    bound = max_workers()
    if workers > bound and not force:
        raise InvalidArgumentError(
            name, workers,
            f"at most {bound} (4 x the {os.cpu_count() or 1} CPUs of this machine); "
            "give --force (force=True) to start more",
        )
    if tasks is not None:
        workers = max(1, min(workers, int(tasks)))
    return workers
