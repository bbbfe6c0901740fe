"""Progress reporting for long runs, one helper for every engine, solver and command.

``progress_bar(total, desc=..., unit=..., enabled=True)`` returns an object with ``update(n)``,
``set_postfix_str(text)`` and ``close()`` (also a context manager):

* stderr is a terminal: a tqdm bar (carriage-return updates);
* stderr is not a terminal (a log file, CI): a few plain lines instead, one at the start, one at
  each further 25 % of ``total`` and one at the end, so a log holds a handful of lines and not
  thousands of carriage-return updates;
* ``enabled=False`` (``--no-progress``): nothing at all.
"""

from __future__ import annotations

import sys
import time

__all__ = ["progress_bar", "PlainProgress", "NoProgress"]


class NoProgress:
    """A progress object that reports nothing."""

    n = 0.0

    def update(self, n=1) -> None:
        """Nothing.

        Parameters
        ----------
        n : float
            Ignored.
        """
        self.n += n

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """Nothing.

        Parameters
        ----------
        text : str
            Ignored.
        refresh : bool
            Ignored.
        """
        pass

    def close(self) -> None:
        """Nothing.
        """
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class PlainProgress(NoProgress):
    """Plain lines on ``stream`` at 0 %, every ``step`` of the total, and at the end.

    Parameters
    ----------
    total, desc, unit, stream, initial, postfix
        As for :func:`progress_bar`.
    step : float
        The fraction of the total between lines.
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
        """Advance by ``n``; writes a line when a step is crossed.

        Parameters
        ----------
        n : float
            The increment.
        """
        self.n += n
        if self._fraction() >= self._next and self._fraction() < 1.0:
            self._emit()

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """Set the text after the value.

        Parameters
        ----------
        text : str
            The text.
        refresh : bool
            Ignored (tqdm's signature).
        """
        self.postfix = text

    def close(self) -> None:
        """Write the final line (once).
        """
        if not self._closed:
            self._closed = True
            self._emit()


def progress_bar(total, desc: str = "", unit: str = "", *, enabled: bool = True, initial=0.0,
                 leave: bool = False, stream=None, postfix: str = ""):
    """A tqdm bar on a terminal, plain lines otherwise, nothing when ``enabled`` is False.

    Parameters
    ----------
    total : float
        The end value.
    desc : str
        The label.
    unit : str
        The unit of the values.
    enabled : bool
        False: report nothing.
    initial : float
        The start value (a resumed run).
    leave : bool
        Keep the tqdm bar after the end.
    stream : file, optional
        Where to write (default stderr).
    postfix : str
        Text after the bar.

    Returns
    -------
    object
        A context manager with ``update``, ``set_postfix_str`` and ``close``.
    """
    if not enabled:
        return NoProgress()
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
    return PlainProgress(total, desc, unit, stream, initial=initial, postfix=postfix)
