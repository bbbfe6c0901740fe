"""Deferred Ctrl-C for the command line's long computations (standard library only).

A KeyboardInterrupt raised by Python's default SIGINT handler lands wherever the interpreter
happens to be, and inside a callback that Python calls on its own (JAX's garbage-collector
callback, a destructor) it is printed as "Exception ignored" and discarded: the run goes on as
if nothing happened.  :func:`deferred_sigint`, which the command line installs around a run,
replaces the handler by one that only records the request; the computation polls it with
:func:`check` at safe points (between the solver's integration windows, before writing files)
and raises KeyboardInterrupt there, from ordinary Python code, so that it cannot be lost and
leaves no JAX computation half-done.  A second Ctrl-C while the first is pending raises at once.

Outside :func:`deferred_sigint` (a Python user calling the library) nothing changes: Python's own
handler raises KeyboardInterrupt as usual, and :func:`check` never raises.
"""

from __future__ import annotations

import contextlib
import signal
import threading

__all__ = ["deferred_sigint", "check", "requested"]

_requested = threading.Event()


def _handler(signum, frame):
    if _requested.is_set():  # a second Ctrl-C: stop now
        raise KeyboardInterrupt
    _requested.set()


@contextlib.contextmanager
def deferred_sigint():
    """Record SIGINT instead of raising it, for the duration of the block.

    Only in the main thread (elsewhere Python cannot install handlers, and the block runs with
    the current handler).  The previous handler is restored on exit and the request cleared.

    Yields
    ------
    None
        Control, with SIGINT recorded (:func:`requested`) instead of raised.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, _handler)
    _requested.clear()
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        _requested.clear()


def requested() -> bool:
    """Whether a Ctrl-C is pending.

    Returns
    -------
    bool
        True after a SIGINT inside :func:`deferred_sigint`; always False outside it.
    """
    return _requested.is_set()


def check() -> None:
    """Raise KeyboardInterrupt if a Ctrl-C is pending (inside :func:`deferred_sigint`).

    Raises
    ------
    KeyboardInterrupt
        When :func:`requested` is True.
    """
    if _requested.is_set():
        raise KeyboardInterrupt
