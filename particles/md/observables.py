"""MD-specific observables of the hard-rod gas.

Energy, histogram, S(k) and C(r) are those of :mod:`particles.observables` applied to the
velocities in label order (``state.velocities``: the lattice conventions); this module adds what
is MD-specific: τ(t), the total momentum, rod positions, the profiles v(x, t) and v(i, t) and
Haff's law (:func:`haff_time`, :func:`haff_energy`).
"""

from __future__ import annotations

import math

import numpy as np

from ..validation import (
    InvalidArgumentError,
    check_positive,
    check_real,
    check_real_array,
    check_restitution,
)
from .state import MDParams, MDState


def _state(state, params=None) -> MDState:
    """``state`` checked to be an :class:`MDState` (of ``params``' N when given)."""
    if not isinstance(state, MDState):
        raise InvalidArgumentError("state", type(state).__name__, "a particles.MDState")
    if params is not None:
        if not isinstance(params, MDParams):
            raise InvalidArgumentError("params", type(params).__name__, "a particles.MDParams")
        if state.velocities.size != params.n:
            raise InvalidArgumentError("params", f"n = {params.n}", "the parameters of this "
                                       f"state (N = {state.velocities.size})")
    return state


def _haff_arguments(restitution, density, t0_energy) -> tuple[float, float, float]:
    return (check_restitution(restitution), check_positive(density, "density"),
            check_positive(t0_energy, "t0_energy"))

__all__ = [
    "collisions_per_particle",
    "total_momentum",
    "rod_positions",
    "profile_x",
    "profile_i",
    "haff_time",
    "haff_energy",
    "initial_cooling_rate",
]


def collisions_per_particle(state: MDState) -> float:
    """τ(t) = 2 · collisions / N (each pair collision involves two particles).

    Parameters
    ----------
    state : particles.MDState
        The MD state.

    Returns
    -------
    float
        τ = 2 · (pair collisions so far) / N.

    Raises
    ------
    particles.InvalidArgumentError
        If ``state`` is not an MDState.
    """
    state = _state(state)
    return 2.0 * state.collisions / state.velocities.size


def total_momentum(state: MDState) -> float:
    """Total momentum Σ_i v_i (unit masses; zero at t = 0 up to round-off).

    Parameters
    ----------
    state : particles.MDState
        The MD state.

    Returns
    -------
    float
        Σ_i v_i.

    Raises
    ------
    particles.InvalidArgumentError
        If ``state`` is not an MDState.
    """
    return float(np.sum(_state(state).velocities))


def rod_positions(state: MDState, params: MDParams, t: float | None = None) -> np.ndarray:
    """Real positions y_i = x_i + i σ of the rods at time t, reduced mod L into [0, L).

    Parameters
    ----------
    state : particles.MDState
        The MD state (positions stored lazily, in reduced coordinates).
    params : particles.MDParams
        The run's parameters (N, rod length σ, ring length L).
    t : float or None, optional
        The time; None (default) means the state's own time.

    Returns
    -------
    numpy.ndarray
        Float array of shape ``(N,)``, in particle-label order.

    Raises
    ------
    particles.InvalidArgumentError
        If ``state`` is not an MDState, ``params`` not the MDParams of its N, or ``t`` not a
        finite real number.
    """
    state = _state(state, params)
    if t is not None:
        t = check_real(t, "t")
    x = state.positions_at(t) + np.arange(params.n) * params.rod_length
    return np.mod(x, params.length)


def profile_x(state: MDState, params: MDParams, t: float | None = None):
    """The profile v(x, t): rod positions in [0, L) sorted increasingly, and their velocities.

    Parameters
    ----------
    state : particles.MDState
        The MD state.
    params : particles.MDParams
        The run's parameters.
    t : float or None, optional
        The time; None (default) means the state's own time.

    Returns
    -------
    tuple of numpy.ndarray
        ``(y, v)``: the sorted positions and the velocities in that order, each of shape
        ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``state`` is not an MDState, ``params`` not the MDParams of its N, or ``t`` not a
        finite real number.
    """
    y = rod_positions(state, params, t)
    order = np.argsort(y, kind="stable")
    return y[order], state.velocities[order]


def profile_i(state: MDState):
    """The profile v(i, t) against particle label i (labels keep their order on the ring).

    Parameters
    ----------
    state : particles.MDState
        The MD state.

    Returns
    -------
    tuple of numpy.ndarray
        ``(i, v)``: the labels 0..N−1 and a copy of the velocities, each of shape ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``state`` is not an MDState.
    """
    state = _state(state)
    return np.arange(state.velocities.size), state.velocities.copy()


def haff_time(restitution: float, density: float, t0_energy: float = 1.0) -> float:
    """Haff's time t₀ = √π / ((1 − r²) n √T₀): the homogeneous cooling state of point-like
    rods (Gaussian velocities, collision rate (2/√π) n √T per particle, each collision losing
    (1 − r²)/4 of the pair's squared relative velocity) has T(t) = T₀ / (1 + t/t₀)² and
    τ(t) = (2/(1 − r²)) ln(1 + t/t₀) collisions per particle.  ``inf`` for r = 1 (no
    cooling).  ``density`` is the reduced density n / (1 − n σ) for rods of length σ.

    Parameters
    ----------
    restitution : float
        The restitution coefficient r.
    density : float
        The (reduced) number density n.
    t0_energy : float, optional
        The initial temperature T₀ (default 1).

    Returns
    -------
    float
        t₀, in units of physical time t.

    Raises
    ------
    particles.InvalidArgumentError
        If ``restitution`` is not in [0, 1] or ``density`` or ``t0_energy`` is not a finite
        number > 0 (booleans and complex numbers refused).
    """
    restitution, density, t0_energy = _haff_arguments(restitution, density, t0_energy)
    if restitution >= 1.0:
        return math.inf
    return math.sqrt(math.pi) / ((1.0 - restitution**2) * density * math.sqrt(t0_energy))


def haff_energy(t, restitution: float, density: float, t0_energy: float = 1.0):
    """Haff's law T₀ / (1 + t/t₀)² with t₀ = :func:`haff_time`.

    Parameters
    ----------
    t : float or array_like
        Physical times.
    restitution : float
        The restitution coefficient r.
    density : float
        The (reduced) number density n.
    t0_energy : float, optional
        The initial temperature T₀ (default 1).

    Returns
    -------
    numpy.ndarray
        T(t), a float array of the shape of ``t``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``t`` is not finite real times >= 0, or as :func:`haff_time`.
    """
    t = check_real_array(t, "t")
    if np.any(t < 0):
        raise InvalidArgumentError("t", t.tolist() if t.size <= 40 else f"shape {t.shape}",
                                   "times >= 0")
    return t0_energy / (1.0 + t / haff_time(restitution, density, t0_energy)) ** 2


def initial_cooling_rate(restitution: float, density: float, t0_energy: float = 1.0) -> float:
    """dT/dt at t = 0⁺ for Gaussian velocities: −(2/√π)(1 − r²) n T₀^{3/2} (the derivative
    of :func:`haff_energy` at t = 0).

    Parameters
    ----------
    restitution : float
        The restitution coefficient r.
    density : float
        The (reduced) number density n.
    t0_energy : float, optional
        The initial temperature T₀ (default 1).

    Returns
    -------
    float
        dT/dt at t = 0⁺ (≤ 0).

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`haff_time`.
    """
    restitution, density, t0_energy = _haff_arguments(restitution, density, t0_energy)
    return -2.0 / math.sqrt(math.pi) * (1.0 - restitution**2) * density * t0_energy**1.5
