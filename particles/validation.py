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
    "check_real",
    "check_dimension",
    "check_real_array",
    "check_edges",
    "check_fit_points",
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
    "shown",
    "SHOWN_CHARACTERS",
]


class InvalidArgumentError(ValueError):
    """A public function received an argument outside its domain.

    Subclasses ``ValueError``, so callers may catch either.  The message names the argument, shows
    the value received and says what was expected; the command line maps this error to exit
    status 2.  The three arguments are kept as the attributes ``name``, ``value`` and
    ``expected``.

    Parameters
    ----------
    name : str
        The name of the argument (or command-line option) that was refused.
    value : object
        The value received, shown with ``repr`` in the message, cut to its first
        :data:`SHOWN_CHARACTERS` characters (and ``...``) when longer; the attribute keeps it
        whole.
    expected : str
        What the argument should have been, in words (e.g. ``"a number in [0, 1]"``).
    """

    def __init__(self, name: str, value, expected: str):
        self.name = name
        self.value = value
        self.expected = expected
        super().__init__(f"argument {name!s}={shown(value)} is invalid: expected {expected}")


#: The most characters of a value's ``repr`` that an error message shows.
SHOWN_CHARACTERS = 200


def shown(value) -> str:
    """``repr(value)`` cut to :data:`SHOWN_CHARACTERS` characters (then ``...`` and the length).

    Parameters
    ----------
    value : object
        Anything; a ``repr`` that fails is replaced by the type's name.

    Returns
    -------
    str
        The text shown for ``value`` in an error message.
    """
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 - a message must never fail
        text = f"<{type(value).__name__}>"
    if len(text) <= SHOWN_CHARACTERS:
        return text
    return f"{text[:SHOWN_CHARACTERS]}... ({len(text)} characters)"


def _is_bool(value) -> bool:
    return isinstance(value, (bool, np.bool_))


def _is_complex(value) -> bool:
    return isinstance(value, (complex, np.complexfloating))


def _as_float(name: str, value) -> float:
    """``value`` as a finite float; booleans and complex numbers are refused, not converted."""
    if _is_bool(value) or _is_complex(value):
        raise InvalidArgumentError(name, value, "a real number")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, value, "a real number") from None
    except OverflowError:  # an int beyond the float range
        raise InvalidArgumentError(name, value, "a finite real number") from None
    if not math.isfinite(x):
        raise InvalidArgumentError(name, value, "a finite real number")
    return x


def check_real(value, name: str) -> float:
    """Check a finite real number (any sign); booleans and complex numbers are refused.

    Parameters
    ----------
    value : float or str
        The value; anything ``float()`` accepts except a bool or a complex number.
    name : str
        The argument name shown in the error.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not a finite real number (naming ``name``).
    """
    return _as_float(name, value)


def check_restitution(r, name: str = "restitution") -> float:
    """Check a restitution coefficient r: a finite real number in [0, 1].

    r = 1 is an elastic collision, r = 0 the perfectly inelastic (sticky) limit.

    Parameters
    ----------
    r : float or str
        The restitution coefficient; anything ``float()`` accepts.
    name : str, optional
        The argument name shown in the error (default ``"restitution"``).

    Returns
    -------
    float
        ``r`` as a float.

    Raises
    ------
    particles.InvalidArgumentError
        If ``r`` is not a real number, not finite, or outside [0, 1] (naming ``name``).
    """
    x = _as_float(name, r)
    if not 0.0 <= x <= 1.0:
        raise InvalidArgumentError(name, r, "a number in [0, 1]")
    return x


def check_positive(value, name: str) -> float:
    """Check a finite real number strictly greater than zero (a density, a length, a time).

    Parameters
    ----------
    value : float or str
        The value; anything ``float()`` accepts.
    name : str
        The argument name shown in the error.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not a real number, not finite, or ``<= 0`` (naming ``name``).
    """
    x = _as_float(name, value)
    if x <= 0.0:
        raise InvalidArgumentError(name, value, "a finite number > 0")
    return x


def check_nonnegative(value, name: str) -> float:
    """Check a finite real number greater than or equal to zero.

    Parameters
    ----------
    value : float or str
        The value; anything ``float()`` accepts.
    name : str
        The argument name shown in the error.

    Returns
    -------
    float
        ``value`` as a float (``-0.0`` as ``0.0``).

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not a real number, not finite, or negative (naming ``name``).
    """
    x = _as_float(name, value)
    if x < 0.0:
        raise InvalidArgumentError(name, value, "a finite number >= 0")
    return x + 0.0  # -0.0 is 0.0 (never shown as -0 in parameters or output)


def check_count(value, name: str, minimum: int) -> int:
    """Check an integer count (number of particles, grid points) of at least ``minimum``.

    A float is accepted only when it equals an integer (``8.0``); booleans (NumPy's included),
    complex numbers and strings are refused.

    Parameters
    ----------
    value : int
        The count.
    name : str
        The argument name shown in the error.
    minimum : int
        The smallest accepted value (inclusive).

    Returns
    -------
    int
        ``value`` as an ``int``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is a bool, complex, a string, not integral, or below ``minimum`` (naming
        ``name``).
    """
    if _is_bool(value) or _is_complex(value) or isinstance(value, str):
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}")
    try:
        as_int = int(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}") from None
    if as_int != value or as_int < minimum:
        raise InvalidArgumentError(name, value, f"an integer >= {minimum}")
    return as_int


def check_dimension(value, name: str = "dimension") -> int:
    """Check a space dimension d ∈ {1, 2, 3}: an integer (``2.0`` accepted), never a bool, a
    complex number or a string.

    Parameters
    ----------
    value : int
        The dimension.
    name : str, optional
        The argument name shown in the error (default ``"dimension"``).

    Returns
    -------
    int
        ``value`` as an ``int``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not 1, 2 or 3 as a real number (naming ``name``).
    """
    if (_is_bool(value) or not isinstance(value, (int, float, np.integer, np.floating))
            or value not in (1, 2, 3)):
        raise InvalidArgumentError(name, value, "1, 2 or 3")
    return int(value)


def check_real_array(values, name: str, *, ndim: int | None = None, min_size: int = 0,
                     finite: bool = True) -> np.ndarray:
    """Check an array of real numbers (for the numerical functions' array arguments).

    Booleans, complex numbers, strings and other objects are refused, not converted; a scalar is
    a 0-dimensional array.

    Parameters
    ----------
    values : array_like
        The values.
    name : str
        The argument name shown in the error.
    ndim : int, optional
        The required number of dimensions (any when None).
    min_size : int, optional
        The fewest elements accepted (default 0).
    finite : bool, optional
        If True (default), NaN and ±inf are refused.

    Returns
    -------
    numpy.ndarray
        ``values`` as a float array.

    Raises
    ------
    particles.InvalidArgumentError
        If ``values`` is not real, has the wrong number of dimensions, fewer than ``min_size``
        elements, or (``finite``) a non-finite element (naming ``name``).
    """
    try:
        raw = np.asarray(values)
        if raw.dtype.kind not in "iuf" and not (raw.dtype == object and all(
                isinstance(x, (int, float, np.integer, np.floating)) and not _is_bool(x)
                for x in raw.ravel())):
            raise TypeError("not real numbers")
        arr = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise InvalidArgumentError(name, _summary(values), "an array of real numbers") from None
    if ndim is not None and arr.ndim != ndim:
        raise InvalidArgumentError(name, _summary(values), f"a {ndim}-dimensional array "
                                   f"(got shape {arr.shape})")
    if arr.size < min_size:
        raise InvalidArgumentError(name, _summary(values), f"at least {min_size} values")
    if finite and not np.all(np.isfinite(arr)):
        raise InvalidArgumentError(name, _summary(values), "finite values (no NaN or inf)")
    return arr


def check_edges(edges, name: str = "edges") -> np.ndarray:
    """Check histogram bin edges: at least two finite, strictly increasing real numbers.

    Parameters
    ----------
    edges : array_like
        The edges.
    name : str, optional
        The argument name shown in the error (default ``"edges"``).

    Returns
    -------
    numpy.ndarray
        The edges as a one-dimensional float array.

    Raises
    ------
    particles.InvalidArgumentError
        If they are not real, not one-dimensional, fewer than two, not finite (NaN inside
        included) or not strictly increasing (naming ``name``).
    """
    arr = check_real_array(edges, name, ndim=1, min_size=2)
    if np.any(np.diff(arr) <= 0):
        raise InvalidArgumentError(name, _summary(edges), "strictly increasing edges")
    return arr


def check_fit_points(x, y, *, fewest: int, name_x: str = "x", name_y: str = "y"):
    """Check the points of a least-squares fit: finite, one-dimensional, of one length, with at
    least ``fewest`` distinct abscissae (a fit through repeated x has no unique solution).

    Parameters
    ----------
    x, y : array_like
        Abscissae and ordinates (``y`` may be two-dimensional: one row per run, each of the
        length of ``x``).
    fewest : int
        The fewest distinct x the fit needs (2 for a line; degree + 1 for a polynomial).
    name_x, name_y : str, optional
        The argument names shown in the error.

    Returns
    -------
    tuple of numpy.ndarray
        ``(x, y)`` as float arrays.

    Raises
    ------
    particles.InvalidArgumentError
        For non-real or non-finite values, mismatched lengths, or fewer than ``fewest``
        distinct x (naming the argument).
    """
    x = check_real_array(x, name_x, ndim=1)
    y = check_real_array(y, name_y)
    if y.ndim not in (1, 2) or y.shape[-1] != x.size:
        raise InvalidArgumentError(name_y, _summary(y), f"{x.size} values per row, one per x")
    distinct = np.unique(x).size
    if distinct < fewest:
        raise InvalidArgumentError(name_x, _summary(x), f"at least {fewest} distinct values "
                                   f"(got {distinct}): the fit is not determined")
    return x, y


class _Text:
    """A value shown in an error message by this text (``repr`` gives it unquoted)."""

    def __init__(self, text: str):
        self.text = text

    def __repr__(self) -> str:
        return self.text


def _summary(values):
    """A value for an error message: a small array as a list, a large one by its shape and its
    first values (never converted whole)."""
    if not isinstance(values, np.ndarray):
        return values
    if values.size <= 40:
        return values.tolist()
    head = ", ".join(repr(x) for x in values.ravel()[:8].tolist())
    return _Text(f"array of shape {values.shape}: [{head}, ...]")


def check_times(times, name: str = "tau", *, strictly: bool = True) -> np.ndarray:
    """Check a non-empty list of finite, non-negative, increasing times.

    Used for output times in either time variable (τ, collisions per particle, or physical
    time t); a scalar is taken as a one-element list.

    Parameters
    ----------
    times : float or array_like
        The times.
    name : str, optional
        The argument name shown in the error (default ``"tau"``).
    strictly : bool, optional
        If True (default), the times must be strictly increasing (no repeats); if False, equal
        neighbours are allowed.

    Returns
    -------
    numpy.ndarray
        The times as a one-dimensional float array.

    Raises
    ------
    particles.InvalidArgumentError
        If ``times`` is not numeric (booleans, complex numbers and strings are refused), empty or
        not one-dimensional, contains a non-finite or negative value, or is not increasing
        (naming ``name``).
    """
    if np.isscalar(times):
        times = [times]
    try:
        raw = np.asarray(times)
        if raw.dtype.kind not in "iuf" and not (raw.dtype == object and all(
                isinstance(x, (int, float, np.integer, np.floating)) and not _is_bool(x)
                for x in raw.ravel())):
            raise TypeError("not real numbers")  # booleans, complex, strings, None
        arr = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise InvalidArgumentError(name, times, "a list of real numbers") from None
    given = times if not isinstance(times, np.ndarray) else times.tolist()
    if arr.ndim != 1 or arr.size == 0:
        raise InvalidArgumentError(name, given, "a non-empty one-dimensional list of times")
    if not np.all(np.isfinite(arr)):
        raise InvalidArgumentError(name, given, "finite times")
    if np.any(arr < 0):
        raise InvalidArgumentError(name, given, "times >= 0")
    steps = np.diff(arr)
    if np.any(steps <= 0 if strictly else steps < 0):
        raise InvalidArgumentError(name, given, "increasing times")
    return arr


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
        if _is_bool(part) or _is_complex(part) or not isinstance(
                part, (str, int, float, np.integer, np.floating)):
            raise InvalidArgumentError(name, text, "a list of real numbers")
        try:
            value = float(part)
        except (ValueError, OverflowError):
            raise InvalidArgumentError(name, text, "a comma-separated list of numbers") from None
        if not math.isfinite(value):
            raise InvalidArgumentError(name, text, f"finite numbers (got {part!s})")
        out.append(value + 0.0)  # "-0" is 0.0
    seen: set[float] = set()
    for value in out:  # 0.0 == -0.0, so "0,-0" is a repeat
        if value in seen:
            raise InvalidArgumentError(name, text, f"distinct values ({value + 0.0:g} is repeated)")
        seen.add(value)
    return out


def parse_name_list(text: str, name: str) -> list[str]:
    """Parse a comma-separated list of names (``--only a,b``).

    Parameters
    ----------
    text : str
        The list as text; surrounding spaces of each element are stripped.
    name : str
        The option name shown in the error.

    Returns
    -------
    list of str
        The names, in the order given.

    Raises
    ------
    particles.InvalidArgumentError
        If the list is empty, has an empty element, or repeats a name (naming ``name``).
    """
    parts = _split_list(str(text), name, "names")
    if len(set(parts)) != len(parts):
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


#: Seeds are any integer in [0, 2**64 - 1], stored exactly: the one bound of the library
#: (:func:`particles.simulate`), the command line and the ensembles (:func:`check_seed`).
SEED_MAX = 2**64 - 1


def check_seed(value, name: str = "seed") -> int:
    """Check a random seed: an integer in [0, :data:`SEED_MAX`] = [0, 2**64 - 1] (a float
    only when it equals an integer; booleans refused).  The one seed rule of
    :func:`particles.simulate`, :func:`parse_seed` (the command line) and the ensembles.

    Parameters
    ----------
    value : int
        The seed.
    name : str, optional
        The argument name shown in the error (default ``"seed"``).

    Returns
    -------
    int
        The seed, exactly.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``name``, for a value that is not an integer in [0, 2**64 - 1].
    """
    expected = "an integer in [0, 2**64 - 1]"
    if isinstance(value, (bool, np.bool_)):
        raise InvalidArgumentError(name, value, expected)
    try:
        as_int = int(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidArgumentError(name, value, expected) from None
    if as_int != value or not 0 <= as_int <= SEED_MAX:
        raise InvalidArgumentError(name, value, expected)
    return as_int


def parse_seed(text, name: str = "seed") -> int:
    """Parse a random seed: an exact integer in [0, 2**64 - 1] (:func:`check_seed`).

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


def check_path(path, name: str) -> Path:
    """Check a file-system path: a non-empty ``str`` or an ``os.PathLike``.

    Anything else (None, a number, a list) is refused here instead of failing deep inside with a
    ``TypeError``.  Nothing is looked up on disk.

    Parameters
    ----------
    path : str or os.PathLike
        The path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a non-empty string or path-like object (naming ``name``).
    """
    if isinstance(path, (str, os.PathLike)) and str(path) != "":
        return Path(path)
    raise InvalidArgumentError(name, path, "a file path (str or os.PathLike)")


def check_choice(value, name: str, choices) -> str:
    """Check that ``value`` is one of ``choices`` (strings).

    A value that is not a string (unhashable ones included) is refused cleanly.

    Parameters
    ----------
    value : str
        The value.
    name : str
        The argument name shown in the error.
    choices : collection of str
        The accepted values; the error lists them sorted.

    Returns
    -------
    str
        ``value``, unchanged.

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not a string in ``choices`` (naming ``name``).
    """
    if isinstance(value, str) and value in choices:
        return value
    raise InvalidArgumentError(name, value, f"one of {sorted(choices)}")


def file_kind(path) -> str | None:
    """Say what exists at ``path``, without following a final symlink.

    Parameters
    ----------
    path : str or os.PathLike
        The path to inspect (with ``os.lstat``).

    Returns
    -------
    str or None
        ``None`` when nothing exists there (or a parent component is not a directory), otherwise
        one of ``"regular file"``, ``"directory"``, ``"symlink"``, ``"character device"``,
        ``"block device"``, ``"FIFO"``, ``"socket"`` or ``"special file"``.
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
    """Find the file that an output written to ``path`` replaces.

    That is ``path`` itself, or the file a symlink (or a chain of them) points to, so that a link
    stays a link and its target is written.  A dangling link is resolved to the file it names,
    which is then created.  Writing replaces the file by a rename, which would turn a device, FIFO
    or socket into a regular file (as root, ``/dev/null`` itself), so those are refused; to
    discard an output, leave the option out.

    Parameters
    ----------
    path : str or os.PathLike
        The output path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        The path to write (the symlink's target when ``path`` is a symlink).

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a path (:func:`check_path`), is an existing directory or a link to one,
        or is anything but a regular file or a new path: a character or block device
        (``/dev/null`` included), a FIFO, a socket (naming ``name``, the path and what it is).
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
    """Check an output file before any work is done, so that a bad path fails at once.

    The file must be a regular file or a new path (:func:`output_target`: never a device, a FIFO,
    a socket or a directory; a symlink is followed), in an existing, writable directory.

    Parameters
    ----------
    path : str or os.PathLike
        The output path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as given (not the symlink's target).

    Raises
    ------
    particles.InvalidArgumentError
        If :func:`output_target` refuses the path, or its directory does not exist or is not
        writable (naming ``name``).
    """
    out = check_path(path, name)
    target = output_target(out, name)
    if not target.parent.is_dir() or not os.access(target.parent, os.W_OK):
        raise InvalidArgumentError(name, str(path), "a file in an existing, writable directory")
    return out


def check_output_dir(path, name: str) -> Path:
    """Check an output folder: an existing writable directory (or a symlink to one), or one that can
    be created.

    A folder that does not exist yet is accepted when its nearest existing ancestor is a writable
    directory.  Nothing is created here.

    Parameters
    ----------
    path : str or os.PathLike
        The folder.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a path, something other than a directory exists there (a file, a
        device, a FIFO, a socket, a dangling symlink: the error names what), the directory is not
        writable, or it cannot be created (naming ``name``).
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

    More processes than that only compete for the same cores (each worker is a process with its
    own interpreter and imports, about a second and 100 MB to start); a bigger number is almost
    always a typo (``--workers 64`` for ``4``).

    Returns
    -------
    int
        ``4 * os.cpu_count()`` (``4`` when the count is unknown).
    """
    return 4 * (os.cpu_count() or 1)


def check_workers(workers, name: str = "workers", *, tasks: int | None = None,
                  force: bool = False) -> int | None:
    """Check a worker count for a parallel run.

    An integer ≥ 1, at most :func:`max_workers` unless ``force``, and never more than ``tasks``:
    a larger count is lowered to it, since idle workers cost start-up time and memory and do
    nothing.

    Parameters
    ----------
    workers : int or None
        The requested number of worker processes; ``None`` stays ``None`` (the caller's default).
    name : str, optional
        The argument name shown in the error (default ``"workers"``).
    tasks : int or None, optional
        The number of tasks to run; when given, the result is at most ``max(1, tasks)``.
    force : bool, optional
        Accept counts above :func:`max_workers` (default False).

    Returns
    -------
    int or None
        The worker count to use, or ``None`` when ``workers`` is ``None``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``workers`` is not an integer ≥ 1 (bools refused), or exceeds :func:`max_workers`
        without ``force`` (naming ``name``).
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
