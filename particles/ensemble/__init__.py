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

* ``manifest.npz`` (kind ``"ensemble-manifest"``): marks the folder as holding the files of
  one ensemble, of format version :data:`FORMAT_VERSION`, and records that ensemble (a hash of
  its model, parameter grid, times and result options) and its seeds.  ``out`` must be a new or
  empty folder or this ensemble's: a folder that holds files and no manifest, a manifest of
  another version or of another ensemble, or one whose seeds the spec drops is refused before
  anything is written (a rerun may add seeds: it runs only the new tasks);
* one file per task, ``task-<key>.npz`` (kind ``"ensemble-task"``), where ``<key>`` is a
  SHA-256 of the task's identity: model, the engine's parameters (``engine.to_dict()``, so
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

from ..models import register_model, registered_models
from .aggregate import EnsembleReport, aggregate
from .cluster import (
    SCHEDULER_TIMEOUT,
    cluster_job_script,
    load_cluster_config,
    local_cluster,
    make_cluster,
)
from .run import AGGREGATE, MANIFEST, run_ensemble
from .spec import FORMAT_VERSION, EnsembleSpec, EnsembleTask, parse_seeds
from .tasks import load_task, run_task

__all__ = [
    "FORMAT_VERSION",
    "MANIFEST",
    "AGGREGATE",
    "SCHEDULER_TIMEOUT",
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



def __getattr__(name: str):
    if name == "MAX_SEED":
        raise ImportError("particles.ensemble.MAX_SEED is particles.validation.SEED_MAX, "
                          "the one seed bound of the library, the command line and the ensembles")
    raise AttributeError(f"module 'particles.ensemble' has no attribute {name!r}")
