"""The collision kernels: what a collision does and how often a pair collides, as values.

A kernel is one frozen class that every solver and engine reads: the kinetic solvers of
:mod:`maxwell_kinetics` and the particle engines of this package evaluate the same formulas
(written with an array module ``xp``: ``numpy`` here, ``jax.numpy`` in the solvers).  It holds

* the post-collision map of a pair (v, w), g = v − w: v′ = v − p g, w′ = w + p g with
  p = (1 + r)/2 (:func:`particles.collision.transfer_fraction`; the floating-point operations of
  :mod:`particles.collision`, in its order);
* the collision rate of a pair, relative to the density: a pair collides at rate
  n · :meth:`Kernel.rate` per unit of the kernel's time, and a bound of it over the pairs whose
  |g| is at most a given spread (:meth:`Kernel.rate_bound`, what a thinned simulation draws its
  candidates with);
* the time the kernel counts, :attr:`Kernel.time_name`: ``"tau"`` (collisions per particle,
  every pair at one rate) or ``"t"`` (physical time at density n);
* its parameters, declared (:class:`KernelParameter`) and checked once, at construction.

Kernels are registered by name in :data:`KERNELS` (:func:`register`); :func:`kernel_class`
reads the registry, and the command line, the engines and the solvers find a kernel there.  A
new kernel is one class with the ``@register`` decorator, in any module (a test, a user's
script): nothing else needs to change for the registry's readers to list and check it.

Conventions: a rate is per unit of the kernel's time and per unit density; velocities are in
the units of the initial law (⟨v²⟩ = 1 at time 0 unless the caller says otherwise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import numpy as np

from .collision import transfer_fraction
from .validation import InvalidArgumentError, check_real, check_restitution

__all__ = [
    "KernelParameter",
    "Kernel",
    "ConstantRate",
    "RelativeVelocity",
    "KERNELS",
    "register",
    "kernel_class",
    "make_kernel",
    "describe_kernels",
    "defines_rate",
]


@dataclass(frozen=True)
class KernelParameter:
    """A kernel's real parameter, declared with its closed range and its default.

    Parameters
    ----------
    name : str
        The argument's name (also the kernel's field and the command line's ``--name``).
    low, high : float
        The closed range [low, high] of accepted values.
    default : float
        The value when none is given.
    doc : str
        What it is, in a few words (the ``kernels`` listing and the command line's help).
    """

    name: str
    low: float
    high: float
    default: float
    doc: str

    def check(self, value) -> float:
        """``value`` as a float in [low, high], or an error naming the parameter.

        Parameters
        ----------
        value : float
            The value given.

        Returns
        -------
        float

        Raises
        ------
        InvalidArgumentError
            Naming the parameter, for a value that is not a finite real number (booleans and
            complex numbers refused) or lies outside [low, high].
        """
        x = check_real(value, self.name)
        if not self.low <= x <= self.high:
            raise InvalidArgumentError(self.name, value, f"a number in [{self.low:g}, "
                                       f"{self.high:g}] ({self.doc})")
        return x

    def to_dict(self) -> dict:
        """The declaration, JSON-able: ``name``, ``low``, ``high``, ``default``, ``doc``.

        Returns
        -------
        dict
        """
        return {"name": self.name, "low": self.low, "high": self.high, "default": self.default,
                "doc": self.doc}


@dataclass(frozen=True)
class Kernel:
    """The base of every collision kernel (module docstring): a frozen value, its restitution
    and its declared :attr:`parameters` checked at construction.

    A kernel subclass is a frozen dataclass that sets :attr:`name`, :attr:`time_name`,
    :attr:`parameters` (one dataclass field per declared parameter, with the same name and
    default) and :meth:`rate` with :meth:`rate_bound`; :meth:`post_collision` is the same for
    every kernel of this package.

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1] (1 elastic, 0 sticky).
    name : str
        Class attribute: the kernel's key in :data:`KERNELS`.
    time_name : str
        Class attribute: ``"tau"`` (collisions per particle) or ``"t"`` (time at density n).
    parameters : tuple of KernelParameter
        Class attribute: the parameters besides the restitution.
    dimensions : tuple of int
        Class attribute: the space dimensions the kernel is defined in.
    fourier_closed : bool
        Class attribute: True when its Fourier-space equation closes (a rate independent of
        the relative velocity): the Fourier solvers carry it.

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` (not a number in [0, 1]) or the declared parameter that is out
        of its range.
    """

    name: ClassVar[str] = ""
    time_name: ClassVar[str] = "tau"
    parameters: ClassVar[tuple[KernelParameter, ...]] = ()
    dimensions: ClassVar[tuple[int, ...]] = (1,)
    fourier_closed: ClassVar[bool] = False

    restitution: float

    def __post_init__(self):
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        for parameter in self.parameters:
            object.__setattr__(self, parameter.name,
                               parameter.check(getattr(self, parameter.name)))

    @property
    def p(self) -> float:
        """The transfer fraction p = (1 + r)/2 (:func:`particles.collision.transfer_fraction`)."""
        return transfer_fraction(self.restitution)

    @property
    def homogeneity(self) -> float | None:
        """γ when the rate depends on |v − w| alone and is homogeneous of degree γ in it,
        rate = rate(1, 0) |v − w|^γ (what the velocity-space solver needs: it follows the
        cooling by rescaling velocities, and rescales the rate with them); None otherwise (the
        default)."""
        return None

    def post_collision(self, v, w, xp=np):
        """The velocities after a collision of a pair (v, w) along the line of the pair: with
        d = (v − w) p, ``(v − d, w + d)``, the operations (and their order) of
        :mod:`particles.collision`, so an engine that calls it agrees bit for bit with one that
        calls :func:`particles.collision.collide_arrays`.

        Parameters
        ----------
        v, w : array
            The partners' velocities (arrays of ``xp``, broadcastable).
        xp : module, default numpy
            The array module (``numpy`` or ``jax.numpy``).

        Returns
        -------
        tuple of array
            ``(v′, w′)``.
        """
        d = (v - w) * self.p
        return v - d, w + d

    def rate(self, v, w, xp=np):
        """The collision rate of a pair with velocities ``v`` and ``w``, per unit of
        :attr:`time_name` and per unit density.

        Parameters
        ----------
        v, w : array
            The partners' velocities (arrays of ``xp``, broadcastable).
        xp : module, default numpy
            The array module.

        Returns
        -------
        array
            The rate of each pair, ≥ 0.

        Raises
        ------
        NotImplementedError
            In this base class.
        """
        raise NotImplementedError(f"{type(self).__name__} defines no collision rate")

    def rate_bound(self, spread: float) -> float:
        """An upper bound of :meth:`rate` over every pair whose |v − w| ≤ ``spread`` (a thinned
        simulation draws candidates at this rate and accepts each with probability
        rate/bound).

        Parameters
        ----------
        spread : float
            The largest |v − w| of the pairs concerned, ≥ 0.

        Returns
        -------
        float
            The bound, ≥ 0.

        Raises
        ------
        NotImplementedError
            In this base class.
        """
        raise NotImplementedError(f"{type(self).__name__} defines no rate bound")

    def to_dict(self) -> dict:
        """The kernel as a JSON-able value: ``{"kernel": name, "restitution": r, ...}`` with
        every declared parameter.

        Returns
        -------
        dict
        """
        out: dict[str, Any] = {"kernel": self.name, "restitution": self.restitution}
        for parameter in self.parameters:
            out[parameter.name] = getattr(self, parameter.name)
        return out


#: The registered kernels by name (:func:`register`).
KERNELS: dict[str, type[Kernel]] = {}


def register(cls: type[Kernel]) -> type[Kernel]:
    """Register a kernel class under its ``name`` (a class decorator); its declarations are
    checked here, once: a name not yet taken, a time ``"tau"`` or ``"t"``, one dataclass field
    per declared parameter with the declared default inside the declared range.

    Parameters
    ----------
    cls : type
        A frozen dataclass subclassing :class:`Kernel`.

    Returns
    -------
    type
        ``cls``, unchanged.

    Raises
    ------
    TypeError
        For a class that is not a :class:`Kernel` dataclass, or whose declarations do not fit.
    ValueError
        For a name already registered to another class (one of the same module and qualified
        name, a class defined again, replaces it).
    """
    if not (isinstance(cls, type) and issubclass(cls, Kernel) and "__dataclass_fields__" in
            vars(cls)):
        raise TypeError(f"{cls!r} is not a dataclass subclassing particles.kernels.Kernel")
    if not (isinstance(cls.name, str) and cls.name.isidentifier()):
        raise TypeError(f"{cls.__name__}.name must be an identifier, got {cls.name!r}")
    if cls.time_name not in ("tau", "t"):
        raise TypeError(f"{cls.__name__}.time_name must be 'tau' or 't', got {cls.time_name!r}")
    known = {f.name: f for f in fields(cls)}
    for parameter in cls.parameters:
        f = known.get(parameter.name)
        if f is None or f.default != parameter.default:
            raise TypeError(f"{cls.__name__}: parameter {parameter.name!r} needs a field of that "
                            f"name with default {parameter.default!r}")
        if not parameter.low <= parameter.default <= parameter.high:
            raise TypeError(f"{cls.__name__}: the default of {parameter.name!r} is outside "
                            f"[{parameter.low}, {parameter.high}]")
    known_cls = KERNELS.get(cls.name, cls)
    redefined = (known_cls.__module__, known_cls.__qualname__) == (cls.__module__,
                                                                   cls.__qualname__)
    if known_cls is not cls and not redefined:  # a class defined again (a rerun cell) replaces
        raise ValueError(f"a kernel named {cls.name!r} is already registered "
                         f"({KERNELS[cls.name].__qualname__})")
    KERNELS[cls.name] = cls
    return cls


def kernel_class(name, argument: str = "kernel",
                 among: tuple[str, ...] | None = None) -> type[Kernel]:
    """The registered kernel class of ``name``, or an error naming ``argument``.

    Parameters
    ----------
    name : str
        A key of :data:`KERNELS`.
    argument : str, optional
        The argument's name in the error (``"kernel"``; the engines' ``"rate"``).
    among : tuple of str, optional
        Only these names are accepted (the kernels a method or an engine carries).

    Returns
    -------
    type
        The kernel class.

    Raises
    ------
    InvalidArgumentError
        Naming ``argument``, listing the accepted names, for anything else (a non-string
        included; a registered kernel outside ``among`` is said to be registered but not
        carried).
    """
    accepted = tuple(KERNELS) if among is None else tuple(n for n in among if n in KERNELS)
    if not (isinstance(name, str) and name in accepted):
        shown = ", ".join(repr(n) for n in accepted)
        if isinstance(name, str) and name in KERNELS:  # registered, but not carried here
            raise InvalidArgumentError(argument, name, f"a kernel carried here: {shown} "
                                       f"({name!r} is registered, but not carried here)")
        raise InvalidArgumentError(argument, name, f"a registered kernel: {shown}")
    return KERNELS[name]


def make_kernel(value, restitution=None, argument: str = "kernel", **params) -> Kernel:
    """A kernel from a :class:`Kernel` (returned as it is) or a registered name and its
    parameters.

    Parameters
    ----------
    value : Kernel or str
        The kernel, or its name in :data:`KERNELS`.
    restitution : float, optional
        r, required with a name.
    argument : str, optional
        The argument's name in errors.
    **params
        The kernel's declared parameters (their defaults otherwise).

    Returns
    -------
    Kernel

    Raises
    ------
    InvalidArgumentError
        Naming ``argument`` for an unknown name, a kernel given together with parameters or a
        name without ``restitution``; naming a parameter the kernel does not declare, or one
        out of its range.
    """
    if isinstance(value, Kernel):
        if restitution is not None or params:
            raise InvalidArgumentError(argument, value, "a kernel or a name with its "
                                       "parameters, not both")
        return value
    cls = kernel_class(value, argument)
    if restitution is None:
        raise InvalidArgumentError("restitution", None, f"a number in [0, 1] for the kernel "
                                   f"{cls.name!r}")
    declared = {p.name for p in cls.parameters}
    for key in params:
        if key not in declared:
            raise InvalidArgumentError(key, params[key], f"no parameter of the kernel "
                                       f"{cls.name!r} (it has: {sorted(declared) or 'none'})")
    return cls(restitution, **params)


def defines_rate(cls: type[Kernel]) -> bool:
    """Whether a kernel class writes out its own :meth:`~Kernel.rate` and
    :meth:`~Kernel.rate_bound` (what a thinned simulation needs).

    Parameters
    ----------
    cls : type
        A kernel class (or a kernel).

    Returns
    -------
    bool
        False for anything that is neither a kernel class nor a kernel (a predicate: it never
        raises; a kernel is judged by its class).
    """
    cls = cls if isinstance(cls, type) else type(cls)
    if not issubclass(cls, Kernel):
        return False
    return cls.rate is not Kernel.rate and cls.rate_bound is not Kernel.rate_bound


def describe_kernels() -> list[dict]:
    """Every registered kernel as a JSON-able row: ``name``, ``time``, ``dimensions``,
    ``fourier_closed``, ``parameters`` (restitution first, then the declared ones, each with
    its range and default) and the first line of its docstring.

    Returns
    -------
    list of dict
    """
    rows = []
    for name, cls in KERNELS.items():
        restitution = KernelParameter("restitution", 0.0, 1.0, math.nan,
                                "restitution coefficient r (1 elastic, 0 sticky)")
        doc = " ".join((cls.__doc__ or "").strip().split("\n\n")[0].split())
        rows.append({"name": name, "time": cls.time_name, "dimensions": list(cls.dimensions),
                     "fourier_closed": cls.fourier_closed,
                     "parameters": [{**restitution.to_dict(), "default": None}]
                     + [p.to_dict() for p in cls.parameters],
                     "summary": doc})
    return rows


@register
@dataclass(frozen=True)
class ConstantRate(Kernel):
    """The pseudo-Maxwell (Ulam) kernel: every pair collides at one rate, whatever its
    velocities; time τ counts collisions per particle.  Its Fourier-space equation closes.

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1].

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` when it is not a number in [0, 1].
    """

    name: ClassVar[str] = "constant"
    time_name: ClassVar[str] = "tau"
    dimensions: ClassVar[tuple[int, ...]] = (1, 2, 3)
    fourier_closed: ClassVar[bool] = True

    def rate(self, v, w, xp=np):
        """1 for every pair (the rate of the Maxwell model, per unit τ).

        Parameters
        ----------
        v, w : array
            The partners' velocities.
        xp : module, default numpy
            The array module.

        Returns
        -------
        array
            Ones, of the broadcast shape of ``v - w``.
        """
        return xp.ones_like(v - w)

    def rate_bound(self, spread: float) -> float:
        """1, whatever the spread.

        Parameters
        ----------
        spread : float
            Unused.

        Returns
        -------
        float
            1.0.
        """
        return 1.0


#: γ of the rate |v − w|^γ: from 0 (the Maxwell model in physical time) to 2, the range of the
#: velocity-space solver (beyond 2 the tails of f grow too fast for a grid of fixed extent).
EXPONENT = KernelParameter("exponent", 0.0, 2.0, 1.0,
                           "gamma of the rate |v - w|^gamma; 1: hard rods")


@register
@dataclass(frozen=True)
class RelativeVelocity(Kernel):
    """Pairs collide at rate n|v − w|^γ, in physical time t at density n: γ = 1 is hard rods
    (the kinetic equation of molecular dynamics under molecular chaos), γ = 0 the Maxwell model
    with τ = n t.

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1].
    exponent : float, optional
        γ ∈ [0, 2] (default 1, hard rods).

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` or ``exponent`` when it is out of its range.
    """

    name: ClassVar[str] = "relative_velocity"
    time_name: ClassVar[str] = "t"
    parameters: ClassVar[tuple[KernelParameter, ...]] = (EXPONENT,)

    exponent: float = 1.0

    def rate(self, v, w, xp=np):
        """|v − w|^γ per unit density and time (1 for γ = 0, also at v = w; |v − w| itself for
        γ = 1, with no power taken).

        Parameters
        ----------
        v, w : array
            The partners' velocities.
        xp : module, default numpy
            The array module.

        Returns
        -------
        array
            The rate of each pair.
        """
        g = xp.abs(v - w)
        if self.exponent == 0.0:
            return xp.ones_like(g)
        if self.exponent == 1.0:
            return g
        return g**self.exponent

    @property
    def homogeneity(self) -> float:
        """γ: the rate |v − w|^γ is homogeneous of degree γ."""
        return self.exponent

    def rate_bound(self, spread: float) -> float:
        """``spread``^γ (``spread`` itself for γ = 1; 1 for γ = 0): the rate is increasing in
        |v − w|.

        Parameters
        ----------
        spread : float
            The largest |v − w|, ≥ 0.

        Returns
        -------
        float
        """
        if self.exponent == 0.0:
            return 1.0
        if self.exponent == 1.0:
            return float(spread)
        return float(spread) ** self.exponent
