"""The record every comparison returns (:class:`Comparison`), its file format, the presets, and
the one registry of the comparisons (:class:`ComparisonSpec`, :func:`register`).

A comparison's result is ``name``, a JSON-able ``summary`` and the figure ``data``.
:meth:`Comparison.save` writes it through :mod:`particles.persistence` (kind ``"comparison"``)
as the arrays of ``data`` plus a JSON skeleton of everything else; :meth:`Comparison.load` reads
it back, and :meth:`Comparison.figure` redraws the figure with the ``plot`` of the comparison
registered under its name.

Sizes (:data:`SIZES`): ``small`` (seconds; the tests and notebooks), ``default`` (what
``maxwell-kinetics reproduce`` runs), ``full`` (the paper's sizes where affordable).  Each
comparison has one preset per size; :func:`preset` applies keyword overrides to it.

The registry.  A comparison is its ``name``, its ``presets`` (size → parameters),
``run(size=None, progress=None, **overrides) -> Comparison``, ``plot(comparison, ax=None)``
(draws only), ``verdicts(summary) -> list of Verdict`` and its ``order``: ``reproduce`` runs the
comparisons by increasing order.  A comparison's module registers it with one line, its last::

    COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=13))

and everything that lists the comparisons reads this registry: :data:`COMPARISONS` (name → run
function, in reproduce's order, what ``reproduce`` runs), :data:`PRESETS`, :data:`VERDICTS`, the
``plot`` that :meth:`Comparison.figure` draws with (:func:`comparison_spec`) and the functions
of :mod:`maxwell_kinetics.app.comparisons` (``kinetic_theory`` …).  These dicts are kept in
place (never rebound), in the order of ``order``, so a name imported from here always sees the
current registry.  Registering a name again with another comparison is refused
(:func:`register`), except a comparison defined again (a module reloaded, a notebook cell run
again: its ``run`` has the same module and qualified name), which replaces it.
:func:`registered` registers for the duration of a ``with`` block (a test's or a notebook's own
comparison) and puts back what was there.

This module imports nothing from the rest of the package.
"""

from __future__ import annotations

import dataclasses
import io
import math
import os
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from particles import persistence
from particles.validation import InvalidArgumentError

from ... import statistics as st

__all__ = [
    "SIZES",
    "Comparison",
    "default_size",
    "preset",
    "jsonable",
    "ComparisonSpec",
    "REGISTRY",
    "COMPARISONS",
    "PRESETS",
    "VERDICTS",
    "register",
    "unregister",
    "registered",
    "comparison_spec",
]

#: The sizes every comparison has a preset for: ``small`` (seconds; the tests and notebooks),
#: ``default`` (what ``maxwell-kinetics reproduce`` runs), ``full`` (the paper's sizes).
SIZES = ("small", "default", "full")


def default_size() -> str:
    """``small`` when the environment variable ``MAXWELL_KINETICS_SMALL`` is set to a non-empty
    value other than ``0`` (tests, notebooks in CI), else ``default``.

    Returns
    -------
    str
        ``"small"`` or ``"default"``.
    """
    flag = os.environ.get("MAXWELL_KINETICS_SMALL", "")
    return "small" if flag not in ("", "0") else "default"


#: Version of the saved Comparison format (3: particles.persistence, hashed; 2 still loads).
_COMPARISON_VERSION = 3


@dataclass
class Comparison:
    """Result of one comparison: ``name``, JSON-able ``summary``, figure ``data``.

    :meth:`save` writes both to one ``.npz`` file (no pickle) and :meth:`load` reads it back, so
    a figure can be redrawn without running the comparison again:
    ``Comparison.load("results/ulam_collapse.npz").figure()``.

    Attributes
    ----------
    name : str
        The comparison's name; it selects the ``plot`` of the comparison registered under it.
    summary : dict
        The numbers the comparison reports (JSON-able after
        :func:`maxwell_kinetics.app.output.clean_json`): the tested quantities, the sizes used and
        the wall-clock ``seconds``.
    data : dict
        What the figure is drawn from: arrays, nested dicts, lists, tuples, histogram
        comparisons and solver solutions (default empty).
    """

    name: str
    summary: dict
    data: dict = field(default_factory=dict, repr=False)

    def figure(self, ax=None):
        """The comparison's figure (a matplotlib ``Figure``), drawn by the comparison's ``plot``
        on new axes or on ``ax`` (a sequence with one axis per panel).

        Parameters
        ----------
        ax : sequence of matplotlib.axes.Axes, optional
            One axis per panel to draw in; default a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``name``, if no comparison is registered under it.
        """
        return comparison_spec(self.name).plot(self, ax)

    def save(self, path) -> None:
        """Save to ``path`` through :mod:`particles.persistence` (kind ``"comparison"``): the
        arrays of ``data`` as entries, everything else as a JSON skeleton that records dict
        keys, tuples, non-finite floats and the records of this package (histogram
        comparisons, solver solutions) exactly.

        Parameters
        ----------
        path : str or os.PathLike
            The ``.npz`` file to write.

        Raises
        ------
        TypeError
            If ``summary`` or ``data`` holds an object of a type that cannot be saved.
        """
        arrays: dict[str, np.ndarray] = {}
        meta = {"name": self.name, "summary": _encode(self.summary, arrays),
                "data": _encode(self.data, arrays)}
        persistence.save(path, "comparison", _COMPARISON_VERSION, arrays, meta)

    @classmethod
    def load(cls, path) -> Comparison:
        """Read a file written by :meth:`save` (also of version 0.1.0); a file that is not one
        raises :class:`~particles.persistence.FileFormatError` naming ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            The ``.npz`` file to read.

        Returns
        -------
        Comparison
            The comparison as it was saved.

        Raises
        ------
        particles.persistence.FileFormatError
            If the file is not one written by :meth:`save` (wrong kind or version, or a
            skeleton that does not decode).
        """
        expected = "a file written by Comparison.save"
        loaded = persistence.load(path, "comparison", (2, _COMPARISON_VERSION), expected=expected)
        skeleton, arrays = loaded.meta, loaded.arrays
        try:
            return cls(skeleton["name"], _decode(skeleton["summary"], arrays),
                       _decode(skeleton["data"], arrays))
        except (ValueError, KeyError, TypeError) as exc:
            raise persistence.FileFormatError(
                path, f"{type(exc).__name__}: {exc}", "path", expected
            ) from None


def _encode(obj, arrays: dict):
    """JSON skeleton of ``obj``; arrays go to ``arrays`` under fresh keys."""
    from ...solution import Solution  # JAX: imported only when a solution may be saved

    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else {"__float__": repr(float(obj))}
    if isinstance(obj, np.ndarray):
        key = f"a{len(arrays)}"
        arrays[key] = obj
        return {"__array__": key}
    if isinstance(obj, dict):
        return {"__dict__": [[_encode(k, arrays), _encode(v, arrays)] for k, v in obj.items()]}
    if isinstance(obj, (list, tuple)):
        items = [_encode(v, arrays) for v in obj]
        return {"__tuple__": items} if isinstance(obj, tuple) else items
    if isinstance(obj, st.HistogramComparison):
        fields = {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
        return {"__histogram__": _encode(fields, arrays)}
    if isinstance(obj, Solution):
        meta, record = obj.to_record()
        return {"__solution__": {"meta": meta, "arrays": _encode(record, arrays)}}
    raise TypeError(f"cannot save an object of type {type(obj).__name__}")


def _decode(node, arrays: dict):
    if isinstance(node, list):
        return [_decode(v, arrays) for v in node]
    if not isinstance(node, dict):
        return node
    if "__array__" in node:
        return arrays[node["__array__"]]
    if "__float__" in node:
        return float(node["__float__"])
    if "__dict__" in node:
        return {_decode(k, arrays): _decode(v, arrays) for k, v in node["__dict__"]}
    if "__tuple__" in node:
        return tuple(_decode(v, arrays) for v in node["__tuple__"])
    if "__histogram__" in node:
        return st.HistogramComparison(**_decode(node["__histogram__"], arrays))
    if "__solution__" in node:
        from ...solution import Solution  # JAX: imported only when a solution is read

        inner = node["__solution__"]
        if isinstance(inner, dict) and "meta" in inner:
            return Solution.from_record(inner["meta"], _decode(inner["arrays"], arrays))
        # version 2 (0.1.0) kept the solution as the bytes of its own .npz file
        blob = io.BytesIO(_decode(inner, arrays).tobytes())
        return Solution.load(blob)
    raise ValueError(f"unknown node {sorted(node)}")


def preset(presets: dict, size: str | None, overrides: dict) -> dict:
    """The parameters of ``presets[size]`` (``size`` None: :func:`default_size`) with the keyword
    ``overrides`` applied and ``"size"`` added; an unknown size or parameter raises
    :class:`~particles.validation.InvalidArgumentError`.

    Parameters
    ----------
    presets : dict
        ``{size: {parameter: value}}`` of one comparison.
    size : str or None
        One of ``"small"``, ``"default"``, ``"full"``; None for :func:`default_size`.
    overrides : dict
        ``{parameter: value}`` replacing preset values; every key must be a preset parameter.

    Returns
    -------
    dict
        The parameters, a new dict with ``"size"`` added.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``size`` for an unknown size, or ``overrides`` for unknown parameter names.
    """
    size = default_size() if size is None else size
    if size not in presets:
        raise InvalidArgumentError("size", size, "one of " + ", ".join(SIZES))
    params = dict(presets[size])
    unknown = set(overrides) - set(params)
    if unknown:
        raise InvalidArgumentError(
            "overrides", sorted(unknown), "parameters among " + ", ".join(sorted(params))
        )
    params.update(overrides)
    params["size"] = size
    return params


def jsonable(params: dict) -> dict:
    """``params`` with arrays as lists and tuples (of tuples) as lists (of lists), for a summary.

    Parameters
    ----------
    params : dict
        Parameters of a comparison (as from :func:`preset`).

    Returns
    -------
    dict
        A new dict with the converted values; other values are kept as they are.
    """
    out = {}
    for k, v in params.items():
        if isinstance(v, np.ndarray):
            v = v.tolist()
        elif isinstance(v, tuple):
            v = [list(x) if isinstance(x, tuple) else x for x in v]
        out[k] = v
    return out


# --------------------------------------------------------------------------- the registry


@dataclass(frozen=True, eq=False)
class ComparisonSpec:
    """What one comparison provides, registered once with :func:`register`.

    The fields are checked when the record is made; two records are equal only when they are
    the same object.

    Attributes
    ----------
    name : str
        The comparison's name: an identifier, the key in :data:`COMPARISONS`, the name of
        its files (``<name>.png``, ``<name>.npz``) and of the package's function.
    presets : Mapping
        ``{size: {parameter: value}}`` with one preset for each of :data:`SIZES` (kept as it is,
        not copied: :data:`PRESETS` holds this very object).
    run : callable
        ``run(size=None, progress=None, **overrides) -> Comparison`` (``reproduce`` also passes
        ``runner=``); its ``Comparison`` carries ``name``.
    plot : callable
        ``plot(comparison, ax=None) -> matplotlib.figure.Figure``: draws the comparison's data.
    verdicts : callable
        ``verdicts(summary) -> list of Verdict``: the claims the comparison tests.
    order : int or float
        Where ``reproduce`` runs it: by increasing order (the twelve of the paper are 1 … 12;
        a number between two puts a comparison between them).  No two comparisons share one.

    Raises
    ------
    TypeError
        For a name that is not an identifier, presets without a mapping for every size, a
        ``run``, ``plot`` or ``verdicts`` that is not callable, or an order that is not a
        finite real number.
    """

    name: str
    presets: Mapping
    run: Callable
    plot: Callable
    verdicts: Callable
    order: int | float

    def __post_init__(self):
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise TypeError(f"a comparison's name must be an identifier, got {self.name!r}")
        if not (isinstance(self.presets, Mapping)
                and all(isinstance(self.presets.get(s), Mapping) for s in SIZES)):
            raise TypeError(f"comparison {self.name!r}: presets must map each size of "
                            f"{list(SIZES)} to its parameters")
        for role in ("run", "plot", "verdicts"):
            if not callable(getattr(self, role)):
                raise TypeError(f"comparison {self.name!r}: {role} must be callable, got "
                                f"{getattr(self, role)!r}")
        if isinstance(self.order, bool) or not (isinstance(self.order, (int, float))
                                                and math.isfinite(self.order)):
            raise TypeError(f"comparison {self.name!r}: order must be a finite number, got "
                            f"{self.order!r}")


#: Every registered comparison by name, in reproduce's order: name → :class:`ComparisonSpec`.
REGISTRY: dict[str, ComparisonSpec] = {}
#: The comparisons of ``reproduce``, in the order it runs them: name → run function.
COMPARISONS: dict[str, Callable] = {}
#: Each comparison's size presets: name → {size: parameters}.
PRESETS: dict[str, Mapping] = {}
#: Each comparison's judge of its claims: name → ``verdicts(summary) -> list of Verdict``.
VERDICTS: dict[str, Callable] = {}


def _rebuild(specs) -> None:
    """Refill the registry's dicts in place from ``specs``, in increasing ``order``."""
    ordered = sorted(specs, key=lambda spec: spec.order)
    for target, role in ((REGISTRY, None), (COMPARISONS, "run"), (PRESETS, "presets"),
                         (VERDICTS, "verdicts")):
        target.clear()
        target.update((s.name, s if role is None else getattr(s, role)) for s in ordered)


def _where(spec: ComparisonSpec) -> str:
    run = spec.run
    return f"{getattr(run, '__module__', '?')}.{getattr(run, '__qualname__', repr(run))}"


def register(spec: ComparisonSpec) -> ComparisonSpec:
    """Register ``spec``: it joins :data:`REGISTRY`, :data:`COMPARISONS`, :data:`PRESETS` and
    :data:`VERDICTS` at the place of its ``order``, and ``Comparison.figure()`` draws the
    comparisons of its name with its ``plot``.

    Parameters
    ----------
    spec : ComparisonSpec
        The comparison.  Registering the same object again changes nothing; one whose ``run``
        has the module and qualified name of the registered one's (the comparison defined
        again) replaces it.

    Returns
    -------
    ComparisonSpec
        ``spec``, unchanged (so that a module can keep it: ``COMPARISON = register(...)``).

    Raises
    ------
    TypeError
        If ``spec`` is not a :class:`ComparisonSpec`.
    ValueError
        Naming the comparison, if its name is registered to another comparison, or another
        comparison runs at its ``order``.
    """
    if not isinstance(spec, ComparisonSpec):
        raise TypeError(f"register takes a ComparisonSpec, got {type(spec).__name__}")
    known = REGISTRY.get(spec.name)
    if known is not None and known is not spec and _where(known) != _where(spec):
        raise ValueError(f"a comparison named {spec.name!r} is already registered "
                         f"(run: {_where(known)}); unregister it first")
    clash = [s.name for s in REGISTRY.values() if s.order == spec.order and s.name != spec.name]
    if clash:
        raise ValueError(f"comparison {spec.name!r}: order {spec.order!r} is already taken by "
                         f"{clash[0]!r}")
    _rebuild([s for s in REGISTRY.values() if s.name != spec.name] + [spec])
    return spec


def unregister(name: str) -> ComparisonSpec:
    """Remove the comparison ``name`` from the registry (and so from :data:`COMPARISONS`,
    :data:`PRESETS`, :data:`VERDICTS` and ``Comparison.figure()``).

    Parameters
    ----------
    name : str
        A key of :data:`REGISTRY`.

    Returns
    -------
    ComparisonSpec
        The comparison removed.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``name``, if no comparison is registered under it.
    """
    spec = comparison_spec(name)
    _rebuild([s for s in REGISTRY.values() if s.name != name])
    return spec


@contextmanager
def registered(spec: ComparisonSpec) -> Iterator[ComparisonSpec]:
    """Register ``spec`` for the duration of a ``with`` block; on leaving it (also on an
    error), the comparison it replaced is registered again, or its name removed.

    Parameters
    ----------
    spec : ComparisonSpec
        The comparison (as for :func:`register`).

    Yields
    ------
    ComparisonSpec
        ``spec``, registered.

    Raises
    ------
    TypeError, ValueError
        As :func:`register`, before the block runs.
    """
    before = REGISTRY.get(spec.name)
    register(spec)
    try:
        yield spec
    finally:
        if REGISTRY.get(spec.name) is spec:
            _rebuild([s for s in REGISTRY.values() if s.name != spec.name]
                     + ([before] if before is not None else []))


def comparison_spec(name: str, argument: str = "name") -> ComparisonSpec:
    """The registered comparison called ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`REGISTRY`.
    argument : str, optional
        The argument's name in the error (default ``"name"``).

    Returns
    -------
    ComparisonSpec
        The comparison.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument``, if no comparison is registered under ``name``; the message lists
        the registered names.
    """
    try:
        return REGISTRY[name]
    except (KeyError, TypeError):
        raise InvalidArgumentError(argument, name, "one of " + ", ".join(REGISTRY)) from None
