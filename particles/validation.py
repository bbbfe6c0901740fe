"""Input checks shared by both packages (NumPy only).

Every public entry point checks its arguments once, here, and a failure names the
argument and shows the value received.  ``InvalidArgumentError`` subclasses
``ValueError`` so callers may catch either.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "InvalidArgumentError",
    "check_restitution",
    "check_times",
    "check_count",
    "check_real",
    "number_text_problem",
    "check_dimension",
    "check_real_array",
    "check_edges",
    "check_fit_points",
    "check_positive",
    "check_nonnegative",
    "check_choice",
    "check_bool",
    "shown",
    "SHOWN_CHARACTERS",
    "SEED_MAX",
    "check_seed",
]

#: Names that lived here before and have one home elsewhere now: a deep import of one of them
#: from this module raises an ImportError naming that home.
_MOVED = {
    **{name: "particles.parsing" for name in (
        "parse_float_list", "parse_name_list", "parse_int", "parse_count", "parse_seed")},
    **{name: "particles.paths" for name in (
        "check_path", "file_kind", "output_target", "check_output_file", "check_output_dir")},
    **{name: "particles.workers" for name in ("max_workers", "check_workers")},
}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"particles.validation.{name} moved to {_MOVED[name]}.{name}")
    raise AttributeError(f"module 'particles.validation' has no attribute {name!r}")


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


def number_text_problem(text: str, value: float) -> str | None:
    """Why the text of a number must be refused although ``float()`` read it as ``value``, or
    None: digit-group underscores (``1_000``, which Python's ``float`` takes as 1000 but a
    typo such as ``1_0e-1`` would silently become 1), and a non-zero number so small that it
    reads as 0.0 (``1e-400``).

    Parameters
    ----------
    text : str
        The number as typed.
    value : float
        What ``float(text)`` gave.

    Returns
    -------
    str or None
        What is expected instead, or None when the text is fine.
    """
    if "_" in text:
        return "a number written without underscores"
    if value == 0.0:
        from decimal import Decimal, InvalidOperation

        try:
            exact = Decimal(text.strip())
        except InvalidOperation:
            return None
        if exact.is_finite() and exact != 0:
            return "a number that is 0 or at least 1e-308 in magnitude (this one reads as 0)"
    return None


def _as_float(name: str, value) -> float:
    """``value`` as a finite float; booleans and complex numbers are refused, not converted;
    a text with underscores or one that underflows to 0 (:func:`number_text_problem`) too."""
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
    if isinstance(value, str):
        problem = number_text_problem(value, x)
        if problem:
            raise InvalidArgumentError(name, value, problem)
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
        ``r`` as a float (``-0.0`` as ``0.0``).

    Raises
    ------
    particles.InvalidArgumentError
        If ``r`` is not a real number, not finite, or outside [0, 1] (naming ``name``).
    """
    x = _as_float(name, r)
    if not 0.0 <= x <= 1.0:
        raise InvalidArgumentError(name, r, "a number in [0, 1]")
    return x + 0.0  # -0.0 is r = 0, and is written as 0.0 in every output


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
                     finite: bool = True, copy: bool = True) -> np.ndarray:
    """Check an array of real numbers (for the numerical functions' array arguments).

    Booleans, complex numbers, strings and other objects are refused, not converted (a boolean
    inside a list of numbers too: ``[True, 2.0]`` is not ``[1.0, 2.0]``); a scalar is a
    0-dimensional array.

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
    copy : bool, optional
        If True (default) the result is a new array; False returns ``values`` itself when it
        already is a float64 array (for read-only callers of large arrays: no N-value copy).

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
        if not isinstance(values, np.ndarray) and _holds_bool(values):
            raise TypeError("a boolean among numbers")  # NumPy reads [True, 2.0] as [1.0, 2.0]
        arr = raw.astype(float, copy=copy)
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


def _holds_bool(values) -> bool:
    """Whether a (nested) list or tuple holds a boolean, or a boolean array."""
    if _is_bool(values):
        return True
    if isinstance(values, np.ndarray):
        return values.dtype.kind == "b"
    if isinstance(values, (list, tuple)):
        return any(_holds_bool(x) for x in values)
    return False


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
        The times as a one-dimensional float array (``-0.0`` as ``0.0``).

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
    return arr + 0.0  # -0.0 is the time 0, saved and written as 0.0


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


def check_bool(value, name: str, *, none: bool = False) -> bool | None:
    """Check that ``value`` is a boolean: ``True`` or ``False`` (NumPy's ``np.True_`` and
    ``np.False_`` too), and, when ``none``, None.  Any other value is refused, truthy or not:
    ``force='no'`` is not ``force=True``.

    Parameters
    ----------
    value : bool
        The value.
    name : str
        The argument name shown in the error.
    none : bool, optional
        Accept None too (an argument where None means "auto"; default False).

    Returns
    -------
    bool or None
        ``value`` as a Python ``bool`` (None stays None).

    Raises
    ------
    particles.InvalidArgumentError
        If ``value`` is not a boolean (nor None when ``none``), naming ``name``.
    """
    if none and value is None:
        return None
    if _is_bool(value):
        return bool(value)
    raise InvalidArgumentError(name, value, "True, False or None" if none else "True or False")
