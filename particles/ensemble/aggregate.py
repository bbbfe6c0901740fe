"""The aggregate of an ensemble (mean and standard error over the seeds of each parameter set)
and the report of a run."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import observables as obs
from .spec import EnsembleSpec
from .tasks import load_task


def _mean_sem(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`particles.observables.mean_sem` over the seeds (axis 0), always as arrays."""
    mean, sem = obs.mean_sem(rows, axis=0)
    return np.asarray(mean, dtype=float), np.asarray(sem, dtype=float)


def aggregate(spec: EnsembleSpec, out, tasks=None, done=None) -> tuple[dict, dict]:
    """(arrays, summary) of the aggregate: for each parameter set ``i``, over the seeds whose
    task file is in ``out`` (``done``: the keys to use; default all present), in the order of
    ``spec.seeds``, mean and standard error of ``energy``, ``momentum``, ``collisions``,
    ``kurtosis`` (⟨v⁴⟩/⟨v²⟩², when every task file has it), ``collisions_per_particle``
    (2·collisions/N, τ for Ulam; MD: its own τ(t)), the engine's extras, the histogram density
    at the last time (when every seed has one on the same edges) and S(k) (when requested).
    Arrays are named ``set<i>.<observable>.mean`` / ``.sem`` (plus ``set<i>.hist.edges``,
    ``set<i>.structure.k``).  The summary is JSON-able (S(k) is in the
    arrays only: N/2 + 1 numbers per row).

    Parameters
    ----------
    spec : particles.ensemble.EnsembleSpec
        The ensemble.
    out : str or os.PathLike
        The folder of the task files.
    tasks : list of particles.ensemble.EnsembleTask, optional
        The tasks (default ``spec.expand()``).
    done : set of str, optional
        The task keys to aggregate (default: every task whose file exists).

    Returns
    -------
    arrays : dict of str to numpy.ndarray
        ``times`` and the per-set means and standard errors.
    summary : dict
        JSON-able: ``model``, the times under the spec's time name, ``sets`` (params, seeds,
        ``n_seeds``, observables), and how ``sem`` is defined.

    Raises
    ------
    particles.persistence.FileFormatError
        (through :func:`load_task`) if a task file used is not that task's readable file.
    particles.validation.InvalidArgumentError
        Naming ``out`` when it is not an existing folder (a mistyped path would give an empty
        aggregate, as if no task had finished).
    """
    out = Path(out)
    if not out.is_dir():
        from ..validation import InvalidArgumentError

        raise InvalidArgumentError("out", str(out), "an existing folder of task files")
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
        if all(r.kurtosis is not None for r in results):  # task files before it: none
            series["kurtosis"] = np.stack([r.kurtosis for r in results])
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


@dataclass(frozen=True)
class EnsembleReport:
    """What :func:`run_ensemble` did.  ``tasks``: the number in the spec; ``ran``: keys run now
    (``resumed``: those continued from a checkpoint); ``skipped``: keys whose valid file was
    already there; ``recomputed``: damaged task files found ({"path", "reason", "params",
    "seed"}), their tasks run again; ``failed``: tasks that raised ({"params", "seed", "key",
    "error", "traceback"}) — empty when every task finished; ``aggregate``: the JSON summary of
    :func:`aggregate`, saved to ``aggregate_path``; ``seconds``: wall clock of each task run
    now, by key, and ``wall_seconds`` of the whole call.

    Attributes
    ----------
    out : str
        The output folder.
    executor : str
        ``"dask"`` or ``"serial"``.
    tasks : int
        Number of tasks in the spec.
    ran, skipped, resumed : tuple of str
        Task keys as described above.
    recomputed, failed : tuple of dict
        Damaged files found, and tasks that raised.
    aggregate : dict
        The JSON summary of :func:`aggregate`.
    aggregate_path : str
        Where the aggregate file is.
    seconds : dict
        Wall-clock seconds of each task run now, by key.
    wall_seconds : float
        Wall-clock seconds of the whole call.
    notes : tuple of str
        Remarks per task, e.g. a refused checkpoint.
    """

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
        """A JSON-able dict (strict JSON: no NaN) of the report (failures without tracebacks).

        Returns
        -------
        dict
            Counts of ``ran``, ``skipped``, ``resumed``; the lists of ``recomputed`` and
            ``failed``; ``ok``, ``aggregate_path``, ``aggregate``, ``wall_seconds``, ``notes``.
        """
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
