"""Observables of a gas of d-dimensional velocities (hard spheres, d = 2, 3): the temperature and
the Sonine coefficients a₂, a₃, and the first Sonine approximation of a₂ in the homogeneous
cooling state (for comparison only).

Definitions (velocities v of shape (N, d), mean u): T = ⟨|v − u|²⟩/d; with c = (v − u)/√(2T),
a₂ = d/(d + 2) · ⟨c⁴⟩/⟨c²⟩² − 1 and a₃ = 1 + 3a₂ − d²/((d + 2)(d + 4)) · ⟨c⁶⟩/⟨c²⟩³, both 0 for
a Maxwellian (⟨c⁴⟩ = d(d + 2)/4, ⟨c⁶⟩ = d(d + 2)(d + 4)/8, ⟨c²⟩ = d/2).
"""

from __future__ import annotations

import math

import numpy as np

from .validation import InvalidArgumentError, check_restitution

__all__ = ["temperature", "sonine_coefficients", "first_sonine_a2", "haff_temperature"]


def _vectors(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.ndim != 2 or v.shape[1] < 1 or v.shape[0] < 1:
        raise InvalidArgumentError("v", f"array of shape {v.shape}", "velocities of shape (N, d)")
    return v


def temperature(v) -> float:
    """T = ⟨|v − u|²⟩/d of velocities ``v`` (N, d), u their mean.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``.

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``v`` when it is not of shape (N, d).
    """
    v = _vectors(v)
    c = v - v.mean(axis=0)
    return float(np.mean(np.sum(c * c, axis=1))) / v.shape[1]


def sonine_coefficients(v) -> dict[str, float]:
    """The temperature and the Sonine coefficients of velocities ``v`` (module docstring).

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``.

    Returns
    -------
    dict
        ``temperature`` T, ``a2`` and ``a3`` (NaN when T = 0).

    Raises
    ------
    InvalidArgumentError
        Naming ``v`` when it is not of shape (N, d).
    """
    v = _vectors(v)
    d = v.shape[1]
    c = v - v.mean(axis=0)
    c2 = np.sum(c * c, axis=1)
    t = float(np.mean(c2)) / d
    if not t > 0.0:
        return {"temperature": t, "a2": math.nan, "a3": math.nan}
    x = c2 / (2.0 * t)  # |c|² of the reduced velocity c = (v − u)/√(2T)
    m2, m4, m6 = float(np.mean(x)), float(np.mean(x * x)), float(np.mean(x * x * x))
    a2 = d / (d + 2.0) * m4 / m2**2 - 1.0
    a3 = 1.0 + 3.0 * a2 - d * d / ((d + 2.0) * (d + 4.0)) * m6 / m2**3
    return {"temperature": t, "a2": a2, "a3": a3}


def first_sonine_a2(restitution: float, dimension: int) -> float:
    """The first Sonine approximation of a₂ in the homogeneous cooling state of smooth inelastic
    hard spheres (van Noije and Ernst): a₂ = 16(1 − α)(1 − 2α²)/(9 + 24d + (8d − 41)α +
    30(1 − α)α²).  An approximation: DSMC differs from it by tens of per cent at small α.

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1].
    dimension : int
        d (2 or 3).

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` or ``dimension`` when out of range.
    """
    a = check_restitution(restitution)
    if dimension not in (2, 3):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    d = dimension
    return 16.0 * (1 - a) * (1 - 2 * a * a) / (9 + 24 * d + (8 * d - 41) * a
                                                 + 30 * (1 - a) * a * a)


def haff_temperature(t, restitution: float, dimension: int, temperature0: float = 1.0):
    """Haff's law of hard spheres started from a Maxwellian of temperature T₀ (density 1,
    a₂ neglected): dT/dt = −ζ₀ T^{3/2}, ζ₀ = (1 − α²) ν₀/d, so T(t) = T₀ (1 + ζ₀ √T₀ t/2)⁻²,
    with ν₀ = 8√π (d = 3), 4√π (d = 2) the collision frequency of a particle at T = 1.

    Parameters
    ----------
    t : array_like
        Times t ≥ 0.
    restitution : float
        α ∈ [0, 1].
    dimension : int
        d (2 or 3).
    temperature0 : float, optional
        T₀ (default 1).

    Returns
    -------
    numpy.ndarray or float
        T(t).

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` or ``dimension`` when out of range.
    """
    a = check_restitution(restitution)
    if dimension not in (2, 3):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    nu0 = (8.0 if dimension == 3 else 4.0) * math.sqrt(math.pi)
    zeta0 = (1.0 - a * a) * nu0 / dimension
    return temperature0 * (1.0 + 0.5 * zeta0 * math.sqrt(temperature0) * np.asarray(t)) ** -2
