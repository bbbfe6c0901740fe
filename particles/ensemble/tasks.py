"""One task of an ensemble: its run (on a worker or in this process, resuming from its
checkpoint) and its file."""

from __future__ import annotations

import time as _time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .. import persistence
from ..driver import CheckpointError, RunResult, simulate
from .spec import FORMAT_VERSION, EnsembleTask

_TASK_KIND = "ensemble-task"


def _save_task(path: Path, task: EnsembleTask, result: RunResult) -> None:
    """The result of ``task`` without its wall-clock seconds (files of one task are identical),
    in the layout of :meth:`particles.driver.RunResult.to_record`."""
    arrays, meta = result.to_record()
    meta.update(seconds=None, task=task.identity)
    persistence.save(path, _TASK_KIND, FORMAT_VERSION, arrays, meta)


def load_task(path, identity: dict | None = None) -> RunResult:
    """The :class:`RunResult` in task file ``path`` (``seconds`` is NaN: task files keep no
    wall-clock time).  With ``identity``, the file must be that task's, else
    :class:`particles.persistence.FileFormatError`.

    Parameters
    ----------
    path : str or os.PathLike
        A task file written by :func:`run_task`.
    identity : dict, optional
        The task's :attr:`particles.ensemble.EnsembleTask.identity` the file must carry.

    Returns
    -------
    particles.driver.RunResult
        The task's result.

    Raises
    ------
    particles.persistence.FileFormatError
        (argument ``path``) if the file is not a readable task file, belongs to another task,
        or lacks an entry.
    """
    loaded = persistence.load(path, _TASK_KIND, (FORMAT_VERSION,), argument="path")
    meta, a = loaded.meta, loaded.arrays
    if identity is not None and meta.get("task") != identity:
        raise persistence.FileFormatError(path, "written for another task", "path",
                                          "this task's file")
    try:
        if "model" not in meta:  # a task file of 0.1: the run's names were kept in the task
            task = meta["task"]
            meta = {**meta, "model": task["model"], "params": meta["engine_params"],
                    "seed": task["seed"]}
        return RunResult.from_record(a, meta)
    except (KeyError, TypeError) as exc:
        raise persistence.FileFormatError(path, f"missing entry {exc}", "path") from None


def run_task(task: EnsembleTask, factory: Callable[..., Any], out: str) -> dict:
    """Run ``task`` (on a worker, or in this process for the serial executor) and write its
    file in ``out``; resume from its checkpoint there if one exists.  Never raises for a failure
    of the run: returns ``{"key", "status": "done" | "failed", "seconds", "resumed", "notes",
    "error", "traceback"}``.

    Parameters
    ----------
    task : particles.ensemble.EnsembleTask
        The task.
    factory : Callable[..., Any]
        The model's factory; ``factory(**task.params)`` builds the engine.
    out : str
        The ensemble's output folder.

    Returns
    -------
    dict
        The record above; ``error`` and ``traceback`` only for a failed task.
    """
    out = Path(out)
    path, ckpt = out / task.filename, out / task.checkpoint_name
    record = {"key": task.key, "status": "done", "seconds": 0.0, "resumed": False, "notes": []}
    started = _time.perf_counter()
    try:
        engine = factory(**task.params)
        kwargs = dict(progress=False, checkpoint=ckpt,
                      structure_factor=task.options["structure_factor"],
                      bins=task.options["bins"],
                      checkpoint_interval=task.options["checkpoint_interval"],
                      snapshots=task.options.get("snapshots", False))
        result = None
        if ckpt.exists():
            try:
                result = simulate(engine, task.times, task.seed, resume=ckpt, **kwargs)
                record["resumed"] = True
            except CheckpointError as exc:  # damaged checkpoint: start again
                record["notes"].append(f"checkpoint refused, run from the start: {exc.reason}")
        if result is None:
            result = simulate(engine, task.times, task.seed, **kwargs)
        _save_task(path, task, result)
        ckpt.unlink(missing_ok=True)
    except Exception as exc:  # noqa: BLE001 - reported with the task, the others go on
        record.update(status="failed", error=f"{type(exc).__name__}: {exc}",
                      traceback=traceback.format_exc())
    record["seconds"] = _time.perf_counter() - started
    return record
