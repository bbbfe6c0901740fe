"""MD-specific observables of the hard-rod gas.

Energy, histogram, S(k) and C(r) are those of :mod:`particles.observables` applied to the
velocities in label order (``state.velocities``: the lattice conventions); this module adds what
is MD-specific: τ(t), the total momentum, rod positions, the profiles v(x, t) and v(i, t) and
Haff's law (:func:`haff_time`, :func:`haff_energy`).
"""

from __future__ import annotations

import math

import numpy as np

from .state import MDParams, MDState

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
    state : MDState
        The state.

    Returns
    -------
    float
    """
    return 2.0 * state.collisions / state.velocities.size


def total_momentum(state: MDState) -> float:
    """Total momentum Σ_i v_i (unit masses; zero at t = 0 up to round-off).

    Parameters
    ----------
    state : MDState
        The state.

    Returns
    -------
    float
    """
    return float(np.sum(state.velocities))


def rod_positions(state: MDState, params: MDParams, t: float | None = None) -> np.ndarray:
    """Real positions y_i = x_i + i σ of the rods at time t, reduced mod L into [0, L).

    Parameters
    ----------
    state : MDState
        The state.
    params : MDParams
        The gas (σ, L).
    t : float, optional
        The time (default the state's).

    Returns
    -------
    numpy.ndarray
    """
    x = state.positions_at(t) + np.arange(params.n) * params.rod_length
    return np.mod(x, params.length)


def profile_x(state: MDState, params: MDParams, t: float | None = None):
    """The profile v(x, t): rod positions in [0, L) sorted increasingly, and their velocities.

    Parameters
    ----------
    state : MDState
        The state.
    params : MDParams
        The gas.
    t : float, optional
        The time (default the state's).

    Returns
    -------
    x, v : numpy.ndarray
        Sorted positions and their velocities.
    """
    y = rod_positions(state, params, t)
    order = np.argsort(y, kind="stable")
    return y[order], state.velocities[order]


def profile_i(state: MDState):
    """The profile v(i, t) against particle label i (labels keep their order on the ring).

    Parameters
    ----------
    state : MDState
        The state.

    Returns
    -------
    i, v : numpy.ndarray
        Labels and velocities.
    """
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
        r.
    density : float
        n (reduced for rods of length σ).
    t0_energy : float
        T₀.

    Returns
    -------
    float
        t₀.
    """
    if restitution >= 1.0:
        return math.inf
    return math.sqrt(math.pi) / ((1.0 - restitution**2) * density * math.sqrt(t0_energy))


def haff_energy(t, restitution: float, density: float, t0_energy: float = 1.0):
    """Haff's law T₀ / (1 + t/t₀)² with t₀ = :func:`haff_time`.

    Parameters
    ----------
    t : float or array_like
        Times.
    restitution, density, t0_energy
        As for :func:`haff_time`.

    Returns
    -------
    float or numpy.ndarray
    """
    t = np.asarray(t, dtype=float)
    return t0_energy / (1.0 + t / haff_time(restitution, density, t0_energy)) ** 2


def initial_cooling_rate(restitution: float, density: float, t0_energy: float = 1.0) -> float:
    """dT/dt at t = 0⁺ for Gaussian velocities: −(2/√π)(1 − r²) n T₀^{3/2} (the derivative
    of :func:`haff_energy` at t = 0).

    Parameters
    ----------
    restitution, density, t0_energy
        As for :func:`haff_time`.

    Returns
    -------
    float
    """
    return -2.0 / math.sqrt(math.pi) * (1.0 - restitution**2) * density * t0_energy**1.5
