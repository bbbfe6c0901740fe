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
        The folder.
    argument : str
        The argument's name.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InvalidArgumentError
        Naming ``argument``.
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
    out : str or os.PathLike
        The output folder.
    size : str
        "small", "default" or "full".
    only : list of str, optional
        Comparison names.
    progress : bool
        Show progress.
    workers : int, optional
        Processes for the particle runs.
    force : bool
        Allow more than 4 × the CPUs.

    Returns
    -------
    dict
        The summary (also written to ``summary.json``).
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
