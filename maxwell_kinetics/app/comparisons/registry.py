"""The one registry of the comparisons: what a comparison provides (:class:`ComparisonSpec`) and
where it is registered (:func:`register`).

A comparison is its ``name``, its ``presets`` (size → parameters), ``run(size=None,
progress=None, **overrides) -> Comparison``, ``plot(comparison, ax=None)`` (draws only),
``verdicts(summary) -> list of Verdict`` and its ``order``: ``reproduce`` runs the comparisons by
increasing order.  A comparison's module registers it with one line, its last::

    COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=13))

and everything that lists the comparisons reads this registry: :data:`COMPARISONS` (name → run
function, in reproduce's order, what ``reproduce`` runs), :data:`PRESETS`, :data:`VERDICTS`, the
``plot`` that :meth:`~maxwell_kinetics.app.comparisons.Comparison.figure` draws with
(:func:`comparison_spec`) and the functions of :mod:`maxwell_kinetics.app.comparisons`
(``kinetic_theory`` …).  These dicts are kept in place (never rebound), in the order of
``order``, so a name imported from here always sees the current registry.

Registering a name again with another comparison is refused (:func:`register`), except a
comparison defined again (a module reloaded, a notebook cell run again: its ``run`` has the same
module and qualified name), which replaces it.  :func:`registered` registers for the duration of
a ``with`` block (a test's or a notebook's own comparison) and puts back what was there.

This module imports nothing from the rest of the package.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass

from particles.validation import InvalidArgumentError

__all__ = [
    "SIZES",
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
