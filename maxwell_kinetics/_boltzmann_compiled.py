"""The compiled functions of the velocity-space solver
(:mod:`maxwell_kinetics.inelastic_boltzmann`): its time integration, right-hand side, steady
residual and Jacobian, each kept in the project's store of compiled executables
(:func:`maxwell_kinetics.compile_cache.call`), so that a warm process neither traces nor
compiles them (nor imports diffrax).

The time integration runs segment by segment between the output times (``lax.scan`` over the
padded times, each segment one ``diffrax.diffeqsolve`` with ``SaveAt(t1=True)``,
``throw=False``; a zero-length segment, the padding or a first time 0, makes no diffrax call).
A single solve with ``SaveAt(ts=times)`` checks its times with host callbacks (equinox's
``error_if``: "saveat.ts must be increasing", "must lie between t0 and t1"), and an executable
with host callbacks cannot be serialized.  Each segment starts with diffrax's initial step
selection; its step budget is the whole solve's ``max_steps``, and the solve fails as soon as the
steps of all segments together pass it (the segment in which that happens ends first: at most
twice ``max_steps`` steps in all).

``TRACES`` counts the traces of each function (a Python side effect that runs only when JAX
traces: a process that loads them from the store traces nothing).  Every call must run with
float64 enabled (``jax.enable_x64(True)``).
"""

from __future__ import annotations

import collections
from dataclasses import dataclass

import jax
import jax.numpy as jnp

from . import _boltzmann_scheme as scheme
from . import compile_cache

__all__ = ["TRACES", "Static", "PLAIN", "rhs", "solve_unjitted", "rates_unjitted",
           "steady_unjitted", "jacobian_unjitted", "Functions"]

#: Traces (= compilations) of each function since import, by name ("solve", "rates", "steady",
#: "jacobian").
TRACES: collections.Counter = collections.Counter()


@dataclass(frozen=True)
class Static:
    """The static (hashable) part of a compiled function: one compilation per value.

    Attributes
    ----------
    max_steps : int
        The time integration's step limit (0 for the functions without one).
    """

    max_steps: int = 0


#: The static part of the functions without a time integration.
PLAIN = Static()


def rhs(t, y, args):
    """d(unit · F, ln s)/dt of the velocity-space solve.

    Parameters
    ----------
    t : float
        Time (unused: the equation is autonomous).
    y : jax.Array
        Shape (N + 1,): unit · F at the nodes (unit: the tables' ``unit``, 1 on a uniform grid)
        and ln s.
    args : tuple
        ``(tables, c, h, density, exponent, lam)``.

    Returns
    -------
    jax.Array
        Shape (N + 1,).
    """
    tables, c, h, density, exponent, lam = args
    rate = density * jnp.exp(exponent * y[-1])  # n s^γ
    if "unit" in tables:  # a mapped grid: the unknown is unit · F
        dF, sigma = scheme.grid_rhs(y[:-1] / tables["unit"], tables, c, h, lam)
        return jnp.concatenate([rate * dF * tables["unit"], (rate * sigma)[None]])
    dF, sigma = scheme.grid_rhs(y[:-1], tables, c, h, lam)
    return jnp.concatenate([rate * dF, (rate * sigma)[None]])


def solve_unjitted(static: Static, y0, times, args, rtol, atol):
    """y at each of ``times`` from y(0) = ``y0`` (the module docstring).

    Parameters
    ----------
    static : Static
        The step limit.
    y0 : jax.Array
        Shape (N + 1,).
    times : jax.Array
        Non-decreasing times ≥ 0, shape (K,).
    args : tuple
        As :func:`rhs`.
    rtol, atol : float
        Tolerances of the PID controller.

    Returns
    -------
    ys : jax.Array
        Shape (K, N + 1).
    ok : jax.Array
        Whether every segment succeeded within the step limit.
    steps : jax.Array
        The time steps of all segments (accepted and rejected).
    """
    import diffrax

    TRACES["solve"] += 1
    term = diffrax.ODETerm(rhs)
    controller = diffrax.PIDController(rtol=rtol, atol=atol)

    def segment(carry, t1):
        y, t0, ok, steps = carry

        def run():
            out = diffrax.diffeqsolve(term, diffrax.Tsit5(), t0, t1, None, y, args=args,
                                      saveat=diffrax.SaveAt(t1=True),
                                      stepsize_controller=controller,
                                      max_steps=static.max_steps, throw=False)
            return (out.ys[0], out.result == diffrax.RESULTS.successful,
                    out.stats["num_steps"].astype(steps.dtype))

        def skip():  # a zero-length segment (padding, t = 0), or after a failure
            return y, jnp.asarray(True), jnp.zeros((), steps.dtype)

        y1, good, taken = jax.lax.cond(ok & (t1 > t0), run, skip)
        steps = steps + taken
        ok = ok & good & (steps <= static.max_steps)
        return (y1, t1, ok, steps), y1

    start = (y0, jnp.zeros((), times.dtype), jnp.asarray(True), jnp.zeros((), jnp.int64))
    (_, _, ok, steps), ys = jax.lax.scan(segment, start, times)
    return ys, ok, steps


def rates_unjitted(static: Static, ys, args):
    """:func:`rhs` at each row of ``ys``.

    Parameters
    ----------
    static : Static
        :data:`PLAIN`.
    ys : jax.Array
        Shape (K, N + 1).
    args : tuple
        As :func:`rhs`.

    Returns
    -------
    jax.Array
        Shape (K, N + 1).
    """
    TRACES["rates"] += 1
    return jax.vmap(lambda y: rhs(0.0, y, args))(ys)


def steady_unjitted(static: Static, F, tables, c, h, lam):
    """The rescaled equation's right-hand side Q_h(F) + σ′ ∂_c(c F).

    Parameters
    ----------
    static : Static
        :data:`PLAIN`.
    F, tables, c, h, lam
        As :func:`maxwell_kinetics._boltzmann_scheme.grid_rhs`.

    Returns
    -------
    jax.Array
        Shape (N,).
    """
    TRACES["steady"] += 1
    return scheme.grid_rhs(F, tables, c, h, lam)[0]


def jacobian_unjitted(static: Static, F, tables, c, h, lam):
    """The Jacobian of :func:`steady_unjitted` in F (forward mode).

    Parameters
    ----------
    static : Static
        :data:`PLAIN`.
    F, tables, c, h, lam
        As :func:`maxwell_kinetics._boltzmann_scheme.grid_rhs`.

    Returns
    -------
    jax.Array
        Shape (N, N).
    """
    TRACES["jacobian"] += 1
    return jax.jacfwd(lambda G: scheme.grid_rhs(G, tables, c, h, lam)[0])(F)


class Functions:
    """The compiled functions, each through :func:`maxwell_kinetics.compile_cache.call` (one
    instance per process: :meth:`get`)."""

    cache: dict = {}

    def __init__(self):
        self._jitted = {name: jax.jit(function, static_argnums=0) for name, function in (
            ("solve", solve_unjitted), ("rates", rates_unjitted), ("steady", steady_unjitted),
            ("jacobian", jacobian_unjitted))}

    @classmethod
    def get(cls) -> Functions:
        """The process's instance.

        Returns
        -------
        Functions
        """
        if "functions" not in cls.cache:
            cls.cache["functions"] = cls()
        return cls.cache["functions"]

    def _call(self, name, function, static, args):
        return compile_cache.call(f"boltzmann_{name}", function, self._jitted[name], static,
                                  args)

    def solve(self, y0, times, args, rtol, atol, max_steps: int):
        """:func:`solve_unjitted` with ``Static(max_steps)``.

        Parameters
        ----------
        y0, times, args, rtol, atol
            As :func:`solve_unjitted`.
        max_steps : int
            The step limit.

        Returns
        -------
        tuple
            ``(ys, ok, steps)``.
        """
        return self._call("solve", solve_unjitted, Static(int(max_steps)),
                          (y0, times, args, rtol, atol))

    def rhs(self, ys, args):
        """:func:`rates_unjitted`.

        Parameters
        ----------
        ys : jax.Array
            Shape (K, N + 1).
        args : tuple
            As :func:`rhs`.

        Returns
        -------
        jax.Array
            Shape (K, N + 1).
        """
        return self._call("rates", rates_unjitted, PLAIN, (ys, args))

    def steady(self, F, tables, c, h, lam):
        """:func:`steady_unjitted`.

        Parameters
        ----------
        F, tables, c, h, lam
            As :func:`maxwell_kinetics._boltzmann_scheme.grid_rhs`.

        Returns
        -------
        jax.Array
            Shape (N,).
        """
        return self._call("steady", steady_unjitted, PLAIN, (F, tables, c, h, lam))

    def jacobian(self, F, tables, c, h, lam):
        """:func:`jacobian_unjitted`.

        Parameters
        ----------
        F, tables, c, h, lam
            As :func:`maxwell_kinetics._boltzmann_scheme.grid_rhs`.

        Returns
        -------
        jax.Array
            Shape (N, N).
        """
        return self._call("jacobian", jacobian_unjitted, PLAIN, (F, tables, c, h, lam))
