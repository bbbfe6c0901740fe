"""The record of a run (:class:`RunResult`) and the files of results and checkpoints: one
layout, written and read through :mod:`particles.persistence` (atomic, hashed)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import observables as obs
from .. import persistence

#: Version of the result and checkpoint formats written now (2: through
#: :mod:`particles.persistence`, with a content hash); 1 (0.1.0, no hash) still loads.
FORMAT_VERSION = 2
READABLE_VERSIONS = (1, 2)


def import_xarray(what: str):
    """The :mod:`xarray` module, or an ``ImportError`` saying that ``what`` needs the optional
    ``xarray`` extra and how to install it."""
    try:
        import xarray
    except ImportError:
        raise ImportError(f"{what} needs xarray, an optional dependency: pip install "
                          "'maxwell-kinetics[xarray]' (or pip install xarray)") from None
    return xarray


#: The time of a result file written before results kept their engine's time name: by model
#: (t for MD and the sticky gas), else the time its rate kernel counts (:func:`time_name_of`).
_TIME_NAMES = {"md": "t", "sticky": "t"}


def time_name_of(model: str, params: dict) -> str:
    """The time a result of ``model`` with ``params`` counts, for a file that did not record
    it: ``"t"`` for MD and the sticky gas, else that of the kernel named by ``params["rate"]``
    (:mod:`particles.kernels`), else ``"tau"``.

    Parameters
    ----------
    model : str
        The engine's name.
    params : dict
        The engine's parameters.

    Returns
    -------
    str
    """
    from ..kernels import KERNELS, ConstantRate

    if model in _TIME_NAMES:
        return _TIME_NAMES[model]
    kernel = KERNELS.get(params.get("rate", ConstantRate.name))
    return kernel.time_name if kernel is not None else "tau"


class CheckpointError(persistence.FileFormatError):
    """A checkpoint or result file that cannot be read or belongs to another run.

    A :class:`particles.persistence.FileFormatError` whose expectation reads "a readable
    checkpoint of this run".

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    reason : str
        Why it was refused.
    argument : str, optional
        The argument name reported (default ``"resume"``).
    """

    def __init__(self, path, reason: str, argument: str = "resume"):
        super().__init__(path, reason, argument, "a readable checkpoint of this run")


def write_file(path, arrays: dict[str, np.ndarray], meta: dict) -> None:
    """Write a result or checkpoint through the one persistence helper (atomic, hashed)."""
    meta = dict(meta)
    kind = meta.pop("kind")
    persistence.save(path, kind, FORMAT_VERSION, arrays, meta)


_ENTRY_PREFIXES = {
    "checkpoint": ("state.", "rec."),
    "result": ("times", "energy", "momentum", "kurtosis", "collisions", "velocities", "hist.",
               "hists.",
               "structure.", "snapshots", "snapshot.", "extra."),
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
            if name in ("rec.hist_count", "hists.count"):  # nt rows of at most 10⁶ bins
                limit = max(nt or 1, 1) * 10**6
            count = int(np.prod(shape, dtype=object)) if shape else 1
            if count > limit:
                return f"declares shape {shape}, more than a run of N = {n} can hold"
        return None

    return check


def read_file(path, argument: str, kind: str, n: int | None = None,
              nt: int | None = None) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of a result (``kind="result"``) or checkpoint (``"checkpoint"``) file,
    read through :func:`particles.persistence.load` with its checks; :class:`CheckpointError`
    naming ``argument`` if it is not one.
    ``n`` and ``nt`` (the run's particles and times, when known) bound each entry's size before
    it is read."""
    try:
        loaded = persistence.load(path, kind, READABLE_VERSIONS, argument=argument,
                                  check_entry=_entry_checker(kind, n, nt))
    except persistence.FileFormatError as exc:
        raise CheckpointError(path, exc.reason, argument) from None
    return loaded.meta, loaded.arrays


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
    ``kurtosis[i]`` = ⟨v⁴⟩/⟨v²⟩² at ``times[i]`` (of the first Cartesian component in d > 1;
    NaN where every velocity is 0; None for a file written before it was recorded);
    ``histograms`` the rescaled histogram at every time (``histograms[-1]`` is ``histogram``),
    kept as counts: nt · (B + 1) numbers, 8 bytes each, for B bins (1000 times of 200 bins:
    1.6 MB), whatever N;
    ``final_state`` the engine's state at the last time (None for a result read from a file:
    files keep the records, not the state).

    Attributes
    ----------
    model : str
        The engine's name (``"ulam"``, ``"lattice"``, ``"md"``, ``"sticky"``, ...).
    params : dict
        The engine's JSON-able parameters.
    seed : int or dict
        The run's seed: an int, or for a ``SeedSequence`` that is not one
        ``{"entropy", "spawn_key", "pool_size"}``.
    times : numpy.ndarray
        The requested times, shape ``(nt,)`` (τ, or t for MD and the sticky gas).
    energy : numpy.ndarray
        ⟨v²⟩ at each time (no factor ½), shape ``(nt,)``.
    momentum : numpy.ndarray
        ⟨v⟩ at each time, shape ``(nt,)``.
    collisions : numpy.ndarray
        Total collisions so far at each time, shape ``(nt,)``.
    velocities : numpy.ndarray
        The final velocities, shape ``(N,)`` (``(N, d)`` in d > 1).
    histogram : particles.observables.Histogram or None
        The rescaled histogram at the last time, or None where undefined.
    seconds : float
        Wall-clock seconds of the run (NaN when a record has none).
    structure : tuple of numpy.ndarray or None
        ``(k, S)``; S of shape ``(nt, N//2 + 1)`` or ``(N//2 + 1,)``.
    snapshots : numpy.ndarray or None
        Velocities at each time, shape ``(nt, N)``.
    extras : dict of str to numpy.ndarray
        Engine-specific scalars per time (e.g. τ(t) for MD).
    histogram_note : str or None
        Why there is no histogram.
    snapshot_extras : dict of str to numpy.ndarray
        Engine per-particle arrays at each time (e.g. MD ``positions``).
    final_state : object
        The engine's last state (not compared; None for a result read from a file).
    histogram_edges : numpy.ndarray or None
        The edges of the histograms in x (None for a record without per-time histograms).
    histogram_counts : numpy.ndarray or None
        Counts per bin at each time, shape ``(nt, B)``.
    kurtosis : numpy.ndarray or None
        ⟨v⁴⟩/⟨v²⟩² at each time (see above).
    histogram_scales : numpy.ndarray or None
        v0 = √E of each time's histogram, shape ``(nt,)`` (0 where E = 0, NaN where the time
        was not recorded, e.g. resumed from a checkpoint that kept no per-time histograms).
    time_name : str
        The time the engine counts, ``"tau"`` or ``"t"`` (its ``time_name``; for a file
        written before results kept it, :func:`time_name_of` its model and parameters).
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
    histogram_edges: np.ndarray | None = field(default=None, repr=False)
    histogram_counts: np.ndarray | None = field(default=None, repr=False)
    histogram_scales: np.ndarray | None = field(default=None, repr=False)
    kurtosis: np.ndarray | None = field(default=None, repr=False)
    time_name: str | None = None

    def __repr__(self) -> str:
        """One line: the model, N, the seed, the saved times and the last energy (the arrays
        are attributes; printing N velocities helps nobody)."""
        name = self.time_name or "time"
        times = np.asarray(self.times)
        span = f"{times[0]:g}..{times[-1]:g}" if times.size else "none"
        last = f", energy {float(np.asarray(self.energy)[-1]):.6g} at the last" if (
            times.size) else ""
        return (f"RunResult(model={self.model!r}, n={self.params.get('n')}, seed={self.seed}, "
                f"{times.size} times {name} = {span}{last})")

    def __post_init__(self):
        if self.time_name is None:  # a record written before results kept it
            object.__setattr__(self, "time_name", time_name_of(self.model, self.params))

    @property
    def histograms(self) -> tuple:
        """The rescaled histogram of x = v/√E (one Cartesian component in d > 1) at each of
        ``times``, on the run's ``bins``: a tuple of :class:`particles.observables.Histogram`
        (None at a time where x is undefined or that was not recorded); the last is
        :attr:`histogram`.  Built from the counts kept per time (nt · (B + 1) numbers).

        Returns
        -------
        tuple of particles.observables.Histogram or None
            One entry per time (empty for a record without per-time histograms).
        """
        if self.histogram_counts is None or self.histogram_edges is None:
            return ()
        n = self.velocities.shape[0]
        return tuple(
            obs.histogram_from_counts(self.histogram_edges, count, n, v0)
            if np.isfinite(v0) and v0 > 0 else None
            for count, v0 in zip(self.histogram_counts, self.histogram_scales, strict=True))

    def to_record(self) -> tuple[dict[str, np.ndarray], dict]:
        """``(arrays, meta)``: the layout of a result file (:meth:`save`, and the ensemble's
        task files).  ``arrays``: ``times``, ``energy``, ``momentum``, ``collisions``,
        ``velocities``, ``hist.*``, ``hists.*`` (the per-time histograms),
        ``structure.k``/``structure.S``, ``snapshots``,
        ``snapshot.<field>`` and ``extra.<name>`` where present; ``meta`` (JSON-able):
        ``model``, ``params``, ``seed``, ``seconds`` (None when NaN), and ``hist`` (samples,
        v0) and ``histogram_note`` where present.  The final state is not part of it.

        Returns
        -------
        arrays : dict of str to numpy.ndarray
            The named arrays.
        meta : dict
            The JSON-able fields.
        """
        arrays = {
            "times": self.times,
            "energy": self.energy,
            "momentum": self.momentum,
            "collisions": self.collisions,
            "velocities": self.velocities,
        }
        meta = {"model": self.model, "params": self.params, "seed": self.seed,
                "seconds": None if np.isnan(self.seconds) else self.seconds,
                "time_name": self.time_name}
        if self.histogram is not None:
            h = self.histogram
            arrays.update({"hist.edges": h.edges, "hist.density": h.density,
                           "hist.error": h.error, "hist.count": h.count})
            meta["hist"] = {"samples": h.samples, "v0": h.v0}
        if self.histogram_note is not None:
            meta["histogram_note"] = self.histogram_note
        if self.histogram_counts is not None:
            arrays.update({"hists.edges": self.histogram_edges,
                           "hists.count": self.histogram_counts,
                           "hists.v0": self.histogram_scales})
        if self.kurtosis is not None:
            arrays["kurtosis"] = self.kurtosis
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
        the readers turn them into a file-format error naming the file.

        Parameters
        ----------
        arrays : dict of str to numpy.ndarray
            The arrays of :meth:`to_record`.
        meta : dict
            The meta fields of :meth:`to_record`.

        Returns
        -------
        RunResult
            The rebuilt result.
        """
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
            seed=meta["seed"] if isinstance(meta["seed"], dict) else int(meta["seed"]),
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
            time_name=meta.get("time_name"),
            snapshot_extras={k[len("snapshot."):]: v for k, v in a.items()
                             if k.startswith("snapshot.")},
            histogram_edges=a.get("hists.edges"),
            histogram_counts=a.get("hists.count"),
            kurtosis=a.get("kurtosis"),
            histogram_scales=a.get("hists.v0"),
        )

    def to_xarray(self):
        """The records as an ``xarray.Dataset`` (needs the optional ``xarray`` extra).

        Coordinates: the time (``tau`` for the constant-rate Ulam and lattice models, ``t`` for
        MD, the sticky gas and ``rate="relative_velocity"``), ``x`` (the bin centres of the
        histograms, with ``x_edges`` as a variable) and, where recorded, ``k`` (the wavenumbers
        of S(k)).  Variables over time: ``energy``, ``momentum``, ``collisions``, ``kurtosis``,
        ``v0`` (each time's √E) and the engine's extras; over
        (time, x): ``density``, ``error`` and ``count`` of the per-time histograms (NaN at a
        time without one); ``structure_factor`` over (time, k) (``structure_factor=True``) or
        k (``"last"``); ``snapshots`` over (time, particle) when recorded.  Attributes:
        ``model``, ``params`` and ``seed`` as JSON text.

        Returns
        -------
        xarray.Dataset
            The labelled records.

        Raises
        ------
        ImportError
            When xarray is not installed, naming the extra to install.
        """
        import json

        xr = import_xarray("RunResult.to_xarray()")
        time = self.time_name  # the engine's (its kernel's) time, never guessed from a name
        data = {"energy": ((time,), self.energy), "momentum": ((time,), self.momentum),
                "collisions": ((time,), self.collisions)}
        if self.kurtosis is not None:
            data["kurtosis"] = ((time,), self.kurtosis)
        coords = {time: self.times}
        hists = self.histograms
        if hists:
            edges = self.histogram_edges
            coords["x"] = 0.5 * (edges[1:] + edges[:-1])
            data["x_edges"] = (("x_edge",), edges)
            nan = np.full(coords["x"].size, np.nan)
            for name in ("density", "error"):
                data[name] = ((time, "x"), np.array(
                    [nan if h is None else getattr(h, name) for h in hists]))
            data["count"] = ((time, "x"), self.histogram_counts)
            data["v0"] = ((time,), self.histogram_scales)
        if self.structure is not None:
            k, s = self.structure
            coords["k"] = k
            data["structure_factor"] = ((time, "k") if s.ndim == 2 else ("k",), s)
        if self.snapshots is not None:
            data["snapshots"] = ((time, "particle"), self.snapshots)
        for key, value in self.extras.items():
            data[key] = ((time,), value)
        attrs = {"model": self.model, "params": json.dumps(self.params),
                 "seed": json.dumps(self.seed)}
        return xr.Dataset(data, coords=coords, attrs=attrs)

    def save(self, path) -> None:
        """Save to ``path`` (an ``.npz`` archive with a JSON ``meta`` entry; the layout of
        :meth:`to_record`).

        Parameters
        ----------
        path : str or os.PathLike
            The output file, written atomically with a content hash.
        """
        arrays, meta = self.to_record()
        write_file(path, arrays, {"kind": "result", **meta})

    @classmethod
    def load(cls, path) -> RunResult:
        """Reload a result written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            A result file (format version 1 or 2).

        Returns
        -------
        RunResult
            The result (``final_state`` None).

        Raises
        ------
        particles.CheckpointError
            (argument ``path``) if the file is not a readable result or lacks an entry.
        """
        meta, arrays = read_file(path, "path", "result")
        try:
            return cls.from_record(arrays, meta)
        except (KeyError, TypeError) as exc:
            raise CheckpointError(path, f"missing entry {exc}", "path") from None

    def summary(self) -> dict:
        """JSON-able summary (the ``--json`` output of ``simulate`` without the extras).

        Returns
        -------
        dict
            ``model``, ``tau`` (the times, whatever the model's time), ``energy``, the last
            ``collisions``, ``kurtosis`` (⟨v⁴⟩/⟨v²⟩² at each time, null where undefined or not
            recorded), ``seconds``, and ``histogram`` (with ``histogram_note`` when None).
        """
        out = {
            "model": self.model,
            "tau": self.times.tolist(),
            "energy": self.energy.tolist(),
            "collisions": int(self.collisions[-1]),
            "kurtosis": (None if self.kurtosis is None else
                         [float(k) if np.isfinite(k) else None for k in self.kurtosis]),
            "seconds": self.seconds,
        }
        if self.histogram is not None:
            out["histogram"] = self.histogram.to_dict()
        elif self.histogram_note is not None:
            out["histogram"] = None
            out["histogram_note"] = self.histogram_note
        return out
