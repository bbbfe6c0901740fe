"""The catalogue of particle models: each model declared once, everything else generated from it.

A :class:`Model` is a name, a factory that builds the model's engine (the engine protocol of
:mod:`particles.driver`) from keyword parameters, and the typed :class:`Parameter` list of those
keywords: kind (``"int"``, ``"float"``, ``"choice"``, ``"flag"``; ``"any"`` for models added
with :func:`register_model` without declarations), default (or :data:`REQUIRED`), validator
(from :mod:`particles.validation`), unit, help text and command-line option.  The model's time
(``"tau"`` or ``"t"``) is not declared here: it is the engine's ``time_name``, that of its
collision kernel (:mod:`particles.kernels`: the lattice with the relative-velocity kernel runs in
MD's t, the constant-rate one in τ).

The kernels of ``ulam`` and ``lattice`` are read from the registry
:data:`particles.kernels.KERNELS` whenever the parameters are read (:attr:`Model.parameters`),
not written here: the parameter ``rate`` (option ``--kernel``; ``--rate``, its alias, is kept for
one release) chooses among the registered kernels the engine carries
(:func:`particles.pair_schedule.ulam_carries`; the lattice's
``particles.lattice.CARRIED_KERNELS``), and the parameters those kernels declare
(:class:`particles.kernels.KernelParameter`, e.g. ``exponent``) are parameters of ``ulam`` too,
each only with a kernel that declares it.  A kernel registered before the command line is built
is one of its choices.

What is generated from :data:`MODELS`: the ``simulate MODEL`` and ``ensemble MODEL`` commands of
the command line (every parameter an option; in ``ensemble`` every option takes a comma list,
which is swept), the models of :class:`particles.ensemble.EnsembleSpec`, and the particle runs of
the comparisons (which pass only a model name and its parameters).  Adding a model or a
parameter is one entry here.

A value given on the command line is read by :meth:`Parameter.parse`; a bad one raises
:class:`particles.validation.InvalidArgumentError` naming the parameter and the text as given,
so every command reports one bad value with the same message.  Conditions that tie parameters
together (rods that fit on the ring, driving only in one dimension) are the engine's, checked
when it is built.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from .initial import LAWS
from .kernels import KERNELS, ConstantRate, Kernel, RelativeVelocity, make_kernel
from .parsing import parse_int
from .validation import (
    InvalidArgumentError,
    check_choice,
    check_count,
    check_dimension,
    check_nonnegative,
    check_positive,
    check_real,
    check_restitution,
)

__all__ = [
    "REQUIRED",
    "KINDS",
    "Parameter",
    "Model",
    "MODELS",
    "get_model",
    "register_model",
    "registered_models",
]


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: The default of a parameter that must be given.
REQUIRED: Any = _Required()
#: The kinds of parameters.
KINDS = ("int", "float", "choice", "flag", "any")
_TRUE, _FALSE = ("true", "yes", "1"), ("false", "no", "0")


@dataclass(frozen=True)
class Parameter:
    """One keyword parameter of a model's factory.

    ``check(value, name)`` validates a value of the right type and returns it normalised (one of
    the checks of :mod:`particles.validation`); ``option`` is the command-line option (default
    ``--`` and the name with ``-`` for ``_``); a ``"flag"`` (a boolean) also has ``switch``, an
    option without a value that sets it to ``not default`` (``--no-constraint``).  ``example``
    is a valid value other than the default (shown in the help, and what the generated tests
    run).  ``needs`` is ``(other, values, words)`` for a parameter that means something only
    when the parameter ``other`` is one of ``values`` (``angular`` only when ``dimension`` is 2
    or 3): giving it otherwise is refused by :meth:`Model.build`, whatever its value.
    ``choices`` and the ``values`` of ``needs`` may be callables, read each time the model's
    parameters are read (:meth:`resolved`): the kernels of the registry.

    Attributes
    ----------
    name : str
        The keyword of the factory.
    kind : str
        One of :data:`KINDS`: ``"int"``, ``"float"``, ``"choice"``, ``"flag"`` or ``"any"``.
    default : object
        The default value, or :data:`REQUIRED`.
    check : callable or None
        ``check(value, name)`` validates and normalises a value; a ``"choice"`` without one
        checks membership of ``choices``.
    unit : str
        Unit shown in the help (e.g. ``"1/length"``).
    help : str
        Help text of the option.
    option : str
        The command-line option; default ``--`` and the name with ``-`` for ``_``.
    switch : str
        For a ``"flag"``: an option without value that sets ``not default``.
    choices : tuple or callable
        The allowed values of a ``"choice"``, or a function without arguments that returns
        them (read when asked: the registered kernels).
    example : object
        A valid non-default value (help and generated tests).
    needs : tuple
        ``(other, values, words)``: the parameter may be given only when ``other`` (given or
        defaulted) is in ``values``; ``words`` says so in the error (e.g. ``"--dimension 2 or
        3"``).  Empty (default): no condition.  ``values`` may be a function without arguments
        that returns them (the kernels whose time is t).
    aliases : tuple of str
        Further options with the same meaning, kept for one release (``--rate`` of
        ``--kernel``); the help of each says so.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``kind``) if ``kind`` is not one of :data:`KINDS`.
    """

    name: str
    kind: str
    default: Any = REQUIRED
    check: Callable[[Any, str], Any] | None = None
    unit: str = ""
    help: str = ""
    option: str = ""
    switch: str = ""
    choices: tuple = ()
    example: Any = None
    needs: tuple = ()
    aliases: tuple = ()

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InvalidArgumentError("kind", self.kind, f"one of {KINDS}")
        if not self.option:
            object.__setattr__(self, "option", "--" + self.name.replace("_", "-"))
        if self.kind == "choice" and self.check is None:
            object.__setattr__(self, "check", functools.partial(_choice, choices=self.choices))

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def resolved(self) -> Parameter:
        """The parameter with its ``choices`` and the values of its ``needs`` read now (they
        may be functions of the registry of kernels); itself when neither is a function.

        Returns
        -------
        Parameter
            A parameter whose ``choices`` and ``needs`` are tuples.
        """
        changes = {}
        if callable(self.choices):
            changes["choices"] = tuple(self.choices())
            if isinstance(self.check, functools.partial) and self.check.func is _choice:
                changes["check"] = None  # the membership check of the choices read now
        if self.needs and callable(self.needs[1]):
            other, values, words = self.needs
            changes["needs"] = (other, tuple(values()), words)
        return dataclasses.replace(self, **changes) if changes else self

    @property
    def label(self) -> str:
        """The name errors show: the option without its dashes (``rod-length``), as typed."""
        return self.option.lstrip("-")

    def validate(self, value):
        """``value`` checked (and normalised) by the parameter's validator.

        Parameters
        ----------
        value : object
            A value of the parameter's type (a ``bool`` for a flag).

        Returns
        -------
        object
            The value, normalised by ``check`` (unchanged when there is none).

        Raises
        ------
        particles.InvalidArgumentError
            (argument: the parameter's name) for a flag that is not a bool, or whatever the
            validator refuses.
        """
        if self.kind == "flag" and not isinstance(value, bool):
            raise InvalidArgumentError(self.name, value, "true or false")
        return value if self.check is None else self.check(value, self.name)

    def parse(self, text: str):
        """The value of the command-line text ``text``, checked; a bad one raises
        :class:`InvalidArgumentError` naming this parameter and ``text`` as given.

        Parameters
        ----------
        text : str
            The text given on the command line (``true/yes/1`` or ``false/no/0`` for a flag).

        Returns
        -------
        object
            The parsed, validated value.

        Raises
        ------
        particles.InvalidArgumentError
            (argument: the option's :attr:`label`, e.g. ``rod-length``; value: ``text``) if the
            text does not parse or the value is refused.
        """
        try:
            if self.kind == "int":
                value = parse_int(text, self.name)
            elif self.kind == "float":
                value = check_real(text, self.name)
            elif self.kind == "flag":
                word = str(text).strip().lower()
                if word not in _TRUE + _FALSE:
                    raise InvalidArgumentError(self.name, text, "true or false")
                value = word in _TRUE
            else:
                value = text
            return self.validate(value)
        except ValueError as exc:  # InvalidArgumentError included: shown with the text given
            expected = getattr(exc, "expected", "a real number")
            raise InvalidArgumentError(self.label, text, expected) from None

    def describe(self) -> str:
        """The help text of the option: help, unit, choices and default.

        Returns
        -------
        str
            E.g. ``"number density N/L > 0 [1/length] (required)"``.
        """
        parts = [self.help]
        if self.unit:
            parts.append(f"[{self.unit}]")
        choices = self.choices() if callable(self.choices) else self.choices
        if choices:
            parts.append("(" + " | ".join(map(str, choices)) + ")")
        default = str(self.default).lower() if isinstance(self.default, bool) else self.default
        parts.append("(required)" if self.required else f"(default {default})")
        return " ".join(p for p in parts if p)


def _choice(value, name, choices):
    return check_choice(value, name, choices() if callable(choices) else choices)


def _count(minimum: int) -> Callable[[Any, str], int]:
    return functools.partial(_check_count, minimum=minimum)


def _check_count(value, name, minimum):
    return check_count(value, name, minimum)


def _dimension(value, name):
    return check_dimension(value, name)


def _restitution(value, name):
    return check_restitution(value, name)


@dataclass(frozen=True)
class Model:
    """A particle model: ``factory(**params)`` builds its engine; ``declared`` and ``extra``
    give the keywords it takes (:attr:`parameters`); ``help`` and ``description`` are its
    command-line texts.

    Parameters
    ----------
    name : str
        The model's name (the command ``simulate NAME``).
    factory : callable
        ``factory(**params)`` returns the engine.
    declared : tuple of Parameter
        The declared keywords (distinct names).
    help : str
        One-line command-line help.
    description : str
        Longer command-line description.
    default_time_name : str
        Time name (``"tau"`` or ``"t"``) of the command line's time option when no engine can
        be built from the parameters' examples.
    extra : callable, optional
        A function without arguments that returns more parameters, read whenever the
        parameters are (the parameters the carried kernels declare); those whose name a
        declared parameter has are left out.  The factory takes them as keywords (``**``).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``parameters``) if two declared parameters share a name.
    """

    name: str
    factory: Callable[..., Any]
    declared: tuple[Parameter, ...]
    help: str = ""
    description: str = ""
    #: the time option's name when no engine can be built from the examples
    default_time_name: str = "tau"
    extra: Callable[[], tuple[Parameter, ...]] | None = None
    _time_names: dict = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "declared", tuple(self.declared))
        names = [p.name for p in self.declared]
        if len(set(names)) != len(names):
            raise InvalidArgumentError("parameters", names, "distinct names")
        object.__setattr__(self, "_time_names", {})

    @property
    def parameters(self) -> tuple[Parameter, ...]:
        """Every parameter, read now: the declared ones (their choices and needs read from the
        registry of kernels, :meth:`Parameter.resolved`), then those of ``extra``."""
        params = tuple(p.resolved() for p in self.declared)
        if self.extra is not None:
            names = {p.name for p in params}
            params += tuple(p for p in self.extra() if p.name not in names)
        return params

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def required(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters if p.required)

    def parameter(self, name: str) -> Parameter:
        """The declared parameter called ``name``.

        Parameters
        ----------
        name : str
            A parameter name.

        Returns
        -------
        Parameter
            Its declaration.

        Raises
        ------
        particles.InvalidArgumentError
            (argument ``params``) if the model has no such parameter.
        """
        for p in self.parameters:
            if p.name == name:
                return p
        raise InvalidArgumentError(
            "params", name, f"a parameter of {self.name}: one of {list(self.names)}")

    def build(self, params: Mapping[str, Any]):
        """The engine of ``params`` (unknown or missing parameters are refused).

        Parameters
        ----------
        params : Mapping[str, Any]
            Keyword parameters of the factory (validated values).

        Returns
        -------
        object
            The engine ``factory(**params)``.

        Raises
        ------
        particles.InvalidArgumentError
            (argument ``params``) for an unknown or missing parameter, or a ``TypeError`` /
            ``ValueError`` of the factory; (argument: the parameter's name) for a parameter
            given without the setting it ``needs`` (:class:`Parameter`); the factory's own
            ``InvalidArgumentError`` passes through, renamed to the option's :attr:`label`
            (``rod-length``) when it names a declared parameter.
        """
        by_name = {p.name: p for p in self.parameters}
        for name in params:
            if name not in by_name:
                self.parameter(name)  # the error naming it
        missing = [p for p in self.required if p not in params]
        if missing:
            raise InvalidArgumentError("params", sorted(params), f"values for {missing}")
        for name, value in params.items():
            needs = by_name[name].needs
            if needs:
                other, values, words = needs
                given = params.get(other, by_name[other].default)
                if isinstance(given, bool) or given not in values:
                    raise InvalidArgumentError(
                        name, value, f"no {by_name[name].option} without {words} (it "
                        f"means nothing at {by_name[other].label} = {given!r})")
        try:
            return self.factory(**params)
        except InvalidArgumentError as exc:
            declared = by_name.get(exc.name)
            if declared is not None and declared.label != exc.name:  # rod_length: --rod-length
                raise InvalidArgumentError(declared.label, exc.value, exc.expected) from None
            raise
        except (TypeError, ValueError) as exc:
            raise InvalidArgumentError(
                "params", dict(params), f"parameters of {self.name} ({exc})"
            ) from None

    def time_name(self, engine) -> str:
        """The name of ``engine``'s time: its ``time_name``.

        Parameters
        ----------
        engine : object
            An engine built by this model.

        Returns
        -------
        str
            ``"tau"`` (collisions per particle) or ``"t"`` (physical time); the model's
            ``default_time_name`` if the engine has none.
        """
        return str(getattr(engine, "time_name", self.default_time_name))

    @property
    def time_names(self) -> tuple[str, ...]:
        """Every time name an engine of this model may have (the time options of the command
        line): the engines built from the examples, once per value of each choice and flag
        (the choices read now: a kernel registered later counts)."""
        parameters = self.parameters
        key = tuple((p.name, p.choices) for p in parameters)
        if key not in self._time_names:
            self._time_names[key] = self._find_time_names(parameters)
        return self._time_names[key]

    def _find_time_names(self, parameters) -> tuple[str, ...]:
        base = {p.name: p.example for p in parameters if p.required}
        if any(v is None for v in base.values()):
            return (self.default_time_name,)
        variants = [{}]
        for p in parameters:
            values = p.choices if p.kind == "choice" else (True, False) if p.kind == "flag" else ()
            variants += [{p.name: v} for v in values]
        names = []
        for extra in variants:
            try:
                name = self.time_name(self.build({**base, **extra}))
            except InvalidArgumentError:
                continue
            if name not in names:
                names.append(name)
        return tuple(names) or (self.default_time_name,)


# --------------------------------------------------------------------------- factories
# Module-level functions: the ensemble sends them to its workers by reference (pickle).


def _ulam(n, restitution, initial="gaussian", dimension=1, angular="uniform", driving=0.0,
          rate=ConstantRate.name, density=1.0, **kernel_parameters):
    from .ulam import Ulam

    # the kernel's declared parameters, if any is given, build it (refusing those it lacks)
    kernel = make_kernel(rate, restitution, "rate", **kernel_parameters) \
        if kernel_parameters else rate
    cls = type(kernel) if isinstance(kernel, Kernel) else KERNELS.get(kernel)
    if cls is not None and 1 not in cls.dimensions and getattr(cls, "direction_law", None):
        from .hard_sphere_dsmc import ulam_sphere_dsmc  # hard spheres: the DSMC of d = 2, 3

        return ulam_sphere_dsmc(n, restitution, initial, dimension, angular, driving, kernel,
                                density)
    return Ulam(n, restitution, initial, dimension=dimension, angular=angular, driving=driving,
                rate=kernel, density=density)


def _lattice(n, restitution, initial="gaussian", constraint=True, rate=ConstantRate.name):
    from .lattice import Lattice

    return Lattice(n, restitution, initial, constraint, rate=rate)


def _md(n, density, restitution, delta=0.0, rod_length=0.0, initial="gaussian", method="fast",
        stop_step=1.0):
    from .md import MDEngine, MDParams

    return MDEngine(MDParams(n, density, restitution, delta, rod_length, initial), method,
                    stop_step=stop_step)


def _sticky(n, density, initial="gaussian"):
    from .sticky import StickyGas, StickyParams

    return StickyGas(StickyParams(n, density, initial))


# --------------------------------------------------------------------------- parameters


def _n(minimum: int, what: str = "particles") -> Parameter:
    return Parameter("n", "int", check=_count(minimum), unit=what, example=40,
                     help=f"number of {what}, an integer >= {minimum} (2e5 is accepted)")


def _restitution_parameter() -> Parameter:
    return Parameter("restitution", "float", check=_restitution, example=0.5,
                     help="restitution coefficient r in [0, 1]")


def _initial() -> Parameter:
    laws = tuple(name for name, law in LAWS.items() if law.sampler is not None)
    return Parameter("initial", "choice", default="gaussian", choices=laws, example="uniform",
                     help="initial velocity law (zero mean, unit energy)")


def _density() -> Parameter:
    return Parameter("density", "float", check=check_positive, unit="1/length", example=1.0,
                     help="number density N/L > 0 (L, the ring length, must stay finite)")


# --------------------------------------------------------------------------- kernels
# Read from the registry particles.kernels.KERNELS each time the parameters are read.


def _ulam_kernels() -> tuple[str, ...]:
    """The registered kernels Ulam carries (:func:`particles.pair_schedule.ulam_carries`)."""
    from .pair_schedule import ulam_carries

    return tuple(name for name, cls in KERNELS.items() if ulam_carries(cls))


def _lattice_kernels() -> tuple[str, ...]:
    """The registered kernels the lattice carries (its rule:
    ``particles.lattice.CARRIED_KERNELS``)."""
    from .lattice import CARRIED_KERNELS

    return tuple(name for name in KERNELS if name in CARRIED_KERNELS)


def _kernels_of_time(carried, time_name: str) -> tuple[str, ...]:
    return tuple(name for name in carried() if KERNELS[name].time_name == time_name)


def _kernel_parameter_check(value, name, declared):
    return declared.check(value)


def _kernel_parameter_example(declared) -> float:
    """A value in the declared range other than the default (halfway to an end)."""
    end = declared.low if declared.default > declared.low else declared.high
    return declared.default + (end - declared.default) / 2.0


def _kernel_rate(carried, what: str) -> Parameter:
    """The choice of the kernel (``--kernel``, alias ``--rate``) among ``carried()``."""
    return Parameter(
        "rate", "choice", default=ConstantRate.name, choices=carried,
        example=RelativeVelocity.name, option="--kernel", aliases=("--rate",),
        help=f"collision kernel of the {what}: a registered kernel it carries (the command "
        f"'kernels' lists them); {ConstantRate.name}: time τ")


def _kernel_parameters(carried) -> tuple[Parameter, ...]:
    """The parameters the kernels ``carried()`` declare, one option each; a parameter declared
    by kernels that disagree on its range is checked by the chosen kernel when it is built."""
    owners: dict[str, list] = {}
    for name in carried():
        for declared in KERNELS[name].parameters:
            owners.setdefault(declared.name, []).append((name, declared))
    params = []
    for pname, found in owners.items():
        names = tuple(name for name, _ in found)
        declared = found[0][1]
        same = all(d == declared for _, d in found)
        check = functools.partial(_kernel_parameter_check, declared=declared) if same \
            else _real
        shown = " or ".join(names)
        params.append(Parameter(
            pname, "float", default=declared.default, check=check,
            example=_kernel_parameter_example(declared),
            help=f"{declared.doc}, in [{declared.low:g}, {declared.high:g}] (only with "
            f"--kernel {shown})",
            needs=("rate", names, f"--kernel {shown}")))
    return tuple(params)


def _real(value, name):
    return check_real(value, name)


MODELS: dict[str, Model] = {}


def _declare(model: Model) -> Model:
    MODELS[model.name] = model
    return model


_declare(Model(
    "ulam", _ulam,
    (
        _n(2),
        _restitution_parameter(),
        _initial(),
        Parameter("dimension", "int", default=1, check=_dimension, example=2,
                  help="velocity dimension d: 1, 2 or 3"),
        Parameter("angular", "choice", default="uniform", choices=("uniform", "hard"),
                  example="hard", help="d > 1: law of the collision direction, uniform on the "
                  "sphere or weighted by |g.n| (only with --dimension 2 or 3)",
                  needs=("dimension", (2, 3), "--dimension 2 or 3")),
        Parameter("driving", "float", default=0.0, check=check_nonnegative,
                  unit="energy per unit time", example=0.1,
                  help="white-noise heating strength D >= 0 (d = 1 only; 0: free cooling)",
                  needs=("dimension", (1,), "--dimension 1")),
        _kernel_rate(_ulam_kernels, "pairs (a rate that depends on the velocities: 1D DSMC "
                     "in the kernel's time, t at density n)"),
        Parameter("density", "float", default=1.0, check=check_positive, unit="1/length",
                  example=2.0,
                  help="number density n > 0 of the pair rate (n/N) rate(v_i, v_j) (only with a "
                  "kernel whose time is t)",
                  needs=("rate", functools.partial(_kernels_of_time, _ulam_kernels, "t"),
                         "a kernel whose time is t")),
    ),
    help="mean-field Ulam model: pseudo-Maxwell in τ, or the Boltzmann DSMC of a kernel in t "
    f"(--kernel {RelativeVelocity.name}: hard rods; --kernel hard_spheres --dimension 2 or 3: "
    "hard disks or spheres)",
    extra=functools.partial(_kernel_parameters, _ulam_kernels),
))

_declare(Model(
    "lattice", _lattice,
    (
        _n(3, "sites"),
        _restitution_parameter(),
        _initial(),
        Parameter("constraint", "flag", default=True, switch="--no-constraint", example=False,
                  help="collide only approaching pairs, v_i > v_{i+1} (false: every chosen "
                  "bond)"),
        _kernel_rate(_lattice_kernels, "bonds (τ = attempts/N; a rate |v_i - v_{i+1}| as for "
                     "MD pairs: MD's t at density 1)"),
    ),
    help="ring lattice model (time τ = attempts / N; t with --kernel "
    f"{RelativeVelocity.name})",
))

_declare(Model(
    "md", _md,
    (
        _n(2),
        _density(),
        _restitution_parameter(),
        Parameter("delta", "float", default=0.0, check=check_nonnegative, unit="velocity",
                  example=0.01,
                  help="regularisation: collisions with |Δv| < δ are elastic (0: none)"),
        Parameter("rod_length", "float", default=0.0, check=check_nonnegative, unit="length",
                  example=0.01, help="rod length σ >= 0 (0: point particles)"),
        _initial(),
        Parameter("method", "choice", default="fast", choices=("fast", "reference"),
                  example="reference",
                  help="light-cone vectorised engine or the sequential heap reference "
                  "(same result)"),
        Parameter("stop_step", "float", default=1.0, check=check_positive, unit="time t",
                  example=0.5, help="the run stops every stop_step of t for progress and "
                  "checkpoints (changes no result)"),
    ),
    help="event-driven molecular dynamics of inelastic hard rods on a ring (time t)",
    description="Exact event-driven MD of N hard rods on a ring.  Exit status 2: bad input "
    "(nothing written); 3: inelastic collapse (set --delta > 0, or increase a tiny one: see "
    "the message).",
))

_declare(Model(
    "sticky", _sticky,
    (_n(2), _density(), _initial()),
    help="the sticky gas (r = 0), exact at any time from the convex minorant (time t)",
    description="Perfectly inelastic point particles on a ring: clusters merge on contact and "
    "move with their mean velocity.  The state at each requested time is computed directly (no "
    "events); the initial state is MD's for the same --n, --density, --initial and --seed.",
))


# --------------------------------------------------------------------------- registration


def get_model(name) -> Model:
    """The model named ``name`` (an error naming ``model`` and listing the models otherwise).

    Parameters
    ----------
    name : str
        A key of :data:`MODELS`.

    Returns
    -------
    Model
        The model.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``model``) if no model has that name.
    """
    if isinstance(name, str) and name in MODELS:
        return MODELS[name]
    raise InvalidArgumentError("model", name, f"one of {sorted(MODELS)}")


def register_model(name: str, factory: Callable[..., Any], *, time_name: str = "tau",
                   parameters=None) -> Model:
    """Add ``name`` to the catalogue: ``factory(**params)`` builds its engine.  ``parameters``
    (a sequence of :class:`Parameter`) declares them; without it they are the keyword
    parameters of ``factory``, of kind ``"any"`` (those without a default are required).
    The engine itself must meet the engine contract (:class:`particles.driver.Engine`, which
    includes its ``time_name``); ``time_name`` here only names the time option of the command
    line when the model's examples cannot build an engine to ask.  The factory
    travels to ensemble workers by reference (by pickle), so it must be importable there.
    Registering a name again replaces it.

    Parameters
    ----------
    name : str
        The model's name (non-empty).
    factory : Callable[..., Any]
        Builds the engine from keyword parameters; must be importable by workers.
    time_name : str, optional
        The time option's name when no engine can be built from the examples (default
        ``"tau"``).
    parameters : sequence of Parameter, optional
        The declared parameters; default: the factory's keywords, of kind ``"any"``.

    Returns
    -------
    Model
        The registered model.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``name``) for an empty or non-string name; (argument ``factory``) if it is
        not callable.
    """
    if not isinstance(name, str) or not name:
        raise InvalidArgumentError("name", name, "a non-empty string")
    if not callable(factory):
        raise InvalidArgumentError("factory", factory, "a callable that builds an engine")
    if parameters is None:
        parameters = []
        for p in inspect.signature(factory).parameters.values():
            if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY):
                default = REQUIRED if p.default is p.empty else p.default
                parameters.append(Parameter(p.name, "any", default=default))
    return _declare(Model(name, factory, tuple(parameters), default_time_name=str(time_name)))


def registered_models() -> dict[str, tuple[str, ...]]:
    """{model name: the parameters it accepts}.

    Returns
    -------
    dict of str to tuple of str
        Each registered model's parameter names.
    """
    return {name: m.names for name, m in MODELS.items()}
