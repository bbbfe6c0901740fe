"""An ensemble's description: the seeds, the spec (model, swept parameters, seeds, times,
options) and the tasks it expands to, each with its identity and key."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import observables as obs
from ..models import get_model
from ..validation import InvalidArgumentError, check_nonnegative, check_seed, check_times

#: Format version of the task, manifest and aggregate files (part of every task's key).
FORMAT_VERSION = 1


#: The most tasks (seeds × parameter sets) one ensemble may hold.  Each task is a run with its
#: own file, and the task list alone takes about 6 KB a task in memory and 0.2 ms a task to build
#: (measured: 10⁴ Ulam tasks in 2.1 s; ``--seeds 1-10000000`` grew to 4.5 GB in 90 s before
#: writing a task).  The count is computed from the ranges before any seed is listed.
MAX_TASKS = 10**5


def _too_many(text, seeds: int, sets: int) -> InvalidArgumentError | None:
    """The refusal of ``seeds`` × ``sets`` tasks beyond :data:`MAX_TASKS` (naming ``seeds``,
    with the count and the cap), or None."""
    total = seeds * sets
    if total <= MAX_TASKS:
        return None
    count = f"{seeds} seeds" if sets == 1 else f"{seeds} seeds x {sets} parameter sets = {total}"
    return InvalidArgumentError(
        "seeds", text, f"at most {MAX_TASKS} tasks (seeds x parameter sets) in one ensemble "
        f"(got {count}); split it into smaller ensembles, each with its own output folder")


def parse_seeds(text: str, *, sets: int = 1) -> tuple[int, ...]:
    """Seeds from a list such as ``"1-16,20,25-27"``: comma-separated integers ≥ 0 and ranges
    ``a-b`` (a ≤ b, both included), in the order given.  Empty elements, descending ranges,
    duplicates and seeds above 2⁶⁴ − 1 are refused, and so is a list whose seeds, times the
    ``sets`` parameter sets they run with, make more than :data:`MAX_TASKS` tasks: that count is
    computed from the ranges' bounds first, before any seed is listed.

    Parameters
    ----------
    text : str
        The seed list, e.g. ``"1-16,20,25-27"``.
    sets : int, optional
        The number of parameter sets each seed runs with (default 1): the ensemble has
        ``sets`` × (number of seeds) tasks.

    Returns
    -------
    tuple of int
        The seeds, in the order given.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``seeds``) for a non-string, a malformed element, a descending range, a seed
        above 2⁶⁴ − 1, more than :data:`MAX_TASKS` tasks in all, an empty list or a repeated
        seed.
    """
    if not isinstance(text, str):
        raise InvalidArgumentError("seeds", text, "a string such as '1-16,20,25-27'")
    ranges: list[tuple[int, int]] = []
    count = 0
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
        try:
            check_seed(hi, "seeds")
        except InvalidArgumentError:
            raise InvalidArgumentError(
                "seeds", text, f"seeds in [0, 2**64 - 1] (got {part!r})"
            ) from None
        ranges.append((lo, hi))
        count += hi - lo + 1
    error = _too_many(text, count, sets)  # arithmetic on the bounds: nothing listed yet
    if error is not None:
        raise error
    seeds: list[int] = []
    for lo, hi in ranges:
        seeds.extend(range(lo, hi + 1))
    return _check_seeds(seeds, text)


def _check_seeds(seeds, shown) -> tuple[int, ...]:
    out = []
    for s in seeds:
        try:
            out.append(check_seed(s, "seeds"))  # the one seed rule (particles.simulate's)
        except InvalidArgumentError:
            raise InvalidArgumentError("seeds", shown, "integers in [0, 2**64 - 1]") from None
    if not out:
        raise InvalidArgumentError("seeds", shown, "at least one seed")
    if len(set(out)) != len(out):
        dup = sorted(s for s, n in Counter(out).items() if n > 1)
        raise InvalidArgumentError("seeds", shown, f"distinct seeds (repeated: {dup[:10]})")
    return tuple(out)


_OPTIONS = ("structure_factor", "bins", "checkpoint_interval", "snapshots")


def _has_bool(values) -> bool:
    """Whether ``values`` (a scalar or a sequence of numbers) holds a boolean, which NumPy
    would take for 0 or 1."""
    if isinstance(values, np.ndarray):
        return values.dtype == bool
    items = values if isinstance(values, (list, tuple)) else [values]
    return any(isinstance(v, (bool, np.bool_)) for v in items)


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
    """One run of an ensemble: ``params`` (the run's values of the spec's parameters),
    ``seed``, the index ``set_index`` of its parameter set in the grid, and ``key``, the hash of
    ``identity`` (what the run's result depends on) that names its file.

    Attributes
    ----------
    model : str
        The model's name.
    params : dict
        The run's parameter values.
    seed : int
        The run's seed.
    times : tuple of float
        The requested times, in the engine's time.
    options : dict
        The spec's checked options.
    set_index : int
        Index of the parameter set in :meth:`EnsembleSpec.parameter_sets`.
    identity : dict
        What the result depends on: model, the engine's parameters, seed, times, result
        options, format version.
    key : str
        The first 24 hex digits of the SHA-256 of ``identity``; names the task's files.
    """

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
        """JSON-able {"params", "seed", "key"} (how failures and damaged files are reported).

        Returns
        -------
        dict
            ``{"params", "seed", "key"}``.
        """
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
    spec fails before any work.

    Attributes
    ----------
    model : str
        A model name of :data:`particles.models.MODELS`.
    params : Mapping[str, Any]
        {name: value or list of values}; stored as {name: tuple of values}.
    seeds : tuple of int
        Distinct seeds, or a string for :func:`parse_seeds`.
    times : tuple of float
        Increasing times ≥ 0 in the engines' time.
    options : Mapping[str, Any]
        ``structure_factor``, ``bins``, ``checkpoint_interval``, ``snapshots``.

    Raises
    ------
    particles.InvalidArgumentError
        For an unknown model or parameter, an empty or repeated list of values (also values
        that build the same engine, such as 1 and 1.0), a boolean for a numeric parameter,
        missing required parameters, bad seeds, engines of different times, bad times,
        unknown or bad options (``structure_factor`` a bool, ``"all"`` or ``"last"``;
        ``checkpoint_interval`` a number), or any value an engine refuses when built (the
        argument is named).
    """

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
            kind = m.parameter(name).kind  # an unknown name is refused
            values = list(value) if isinstance(value, (list, tuple)) else [value]
            if not values:
                raise InvalidArgumentError(name, value, "a non-empty list (the grid is empty)")
            values = [_json_value(name, v) for v in values]
            if kind in ("int", "float") and any(isinstance(v, bool) for v in values):
                raise InvalidArgumentError(name, value, "numbers, not booleans")
            if len({json.dumps(v) for v in values}) != len(values):
                raise InvalidArgumentError(name, value, "distinct values")
            params[name] = tuple(values)
        missing = [p for p in m.required if p not in params]
        if missing:
            raise InvalidArgumentError("params", sorted(params), f"values for {missing}")
        object.__setattr__(self, "params", params)
        # the number of tasks, before the grid or the seeds are listed (MAX_TASKS)
        sets = math.prod(len(values) for values in params.values())
        if sets > MAX_TASKS:
            raise InvalidArgumentError(
                "params", {k: list(v) for k, v in params.items()},
                f"at most {MAX_TASKS} tasks (seeds x parameter sets) in one ensemble (got "
                f"{sets} parameter sets); split it into smaller ensembles")
        if isinstance(self.seeds, str):
            seeds = parse_seeds(self.seeds, sets=sets)
        elif isinstance(self.seeds, (bytes, bytearray, Mapping)):
            raise InvalidArgumentError("seeds", self.seeds, "a list of integers or a string")
        else:
            try:
                size = len(self.seeds)  # a list or a range: counted without listing it
            except (TypeError, OverflowError):  # no length, or range(10**30)
                size = None
            if size is not None and (error := _too_many(self.seeds, size, sets)) is not None:
                raise error
            try:  # an iterator: listed up to one seed past the cap, never further
                seeds = list(itertools.islice(iter(self.seeds), MAX_TASKS // sets + 1))
            except TypeError:
                raise InvalidArgumentError("seeds", self.seeds, "a list of integers") from None
            if (error := _too_many(self.seeds, len(seeds), sets)) is not None:
                raise error
        object.__setattr__(self, "seeds", _check_seeds(seeds, self.seeds))
        engines = [m.build(values) for values in self.parameter_sets()]  # bad values fail here
        seen = {}
        for values, engine in zip(self.parameter_sets(), engines, strict=True):
            ident = json.dumps(engine.to_dict(), sort_keys=True)
            if ident in seen:  # e.g. 1 and 1.0, or 100 and 1e2: one engine, one set of tasks
                raise InvalidArgumentError(
                    "params", {k: list(v) for k, v in params.items()},
                    f"values giving distinct engines ({seen[ident]} and {values} are the same)")
            seen[ident] = values
        time_names = sorted({m.time_name(e) for e in engines})
        if len(time_names) != 1:
            raise InvalidArgumentError(
                "params", {k: list(v) for k, v in params.items()},
                f"parameter sets whose engines share one time (got {time_names})",
            )
        object.__setattr__(self, "_time_name", time_names[0])
        if _has_bool(self.times):
            raise InvalidArgumentError(time_names[0], self.times, "times, not booleans")
        times = check_times(self.times, time_names[0])
        object.__setattr__(self, "times", tuple(float(t) for t in times))
        if not isinstance(self.options, Mapping):
            raise InvalidArgumentError("options", self.options, f"a mapping of {_OPTIONS}")
        options = dict(self.options)
        unknown = [k for k in options if k not in _OPTIONS]
        if unknown:
            raise InvalidArgumentError("options", unknown, f"options among {list(_OPTIONS)}")
        sf = options.get("structure_factor", False)
        if not (isinstance(sf, bool) or (isinstance(sf, str) and sf in ("all", "last"))):
            raise InvalidArgumentError("structure_factor", sf, "False, True, 'all' or 'last'")
        options["structure_factor"] = {True: True, "all": True}.get(sf, sf)
        bins = options.get("bins")
        edges = obs.rescaled_histogram(np.array([1.0, -1.0]), bins).edges  # validates bins
        options["bins"] = None if bins is None else [float(e) for e in edges]
        snaps = options.get("snapshots", False)
        if not isinstance(snaps, bool):
            raise InvalidArgumentError("snapshots", snaps, "True or False")
        options["snapshots"] = snaps
        interval = options.get("checkpoint_interval", 60.0)
        if isinstance(interval, (bool, np.bool_)):
            raise InvalidArgumentError("checkpoint_interval", interval, "a number of seconds")
        options["checkpoint_interval"] = check_nonnegative(interval, "checkpoint_interval")
        object.__setattr__(self, "options", options)
        self.expand()  # builds every engine: bad values fail here

    @property
    def time_name(self) -> str:
        """The name of the time of the spec's engines (``engine.time_name``: ``"tau"``, or
        ``"t"`` for MD, the sticky gas and the lattice of rate |Δ|)."""
        return self._time_name

    def parameter_sets(self) -> list[dict]:
        """The grid: one dict per parameter set, first parameter slowest.

        Returns
        -------
        list of dict
            The Cartesian product of the parameters' values.
        """
        names = list(self.params)
        return [dict(zip(names, combo, strict=True))
                for combo in itertools.product(*(self.params[n] for n in names))]

    def expand(self) -> list[EnsembleTask]:
        """The tasks: every parameter set × every seed (seeds fastest).

        Returns
        -------
        list of particles.ensemble.EnsembleTask
            One task per (parameter set, seed), each with its identity and key.
        """
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
                    "params": engine.to_dict(),
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
        """JSON-able description (stored in the aggregate).

        Returns
        -------
        dict
            ``model``, ``params`` (lists), ``seeds``, ``times``, ``options``.
        """
        return {"model": self.model, "params": {k: list(v) for k, v in self.params.items()},
                "seeds": list(self.seeds), "times": list(self.times),
                "options": dict(self.options)}


def __getattr__(name: str):
    if name == "MAX_SEED":
        raise ImportError("particles.ensemble.spec.MAX_SEED is particles.validation.SEED_MAX, "
                          "the one seed bound of the library, the command line and the ensembles")
    raise AttributeError(f"module 'particles.ensemble.spec' has no attribute {name!r}")
