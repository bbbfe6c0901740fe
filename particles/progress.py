"""Progress reporting for long runs, one helper for every engine, solver and command.

``progress_bar(total, desc=..., unit=..., enabled=True)`` returns an object with ``update(n)``,
``set_postfix_str(text)`` and ``close()`` (also a context manager):

* ``enabled=None``, the default of every function of the API that takes ``progress``: a tqdm
  bar when stderr is a terminal, tqdm's notebook widget in a Jupyter kernel (when ipywidgets is
  installed), and nothing otherwise (a script whose stderr goes to a log, a test, a notebook
  without ipywidgets);
* ``enabled=True`` (the command line): a tqdm bar on a terminal, the notebook widget in a
  Jupyter kernel with ipywidgets, and otherwise a few plain lines, one at the start, one at each
  further 25 % of ``total`` and one at the end, so a log holds a handful of lines and not
  thousands of carriage-return updates;
* ``enabled=False`` (``--no-progress``): nothing at all.
"""

from __future__ import annotations

import sys
import time

from .validation import check_bool

__all__ = ["progress_bar", "progress_enabled", "PlainProgress", "NoProgress", "in_notebook"]


def in_notebook() -> bool:
    """Whether this process is a Jupyter kernel whose front end can show tqdm's notebook widget
    (an IPython kernel shell, with ipywidgets importable).

    Returns
    -------
    bool
        True in a Jupyter kernel with ipywidgets installed, else False.
    """
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    shell = ipython.get_ipython()
    if shell is None or type(shell).__name__ != "ZMQInteractiveShell":
        return False
    import importlib.util

    return importlib.util.find_spec("ipywidgets") is not None


class NoProgress:
    """A progress object that reports nothing (``enabled=False``, ``--no-progress``).

    It counts the progress in ``n`` and accepts the calls of a tqdm bar, so that callers need not
    test whether progress is shown.  Also a context manager (closed on exit).
    """

    n = 0.0

    def update(self, n=1) -> None:
        """Add ``n`` to the progress count (nothing is printed).

        Parameters
        ----------
        n : float, optional
            The progress made since the last call (default 1).
        """
        self.n += n

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """Accept a status text after the bar, and ignore it.

        Parameters
        ----------
        text : str
            The text (unused).
        refresh : bool, optional
            Accepted for compatibility with tqdm (unused).
        """
        pass

    def close(self) -> None:
        """Finish the progress report (nothing to do)."""
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class PlainProgress(NoProgress):
    """Progress as a few plain lines, for a stream that is not a terminal (a log file, CI).

    A line is printed at the start, whenever the progress passes a further ``step`` of
    ``total``, and at ``close()``; each shows the percentage, ``n/total unit``, the seconds
    elapsed and the postfix text.  A log thus holds a handful of lines and not thousands of
    carriage-return updates.

    Parameters
    ----------
    total : float
        The amount of work at completion (a falsy total shows 0 %).
    desc : str, optional
        The label at the start of each line.
    unit : str, optional
        The unit of the progress count, shown after the numbers.
    stream : file-like or None, optional
        Where the lines go (default ``sys.stderr``).
    step : float, optional
        The fraction of ``total`` between two lines (default 0.25).
    initial : float, optional
        The progress already made (a resumed run; default 0).
    postfix : str, optional
        A status text appended to each line.
    """

    def __init__(self, total, desc="", unit="", stream=None, step=0.25, initial=0.0,
                 postfix=""):
        self.total = float(total) if total else 0.0
        self.desc = desc
        self.unit = unit
        self.stream = stream if stream is not None else sys.stderr
        self.step = step
        self.n = float(initial)
        self.postfix = postfix
        self.started = time.perf_counter()
        self._next = 0.0
        self._closed = False
        self._emit()

    def _fraction(self) -> float:
        return min(1.0, self.n / self.total) if self.total > 0 else 0.0

    def _emit(self) -> None:
        f = self._fraction()
        elapsed = time.perf_counter() - self.started
        extra = f" {self.postfix}" if self.postfix else ""
        print(f"{self.desc}: {100 * f:3.0f}% | {self.n:.4g}/{self.total:.4g} {self.unit} "
              f"[{elapsed:.1f} s]{extra}", file=self.stream, flush=True)
        while self._next <= f:
            self._next += self.step

    def update(self, n=1) -> None:
        """Add ``n`` to the progress, printing a line when it passes the next ``step`` of the total.

        The final line (100 %) is left to ``close()``.

        Parameters
        ----------
        n : float, optional
            The progress made since the last call (default 1).
        """
        self.n += n
        if self._fraction() >= self._next and self._fraction() < 1.0:
            self._emit()

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """Set the status text appended to the following lines.

        Parameters
        ----------
        text : str
            The text.
        refresh : bool, optional
            Accepted for compatibility with tqdm (a line is printed only on progress).
        """
        self.postfix = text

    def close(self) -> None:
        """Print the final line (once; later calls do nothing)."""
        if not self._closed:
            self._closed = True
            self._emit()


def progress_enabled(enabled: bool | None) -> bool:
    """Whether a ``progress`` value shows anything: False never, True always, None (the API's
    default) on a terminal (standard error) or in a notebook only.

    Parameters
    ----------
    enabled : bool or None
        The ``progress`` argument.

    Returns
    -------
    bool
        True when progress is shown.
    """
    if enabled is None:
        isatty = getattr(sys.stderr, "isatty", None)
        return in_notebook() or bool(isatty is not None and isatty())
    return bool(enabled)


def progress_bar(total, desc: str = "", unit: str = "", *, enabled: bool | None = True,
                 initial=0.0,
                 leave: bool = False, stream=None, postfix: str = ""):
    """A progress reporter: a tqdm bar on a terminal, plain lines otherwise, nothing when disabled.

    The returned object has ``update(n)``, ``set_postfix_str(text)`` and ``close()`` and is a
    context manager.

    Parameters
    ----------
    total : float
        The amount of work at completion (in ``unit``: τ, time, tasks).
    desc : str, optional
        The label of the bar.
    unit : str, optional
        The unit of the progress count.
    enabled : bool or None, optional
        None: a bar on a terminal or in a notebook, nothing otherwise; True: the same, but plain
        lines where no bar can be drawn; False (``--no-progress``): nothing (default True).
    initial : float, optional
        The progress already made, e.g. by a resumed run (default 0).
    leave : bool, optional
        Keep a tqdm bar on the terminal after it is closed (default False).
    stream : file-like or None, optional
        Where to report (default ``sys.stderr``); a bar is drawn only when ``stream.isatty()``.
    postfix : str, optional
        A status text shown after the bar.

    Returns
    -------
    tqdm.tqdm or tqdm.notebook.tqdm or PlainProgress or NoProgress
        The progress object.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``enabled`` when it is neither a bool nor None (``'no'`` is not False).
    """
    enabled = check_bool(enabled, "enabled", none=True)
    if enabled is False:
        return NoProgress()
    if stream is None and in_notebook():
        from tqdm.notebook import tqdm as notebook_tqdm

        bar = notebook_tqdm(total=float(total), initial=float(initial), desc=desc, unit=unit,
                            leave=leave)
        if postfix:
            bar.set_postfix_str(postfix)
        return bar
    stream = stream if stream is not None else sys.stderr
    isatty = getattr(stream, "isatty", None)
    if isatty is not None and isatty():
        from tqdm import tqdm

        bar = tqdm(total=float(total), initial=float(initial), desc=desc, unit=unit,
                   leave=leave, file=stream,
                   bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}<{remaining}]{postfix}")
        if postfix:
            bar.set_postfix_str(postfix)
        return bar
    if enabled is None:
        return NoProgress()
    return PlainProgress(total, desc, unit, stream, initial=initial, postfix=postfix)
