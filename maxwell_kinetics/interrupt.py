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

__all__ = ["deferred_sigint", "check", "requested", "run_interruptibly", "abandoned",
           "join_abandoned"]

_requested = threading.Event()
#: Worker threads of :func:`run_interruptibly` left running after a Ctrl-C.
_abandoned: list[threading.Thread] = []


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


def run_interruptibly(work, name: str = "computation"):
    """``work()`` in a daemon thread while the calling thread waits in steps of 0.1 s, so that
    a Ctrl-C reaches the caller within about 0.1 s even while ``work`` sits in one long call
    that Python cannot interrupt (a compiled JAX loop).

    Python's own handler raises KeyboardInterrupt in the waiting thread; under
    :func:`deferred_sigint` the wait calls :func:`check`.  The abandoned thread runs on until
    its call returns, its result discarded (it is a daemon: it does not keep the process
    alive; :func:`abandoned` tells a program that is about to exit that one still runs).

    Parameters
    ----------
    work : callable
        Called with no arguments.
    name : str, default "computation"
        The thread's name (seen in debuggers and tracebacks).

    Returns
    -------
    object
        What ``work()`` returned.

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C while ``work`` runs.
    BaseException
        Whatever ``work`` raised, re-raised in the calling thread.
    """
    out: dict = {}

    def run():
        try:
            out["value"] = work()
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller
            out["error"] = exc

    worker = threading.Thread(target=run, name=name, daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(0.1)
            check()
    except BaseException:
        if worker.is_alive():
            _abandoned.append(worker)
        raise
    if "error" in out:
        raise out["error"]
    return out["value"]


def abandoned() -> bool:
    """Whether a worker of :func:`run_interruptibly` left behind by a Ctrl-C still runs.

    A process must not run the interpreter's normal shutdown while one does: the thread is
    torn down inside a compiled JAX call, which aborts the process (exit status 134 instead of
    the 130 of an interrupt).  The command line ends such a process with ``os._exit``.

    Returns
    -------
    bool
    """
    return any(worker.is_alive() for worker in _abandoned)


def join_abandoned(timeout: float | None = None) -> bool:
    """Wait for the workers that :func:`run_interruptibly` left behind to end (their results
    are discarded): a Python program that goes on, or ends normally, after a Ctrl-C without
    the JAX computation still running in the background.

    Parameters
    ----------
    timeout : float, optional
        Seconds to wait in all (default: as long as it takes).

    Returns
    -------
    bool
        True when none is left running.
    """
    import time

    end = None if timeout is None else time.monotonic() + timeout
    for worker in list(_abandoned):
        worker.join(None if end is None else max(0.0, end - time.monotonic()))
    _abandoned[:] = [worker for worker in _abandoned if worker.is_alive()]
    return not _abandoned
