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

__all__ = ["temperature", "sonine_coefficients", "first_sonine_a2", "haff_temperature",
           "collision_frequency", "window_times", "maxwell_hcs_a2", "maxwell_a2_relaxation"]


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
    zeta0 = (1.0 - a * a) * collision_frequency(dimension) / dimension
    return temperature0 * (1.0 + 0.5 * zeta0 * math.sqrt(temperature0) * np.asarray(t)) ** -2


def collision_frequency(dimension: int) -> float:
    """ν₀: the collision frequency of a particle of a Maxwellian gas of T = 1 at density 1,
    8√π in d = 3 and 4√π in d = 2 (the rate |g·n| over the whole sphere).

    Parameters
    ----------
    dimension : int
        d, 2 or 3.

    Returns
    -------
    float
    """
    return (8.0 if dimension == 3 else 4.0) * math.sqrt(math.pi)


def window_times(restitution: float, dimension: int, collisions) -> np.ndarray:
    """The times t at which a gas cooling by Haff's law from T = 1 has had ``collisions``
    collisions per particle: ∫ν₀√T dt = c gives t = (2/ζ₀)(e^{ζ₀c/(2ν₀)} − 1),
    ζ₀ = (1 − α²)ν₀/d.

    Parameters
    ----------
    restitution : float
        α < 1.
    dimension : int
        d.
    collisions : array_like
        Collisions per particle.

    Returns
    -------
    numpy.ndarray
    """
    nu0 = collision_frequency(dimension)
    zeta0 = (1.0 - restitution**2) * nu0 / dimension
    return (2.0 / zeta0) * np.expm1(zeta0 * np.asarray(collisions, dtype=float) / (2.0 * nu0))


def _maxwell_moment_rates(restitution: float, dimension: int) -> tuple[float, float, float]:
    """(k₄, k₀, μ) of the Maxwell model's fourth-moment equation dM₄/dt = k₄M₄ + k₀E², with
    E² ∝ e^{−μt} (derivation in :func:`maxwell_hcs_a2`)."""
    d, alpha = dimension, restitution
    small, big = (1.0 - alpha) / 4.0, (1.0 + alpha) / 4.0
    u = 0.5 + small  # the weight of v in u = V + (1 − α)/4 g
    a, b, c = u * u + big * big, 2.0 * big * big, 2.0 * big * (u - big)
    k4 = a * a + b * b - 1.0 + 4.0 * big * big * (u * u + big * big) / d
    k0 = (2.0 * a * b + c * c / d + 4.0 * big * big * (u * u + big * big) / d
          - 16.0 * big**3 * u / d**2)
    mu = (1.0 - alpha**2) / 2.0
    return k4, k0, mu


def maxwell_hcs_a2(restitution: float, dimension: int) -> float:
    """The exact a₂ of the homogeneous cooling state of the inelastic Maxwell model of
    :class:`particles.sphere_kernels.VariableHardSpheres` with exponent 0 (each pair collides
    at rate 1, σ isotropic: v′ = V + (1 − α)/4 g + (1 + α)/4 |g| σ).

    Its moment equations close.  With E = ⟨|v|²⟩ and M₄ = ⟨|v|⁴⟩ (u = 0):
    E_σ|v′|² = a|v|² + b|w|² + c v·w (a = u₁² + B², b = 2B², c = 2B(u₁ − B), B = (1 + α)/4,
    u₁ = (3 − α)/4) and E_σ|v′|⁴ = (E_σ|v′|²)² + 4B²|g|²|u|²/d, so dE/dt = −μE/2 with
    μ = (1 − α²)/2 and dM₄/dt = k₄M₄ + k₀E² with
    k₄ = a² + b² − 1 + 4B²(u₁² + B²)/d and
    k₀ = 2ab + c²/d + 4B²(u₁² + B²)/d − 16B³u₁/d².
    K = M₄/E² then obeys dK/dt = (k₄ + μ)K + k₀, stable for k₄ + μ < 0, with the fixed point
    K* = −k₀/(k₄ + μ); a₂ = d/(d + 2) K* − 1 (a Maxwellian has K = (d + 2)/d).  The tests check
    k₄ and k₀ against a Monte Carlo average of the kernel's own collision map.

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1).
    dimension : int
        d, 2 or 3.

    Returns
    -------
    float
        a₂ of the cooling state (0.4615 in d = 2 and 0.2857 in d = 3 at α = 0.5).
    """
    k4, k0, mu = _maxwell_moment_rates(restitution, dimension)
    return dimension / (dimension + 2.0) * (-k0 / (k4 + mu)) - 1.0


def maxwell_a2_relaxation(restitution: float, dimension: int) -> float:
    """The rate −(k₄ + μ) at which the Maxwell model's a₂ relaxes to its cooling-state value
    per unit t (:func:`maxwell_hcs_a2`): 0.114 in d = 2 and 0.164 in d = 3 at α = 0.5.

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1).
    dimension : int
        d, 2 or 3.

    Returns
    -------
    float
    """
    k4, _, mu = _maxwell_moment_rates(restitution, dimension)
    return -(k4 + mu)
