"""Running an ensemble: the output folder (manifest, task files, aggregate), the tasks left to
run, their execution (serial or on dask) and the report."""

from __future__ import annotations

import hashlib
import json
import os
import time as _time
import traceback
from pathlib import Path

from .. import persistence
from ..models import get_model
from ..paths import check_output_dir
from ..progress import progress_bar
from ..validation import InvalidArgumentError
from ..workers import check_workers
from .aggregate import EnsembleReport, aggregate
from .cluster import check_scheduler, connect, load_cluster_config, require_jobqueue
from .spec import FORMAT_VERSION, EnsembleSpec
from .tasks import load_task, run_task

MANIFEST = "manifest.npz"
AGGREGATE = "ensemble.npz"


def _folder_identity(spec: EnsembleSpec, tasks) -> dict:
    """What a folder's manifest records of its ensemble: ``ensemble``, a hash of everything
    but the seeds (model, the set of the parameter sets' engines, times, result options,
    format version, as in the tasks' identities), and the ``seeds``."""
    sets = {}
    for task in tasks:
        sets.setdefault(task.set_index, {k: v for k, v in task.identity.items() if k != "seed"})
    # the grid as a set: the same values given in another order are the same ensemble
    text = json.dumps(sorted(json.dumps(v, sort_keys=True) for v in sets.values()))
    return {"ensemble": hashlib.sha256(text.encode()).hexdigest()[:24],
            "seeds": [int(s) for s in spec.seeds]}


def _describe(spec_dict) -> str:
    """A short description of a recorded spec for an error message."""
    if not isinstance(spec_dict, dict):
        return "another ensemble"
    return (f"model {spec_dict.get('model')!r}, parameters {spec_dict.get('params')}, "
            f"times {spec_dict.get('times')}")[:300]


def _seed_text(seeds) -> str:
    seeds = sorted(seeds)
    text = ",".join(str(s) for s in seeds[:8])
    return text + (f",... ({len(seeds)} seeds)" if len(seeds) > 8 else "")


def _check_folder(out: Path, spec: EnsembleSpec, tasks, identity: dict, shared: bool) -> bool:
    """Refuse an ``out`` that is not this ensemble's folder: a folder that is not empty and has
    no manifest (the user's own files), a manifest of another format version (or unreadable),
    or one of another ensemble (another model, parameter grid, times or result options), or of
    this ensemble with seeds that the new spec drops, or a shared folder.  A manifest written
    before manifests recorded their ensemble is accepted when every task file in the folder is
    one of this spec's.  With ``shared``, any manifest of this version that records no single
    ensemble is accepted.  Returns whether the manifest must be (re)written."""
    if not out.exists():
        return True
    manifest = out / MANIFEST
    if not (manifest.exists() or manifest.is_symlink()):
        try:
            entries = sorted(p.name for p in out.iterdir())
        except OSError as exc:
            raise InvalidArgumentError("out", str(out), f"a readable folder ({exc})") from None
        if entries:
            shown = ", ".join(repr(e) for e in entries[:3]) + (", ..." if len(entries) > 3 else "")
            raise InvalidArgumentError(
                "out", str(out),
                f"a new or empty folder, or an ensemble's own folder (this one holds "
                f"{len(entries)} entr{'y' if len(entries) == 1 else 'ies'} ({shown}) and no "
                f"{MANIFEST}: it is not an ensemble's, and its files could be replaced); "
                f"give --out a new folder")
        return True
    try:
        loaded = persistence.load(manifest, "ensemble-manifest", (FORMAT_VERSION,),
                                  argument="out")
    except persistence.FileFormatError as exc:
        raise InvalidArgumentError(
            "out", str(out),
            f"a folder of ensemble files of format version {FORMAT_VERSION} "
            f"({MANIFEST}: {exc.reason})",
        ) from None
    meta = loaded.meta if isinstance(loaded.meta, dict) else {}
    if shared:
        if "ensemble" in meta:
            raise InvalidArgumentError(
                "out", str(out),
                f"a folder of task files shared by many ensembles, not one ensemble's own "
                f"({MANIFEST} records {_describe(meta.get('spec'))})")
        return meta.get("shared") is not True
    if meta.get("shared") is True:
        raise InvalidArgumentError(
            "out", str(out),
            "one ensemble's own folder, not one whose task files many ensembles share (such as "
            "the runs folder of reproduce): give --out a new folder")
    if "ensemble" not in meta:  # a manifest of an earlier release: judge by the task files
        keys = {t.key for t in tasks}
        foreign = sorted(p.name for p in out.glob("task-*.npz")
                         if p.name.split(".")[0][len("task-"):] not in keys)
        if foreign:
            raise InvalidArgumentError(
                "out", str(out),
                f"a folder of this ensemble's tasks ({len(foreign)} task files of another "
                f"ensemble, e.g. {foreign[0]!r}): give --out a new folder")
        return True
    if meta["ensemble"] != identity["ensemble"]:
        raise InvalidArgumentError(
            "out", str(out),
            f"a folder of this ensemble, not of another one ({MANIFEST} records "
            f"{_describe(meta.get('spec'))}; this one is {_describe(spec.to_dict())}): give "
            f"--out a new folder")
    dropped = set(meta.get("seeds", [])) - set(identity["seeds"])
    if dropped:
        raise InvalidArgumentError(
            "out", str(out),
            f"seeds including every seed of this folder's ensemble (--seeds drops "
            f"{_seed_text(dropped)}, whose results the aggregate would lose; a rerun may add "
            f"seeds, not remove them)")
    return meta.get("seeds") != identity["seeds"]


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
                 cluster: str | None = None, config=None, progress: bool | None = None,
                 executor: str = "dask", force: bool = False,
                 shared: bool = False) -> EnsembleReport:
    """Run the tasks of ``spec`` that have no valid file in ``out`` and aggregate them all.

    ``executor="dask"``: a local cluster of ``workers`` processes (default: the number of
    CPUs; never more than the tasks left to run, and at most
    :func:`particles.workers.max_workers`, 4 × the CPUs, unless ``force``), or
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
    progress : bool or None, optional
        None (default): a bar on a terminal or in a notebook, nothing otherwise; True: a bar,
        or a few plain lines where no bar can be drawn; False: nothing
        (:func:`particles.progress.progress_bar`).
    executor : str, optional
        ``"dask"`` (default) or ``"serial"``.
    force : bool, optional
        Allow more workers than :func:`particles.workers.max_workers`.
    shared : bool, optional
        ``out`` holds the task files of many ensembles (the comparisons' runs of
        ``reproduce``): its manifest records no single ensemble, and any manifest of this
        format version that records none is accepted (default False: ``out`` is this
        ensemble's own folder, see the module docstring).

    Returns
    -------
    EnsembleReport
        What was run, skipped, recomputed and failed, and the aggregate summary.

    Raises
    ------
    particles.InvalidArgumentError
        For a ``spec`` that is not an :class:`EnsembleSpec`, a bad ``out`` or ``executor``,
        a ``progress``, ``force`` or ``shared`` that is not a bool, a ``scheduler`` that is
        not an address,
        more than one of ``workers``, ``scheduler``, ``cluster`` (or any with the serial
        executor), a bad worker count, a bad cluster ``config`` or one without ``cluster``,
        a ``cluster`` without the optional dask-jobqueue installed,
        or an ``out`` that is not this ensemble's folder: a folder that holds files and no
        manifest, a manifest of another format version, of another ensemble (model,
        parameter grid, times, result options) or of seeds that ``spec`` drops (a rerun may
        add seeds).
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
    if progress is not None and not isinstance(progress, bool):
        raise InvalidArgumentError("progress", progress, "True, False or None")
    for name, value in (("force", force), ("shared", shared)):
        if not isinstance(value, bool):
            raise InvalidArgumentError(name, value, "True or False")
    workers = check_workers(workers, "workers", force=force)
    if scheduler is not None:
        check_scheduler(scheduler)
    if cluster is not None:  # checked before any work
        if cluster not in ("slurm", "pbs"):
            raise InvalidArgumentError("cluster", cluster, "'slurm' or 'pbs'")
        require_jobqueue(cluster)
        if config is None:
            raise InvalidArgumentError("config", None,
                                       "the batch cluster's TOML file (required with cluster)")
        load_cluster_config(config, cluster)
    elif config is not None:
        raise InvalidArgumentError("config", config, "only with cluster='slurm' or 'pbs'")
    tasks = spec.expand()
    identity = _folder_identity(spec, tasks)
    write_manifest = _check_folder(out, spec, tasks, identity, shared)
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
        if write_manifest:
            described = {k: v for k, v in spec.to_dict().items() if k != "seeds"}  # once
            recorded = {"shared": True} if shared else {
                **identity, "spec": json.loads(json.dumps(described))}
            persistence.save(out / MANIFEST, "ensemble-manifest", FORMAT_VERSION, {},
                             {"writer": "particles.ensemble", **recorded}, argument="out")
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


def _execute(client, todo, factory, out: Path, progress: bool | None) -> list[dict]:
    bar = progress_bar(len(todo), "ensemble", "tasks", enabled=progress if todo else False)
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
