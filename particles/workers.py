"""Worker limits of parallel runs: the largest worker count accepted without ``force`` and the
check of a requested count.
"""

from __future__ import annotations

import os

import numpy as np

from .validation import InvalidArgumentError, check_bool

__all__ = [
    "max_workers",
    "check_workers",
]


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
        without ``force`` (naming ``name``); naming ``force`` when it is not a bool.
    """
    force = check_bool(force, "force")
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
