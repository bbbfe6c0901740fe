"""Checkpoints of a run: the records so far, the identity of the run, writing and reading a
checkpoint with its consistency checks, and the lock that keeps two runs off one checkpoint."""

from __future__ import annotations

import errno
import json
import math
import os
from pathlib import Path

import numpy as np

from .. import observables as obs
from .. import persistence
from ..validation import InvalidArgumentError
from .result import FORMAT_VERSION, CheckpointError, read_file


def _kurtosis_from_squares(squares: np.ndarray, e2: float, v: np.ndarray) -> float:
    """⟨v⁴⟩/⟨v²⟩² from ``squares`` = v² (squared again in place: the caller's scratch) and its
    mean ``e2``; :func:`particles.observables.kurtosis` (the same value to round-off) where v⁴
    could under- or overflow (⟨v²⟩ below 1e-140 or not finite, ⟨v⁴⟩ not finite)."""
    if not 1e-140 <= e2 < math.inf:
        return obs.kurtosis(v)
    with np.errstate(over="ignore", under="ignore"):  # an overflow is caught just below
        np.multiply(squares, squares, out=squares)
        e4 = float(np.mean(squares))
    if not e4 < math.inf:
        return obs.kurtosis(v)
    return e4 / (e2 * e2)


def _histogram_record(v, energy, classes, edges, scratch=None) -> tuple[np.ndarray | int, float]:
    """The counts of x = v/v0 on ``edges`` and v0 = √⟨v²⟩, as
    :func:`particles.observables.rescaled_histogram` computes them (the same counts and v0, bit
    for bit): v0 from ``energy`` = ⟨v²⟩ when it is a normal float (else recomputed without
    underflow), and the counts from the distinct velocities ``classes = (values, counts)`` when
    the engine gives them.  x is written into ``scratch`` (an array like ``v``) when given.
    ``(0, 0.0)`` when every velocity is 0 (x undefined)."""
    if classes is not None:
        values, counts = classes
        if not np.any(values):
            return 0, 0.0
    elif not np.any(v):
        return 0, 0.0
    if energy is None or not np.finfo(float).tiny <= energy < math.inf:
        h = obs.rescaled_histogram(v, edges)  # ⟨v²⟩ under- or overflows
        return h.count, h.v0
    v0 = math.sqrt(energy)
    if classes is not None:  # each value counted as often as particles hold it
        count, _ = np.histogram(values / v0, bins=edges, weights=np.asarray(counts, np.int64))
    else:
        x = np.divide(v, v0, out=scratch)
        count, _ = np.histogram(x, bins=edges)
    return count, v0


class Records:
    """Per-time records of a run in progress (also what a checkpoint stores)."""

    def __init__(self, nt: int, n: int, structure: str | None, snapshots: bool,
                 snapshot_fields: tuple[str, ...] = (), edges=None):
        self.done = 0
        # The rescaled histogram at every time (RunResult.histograms): its counts on ``edges``
        # and its scale v0 = sqrt(E) (0 where E = 0 and x is undefined; NaN: not recorded),
        # nt * (B + 1) numbers in all.
        self.hist_edges = None if edges is None else np.asarray(edges, dtype=float)
        self.hist_count = self.hist_v0 = None  # none recorded (edges None)
        if self.hist_edges is not None:
            self.hist_count = np.zeros((nt, self.hist_edges.size - 1), dtype=np.int64)
            self.hist_v0 = np.full(nt, np.nan)
        self.energy = np.full(nt, np.nan)
        self.momentum = np.full(nt, np.nan)
        # ⟨v⁴⟩/⟨v²⟩² of the velocities (of the first Cartesian component in d > 1; NaN where
        # every velocity is 0)
        self.kurtosis = np.full(nt, np.nan)
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
        # The engine's own arrays: trusted, never validated or copied here (a run of 10⁷
        # particles records 20 times).  An engine whose velocities take few distinct values
        # (the sticky gas's clusters) gives them with their multiplicities, and the kurtosis
        # and histogram are computed from those.
        hook = getattr(engine, "velocity_classes", None)
        classes = hook(state) if hook is not None else None
        scratch = None  # one temporary of N values serves the energy, kurtosis and histogram
        if v.ndim == 2:  # (N, d) velocities: ⟨|v|²⟩ per particle and |⟨v⟩|
            self.energy[i] = float(np.mean(np.einsum("ij,ij->i", v, v)))
            self.momentum[i] = float(np.linalg.norm(v.mean(axis=0)))
            first = np.ascontiguousarray(v[:, 0])
            with np.errstate(over="ignore"):
                scratch = first * first
                e_first = float(np.mean(scratch))
        else:
            first = v
            with np.errstate(over="ignore"):  # as observables.energy: inf beyond ~1e154
                scratch = v * v
                e_first = float(np.mean(scratch))
            self.energy[i] = e_first
            self.momentum[i] = float(np.mean(v))
        if classes is not None:
            self.kurtosis[i] = obs.weighted_kurtosis(*classes)
        else:
            self.kurtosis[i] = _kurtosis_from_squares(scratch, e_first, first)
        self.collisions[i] = int(state.collisions)
        if self.hist_edges is not None:
            self.hist_count[i], self.hist_v0[i] = _histogram_record(
                first, e_first, classes, self.hist_edges, scratch)
        del scratch  # freed before the structure factor's own arrays of N values
        if self.structure is not None and not (self.structure_last and i < nt - 1):
            self.structure[0 if self.structure_last else i] = obs.structure_factor(v)[1]
        if self.snapshots is not None:
            self.snapshots[i] = v
        if self.snapshot_extras:
            for key, value in engine.snapshot_arrays(state).items():
                self.snapshot_extras[key][i] = value
        for key, value in engine.observe(state).items():
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
            "rec.kurtosis": unrecorded_from(self.kurtosis, done),
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
        if self.hist_edges is not None:
            out["rec.hist_count"] = unrecorded_from(self.hist_count, done)
            out["rec.hist_v0"] = unrecorded_from(self.hist_v0, done)
        return out

    def restore(self, arrays: dict[str, np.ndarray], done: int, seconds: float) -> None:
        self.done = done
        self.seconds = seconds
        self.energy = arrays["rec.energy"]
        self.momentum = arrays["rec.momentum"]
        kurtosis = arrays.get("rec.kurtosis")  # absent from checkpoints written before it
        if kurtosis is not None:
            self.kurtosis = np.asarray(kurtosis, dtype=float)
        self.collisions = arrays["rec.collisions"]
        if self.structure is not None:
            self.structure = arrays["rec.structure"]
        if self.snapshots is not None:
            self.snapshots = arrays["rec.snapshots"]
        for key in self.snapshot_extras:
            self.snapshot_extras[key] = arrays["rec.snapshot." + key]
        prefix = "rec.extra."
        self.extras = {k[len(prefix) :]: v for k, v in arrays.items() if k.startswith(prefix)}
        if self.hist_edges is not None:
            count, v0 = arrays.get("rec.hist_count"), arrays.get("rec.hist_v0")
            if count is not None and v0 is not None:
                self.hist_count, self.hist_v0 = np.asarray(count), np.asarray(v0, dtype=float)
            else:  # a checkpoint written before per-time histograms: those times have none
                self.hist_v0[:] = np.nan


def seed_record(seed):
    """The JSON form of a run's seed: the int itself, or for a
    :class:`numpy.random.SeedSequence` that is not a plain int seed (a spawned child, a large
    or sequence entropy) ``{"entropy", "spawn_key", "pool_size"}``."""
    if isinstance(seed, np.random.SeedSequence):
        entropy = seed.entropy
        entropy = int(entropy) if np.isscalar(entropy) else [int(e) for e in entropy]
        return {"entropy": entropy, "spawn_key": [int(k) for k in seed.spawn_key],
                "pool_size": int(seed.pool_size)}
    if isinstance(seed, dict):  # already a record
        return seed
    return int(seed)


def seed_source(record):
    """What ``numpy.random.default_rng`` takes for a seed record of :func:`seed_record`."""
    if isinstance(record, dict):
        return np.random.SeedSequence(record["entropy"], spawn_key=tuple(record["spawn_key"]),
                                      pool_size=int(record["pool_size"]))
    return int(record)


def run_identity(engine, times, seed, edges, structure, snapshots, histograms=True) -> dict:
    identity = {
        "model": engine.name,
        "params": engine.to_dict(),
        "times": [float(t) for t in times],
        "seed": seed_record(seed),
        "options": {
            "bins": [float(e) for e in edges],
            # True for "all" (what every checkpoint so far holds), "last", or False
            "structure_factor": {None: False, "all": True, "last": "last"}[structure],
            "snapshots": bool(snapshots),
        },
    }
    if not histograms:  # only where off: the runs before the option keep their identity
        identity["options"]["histograms"] = False
    return json.loads(json.dumps(identity))  # normalise tuples, numpy scalars


def save_checkpoint(path, identity, state, rng_state, records: Records) -> None:
    arrays = {"state." + k: np.asarray(v) for k, v in state.to_arrays().items()}
    arrays.update(records.arrays())
    meta = {
        "run": identity,
        "rng": rng_state,
        "done": records.done,
        "seconds": records.seconds,
    }
    # errors name the argument ``checkpoint`` (a full disk: persistence.WriteError)
    persistence.save(path, "checkpoint", FORMAT_VERSION, arrays, meta, argument="checkpoint")


def load_checkpoint(path, engine, identity, records: Records):
    n = int(identity["params"]["n"])
    meta, arrays = read_file(path, "resume", "checkpoint", n, len(identity["times"]))
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
        rng = np.random.default_rng(seed_source(identity["seed"]))
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


def _inconsistency(engine, times: list[float], state, records: Records) -> str | None:
    """Why the fields of a checkpoint disagree with each other or with the run, or ``None``.

    A checkpoint the driver wrote satisfies all of these: ``done`` (records made) is between 0
    and the number of times; the recorded entries are finite and the others are unrecorded
    (NaN); the record arrays have one entry per time (S(k) and snapshots: N/2 + 1 and N wide);
    the state is finite, its collisions at least the last recorded count, and its time is a
    stop of the driver after the last recorded time: ``times[done-1]`` (0 if none), reached by
    the engine's ``next_stop`` grid and not beyond ``times[done]`` (equal to the last time once
    all are done).  Editing any one of them is caught here."""
    nt = len(times)
    n = int(engine.to_dict()["n"])
    done = records.done
    if not 0 <= done <= nt:
        return f"done={done}, the run has {nt} requested times (0 <= done <= {nt})"
    if not (math.isfinite(records.seconds) and records.seconds >= 0):
        return f"seconds={records.seconds!r}, expected a finite number >= 0"
    shapes = {
        "rec.energy": (records.energy, (nt,)),
        "rec.momentum": (records.momentum, (nt,)),
        "rec.kurtosis": (records.kurtosis, (nt,)),
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
    if records.hist_edges is not None:
        shapes["rec.hist_count"] = (records.hist_count, (nt, records.hist_edges.size - 1))
        shapes["rec.hist_v0"] = (records.hist_v0, (nt,))
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
    d = int(engine.to_dict().get("dimension", 1))
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


class CheckpointLock:
    """An exclusive ``flock`` on ``<checkpoint>.lock`` while a run writes ``checkpoint`` (the
    kernel drops it when the process dies, so a killed run leaves no stale lock).

    The lock file lies beside the file the checkpoint is written to (a symlink is followed, so
    two runs given two links to one file share one lock).  Where ``<name>.lock`` would pass the
    file system's limit on names (a legal name of 251 to 255 bytes), the lock is the short
    ``.<hash of name>.lock`` instead (:func:`particles.persistence.sibling_name`).  A lock that
    cannot be created (a directory or a symlink in its place, no permission, a disk full of
    inodes) raises :class:`particles.InvalidArgumentError` naming ``checkpoint`` and the lock
    file, before the run starts.
    """

    def __init__(self, checkpoint):
        self.path = None
        if checkpoint is not None:
            target = Path(os.path.realpath(checkpoint))
            self.path = target.parent / persistence.sibling_name(target, ".lock")
        self.checkpoint = checkpoint
        self.fd = None

    def __enter__(self):
        if self.path is None:
            return self
        import fcntl

        try:  # never through a symlink: that would create a file wherever it points
            self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o666)
        except OSError as exc:
            reason = exc.strerror or str(exc)
            if exc.errno == errno.ELOOP:
                reason = "it is a symlink"
            raise InvalidArgumentError(
                "checkpoint", str(self.checkpoint),
                f"a checkpoint whose lock file {self.path} can be created ({reason})",
            ) from None
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(self.fd)
            self.fd = None
            raise CheckpointError(
                self.checkpoint, "another run is writing this checkpoint now", "checkpoint",
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


def read_checkpoint(path, argument: str = "path") -> dict:
    """The content of the checkpoint file at ``path``, read through the persistence helper with
    its checks (content hash, entry names and sizes); :class:`CheckpointError` naming
    ``argument`` when it is not a checkpoint.

    Returns ``{"run", "done", "seconds", "state", "records"}``: ``run`` the identity of the run
    that wrote it (model, parameters, times, seed, options), ``done`` the number of requested
    times recorded, ``seconds`` the wall-clock time so far, ``state`` the engine's state arrays
    (``engine.state_from_arrays(state)`` rebuilds the state) and ``records`` the record arrays
    (``energy``, ``momentum``, ``collisions``, ... per requested time; NaN where not yet
    recorded).  Reading it runs nothing and checks nothing against an engine: to continue the
    run, pass the file to :func:`particles.driver.simulate` as ``resume``.

    Parameters
    ----------
    path : str or os.PathLike
        The checkpoint file.
    argument : str, optional
        The argument name errors report (default ``"path"``).

    Returns
    -------
    dict
        ``{"run", "done", "seconds", "state", "records"}`` as described above.

    Raises
    ------
    particles.CheckpointError
        (argument ``argument``) if the file is not a readable, complete checkpoint.
    """
    meta, arrays = read_file(path, argument, "checkpoint")
    try:
        return {
            "run": meta["run"],
            "done": int(meta["done"]),
            "seconds": float(meta["seconds"]),
            "state": {k[len("state."):]: v for k, v in arrays.items() if k.startswith("state.")},
            "records": {k[len("rec."):]: v for k, v in arrays.items() if k.startswith("rec.")},
        }
    except (KeyError, TypeError, ValueError) as exc:
        raise CheckpointError(path, f"incomplete checkpoint: {type(exc).__name__}: {exc}",
                              argument) from None
