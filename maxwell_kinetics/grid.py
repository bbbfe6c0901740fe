"""The log-uniform q grid of the kinetic solver and local Lagrange interpolation on it.

The rescaled characteristic function G(q, τ) is stored for q ≥ 0 on the grid

    s_j = ln q_j = s_min + j h,   j = 0 .. n − 1,   q_min = e^{s_min},  q_max = e^{s_max}.

In s the transport term of the rescaled equation is a shift at constant speed λ and the gain
term samples G at s + ln p and s + ln(1 − p): on a uniform s grid every shift is a
fixed stencil.  Values between nodes come from centred Lagrange interpolation of ``order``
points (even), whose error is O(h^order) for smooth G(s).

Outside the grid:

* q < q_min: the small-q expansion G = 1 − q²/2 − i m₃ q³/6 + O(q³), with m₃ = ⟨x³⟩ conserved.
  Omitted terms are O(q_min³) (the |q|³/3 of f̂ that builds up at late times) and
  O(m₄(τ) q_min⁴).
* q > q_max: G is taken from the free-streaming asymptotics e^{−τ} φ(q e^{λτ}) of the initial
  law (the gain term there is of second order in the small values of G); once this is below
  round-off it is zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from particles.validation import (
    InvalidArgumentError,
    check_bool,
    check_count,
    check_dimension,
    check_nonnegative,
    check_positive,
    check_real,
)


def _is_bool(value) -> bool:
    return isinstance(value, (bool, np.bool_))


def _number(value, name: str) -> float:
    """A real number given as a number (a bool or a text is refused, naming ``name``)."""
    if isinstance(value, (str, bytes)):
        raise InvalidArgumentError(name, value, "a real number")
    return check_real(value, name)

__all__ = ["Resolution", "RESOLUTIONS", "get_resolution", "lagrange_weights", "estimate_solve",
           "check_solve_budget", "format_seconds", "MAX_SOLVE_SECONDS"]


#: Beyond this τ the free-streaming inflow e^{−τ} φ of the solver is below 4e-18 and is set to
#: zero (used by :mod:`maxwell_kinetics.solver` and its JAX scheme).
INFLOW_CUT = 40.0

@dataclass(frozen=True)
class Resolution:
    """A named discretisation of s = ln q: spacing ``h``, interpolation ``order``, range.

    The grid is s_j = s_min + j h, j = 0 .. n − 1, with q = k·v0(τ) the rescaled wave number
    (module docstring); its last point is the largest s_j ≤ s_max.

    Attributes
    ----------
    name : str
        Name of the resolution (a key of ``RESOLUTIONS`` for the offered ones).
    h : float
        Spacing in s = ln q, finite and > 0.
    order : int, default 8
        Number of points of the centred Lagrange interpolation (even, ≥ 2); error O(h^order).
    s_min : float, default −24.0
        ln q_min.
    s_max : float, default ln 36
        Upper bound of ln q_max.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``h``, ``order`` or ``s_min`` when the spacing is not finite and positive, the
        order is not an even number ≥ 2, or s_min ≥ s_max.
    """

    name: str
    h: float
    order: int = 8
    s_min: float = -24.0
    s_max: float = math.log(36.0)

    def __post_init__(self):
        if not _number(self.h, "h") > 0:
            raise InvalidArgumentError("h", self.h, "a finite spacing > 0")
        if _is_bool(self.order) or check_count(self.order, "order", 2) % 2:
            raise InvalidArgumentError("order", self.order, "an even number of points >= 2")
        if not _number(self.s_min, "s_min") < _number(self.s_max, "s_max"):
            raise InvalidArgumentError("s_min", self.s_min, f"a value below s_max={self.s_max}")

    @property
    def n(self) -> int:
        """Number of grid points."""
        return int(math.floor((self.s_max - self.s_min) / self.h + 1e-9)) + 1

    @property
    def s(self) -> np.ndarray:
        """The nodes s_j = s_min + j h, j = 0 .. n − 1."""
        return self.s_min + self.h * np.arange(self.n)

    @property
    def q(self) -> np.ndarray:
        """The rescaled wave numbers q_j = e^{s_j}."""
        return np.exp(self.s)

    @property
    def q_min(self) -> float:
        """The first node, e^{s_min}."""
        return math.exp(self.s_min)

    @property
    def q_max(self) -> float:
        """The last node, e^{s_min + (n − 1) h} (≤ e^{s_max})."""
        return math.exp(self.s_min + self.h * (self.n - 1))


#: The offered resolutions, coarse to fine (spacing halves at fixed order).
RESOLUTIONS: dict[str, Resolution] = {
    r.name: r
    for r in (
        Resolution("coarse", h=0.1),
        Resolution("default", h=0.05),
        Resolution("fine", h=0.025),
        Resolution("finest", h=0.0125),
    )
}


def get_resolution(resolution) -> Resolution:
    """A ``Resolution`` passes through; a name is looked up in :data:`RESOLUTIONS`.

    Parameters
    ----------
    resolution : str or Resolution
        A name ("coarse", "default", "fine", "finest") or a grid.

    Returns
    -------
    Resolution
        The grid.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``resolution``, for an unknown name or another type.
    """
    if isinstance(resolution, Resolution):
        return resolution
    try:
        return RESOLUTIONS[resolution]
    except (KeyError, TypeError):
        raise InvalidArgumentError(
            "resolution", resolution, "one of " + ", ".join(RESOLUTIONS)
        ) from None


def lagrange_weights(offset: float, order: int) -> tuple[int, np.ndarray]:
    """Weights for interpolating at fractional grid position ``j + offset`` from its neighbours.

    Returns ``(first, w)``: value ≈ Σ_k w[k] · G[j + first + k], k = 0 .. order − 1, with the
    stencil centred on the interval that contains the target.  Exact for polynomials of degree
    ``order − 1``.

    Parameters
    ----------
    offset : float
        Target position in units of the grid step, relative to a node j (may be negative).
    order : int
        Number of stencil points (even).

    Returns
    -------
    first : int
        Offset of the first stencil point relative to j.
    w : numpy.ndarray
        The ``order`` Lagrange weights.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``offset`` is not a finite real number or ``order`` not an even integer >= 2.
    """
    from particles.validation import InvalidArgumentError, check_count, check_real

    offset = check_real(offset, "offset")
    order = check_count(order, "order", 2)
    if order % 2:
        raise InvalidArgumentError("order", order, "an even integer >= 2")
    base = math.floor(offset)
    frac = offset - base
    first = base - order // 2 + 1
    nodes = np.arange(order) - (order // 2 - 1)  # positions relative to `base`
    w = np.ones(order)
    for k in range(order):
        for m in range(order):
            if m != k:
                w[k] *= (frac - nodes[m]) / (nodes[k] - nodes[m])
    return first, w


#: Seconds per grid node and window of a solve after compilation, by dimension (d ≥ 2 with the
#: "fast" η rule at 16 η nodes; other rules and node counts scale it, :func:`estimate_solve`).
#: Measured on the 2-core development machine, r = 0.5, coarse and default grids, one core:
#: 1.3–1.6 µs in 1D, 5.6–6.1 µs in 2D (3D within 10 % of 2D); rounded up.
SECONDS_PER_NODE_WINDOW = {1: 1.7e-6, 2: 6.5e-6, 3: 6.5e-6}
#: A solve estimated to take longer than this (one day) is refused unless forced (``--force``).
MAX_SOLVE_SECONDS = 86400.0
#: How the refusal of a long solve tells the user to force it (the command line shows --force).
FORCE = "force=True (--force on the command line)"


def estimate_solve(grid: Resolution, tau_max: float, n_times: int, *, dimension: int = 1,
                   angular_rule: str = "fast", window: float = 2.0,
                   angular_nodes: int = 16) -> dict:
    """What a solve will cost, before it starts: ``windows`` (τ_max / ``window``: each is one
    integration over the grid), ``seconds`` (windows × grid nodes ×
    :data:`SECONDS_PER_NODE_WINDOW`, after compilation, which adds a few seconds to the first
    solve of a process) and ``memory`` in bytes (the stored G and deviation at every output
    time, 24 bytes per node and time, plus the working state).

    Parameters
    ----------
    grid : Resolution
        The q grid.
    tau_max : float
        Last τ of the solve (collisions per particle).
    n_times : int
        Number of output times.
    dimension : int, default 1
        Space dimension (d ≥ 2 costs more per node).
    angular_rule : str, default "fast"
        The η quadrature rule in d ≥ 2.
    window : float, default 2.0
        Length in τ of one integration window.
    angular_nodes : int, default 16
        The η nodes of the gain in d ≥ 2 (``solve``'s ``angular_nodes``).

    Returns
    -------
    dict
        ``{"windows": float, "seconds": float, "memory": float}`` (memory in bytes).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``tau`` (not a finite number >= 0), ``window`` (not > 0), ``n_times`` (not an integer
        >= 1) or ``dimension`` (not 1, 2 or 3).

    Notes
    -----
    In d ≥ 2 the cost per node is that of the "fast" rule at 16 η nodes
    (:data:`SECONDS_PER_NODE_WINDOW`) scaled by the η nodes per state node of the chosen rule
    and ``angular_nodes``
    (:func:`maxwell_kinetics.angular_tiers.angular_nodes_per_state_node`) over those of that
    reference:
    the gain's sum over η is the bulk of a step, so the time is proportional to that count
    (measured: "accurate" at 16 nodes, 2.25 times the count, took 2.3 times the time).
    """
    tau_max, window = check_nonnegative(tau_max, "tau"), check_positive(window, "window")
    n_times, dimension = check_count(n_times, "n_times", 1), check_dimension(dimension)
    windows = tau_max / window
    per = SECONDS_PER_NODE_WINDOW.get(int(dimension), SECONDS_PER_NODE_WINDOW[3])
    memory = 24.0 * grid.n * (n_times + 64)
    if int(dimension) > 1:
        from .angular_tiers import angular_nodes_per_state_node

        count = angular_nodes_per_state_node(grid, angular_rule, angular_nodes)
        per *= count / angular_nodes_per_state_node(grid, "fast", 16)
        memory += 16.0 * grid.n * count  # the gain's shifts and weights per η node
    return {"windows": windows, "seconds": windows * grid.n * per, "memory": memory}


def format_seconds(seconds: float) -> str:
    """A duration in words: ``"40 s"``, ``"12 min"``, ``"3.5 h"``, ``"12 days"``.

    Parameters
    ----------
    seconds : float
        The duration; a non-finite value is written as ``str(seconds)``.

    Returns
    -------
    str
        Seconds below 2 min, minutes below 2 h, hours below 2 days, else days.
    """
    if not math.isfinite(seconds):
        return str(seconds)
    if seconds < 120:
        return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.3g} days"


def check_solve_budget(grid: Resolution, tau_max: float, n_times: int, *, window: float = 2.0,
                       force: bool = False, name: str = "tau", dimension: int = 1,
                       angular_rule: str = "fast", angular_nodes: int = 16) -> dict:
    """:func:`estimate_solve`, then refuse (:class:`InvalidArgumentError` naming ``name``) a
    solve that cannot fit in the memory available, and one estimated to take more than
    :data:`MAX_SOLVE_SECONDS` unless ``force``.  Returns the estimate.

    Parameters
    ----------
    grid : Resolution
        The q grid.
    tau_max : float
        Last τ of the solve.
    n_times : int
        Number of output times.
    window : float, default 2.0
        Length in τ of one integration window.
    force : bool, default False
        Run a long solve anyway (the memory check still applies).
    name : str, default "tau"
        Argument name that the error reports (the caller's option).
    dimension : int, default 1
        Space dimension.
    angular_rule : str, default "fast"
        The η quadrature rule in d ≥ 2.
    angular_nodes : int, default 16
        The η nodes of the gain in d ≥ 2.

    Returns
    -------
    dict
        The estimate of :func:`estimate_solve`.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``name``, if the estimated memory exceeds the memory available, or the estimated
        time exceeds ``MAX_SOLVE_SECONDS`` and ``force`` is False; naming ``force`` when it is
        not a bool (``'no'`` is not True).
    """
    force = check_bool(force, "force")
    from particles.budget import available_memory, format_bytes

    from .angular_tiers import angular_nodes_per_state_node

    estimate = estimate_solve(grid, tau_max, n_times, dimension=dimension,
                              angular_rule=angular_rule, window=window,
                              angular_nodes=angular_nodes)
    memory, seconds = estimate["memory"], estimate["seconds"]
    available = available_memory()
    if not memory <= available:
        many_nodes = int(dimension) > 1 and 16.0 * grid.n * angular_nodes_per_state_node(
            grid, angular_rule, angular_nodes) > 24.0 * grid.n * n_times
        raise InvalidArgumentError(
            *(("angular_nodes", angular_nodes) if many_nodes
              else (name, f"{n_times} output times")),
            f"a solve that fits in the {format_bytes(available)} of memory available "
            f"(estimate {format_bytes(memory)})",
        )
    if not force and not seconds <= MAX_SOLVE_SECONDS:
        eta = "" if int(dimension) == 1 else (
            f" with {angular_nodes_per_state_node(grid, angular_rule, angular_nodes):.3g} η "
            f"nodes each ({angular_rule!r} rule, angular_nodes={angular_nodes})")
        raise InvalidArgumentError(
            name, tau_max,
            f"a solve estimated to take at most {format_seconds(MAX_SOLVE_SECONDS)} (this one: "
            f"{estimate['windows']:.3g} windows of {window:g} in τ on {grid.n} nodes"
            f"{eta}, about "
            f"{format_seconds(seconds)}); pass {FORCE} to run it anyway",
        )
    return estimate
