"""Run every comparison, write PNG figures and ``summary.json`` (the job behind
``maxwell-kinetics reproduce``, :mod:`maxwell_kinetics.commands.reproduce`).

The default size finishes in minutes on two cores (measured run times are in ``summary.json``);
``--full`` runs the paper's sizes where affordable; ``--small`` is the size of the tests.
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

from particles import persistence
from particles.validation import InvalidArgumentError, check_workers

from .output import clean_json

__all__ = ["prepare_output", "run_all"]


def prepare_output(out, argument: str = "out") -> Path:
    """Create the output folder and prove that a file can be written in it, before any work;
    a failure raises ``InvalidArgumentError`` naming ``argument``.

    Parameters
    ----------
    out : str or os.PathLike
        The output folder; missing parents are created (and removed again on failure).
    argument : str, optional
        The argument's name for the error message (default ``"out"``).

    Returns
    -------
    pathlib.Path
        The folder, which exists and is writable.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If the folder cannot be created or a file cannot be written in it.
    """
    out = Path(out)
    created = [p for p in (out, *out.parents) if not p.exists()]
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as exc:
        for folder in created:  # nothing written: remove the folders made here
            try:
                folder.rmdir()
            except OSError:
                pass
        raise InvalidArgumentError(
            argument, str(out), f"a writable directory ({exc.strerror or exc})"
        ) from None
    return out


def run_all(out="results", size="default", only=None, progress=True, workers=None,
            force: bool = False) -> dict:
    """Run the comparisons (``only``: a list of names); write ``<name>.png``, ``<name>.npz``
    (:meth:`Comparison.save`: summary and figure data, reload with ``Comparison.load``) and
    ``summary.json``.

    With ``workers`` (an integer), or at ``size="full"``, the particle runs of fixed times go
    through the ensemble engine on dask (``workers`` processes; default one per core), one task
    file per run in ``<out>/runs``: a rerun after an interruption takes the finished runs from
    there, and the results equal the serial ones bit for bit.  More workers than
    :func:`particles.validation.max_workers` (4 × the CPUs) are refused unless ``force``.

    Parameters
    ----------
    out : str or os.PathLike, optional
        The output folder (default ``"results"``), created if needed.
    size : str, optional
        ``"small"`` (the tests' size), ``"default"`` (minutes) or ``"full"`` (the paper's sizes).
    only : list of str, optional
        Names of the comparisons to run (keys of ``COMPARISONS``); default all, in order.
    progress : bool, optional
        Print a line before and after each comparison, and let the comparisons show progress
        (default true).
    workers : int, optional
        Number of dask processes for the particle runs through the ensemble engine; default
        serial (except at ``size="full"``).
    force : bool, optional
        Allow more workers than :func:`particles.validation.max_workers`.

    Returns
    -------
    dict
        The contents of ``summary.json``: ``size``, ``comparisons`` (``{name: summary}``) and
        the total wall-clock ``seconds``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From the validators it calls: too many ``workers`` without ``force``, or an unusable
        ``out`` folder.
    """
    import matplotlib.pyplot as plt

    from .comparisons import COMPARISONS, ParticleRuns

    names = list(COMPARISONS) if only is None else list(only)
    check_workers(workers, "workers", force=force)
    out = prepare_output(out)
    ensemble = workers is not None or size == "full"
    runner = ParticleRuns(out / "runs" if ensemble else None, workers, force)
    summary = {"size": size, "comparisons": {}}
    start = time.perf_counter()
    for name in names:
        if progress:
            print(f"[reproduce] {name} ...", flush=True)
        result = COMPARISONS[name](size, progress=progress, runner=runner)
        fig = result.figure()
        persistence.save_figure(fig, out / f"{name}.png", "out", dpi=110)
        result.save(out / f"{name}.npz")
        plt.close(fig)
        summary["comparisons"][name] = clean_json(result.summary)
        if progress:
            print(f"[reproduce] {name}: {result.summary.get('seconds', 0):.1f} s",
                  flush=True)
    summary["seconds"] = time.perf_counter() - start
    persistence.write_text(out / "summary.json",
                           json.dumps(clean_json(summary), indent=1, allow_nan=False), "out")
    return summary
