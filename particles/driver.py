"""The run driver shared by every particle model: initial velocities, the run loop, progress bar,
checkpoint / resume, Ctrl-C, and saving / loading results.

Engine protocol
---------------
An engine (``particles.ulam.Ulam``, ``particles.lattice.Lattice``, the MD engine) is an object with

* ``name: str`` — ``"ulam"``, ``"lattice"``, ``"md"``;
* ``params() -> dict`` — JSON-able parameters, including ``"n"`` (the number of particles);
  a checkpoint written with other parameters is rejected;
* ``initial_state(rng) -> state``;
* ``advance(state, until, rng) -> state`` — the exact dynamics from ``state.time`` up to ``until``
  (τ for Ulam and lattice, t for MD).  It must not modify ``state`` (the driver keeps the last
  completed state for Ctrl-C), and its result may depend on ``until`` only through the exact
  dynamics and the RNG stream, so the driver only calls it with deterministic stopping points;
* ``next_stop(time) -> float`` — the next deterministic stopping point strictly after ``time``
  (a fixed grid of the model's time): the driver advances to ``min(next_stop(t), next requested
  time)``.  Because stops never depend on wall-clock time, a resumed run repeats an uninterrupted
  one bit for bit;
* ``state_from_arrays(arrays) -> state`` — rebuild a state from ``state.to_arrays()``;
* optionally ``observe(state) -> dict[str, float]`` — extra scalars recorded at each requested
  time (e.g. τ(t) for MD).
* optionally ``snapshot_fields: tuple[str, ...]`` and ``snapshot_arrays(state) -> dict`` —
  per-particle arrays recorded with each snapshot (``snapshots=True``), e.g. the MD rods'
  positions; they are kept in checkpoints and in ``RunResult.snapshot_extras``;
* optionally ``time_name: str`` — the name of the model's time in messages (default ``"tau"``;
  ``"t"`` for MD).

A state is a frozen dataclass with at least ``time: float``, ``velocities: ndarray``,
``collisions: int`` and ``to_arrays() -> dict[str, ndarray]``.

All randomness comes from one ``np.random.default_rng(seed)``.
"""

from __future__ import annotations

import json
import math
import os
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from . import budget, persistence
from . import observables as obs
from .initial import get_law
from .progress import progress_bar
from .validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_output_file,
    check_path,
    check_times,
)

__all__ = [
    "CheckpointError",
    "Engine",
    "RunResult",
    "initial_velocities",
    "simulate",
    "next_grid_point",
]

#: Version of the result and checkpoint formats written now (2: through
#: :mod:`particles.persistence`, with a content hash); 1 (0.1.0, no hash) still loads.
FORMAT_VERSION = 2
_READABLE_VERSIONS = (1, 2)


class CheckpointError(persistence.FileFormatError):
    """A checkpoint or result file that cannot be read or belongs to another run."""

    def __init__(self, path, reason: str, argument: str = "resume"):
        super().__init__(path, reason, argument, "a readable checkpoint of this run")


class Engine(Protocol):  # pragma: no cover - typing only
    name: str

    def params(self) -> dict: ...

    def initial_state(self, rng: np.random.Generator) -> Any: ...

    def advance(self, state: Any, until: float, rng: np.random.Generator) -> Any: ...

    def next_stop(self, time: float) -> float: ...

    def state_from_arrays(self, arrays: dict[str, np.ndarray]) -> Any: ...


def initial_velocities(law, n: int, rng: np.random.Generator) -> np.ndarray:
    """Draw ``n`` velocities from ``law`` (a name or an ``InitialLaw``), then subtract their mean
    and rescale them so that the mean is 0 and ⟨v²⟩ = 1 up to round-off."""
    n = check_count(n, "n", 2)
    v = get_law(law).sample(rng, n)
    v = v - v.mean()
    e = float(np.mean(v * v))
    if not e > 0.0:
        raise InvalidArgumentError(
            "initial", getattr(law, "name", law), "a law with non-zero variance"
        )
    v *= 1.0 / math.sqrt(e)
    return v


def next_grid_point(time: float, step: float) -> float:
    """Smallest ``m * step`` (m an integer) strictly greater than ``time``."""
    m = math.floor(time / step) + 1
    while m * step <= time:
        m += 1
    while m > 1 and (m - 1) * step > time:
        m -= 1
    return m * step


# --------------------------------------------------------------------------- files


def _write_npz(path, arrays: dict[str, np.ndarray], meta: dict) -> None:
    """Write a result or checkpoint through the one persistence helper (atomic, hashed)."""
    meta = dict(meta)
    kind = meta.pop("kind")
    persistence.save(path, kind, FORMAT_VERSION, arrays, meta)


_ENTRY_PREFIXES = {
    "checkpoint": ("state.", "rec."),
    "result": ("times", "energy", "momentum", "collisions", "velocities", "hist.", "structure.",
               "snapshots", "snapshot.", "extra."),
}


def _entry_checker(kind: str, n: int | None, nt: int | None):
    """A check of each entry's header before its data is read: the names a file of ``kind``
    holds, and (when the run is known) at most ``max(nt, 1) · (n + 2) · d`` elements per entry,
    d ≤ 3 the velocity dimension: the largest record, snapshots of every time, is nt · n."""
    prefixes = _ENTRY_PREFIXES[kind]

    def check(name, dtype, shape, meta):
        if not name.startswith(prefixes):
            return f"not an entry of a {kind} file"
        if n is not None:
            limit = max(nt or 1, 1) * (n + 2) * 3
            count = int(np.prod(shape, dtype=object)) if shape else 1
            if count > limit:
                return f"declares shape {shape}, more than a run of N = {n} can hold"
        return None

    return check


def _read_npz(path, argument: str, kind: str, n: int | None = None,
              nt: int | None = None) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of a result (``kind="result"``) or checkpoint (``"checkpoint"``) file,
    read through :func:`particles.persistence.load` with its checks; :class:`CheckpointError`
    naming ``argument`` if it is not one.
    ``n`` and ``nt`` (the run's particles and times, when known) bound each entry's size before
    it is read."""
    try:
        loaded = persistence.load(path, kind, _READABLE_VERSIONS, argument=argument,
                                  check_entry=_entry_checker(kind, n, nt))
    except persistence.FileFormatError as exc:
        raise CheckpointError(path, exc.reason, argument) from None
    return loaded.meta, loaded.arrays


# --------------------------------------------------------------------------- results


@dataclass(frozen=True)
class RunResult:
    """What a run recorded at its requested times ``times`` (τ, or t for MD).

    ``energy[i]`` = ⟨v²⟩, ``momentum[i]`` = ⟨v⟩, ``collisions[i]`` = total collisions so far;
    ``histogram`` is the rescaled histogram at the last time, or ``None`` where x = v/√E is
    undefined (every velocity 0: a valid end state, e.g. r = 0 and N = 2 after one collision),
    with the reason in ``histogram_note``; ``structure`` is ``(k, S)`` with
    ``S[i]`` the structure factor at ``times[i]`` (``structure_factor=True``), or ``S`` of one
    row, at the last time (``structure_factor="last"``); ``S[-1]`` is the last time either way;
    ``snapshots[i]`` the
    velocities at ``times[i]`` (when requested); ``velocities`` the final velocities;
    ``extras`` engine-specific scalars per time; ``snapshot_extras[name][i]`` the engine's
    per-particle arrays at ``times[i]`` (with ``snapshots``, e.g. MD ``positions``);
    ``seconds`` the wall-clock time of the run (of all its resumed pieces);
    ``final_state`` the engine's state at the last time (None for a result read from a file:
    files keep the records, not the state).
    """

    model: str
    params: dict
    seed: int
    times: np.ndarray
    energy: np.ndarray
    momentum: np.ndarray
    collisions: np.ndarray
    velocities: np.ndarray
    histogram: obs.Histogram | None
    seconds: float
    structure: tuple[np.ndarray, np.ndarray] | None = None
    snapshots: np.ndarray | None = None
    extras: dict[str, np.ndarray] = field(default_factory=dict)
    histogram_note: str | None = None
    snapshot_extras: dict[str, np.ndarray] = field(default_factory=dict)
    final_state: Any = field(default=None, compare=False, repr=False)

    def to_record(self) -> tuple[dict[str, np.ndarray], dict]:
        """``(arrays, meta)``: the layout of a result file (:meth:`save`, and the ensemble's
        task files).  ``arrays``: ``times``, ``energy``, ``momentum``, ``collisions``,
        ``velocities``, ``hist.*``, ``structure.k``/``structure.S``, ``snapshots``,
        ``snapshot.<field>`` and ``extra.<name>`` where present; ``meta`` (JSON-able):
        ``model``, ``params``, ``seed``, ``seconds`` (None when NaN), and ``hist`` (samples,
        v0) and ``histogram_note`` where present.  The final state is not part of it."""
        arrays = {
            "times": self.times,
            "energy": self.energy,
            "momentum": self.momentum,
            "collisions": self.collisions,
            "velocities": self.velocities,
        }
        meta = {"model": self.model, "params": self.params, "seed": self.seed,
                "seconds": None if np.isnan(self.seconds) else self.seconds}
        if self.histogram is not None:
            h = self.histogram
            arrays.update({"hist.edges": h.edges, "hist.density": h.density,
                           "hist.error": h.error, "hist.count": h.count})
            meta["hist"] = {"samples": h.samples, "v0": h.v0}
        if self.histogram_note is not None:
            meta["histogram_note"] = self.histogram_note
        if self.structure is not None:
            arrays["structure.k"], arrays["structure.S"] = self.structure
        if self.snapshots is not None:
            arrays["snapshots"] = self.snapshots
        for key, value in self.snapshot_extras.items():
            arrays["snapshot." + key] = value
        for key, value in self.extras.items():
            arrays["extra." + key] = value
        return arrays, meta

    @classmethod
    def from_record(cls, arrays: dict[str, np.ndarray], meta: dict) -> RunResult:
        """The inverse of :meth:`to_record` (``final_state`` None; ``seconds`` NaN when the
        record has none).  ``KeyError`` or ``TypeError`` when an entry is missing or malformed;
        the readers turn them into a file-format error naming the file."""
        a = arrays
        hist = None
        if "hist.edges" in a:
            edges = a["hist.edges"]
            hist = obs.Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), a["hist.density"],
                                 a["hist.error"], a["hist.count"], int(meta["hist"]["samples"]),
                                 float(meta["hist"]["v0"]))
        seconds = meta.get("seconds")
        return cls(
            model=meta["model"],
            params=meta["params"],
            seed=int(meta["seed"]),
            times=a["times"],
            energy=a["energy"],
            momentum=a["momentum"],
            collisions=a["collisions"],
            velocities=a["velocities"],
            histogram=hist,
            seconds=float("nan") if seconds is None else float(seconds),
            structure=(a["structure.k"], a["structure.S"]) if "structure.k" in a else None,
            snapshots=a.get("snapshots"),
            extras={k[len("extra."):]: v for k, v in a.items() if k.startswith("extra.")},
            histogram_note=meta.get("histogram_note"),
            snapshot_extras={k[len("snapshot."):]: v for k, v in a.items()
                             if k.startswith("snapshot.")},
        )

    def save(self, path) -> None:
        """Save to ``path`` (an ``.npz`` archive with a JSON ``meta`` entry; the layout of
        :meth:`to_record`)."""
        arrays, meta = self.to_record()
        _write_npz(path, arrays, {"kind": "result", **meta})

    @classmethod
    def load(cls, path) -> RunResult:
        """Reload a result written by :meth:`save`."""
        meta, arrays = _read_npz(path, "path", "result")
        try:
            return cls.from_record(arrays, meta)
        except (KeyError, TypeError) as exc:
            raise CheckpointError(path, f"missing entry {exc}", "path") from None

    def summary(self) -> dict:
        """JSON-able summary (the ``--json`` output of ``simulate`` without the extras)."""
        out = {
            "model": self.model,
            "tau": self.times.tolist(),
            "energy": self.energy.tolist(),
            "collisions": int(self.collisions[-1]),
            "seconds": self.seconds,
        }
        if self.histogram is not None:
            out["histogram"] = self.histogram.to_dict()
        elif self.histogram_note is not None:
            out["histogram"] = None
            out["histogram_note"] = self.histogram_note
        return out


# --------------------------------------------------------------------------- the run loop


def _structure_mode(value) -> str | None:
    """``structure_factor`` option: False → None, True or ``"all"`` → ``"all"``, ``"last"``."""
    if value is False or value is None:
        return None
    if value is True or value == "all":
        return "all"
    if value == "last":
        return "last"
    raise InvalidArgumentError("structure_factor", value, "False, True, 'all' or 'last'")


class _Records:
    """Per-time records of a run in progress (also what a checkpoint stores)."""

    def __init__(self, nt: int, n: int, structure: str | None, snapshots: bool,
                 snapshot_fields: tuple[str, ...] = ()):
        self.done = 0
        self.energy = np.full(nt, np.nan)
        self.momentum = np.full(nt, np.nan)
        self.collisions = np.zeros(nt, dtype=np.int64)
        # S(k) at every time ("all": nt rows of N/2 + 1, 40 MB per time at N = 1e7) or at the
        # last time only ("last": one row).
        self.structure_last = structure == "last"
        rows = 1 if self.structure_last else nt
        self.structure = np.full((rows, n // 2 + 1), np.nan) if structure else None
        self.snapshots = np.full((nt, n), np.nan) if snapshots else None
        # per-particle arrays an engine adds to each snapshot (MD: the rods' positions)
        self.snapshot_extras = {name: np.full((nt, n), np.nan) for name in snapshot_fields}
        self.extras: dict[str, np.ndarray] = {}
        self.seconds = 0.0

    def record(self, engine, state, nt: int) -> None:
        """Record the observables of ``state`` as entry ``done`` and count it (a Ctrl-C in here
        may leave entry ``done`` half written: :meth:`arrays` never stores it)."""
        i = self.done
        v = state.velocities
        if v.ndim == 2:  # (N, d) velocities: ⟨|v|²⟩ per particle and |⟨v⟩|
            self.energy[i] = float(np.mean(np.einsum("ij,ij->i", v, v)))
            self.momentum[i] = float(np.linalg.norm(v.mean(axis=0)))
        else:
            self.energy[i] = obs.energy(v)
            self.momentum[i] = obs.momentum(v)
        self.collisions[i] = int(state.collisions)
        if self.structure is not None and not (self.structure_last and i < nt - 1):
            self.structure[0 if self.structure_last else i] = obs.structure_factor(v)[1]
        if self.snapshots is not None:
            self.snapshots[i] = v
        if self.snapshot_extras:
            for key, value in engine.snapshot_arrays(state).items():
                self.snapshot_extras[key][i] = value
        observe = getattr(engine, "observe", None)
        if observe is not None:
            for key, value in observe(state).items():
                self.extras.setdefault(key, np.full(nt, np.nan))[i] = value
        self.done += 1

    def arrays(self) -> dict[str, np.ndarray]:
        """The records as stored in a checkpoint: the rows from ``done`` on are unrecorded
        (NaN; 0 for the integer collision counts), whatever an interrupted :meth:`record` wrote
        there, so a checkpoint saved at any moment is consistent."""
        done = self.done

        def unrecorded_from(a, row):
            fill = 0 if a.dtype.kind in "iu" else np.nan
            tail = a[row:]
            if np.array_equal(tail, np.full_like(tail, fill), equal_nan=True):
                return a  # nothing to reset: no copy
            a = a.copy()
            a[row:] = fill
            return a

        out = {
            "rec.energy": unrecorded_from(self.energy, done),
            "rec.momentum": unrecorded_from(self.momentum, done),
            "rec.collisions": unrecorded_from(self.collisions, done),
        }
        if self.structure is not None:
            # "last": its one row is recorded only together with the last time
            row = int(done == self.energy.size) if self.structure_last else done
            out["rec.structure"] = unrecorded_from(self.structure, row)
        if self.snapshots is not None:
            out["rec.snapshots"] = unrecorded_from(self.snapshots, done)
        for key, value in self.snapshot_extras.items():
            out["rec.snapshot." + key] = unrecorded_from(value, done)
        for key, value in self.extras.items():
            out["rec.extra." + key] = unrecorded_from(value, done)
        return out

    def restore(self, arrays: dict[str, np.ndarray], done: int, seconds: float) -> None:
        self.done = done
        self.seconds = seconds
        self.energy = arrays["rec.energy"]
        self.momentum = arrays["rec.momentum"]
        self.collisions = arrays["rec.collisions"]
        if self.structure is not None:
            self.structure = arrays["rec.structure"]
        if self.snapshots is not None:
            self.snapshots = arrays["rec.snapshots"]
        for key in self.snapshot_extras:
            self.snapshot_extras[key] = arrays["rec.snapshot." + key]
        prefix = "rec.extra."
        self.extras = {k[len(prefix) :]: v for k, v in arrays.items() if k.startswith(prefix)}


def _run_identity(engine, times, seed, edges, structure, snapshots) -> dict:
    identity = {
        "model": engine.name,
        "params": engine.params(),
        "times": [float(t) for t in times],
        "seed": int(seed),
        "options": {
            "bins": [float(e) for e in edges],
            # True for "all" (what every checkpoint so far holds), "last", or False
            "structure_factor": {None: False, "all": True, "last": "last"}[structure],
            "snapshots": bool(snapshots),
        },
    }
    return json.loads(json.dumps(identity))  # normalise tuples, numpy scalars


def _save_checkpoint(path, identity, state, rng_state, records: _Records) -> None:
    arrays = {"state." + k: np.asarray(v) for k, v in state.to_arrays().items()}
    arrays.update(records.arrays())
    meta = {
        "kind": "checkpoint",
        "run": identity,
        "rng": rng_state,
        "done": records.done,
        "seconds": records.seconds,
    }
    _write_npz(path, arrays, meta)


def _load_checkpoint(path, engine, identity, records: _Records):
    n = int(identity["params"]["n"])
    meta, arrays = _read_npz(path, "resume", "checkpoint", n, len(identity["times"]))
    run = meta.get("run", {})
    arrays = _structure_all_to_last(run, identity, arrays)
    diffs = [key for key in identity if run.get(key) != identity[key]]
    if diffs:
        shown = ", ".join(f"{k}: file {run.get(k)!r} vs run {identity[k]!r}" for k in diffs)
        if len(shown) > 400:
            shown = shown[:400] + "..."
        raise CheckpointError(path, f"written for a different run; {shown}")
    try:
        state = engine.state_from_arrays(
            {k[len("state.") :]: v for k, v in arrays.items() if k.startswith("state.")}
        )
        done = meta["done"]
        if isinstance(done, bool) or not isinstance(done, int):
            raise ValueError(f"done={done!r} is not an integer")
        records.restore(arrays, done, float(meta["seconds"]))
        rng = np.random.default_rng(identity["seed"])
        rng.bit_generator.state = meta["rng"]
    except (KeyError, TypeError, ValueError) as exc:
        raise CheckpointError(path, f"incomplete checkpoint: {type(exc).__name__}: {exc}") from None
    problem = _inconsistency(engine, identity["times"], state, records)
    if problem is not None:
        raise CheckpointError(path, f"inconsistent checkpoint: {problem}")
    return state, rng


def _structure_all_to_last(run: dict, identity: dict, arrays: dict) -> dict:
    """Let a run that keeps S(k) at its last time only (``"last"``, what the CLI asks for) resume
    a checkpoint that kept it at every time (``True``, e.g. written by an earlier version of the
    CLI): the dynamics is the same, only the last row is kept.  ``run`` (the file's identity) is
    updated in place to match; anything else about the files is checked as usual."""
    options, wanted = run.get("options"), identity["options"]
    if not (isinstance(options, dict) and options.get("structure_factor") is True
            and wanted["structure_factor"] == "last"):
        return arrays
    rows = arrays.get("rec.structure")
    if rows is None or np.ndim(rows) != 2 or len(rows) != len(identity["times"]):
        return arrays  # not a well-formed "all" file: let the usual checks name the problem
    options["structure_factor"] = "last"
    arrays = dict(arrays)
    arrays["rec.structure"] = np.asarray(rows)[-1:]
    return arrays


#: Stops walked at most when checking that a checkpoint's time is one the driver stops at.
_MAX_STOPS_CHECKED = 100_000


def _inconsistency(engine, times: list[float], state, records: _Records) -> str | None:
    """Why the fields of a checkpoint disagree with each other or with the run, or ``None``.

    A checkpoint the driver wrote satisfies all of these: ``done`` (records made) is between 0
    and the number of times; the recorded entries are finite and the others are unrecorded
    (NaN); the record arrays have one entry per time (S(k) and snapshots: N/2 + 1 and N wide);
    the state is finite, its collisions at least the last recorded count, and its time is a
    stop of the driver after the last recorded time: ``times[done-1]`` (0 if none), reached by
    the engine's ``next_stop`` grid and not beyond ``times[done]`` (equal to the last time once
    all are done).  Editing any one of them is caught here."""
    nt = len(times)
    n = int(engine.params()["n"])
    done = records.done
    if not 0 <= done <= nt:
        return f"done={done}, the run has {nt} requested times (0 <= done <= {nt})"
    if not (math.isfinite(records.seconds) and records.seconds >= 0):
        return f"seconds={records.seconds!r}, expected a finite number >= 0"
    shapes = {
        "rec.energy": (records.energy, (nt,)),
        "rec.momentum": (records.momentum, (nt,)),
        "rec.collisions": (records.collisions, (nt,)),
    }
    if records.structure is not None:
        rows = 1 if records.structure_last else nt
        shapes["rec.structure"] = (records.structure, (rows, n // 2 + 1))
    if records.snapshots is not None:
        shapes["rec.snapshots"] = (records.snapshots, (nt, n))
    for key, value in records.snapshot_extras.items():
        shapes["rec.snapshot." + key] = (value, (nt, n))
    for key, value in records.extras.items():
        shapes["rec.extra." + key] = (value, (nt,))
    for key, (value, shape) in shapes.items():
        if np.shape(value) != shape:
            return f"{key} has shape {np.shape(value)}, expected {shape}"
    for key in ("rec.energy", "rec.momentum"):
        value = shapes[key][0]
        if not np.all(np.isfinite(value[:done])):
            return f"{key} is not finite among the {done} recorded entries (done={done})"
        if not np.all(np.isnan(value[done:])):
            return f"{key} has entries beyond the {done} recorded (done={done})"
    recorded = records.collisions[:done]
    if np.any(recorded < 0) or np.any(np.diff(recorded) < 0):
        return f"rec.collisions={recorded.tolist()} is not a non-decreasing count"
    t = float(state.time)
    v = np.asarray(state.velocities)
    d = int(engine.params().get("dimension", 1))
    shape = (n,) if d == 1 else (n, d)
    if v.shape != shape or not np.all(np.isfinite(v)):
        return f"state.velocities: shape {v.shape}, expected {shape} and finite"
    collisions = int(state.collisions)
    last = int(recorded[-1]) if done else 0
    if collisions < last:
        return f"state.collisions={collisions} is below the last recorded count {last}"
    start = float(times[done - 1]) if done else 0.0
    end = float(times[done]) if done < nt else start
    if not start <= t <= end:
        return (
            f"state.time={t!r}, expected between the last recorded time {start!r} and the next "
            f"requested time {end!r} (done={done})"
        )
    if done and t == start and collisions != last:
        return f"state.collisions={collisions}, recorded {last} at the same time {t!r}"
    stop, walked = start, 0
    while stop < t and walked < _MAX_STOPS_CHECKED:
        stop = min(float(engine.next_stop(stop)), end)
        walked += 1
    if stop != t and walked < _MAX_STOPS_CHECKED:
        return (
            f"state.time={t!r} is not a stop of this run between {start!r} and {end!r} "
            f"(the stop grid passes {stop!r})"
        )
    return None


def _final_histogram(v: np.ndarray, edges) -> tuple[obs.Histogram | None, str | None]:
    """The rescaled histogram of the final velocities (of one Cartesian component in d > 1), or
    ``(None, reason)`` where it is undefined.

    A state with every velocity 0 (energy 0) is a valid end of a run, not bad input: r = 0 makes
    colliding velocities equal, so N = 2 reaches it after one collision.  x = v/√E has no meaning
    there, so no histogram is made (``rescaled_histogram`` would raise, and a raise after the
    run would turn a valid run into exit status 2)."""
    if v.ndim == 2:
        v = np.ascontiguousarray(v[:, 0])
    if not np.any(v):
        return None, "every velocity is 0 at the last time (energy 0): x = v/sqrt(E) is undefined"
    return obs.rescaled_histogram(v, edges), None


def simulate(
    engine,
    times,
    seed,
    *,
    progress: bool = True,
    checkpoint=None,
    resume=None,
    bins=None,
    structure_factor: bool = False,
    snapshots: bool = False,
    checkpoint_interval: float = 60.0,
    force: bool = False,
) -> RunResult:
    """Run ``engine`` from its initial state through the requested ``times`` (increasing, ≥ 0).

    Records at every requested time the energy ⟨v²⟩, the mean velocity, the total number of
    collisions, the structure factor (``structure_factor=True`` or ``"all"``; ``"last"`` keeps
    it at the last time only, which is all the CLI prints: one row of N/2 + 1 floats instead of
    one per time) and the velocities (``snapshots=True``); at the last time the rescaled
    histogram on ``bins`` (edges in x = v/√E, default
    :data:`particles.observables.DEFAULT_EDGES`).

    ``seed`` (an integer ≥ 0) seeds the one ``np.random.default_rng`` of the run.  With
    ``checkpoint=PATH`` the state, the RNG state and the records so far are written to PATH
    every ``checkpoint_interval`` wall-clock seconds (at the engine's stops), at the end, and on
    Ctrl-C before the ``KeyboardInterrupt`` propagates; the propagating exception then carries
    the path as ``checkpoint_saved`` (absent if nothing was saved on the interrupt, e.g. when it
    came before the run loop).  ``resume=PATH`` continues from such a
    file; the run (model, parameters, times, seed, options) must be the one that wrote it, else
    :class:`CheckpointError`.  A resumed run equals an uninterrupted one bit for bit.  While
    the run writes ``checkpoint`` it holds a lock on ``<checkpoint>.lock``: a second run on the
    same path is refused (:class:`CheckpointError` naming it).

    Before anything is drawn, the run's memory and work are estimated
    (:mod:`particles.budget`): a run that cannot fit in the memory available is refused, and so
    is one of more than 10¹³ events unless ``force=True``.
    """
    times = check_times(times, getattr(engine, "time_name", "tau"))
    seed = check_count(seed, "seed", 0)
    hist_edges = obs.rescaled_histogram(np.array([1.0, -1.0]), bins).edges  # validates bins
    checkpoint_interval = check_nonnegative(checkpoint_interval, "checkpoint_interval")
    structure_factor = _structure_mode(structure_factor)
    snapshots = bool(snapshots)
    if checkpoint is not None:
        checkpoint = check_output_file(checkpoint, "checkpoint")
    _check_engine(engine)
    if int(engine.params().get("dimension", 1)) != 1 and (structure_factor or snapshots):
        raise InvalidArgumentError(
            "structure_factor" if structure_factor else "snapshots", True,
            "a one-dimensional model (S(k) and snapshots are recorded in d = 1 only)",
        )
    identity = _run_identity(engine, times, seed, hist_edges, structure_factor, snapshots)
    time_name = getattr(engine, "time_name", "tau")
    estimate = budget.check_budget(
        budget.estimate_run(engine.name, identity["params"], float(times[-1]),
                            n_times=len(times), structure=structure_factor, snapshots=snapshots),
        force=force, time_name=time_name,
    )
    n = int(engine.params()["n"])
    with _CheckpointLock(checkpoint):
        fields = tuple(getattr(engine, "snapshot_fields", ())) if snapshots else ()
        records = _Records(len(times), n, structure_factor, snapshots, fields)
        if resume is not None:
            state, rng = _load_checkpoint(check_path(resume, "resume"), engine, identity,
                                          records)
        else:
            rng = np.random.default_rng(seed)
            state = engine.initial_state(rng)
        return _run(engine, times, seed, identity, state, rng, records, progress, checkpoint,
                    checkpoint_interval, hist_edges, estimate)


def _check_engine(engine) -> None:
    """The engine protocol, checked at the boundary (a wrong object is bad input, not an
    AttributeError deep inside)."""
    missing = [name for name in ("name", "params", "initial_state", "advance", "next_stop",
                                 "state_from_arrays") if not hasattr(engine, name)]
    if missing:
        raise InvalidArgumentError(
            "engine", type(engine).__name__, f"an engine of the driver protocol (missing {missing})"
        )


class _CheckpointLock:
    """An exclusive ``flock`` on ``<checkpoint>.lock`` while a run writes ``checkpoint`` (the
    kernel drops it when the process dies, so a killed run leaves no stale lock)."""

    def __init__(self, checkpoint):
        self.path = None if checkpoint is None else Path(str(checkpoint) + ".lock")
        self.fd = None

    def __enter__(self):
        if self.path is None:
            return self
        import fcntl

        self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(self.fd)
            self.fd = None
            raise CheckpointError(
                self.path.with_suffix(""), "another run is writing this checkpoint now",
                "checkpoint",
            ) from None
        return self

    def __exit__(self, *exc):
        if self.fd is not None:
            try:
                os.unlink(self.path)
            except OSError:
                pass
            os.close(self.fd)  # closing releases the lock
            self.fd = None


def _run(engine, times, seed, identity, state, rng, records, progress, checkpoint,
         checkpoint_interval, hist_edges, estimate) -> RunResult:
    """The run loop of :func:`simulate` (arguments checked, lock held)."""
    rng_state = rng.bit_generator.state

    started = _time.perf_counter()
    seconds_before = records.seconds
    last_save = _time.monotonic()
    bar = None
    if progress:
        bar = progress_bar(float(times[-1]), engine.name, getattr(engine, "time_name", "τ"),
                           initial=float(state.time), postfix=f"estimate {estimate.describe()}")
    try:
        while records.done < len(times):
            target = float(times[records.done])
            while state.time < target:
                stop = min(float(engine.next_stop(state.time)), target)
                new = engine.advance(state, stop, rng)
                new_rng_state = rng.bit_generator.state
                # One statement: Ctrl-C cannot separate the state from its RNG state.
                state, rng_state, previous = new, new_rng_state, state
                if bar is not None:
                    bar.update(state.time - previous.time)
                if checkpoint is not None and _time.monotonic() - last_save >= checkpoint_interval:
                    records.seconds = seconds_before + _time.perf_counter() - started
                    _save_checkpoint(checkpoint, identity, state, rng_state, records)
                    last_save = _time.monotonic()
            records.record(engine, state, len(times))
    except KeyboardInterrupt as exc:
        if checkpoint is not None:
            records.seconds = seconds_before + _time.perf_counter() - started
            _save_checkpoint(checkpoint, identity, state, rng_state, records)
            exc.checkpoint_saved = str(checkpoint)  # only once the file is in place
        raise
    finally:
        if bar is not None:
            bar.close()
    records.seconds = seconds_before + _time.perf_counter() - started
    v = state.velocities
    histogram, histogram_note = _final_histogram(v, hist_edges)  # before anything is written
    if checkpoint is not None:
        _save_checkpoint(checkpoint, identity, state, rng_state, records)

    structure = None
    if records.structure is not None:
        structure = (obs.wavenumbers(v.size), records.structure)
    return RunResult(
        model=engine.name,
        params=identity["params"],
        seed=seed,
        times=times,
        energy=records.energy,
        momentum=records.momentum,
        collisions=records.collisions,
        velocities=v,
        histogram=histogram,
        seconds=records.seconds,
        structure=structure,
        snapshots=records.snapshots,
        snapshot_extras=records.snapshot_extras,
        extras=records.extras,
        histogram_note=histogram_note,
        final_state=state,
    )
