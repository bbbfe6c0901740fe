"""Ensembles: many runs of one particle model over a grid of parameters and a set of seeds.

An ensemble is an :class:`EnsembleSpec`: a model of the catalogue :mod:`particles.models`
(``"ulam"``, ``"lattice"``, ``"md"``, ``"sticky"``, or any name added with
:func:`register_model`), its parameters (a value, or a list of values that is swept), the seeds,
the requested times (in the engines' time, ``engine.time_name``: τ for Ulam and the constant-rate
lattice, t for MD, the sticky gas and the lattice of rate |Δ|) and options of
:func:`particles.driver.simulate` (``structure_factor``, ``bins``, ``checkpoint_interval``).
:meth:`EnsembleSpec.expand` gives the tasks: the Cartesian product of the swept parameters (in
the order the parameters are given, the first one slowest) times the seeds (fastest).

:func:`run_ensemble` runs the tasks and writes, in the output folder ``out``:

* ``manifest.npz`` (kind ``"ensemble-manifest"``): marks the folder as holding ensemble files
  of format version :data:`FORMAT_VERSION`; a folder of another version is refused;
* one file per task, ``task-<key>.npz`` (kind ``"ensemble-task"``), where ``<key>`` is a
  SHA-256 of the task's identity: model, the engine's parameters (``engine.params()``, so
  ``n=1e6`` and ``n=1000000`` are one task), seed, times, the options that change the result
  (``structure_factor``, histogram edges) and :data:`FORMAT_VERSION`.  A task file holds the
  :class:`particles.driver.RunResult` arrays and its identity, and NOT the wall-clock time, so
  two runs of one task write byte-identical files (measured, NumPy 2.4: ``np.savez`` stamps
  zip entries with a fixed date); the seconds are in the report;
* ``task-<key>.ckpt.npz``: the checkpoint of a task in progress (every ``checkpoint_interval``
  seconds, default 60); a rerun resumes from it and deletes it once the task file is written;
* ``ensemble.npz`` (kind ``"ensemble"``): the aggregate of the last run, per parameter set the
  mean and standard error over its seeds of each observable (see :func:`aggregate`).

A rerun skips the tasks whose file is present, loads (the content hash is verified) and holds
the task's identity; a truncated or otherwise damaged file is reported in
``EnsembleReport.recomputed`` and its task run again.  A task that raises (e.g.
``particles.md.InelasticCollapseError``) does not stop the others; it is listed in
``EnsembleReport.failed`` with its parameters and seed.  A worker process that dies in the
middle of a task (killed, out of memory) is replaced by dask and the task is run again
(resuming from its checkpoint, if one was written): a resumed run equals an uninterrupted one
bit for bit, so the aggregate does not depend on it.

Executors: ``"dask"`` (default) on :mod:`dask.distributed` — a ``LocalCluster`` of ``workers``
single-threaded processes, an existing scheduler (``scheduler="tcp://host:8786"``; the output
folder must then be visible to its workers at the same path) or a batch cluster
(``cluster="slurm"`` or ``"pbs"`` with a TOML ``config``, :func:`load_cluster_config`) — or
``"serial"``: the tasks one after the other in this process, no dask (reference and tests).
dask is imported only when it is used.

Standard error: ``sem = s / sqrt(m)`` with ``s`` the sample standard deviation (ddof = 1) over
the ``m`` seeds that finished; NaN where m = 1.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import time as _time
import traceback
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import observables as obs
from . import persistence
from .driver import CheckpointError, RunResult, simulate
from .models import get_model, register_model, registered_models
from .progress import progress_bar
from .validation import (
    InvalidArgumentError,
    check_nonnegative,
    check_output_dir,
    check_times,
    check_workers,
)

__all__ = [
    "FORMAT_VERSION",
    "EnsembleSpec",
    "EnsembleTask",
    "EnsembleReport",
    "register_model",
    "registered_models",
    "parse_seeds",
    "run_ensemble",
    "run_task",
    "load_task",
    "aggregate",
    "load_cluster_config",
    "make_cluster",
    "local_cluster",
    "cluster_job_script",
]

#: Format version of the task, manifest and aggregate files (part of every task's key).
FORMAT_VERSION = 1
#: Largest seed accepted (``np.random.default_rng`` takes any integer ≥ 0; 64 bits is plenty).
MAX_SEED = 2**64 - 1
MANIFEST = "manifest.npz"
AGGREGATE = "ensemble.npz"
#: Seconds allowed to connect to an existing scheduler (``scheduler=ADDRESS``).
SCHEDULER_TIMEOUT = 10.0

# --------------------------------------------------------------------------- model registry


# The models are those of the catalogue, :mod:`particles.models` (``register_model`` adds one).


# --------------------------------------------------------------------------- seeds


def parse_seeds(text: str) -> tuple[int, ...]:
    """Seeds from a list such as ``"1-16,20,25-27"``: comma-separated integers ≥ 0 and ranges
    ``a-b`` (a ≤ b, both included), in the order given.  Empty elements, descending ranges,
    duplicates and seeds above 2⁶⁴ − 1 are refused."""
    if not isinstance(text, str):
        raise InvalidArgumentError("seeds", text, "a string such as '1-16,20,25-27'")
    seeds: list[int] = []
    for part in text.split(","):
        part = part.strip()
        bounds = [b.strip() for b in part.split("-")] if part else [""]
        if len(bounds) > 2 or not all(b.isdigit() and b.isascii() for b in bounds):
            raise InvalidArgumentError(
                "seeds", text, f"comma-separated integers >= 0 and ranges a-b (element {part!r})"
            )
        lo, hi = int(bounds[0]), int(bounds[-1])
        if hi < lo:
            raise InvalidArgumentError("seeds", text, f"ascending ranges (got {part!r})")
        if hi > MAX_SEED:
            raise InvalidArgumentError("seeds", text, f"seeds <= 2**64 - 1 (got {part!r})")
        if hi - lo > 10**7:
            raise InvalidArgumentError("seeds", text, f"ranges of at most 10**7 seeds ({part!r})")
        seeds.extend(range(lo, hi + 1))
    return _check_seeds(seeds, text)


def _check_seeds(seeds, shown) -> tuple[int, ...]:
    out = []
    for s in seeds:
        if isinstance(s, (bool, np.bool_)) or not isinstance(s, (int, np.integer)):
            raise InvalidArgumentError("seeds", shown, "integers >= 0")
        if not 0 <= int(s) <= MAX_SEED:
            raise InvalidArgumentError("seeds", shown, "integers in [0, 2**64 - 1]")
        out.append(int(s))
    if not out:
        raise InvalidArgumentError("seeds", shown, "at least one seed")
    dup = sorted({s for s in out if out.count(s) > 1}) if len(set(out)) != len(out) else []
    if dup:
        raise InvalidArgumentError("seeds", shown, f"distinct seeds (repeated: {dup[:10]})")
    return tuple(out)


# --------------------------------------------------------------------------- spec and tasks

_OPTIONS = ("structure_factor", "bins", "checkpoint_interval", "snapshots")


def _json_value(name: str, value):
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        if not math.isfinite(value):
            raise InvalidArgumentError(name, value, "a finite number")
        return float(value)
    raise InvalidArgumentError(name, value, "a number, a string or a boolean (or a list of them)")


@dataclass(frozen=True)
class EnsembleTask:
    """One run of an ensemble: ``params`` (this task's values of the spec's parameters),
    ``seed``, the index ``set_index`` of its parameter set in the grid, and ``key``, the hash of
    ``identity`` (what the run's result depends on) that names its file."""

    model: str
    params: dict
    seed: int
    times: tuple[float, ...]
    options: dict
    set_index: int
    identity: dict = field(repr=False)
    key: str = ""

    @property
    def filename(self) -> str:
        return f"task-{self.key}.npz"

    @property
    def checkpoint_name(self) -> str:
        return f"task-{self.key}.ckpt.npz"

    def describe(self) -> dict:
        """JSON-able {"params", "seed"} (how failures and damaged files are reported)."""
        return {"params": dict(self.params), "seed": self.seed, "key": self.key}


@dataclass(frozen=True)
class EnsembleSpec:
    """What to run: ``model`` (a name of the catalogue :mod:`particles.models`); ``params``,
    {name: value or list of values} (a list is swept; every list must be non-empty and without
    repeats); ``seeds`` (integers in [0, 2⁶⁴ − 1], distinct, or a string for
    :func:`parse_seeds`); ``times`` (increasing, ≥ 0, in the engines' time
    :attr:`time_name`; every engine of the grid must have the same); ``options``:
    ``structure_factor`` (False, True/"all" or "last"), ``bins`` (histogram edges in
    x = v/√E), ``checkpoint_interval`` (seconds between a task's checkpoints,
    default 60).  Everything is checked here and every engine of the grid is built, so a bad
    spec fails before any work."""

    model: str
    params: Mapping[str, Any]
    seeds: tuple[int, ...]
    times: tuple[float, ...]
    options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        m = get_model(self.model)
        if not isinstance(self.params, Mapping):
            raise InvalidArgumentError("params", self.params, "a mapping {name: value or list}")
        params = {}
        for name, value in self.params.items():
            m.parameter(name)  # an unknown name is refused
            values = list(value) if isinstance(value, (list, tuple)) else [value]
            if not values:
                raise InvalidArgumentError(name, value, "a non-empty list (the grid is empty)")
            values = [_json_value(name, v) for v in values]
            if len({json.dumps(v) for v in values}) != len(values):
                raise InvalidArgumentError(name, value, "distinct values")
            params[name] = tuple(values)
        missing = [p for p in m.required if p not in params]
        if missing:
            raise InvalidArgumentError("params", sorted(params), f"values for {missing}")
        object.__setattr__(self, "params", params)
        seeds = parse_seeds(self.seeds) if isinstance(self.seeds, str) else self.seeds
        try:
            seeds = list(seeds)
        except TypeError:
            raise InvalidArgumentError("seeds", self.seeds, "a list of integers") from None
        object.__setattr__(self, "seeds", _check_seeds(seeds, self.seeds))
        engines = [m.build(values) for values in self.parameter_sets()]  # bad values fail here
        time_names = sorted({m.time_name(e) for e in engines})
        if len(time_names) != 1:
            raise InvalidArgumentError(
                "params", {k: list(v) for k, v in params.items()},
                f"parameter sets whose engines share one time (got {time_names})",
            )
        object.__setattr__(self, "_time_name", time_names[0])
        times = check_times(self.times, time_names[0])
        object.__setattr__(self, "times", tuple(float(t) for t in times))
        if not isinstance(self.options, Mapping):
            raise InvalidArgumentError("options", self.options, f"a mapping of {_OPTIONS}")
        options = dict(self.options)
        unknown = [k for k in options if k not in _OPTIONS]
        if unknown:
            raise InvalidArgumentError("options", unknown, f"options among {list(_OPTIONS)}")
        sf = options.get("structure_factor", False)
        if sf not in (False, True, "all", "last"):
            raise InvalidArgumentError("structure_factor", sf, "False, True, 'all' or 'last'")
        options["structure_factor"] = {True: True, "all": True}.get(sf, sf)
        bins = options.get("bins")
        edges = obs.rescaled_histogram(np.array([1.0, -1.0]), bins).edges  # validates bins
        options["bins"] = None if bins is None else [float(e) for e in edges]
        snaps = options.get("snapshots", False)
        if not isinstance(snaps, bool):
            raise InvalidArgumentError("snapshots", snaps, "True or False")
        options["snapshots"] = snaps
        options["checkpoint_interval"] = check_nonnegative(
            options.get("checkpoint_interval", 60.0), "checkpoint_interval"
        )
        object.__setattr__(self, "options", options)
        self.expand()  # builds every engine: bad values fail here

    @property
    def time_name(self) -> str:
        """The name of the time of the spec's engines (``engine.time_name``: ``"tau"``, or
        ``"t"`` for MD, the sticky gas and the lattice of rate |Δ|)."""
        return self._time_name

    def parameter_sets(self) -> list[dict]:
        """The grid: one dict per parameter set, first parameter slowest."""
        names = list(self.params)
        return [dict(zip(names, combo, strict=True))
                for combo in itertools.product(*(self.params[n] for n in names))]

    def expand(self) -> list[EnsembleTask]:
        """The tasks: every parameter set × every seed (seeds fastest)."""
        m = get_model(self.model)
        edges = obs.rescaled_histogram(np.array([1.0, -1.0]), self.options["bins"]).edges
        result_options = {
            "structure_factor": self.options["structure_factor"],
            "bins": [float(e) for e in edges],
        }
        if self.options["snapshots"]:  # only then, so that earlier task keys stay valid
            result_options["snapshots"] = True
        tasks = []
        for index, values in enumerate(self.parameter_sets()):
            engine = m.build(values)
            for seed in self.seeds:
                identity = json.loads(json.dumps({
                    "model": self.model,
                    "params": engine.params(),
                    "seed": seed,
                    "times": list(self.times),
                    "options": result_options,
                    "version": FORMAT_VERSION,
                }))
                key = hashlib.sha256(json.dumps(identity, sort_keys=True).encode()).hexdigest()
                tasks.append(EnsembleTask(self.model, values, seed, self.times, dict(self.options),
                                          index, identity, key[:24]))
        return tasks

    def to_dict(self) -> dict:
        """JSON-able description (stored in the aggregate)."""
        return {"model": self.model, "params": {k: list(v) for k, v in self.params.items()},
                "seeds": list(self.seeds), "times": list(self.times),
                "options": dict(self.options)}


# --------------------------------------------------------------------------- one task

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
    :class:`particles.persistence.FileFormatError`."""
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
    "error", "traceback"}``."""
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


# --------------------------------------------------------------------------- aggregate


def _mean_sem(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`particles.observables.mean_sem` over the seeds (axis 0), always as arrays."""
    mean, sem = obs.mean_sem(rows, axis=0)
    return np.asarray(mean, dtype=float), np.asarray(sem, dtype=float)


def aggregate(spec: EnsembleSpec, out, tasks=None, done=None) -> tuple[dict, dict]:
    """(arrays, summary) of the aggregate: for each parameter set ``i``, over the seeds whose
    task file is in ``out`` (``done``: the keys to use; default all present), in the order of
    ``spec.seeds``, mean and standard error of ``energy``, ``momentum``, ``collisions``,
    ``collisions_per_particle`` (2·collisions/N, τ for Ulam; MD: its own τ(t)), the engine's
    extras, the histogram density at the last time (when every seed has one on the same edges)
    and S(k) (when requested).  Arrays are named ``set<i>.<observable>.mean`` / ``.sem`` (plus
    ``set<i>.hist.edges``, ``set<i>.structure.k``).  The summary is JSON-able (S(k) is in the
    arrays only: N/2 + 1 numbers per row)."""
    out = Path(out)
    tasks = spec.expand() if tasks is None else tasks
    arrays: dict[str, np.ndarray] = {"times": np.asarray(spec.times)}
    sets = []
    for index, values in enumerate(spec.parameter_sets()):
        mine = [t for t in tasks if t.set_index == index]
        if done is None:
            use = [t for t in mine if (out / t.filename).exists()]
        else:
            use = [t for t in mine if t.key in done]
        results = [load_task(out / t.filename, t.identity) for t in use]
        entry = {"index": index, "params": values, "seeds": [t.seed for t in use],
                 "n_seeds": len(results), "observables": {}}
        sets.append(entry)
        if not results:
            continue
        series = {
            "energy": np.stack([r.energy for r in results]),
            "momentum": np.stack([r.momentum for r in results]),
            "collisions": np.stack([r.collisions.astype(float) for r in results]),
        }
        for key in results[0].extras:
            if all(key in r.extras for r in results):
                series[key] = np.stack([r.extras[key] for r in results])
        if "collisions_per_particle" not in series:
            n = np.array([float(r.params["n"]) for r in results])[:, None]
            series["collisions_per_particle"] = 2.0 * series["collisions"] / n
        hists = [r.histogram for r in results]
        if all(h is not None for h in hists) and all(
            np.array_equal(h.edges, hists[0].edges) for h in hists
        ):
            series["hist.density"] = np.stack([h.density for h in hists])
            arrays[f"set{index}.hist.edges"] = hists[0].edges
        if all(r.structure is not None for r in results):
            arrays[f"set{index}.structure.k"] = results[0].structure[0]
            series["structure.S"] = np.stack([r.structure[1] for r in results])
        for key, rows in series.items():
            mean, sem = _mean_sem(rows)
            arrays[f"set{index}.{key}.mean"], arrays[f"set{index}.{key}.sem"] = mean, sem
            if key != "structure.S":
                entry["observables"][key] = {"mean": _json_list(mean), "sem": _json_list(sem)}
        if f"set{index}.hist.edges" in arrays:
            entry["observables"]["hist.density"]["edges"] = _json_list(hists[0].edges)
    summary = {"model": spec.model, spec.time_name: list(spec.times), "sets": sets,
               "sem": "sample standard deviation (ddof=1) / sqrt(n_seeds); null for one seed"}
    return arrays, summary


def _json_list(a: np.ndarray) -> list:
    """A list with NaN and infinities as None (strict JSON)."""
    return [float(x) if math.isfinite(x) else None for x in np.asarray(a, dtype=float).ravel()]


# --------------------------------------------------------------------------- report


@dataclass(frozen=True)
class EnsembleReport:
    """What :func:`run_ensemble` did.  ``tasks``: the number in the spec; ``ran``: keys run now
    (``resumed``: those continued from a checkpoint); ``skipped``: keys whose valid file was
    already there; ``recomputed``: damaged task files found ({"path", "reason", "params",
    "seed"}), their tasks run again; ``failed``: tasks that raised ({"params", "seed", "key",
    "error", "traceback"}) — empty when every task finished; ``aggregate``: the JSON summary of
    :func:`aggregate`, saved to ``aggregate_path``; ``seconds``: wall clock of each task run
    now, by key, and ``wall_seconds`` of the whole call."""

    out: str
    executor: str
    tasks: int
    ran: tuple[str, ...]
    skipped: tuple[str, ...]
    resumed: tuple[str, ...]
    recomputed: tuple[dict, ...]
    failed: tuple[dict, ...]
    aggregate: dict
    aggregate_path: str
    seconds: dict
    wall_seconds: float
    notes: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return not self.failed

    def to_json(self) -> dict:
        """A JSON-able dict (strict JSON: no NaN) of the report (failures without tracebacks)."""
        return {
            "out": self.out,
            "executor": self.executor,
            "tasks": self.tasks,
            "ran": len(self.ran),
            "skipped": len(self.skipped),
            "resumed": len(self.resumed),
            "recomputed": list(self.recomputed),
            "failed": [{k: v for k, v in f.items() if k != "traceback"} for f in self.failed],
            "ok": self.ok,
            "aggregate_path": self.aggregate_path,
            "aggregate": self.aggregate,
            "wall_seconds": self.wall_seconds,
            "notes": list(self.notes),
        }


# --------------------------------------------------------------------------- folder


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


# --------------------------------------------------------------------------- clusters

_CLUSTER_KEYS = {
    "queue": str, "walltime": str, "cores": int, "memory": str, "processes": int, "jobs": int,
    "account": str, "job_extra_directives": list, "job_script_prologue": list, "interface": str,
    "local_directory": str, "log_directory": str, "python": str, "dashboard_address": str,
}


def load_cluster_config(path, cluster: str) -> dict:
    """Settings of a batch cluster from a TOML file (top-level keys, or a ``[slurm]`` /
    ``[pbs]`` table)::

        queue = "normal"          # SLURM partition / PBS queue
        walltime = "02:00:00"     # per job
        cores = 16                # cores per job (required)
        memory = "64GB"           # memory per job (required)
        processes = 16            # worker processes per job (default: cores, 1 thread each)
        jobs = 4                  # jobs started (default 1)
        account = "proj42"        # optional: account / project
        job_extra_directives = ["--constraint=cpu"]
        job_script_prologue = ["module load python"]
        interface = "ib0"         # optional network interface
        local_directory = "/tmp"  # optional worker scratch
        log_directory = "logs"    # optional job logs
        dashboard_address = ":8787"  # optional; default ":0" (a free port)

    The values go to ``dask_jobqueue.SLURMCluster`` / ``PBSCluster`` under the same names."""
    if cluster not in ("slurm", "pbs"):
        raise InvalidArgumentError("cluster", cluster, "'slurm' or 'pbs'")
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except (OSError, TypeError) as exc:
        raise InvalidArgumentError("config", str(path), f"a readable TOML file ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InvalidArgumentError("config", str(path), f"valid TOML ({exc})") from None
    if isinstance(data.get(cluster), dict):
        data = data[cluster]
    settings = {}
    for key, value in data.items():
        if key in ("slurm", "pbs"):
            continue
        kind = _CLUSTER_KEYS.get(key)
        if kind is None:
            raise InvalidArgumentError("config", f"{path}: {key}",
                                       f"keys among {sorted(_CLUSTER_KEYS)}")
        if not isinstance(value, kind) or isinstance(value, bool) or (
            kind is int and value < 1
        ) or (kind is list and not all(isinstance(v, str) for v in value)):
            wanted = "an integer >= 1" if kind is int else f"a {kind.__name__}"
            raise InvalidArgumentError("config", f"{path}: {key} = {value!r}", f"{key}: {wanted}")
        settings[key] = value
    missing = [k for k in ("cores", "memory") if k not in settings]
    if missing:
        raise InvalidArgumentError("config", str(path), f"the keys {missing}")
    settings.setdefault("processes", settings["cores"])
    settings.setdefault("jobs", 1)
    return settings


def local_cluster(workers: int | None = None):
    """A ``dask.distributed.LocalCluster`` of ``workers`` single-threaded worker processes
    (default: one per core) with one BLAS/OpenMP thread each, and WITHOUT distributed's default
    ``MALLOC_TRIM_THRESHOLD_=65536``: with it glibc gives every large temporary array back to the
    OS, and the engines' O(N) temporaries then pay page faults on every allocation (measured,
    8 Ulam runs of N = 1e6 to τ = 10: 1.1–1.7 s per task on the workers against 0.43 s in the
    parent process; 0.5–1.0 s without it)."""
    import dask
    from distributed import LocalCluster

    environ = {name: 1 for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                    "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")}
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}):
        # ":0" and no dashboard: the scheduler's HTTP routes on a free port (the default 8787
        # may be taken by another cluster, and dask then warns)
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            dashboard_address=":0", scheduler_kwargs={"dashboard": False})


def make_cluster(cluster: str, settings: dict):
    """A ``dask_jobqueue.SLURMCluster`` or ``PBSCluster`` (no job submitted yet; scale it with
    ``cluster.scale(jobs=settings["jobs"])``)."""
    import dask_jobqueue

    kwargs = {k: v for k, v in settings.items() if k not in ("jobs", "dashboard_address")}
    kwargs["scheduler_options"] = {"dashboard_address": settings.get("dashboard_address", ":0")}
    cls = {"slurm": dask_jobqueue.SLURMCluster, "pbs": dask_jobqueue.PBSCluster}[cluster]
    return cls(**kwargs)


def cluster_job_script(cluster: str, config) -> str:
    """The batch script the cluster would submit per job (needs no batch system)."""
    settings = load_cluster_config(config, cluster)
    c = make_cluster(cluster, settings)
    try:
        return c.job_script()
    finally:
        c.close()


# --------------------------------------------------------------------------- running


def _connect(executor, workers, scheduler, cluster, config):
    """(client, closer) for the dask executors; errors name the argument."""
    from distributed import Client

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as exc:
            raise InvalidArgumentError(
                "scheduler", scheduler,
                f"the address of a reachable dask scheduler (no connection within "
                f"{SCHEDULER_TIMEOUT:g} s: {type(exc).__name__})",
            ) from None
        return client, [client.close]
    if cluster is not None:
        settings = load_cluster_config(config, cluster)
        c = make_cluster(cluster, settings)
        c.scale(jobs=settings["jobs"])
        client = Client(c)
        return client, [client.close, c.close]
    c = local_cluster(workers)
    client = Client(c)
    return client, [client.close, c.close]


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
    does not raise: see ``report.failed``.  See the module docstring for the files."""
    started = _time.perf_counter()
    if not isinstance(spec, EnsembleSpec):
        raise InvalidArgumentError("spec", spec, "an EnsembleSpec")
    out = check_output_dir(out, "out")
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
        client, closers = _connect(executor, local, scheduler, cluster, config)
    try:
        out.mkdir(parents=True, exist_ok=True)
        if not (out / MANIFEST).exists():
            persistence.save(out / MANIFEST, "ensemble-manifest", FORMAT_VERSION, {},
                             {"writer": "particles.ensemble"})
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
                     json.loads(json.dumps(meta, allow_nan=True)))
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
