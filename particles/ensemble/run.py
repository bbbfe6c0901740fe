"""Running an ensemble: the output folder (manifest, task files, aggregate), the tasks left to
run, their execution (serial or on dask) and the report."""

from __future__ import annotations

import json
import os
import time as _time
import traceback
from pathlib import Path

from .. import persistence
from ..models import get_model
from ..progress import progress_bar
from ..validation import InvalidArgumentError, check_output_dir, check_workers
from .aggregate import EnsembleReport, aggregate
from .cluster import connect, load_cluster_config
from .spec import FORMAT_VERSION, EnsembleSpec
from .tasks import load_task, run_task

MANIFEST = "manifest.npz"
AGGREGATE = "ensemble.npz"


def _check_folder(out: Path) -> None:
    """Refuse a folder whose manifest is of another format version (or unreadable)."""
    manifest = out / MANIFEST
    if not manifest.exists():
        return
    try:
        persistence.load(manifest, "ensemble-manifest", (FORMAT_VERSION,), argument="out")
    except persistence.FileFormatError as exc:
        raise InvalidArgumentError(
            "out", str(out),
            f"a folder of ensemble files of format version {FORMAT_VERSION} "
            f"({MANIFEST}: {exc.reason})",
        ) from None


def _check_existing(out: Path, tasks) -> tuple[set, list]:
    """(keys with a valid file, damaged files removed)."""
    valid, damaged = set(), []
    for task in tasks:
        path = out / task.filename
        if not path.exists():
            continue
        try:
            load_task(path, task.identity)
        except persistence.FileFormatError as exc:
            damaged.append({"path": str(path), "reason": exc.reason, **task.describe()})
            path.unlink(missing_ok=True)
        else:
            valid.add(task.key)
    return valid, damaged


def run_ensemble(spec: EnsembleSpec, out, *, workers: int | None = None, scheduler=None,
                 cluster: str | None = None, config=None, progress: bool = True,
                 executor: str = "dask", force: bool = False) -> EnsembleReport:
    """Run the tasks of ``spec`` that have no valid file in ``out`` and aggregate them all.

    ``executor="dask"``: a local cluster of ``workers`` processes (default: the number of
    CPUs; never more than the tasks left to run, and at most
    :func:`particles.validation.max_workers`, 4 × the CPUs, unless ``force``), or
    ``scheduler=ADDRESS`` (an existing cluster; connection timeout :data:`SCHEDULER_TIMEOUT`
    seconds), or ``cluster="slurm"|"pbs"`` with ``config`` (TOML, :func:`load_cluster_config`).
    ``executor="serial"``: in this process, no dask.  Bad arguments raise
    :class:`InvalidArgumentError` before anything is written.  A failing task
    does not raise: see ``report.failed``.  See the module docstring for the files.

    Parameters
    ----------
    spec : particles.ensemble.EnsembleSpec
        What to run.
    out : str or os.PathLike
        The output folder (task files, manifest, aggregate).
    workers : int, optional
        Local worker processes (dask executor).
    scheduler : str, optional
        Address of an existing dask scheduler.
    cluster : str, optional
        ``"slurm"`` or ``"pbs"``.
    config : str or os.PathLike, optional
        The cluster's TOML file (only with ``cluster``).
    progress : bool, optional
        Show a progress bar (default True).
    executor : str, optional
        ``"dask"`` (default) or ``"serial"``.
    force : bool, optional
        Allow more workers than :func:`particles.validation.max_workers`.

    Returns
    -------
    EnsembleReport
        What was run, skipped, recomputed and failed, and the aggregate summary.

    Raises
    ------
    particles.InvalidArgumentError
        For a ``spec`` that is not an :class:`EnsembleSpec`, a bad ``out`` or ``executor``,
        more than one of ``workers``, ``scheduler``, ``cluster`` (or any with the serial
        executor), a bad worker count, a bad cluster ``config`` or one without ``cluster``,
        or an ``out`` folder that is not an ensemble's.
    """
    started = _time.perf_counter()
    if not isinstance(spec, EnsembleSpec):
        raise InvalidArgumentError("spec", spec, "an EnsembleSpec")
    out = check_output_dir(persistence.check_name_length(out, "out"), "out")
    if executor not in ("dask", "serial"):
        raise InvalidArgumentError("executor", executor, "'dask' or 'serial'")
    given = {"workers": workers, "scheduler": scheduler, "cluster": cluster}
    chosen = [name for name, value in given.items() if value is not None]
    if len(chosen) > 1 or (executor == "serial" and chosen):
        name = chosen[-1]
        raise InvalidArgumentError(name, given[name],
                                   "one of workers, scheduler, cluster (dask executor only)")
    workers = check_workers(workers, "workers", force=force)
    if cluster is not None:
        load_cluster_config(config, cluster)  # checked before any work
    elif config is not None:
        raise InvalidArgumentError("config", config, "only with cluster='slurm' or 'pbs'")
    if out.exists():
        _check_folder(out)
    tasks = spec.expand()
    model = get_model(spec.model)

    valid, damaged = _check_existing(out, tasks)
    todo = [t for t in tasks if t.key not in valid]
    closers = []
    client = None
    if executor == "dask" and todo:
        # a local cluster of no more workers than tasks: idle ones only cost start-up
        local = min(workers or os.cpu_count() or 1, len(todo))
        client, closers = connect(executor, local, scheduler, cluster, config)
    try:
        out.mkdir(parents=True, exist_ok=True)
        if not (out / MANIFEST).exists():
            persistence.save(out / MANIFEST, "ensemble-manifest", FORMAT_VERSION, {},
                             {"writer": "particles.ensemble"}, argument="out")
        records = _execute(client, todo, model.factory, out.absolute(), progress)
    finally:
        for close in closers:
            close()

    by_key = {t.key: t for t in tasks}
    failed = []
    for rec in records:
        if rec["status"] != "done":
            failed.append({**by_key[rec["key"]].describe(), "error": rec.get("error"),
                           "traceback": rec.get("traceback", "")})
    done = valid | {r["key"] for r in records if r["status"] == "done"}
    arrays, summary = aggregate(spec, out, tasks, done)
    summary["failed"] = len(failed)
    meta = {"spec": spec.to_dict(), "summary": summary, "tasks": len(tasks),
            "failed": [{k: v for k, v in f.items() if k != "traceback"} for f in failed]}
    persistence.save(out / AGGREGATE, "ensemble", FORMAT_VERSION, arrays,
                     json.loads(json.dumps(meta, allow_nan=True)), argument="out")
    notes = tuple(f"{r['key']}: {n}" for r in records for n in r.get("notes", []))
    return EnsembleReport(
        out=str(out), executor=executor, tasks=len(tasks),
        ran=tuple(r["key"] for r in records), skipped=tuple(sorted(valid)),
        resumed=tuple(r["key"] for r in records if r.get("resumed")),
        recomputed=tuple(damaged), failed=tuple(failed), aggregate=summary,
        aggregate_path=str(out / AGGREGATE),
        seconds={r["key"]: r["seconds"] for r in records},
        wall_seconds=_time.perf_counter() - started, notes=notes,
    )


def _execute(client, todo, factory, out: Path, progress: bool) -> list[dict]:
    bar = progress_bar(len(todo), "ensemble", "tasks", enabled=progress and bool(todo))
    records = []
    try:
        if client is None:
            for task in todo:
                records.append(run_task(task, factory, str(out)))
                bar.update(1)
            return records
        from distributed import as_completed

        futures = {client.submit(run_task, task, factory, str(out), key=f"ensemble-{task.key}",
                                 pure=False): task for task in todo}
        for future in as_completed(list(futures)):
            task = futures[future]
            try:
                records.append(future.result())
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker: a worker died too often
                records.append({"key": task.key, "status": "failed", "seconds": float("nan"),
                                "error": f"{type(exc).__name__}: {exc}",
                                "traceback": traceback.format_exc()})
            bar.update(1)
        order = {t.key: i for i, t in enumerate(todo)}
        records.sort(key=lambda r: order[r["key"]])
        return records
    finally:
        bar.close()
