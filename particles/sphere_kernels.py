"""The kernels of smooth inelastic hard spheres in d = 2, 3: :class:`HardSpheres` and the
variable-hard-sphere family :class:`VariableHardSpheres`, registered in
:data:`particles.kernels.KERNELS` when :mod:`particles` is imported.

Their rates take d-vectors (last axis of length d = 2 or 3) and sum the integral over the
collision direction; their post-collision maps take that direction (``direction=``), drawn from
the kernel's ``direction_law`` (:data:`DIRECTION_LAWS`).  The DSMC that runs them is
:mod:`particles.hard_sphere_dsmc`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .kernels import Kernel, KernelParameter, register
from .validation import InvalidArgumentError

__all__ = ["DIRECTION_LAWS", "HardSpheres", "VariableHardSpheres", "VHS_EXPONENT"]


#: The laws of the collision direction of a kernel in d = 2, 3 (its ``direction_law``):
#: ``"hard"``, n on the whole unit sphere with density ∝ |ĝ·n| (the map v′ = v − p (g·n) n);
#: ``"isotropic"``, σ uniform on the unit sphere (the map of :class:`VariableHardSpheres`).
DIRECTION_LAWS = ("hard", "isotropic")


def _sphere_dimension(v, w) -> int:
    """d of the d-vectors ``v`` and ``w`` (their last axis), 2 or 3, else an error."""
    d = int(np.shape(v)[-1]) if np.ndim(v) else 0
    if d not in (2, 3) or (np.ndim(w) and int(np.shape(w)[-1]) != d):
        raise InvalidArgumentError("v", f"arrays of shapes {np.shape(v)}, {np.shape(w)}",
                                   "d-vectors (last axis of length 2 or 3) of one d")
    return d


def _dot(a, b, d: int):
    """Σ_c a[..., c] b[..., c], summed component by component (a fixed order of operations:
    the same bits for one pair as for many)."""
    out = a[..., 0] * b[..., 0]
    for c in range(1, d):
        out = out + a[..., c] * b[..., c]
    return out


def _direction(direction):
    if direction is None:
        raise InvalidArgumentError("direction", None, "a unit vector per pair (the collision "
                                   "direction, drawn from the kernel's direction_law)")
    return direction


@register
@dataclass(frozen=True)
class HardSpheres(Kernel):
    """Smooth inelastic hard spheres (d = 3) or disks (d = 2) of constant restitution α, in
    time t at density n (m = 1, f normalised to 1):
    ∂f/∂t = Q(f, f), Q(f, f)(v) = ∫ dw ∫_{S^{d−1}} dn |g·n| [α⁻² f(v*) f(w*) − f(v) f(w)],
    g = v − w, the n-integral over the whole unit sphere (no step function).

    A collision along n maps v′ = v − (1+α)/2 (g·n) n, w′ = w + (1+α)/2 (g·n) n
    (:meth:`post_collision`); the weak form is
    d/dt ∫ψ f = ∫∫ f(v) f(w) ∫ dn |g·n| [ψ(v′) − ψ(v)].  A pair's rate (:meth:`rate`, the
    n-integral summed) is β_d |g| with β_d = ∫ |ĝ·n| dn = 2π (d = 3), 4 (d = 2), and given g
    the direction n has density |ĝ·n|/β_d on the sphere (``direction_law = "hard"``, what
    ``angular="hard"`` of :mod:`particles.ulam_kinematics` samples; n and −n are one
    collision).  A particle collides at rate ν = β_d ⟨|v − w|⟩ (8√π for the Maxwellian of
    T = 1 in d = 3, 4√π in d = 2), so pairs collide ν/2 times per particle and unit t; per
    collision Σ|v|² drops by (1 − α²)/2 (g·n)², and a Maxwellian of temperature T cools at
    dT/dt = −ζ T, ζ = (1 − α²) ν √T / d (ν at T = 1).

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1].

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` when it is not a number in [0, 1].
    """

    name: ClassVar[str] = "hard_spheres"
    time_name: ClassVar[str] = "t"
    dimensions: ClassVar[tuple[int, ...]] = (2, 3)
    #: The law of the collision direction n given g (:data:`DIRECTION_LAWS`).
    direction_law: ClassVar[str] = "hard"

    @staticmethod
    def sphere_factor(dimension: int) -> float:
        """β_d = ∫_{S^{d−1}} |ĝ·n| dn = 2π^{(d−1)/2}/Γ((d + 1)/2): 4 (d = 2), 2π (d = 3).

        Parameters
        ----------
        dimension : int
            d, 2 or 3.

        Returns
        -------
        float

        Raises
        ------
        InvalidArgumentError
            Naming ``dimension`` when it is not 2 or 3.
        """
        if dimension not in (2, 3):
            raise InvalidArgumentError("dimension", dimension, "2 or 3")
        return 4.0 if dimension == 2 else 2.0 * math.pi

    @property
    def homogeneity(self) -> float:
        """1: the rate β_d |v − w| is homogeneous of degree 1 in |v − w|."""
        return 1.0

    def rate(self, v, w, xp=np):
        """The total rate of a pair of d-vectors per unit t and density: the n-integral
        ∫ dn |g·n| = β_d |v − w| (d read from the last axis).

        Parameters
        ----------
        v, w : array
            Velocities, shape ``(..., d)``, d = 2 or 3 (arrays of ``xp``, broadcastable).
        xp : module, default numpy
            The array module.

        Returns
        -------
        array
            The rate of each pair, shape ``(...)``.

        Raises
        ------
        InvalidArgumentError
            Naming ``v`` when the last axis is not of length 2 or 3.
        """
        d = _sphere_dimension(v, w)
        g = v - w
        return self.sphere_factor(d) * xp.sqrt(_dot(g, g, d))

    def rate_bound(self, spread: float, dimension: int | None = None) -> float:
        """β_d · ``spread`` (β_3 = 2π, the larger, when ``dimension`` is not given).

        Parameters
        ----------
        spread : float
            The largest |v − w|, ≥ 0.
        dimension : int, optional
            d, 2 or 3.

        Returns
        -------
        float
        """
        return self.sphere_factor(3 if dimension is None else dimension) * float(spread)

    def post_collision(self, v, w, xp=np, *, direction=None):
        """v′ = v − p (g·n) n, w′ = w + p (g·n) n, p = (1 + α)/2, with δ = (g·n) p n computed
        once (the operations of :func:`particles.ulam_kinematics.collide_vectors`).

        Parameters
        ----------
        v, w : array
            Velocities, shape ``(..., d)``.
        xp : module, default numpy
            The array module.
        direction : array
            The unit vectors n, shape ``(..., d)``.

        Returns
        -------
        tuple of array
            ``(v′, w′)``.

        Raises
        ------
        InvalidArgumentError
            Naming ``direction`` when it is not given, or ``v`` for vectors not of d = 2, 3.
        """
        n = _direction(direction)
        d = _sphere_dimension(v, w)
        delta = (_dot(v - w, n, d) * self.p)[..., None] * n
        return v - delta, w + delta


#: γ of the variable-hard-sphere rate |g|^γ (0: the Maxwell model, 1: hard spheres' |g|).
VHS_EXPONENT = KernelParameter("exponent", 0.0, 1.0, 1.0,
                               "gamma of the rate |v - w|^gamma; 0: Maxwell molecules")


@register
@dataclass(frozen=True)
class VariableHardSpheres(Kernel):
    """Variable hard spheres in d = 2, 3, time t at density n: a pair collides at rate
    |v − w|^γ (γ ∈ [0, 1]) and scatters isotropically, v′ = (v + w)/2 + (1 − α)/4 g +
    (1 + α)/4 |g| σ, w′ = (v + w)/2 − (1 − α)/4 g − (1 + α)/4 |g| σ with σ uniform on the unit
    sphere (``direction_law = "isotropic"``).

    This is the n-form v′ = v − (1+α)/2 (g·n) n with σ = ĝ − 2(ĝ·n)n, so σ uniform means n of
    density ∝ |ĝ·n|^{d−2}: at γ = 0 it is the Maxwell model of :class:`particles.Ulam` with
    ``angular="hard"`` in d = 3 and ``angular="uniform"`` in d = 2, every particle colliding at
    rate 1, so τ = n t.  In d = 3 and γ = 1 it is :class:`HardSpheres` with t scaled by
    β_3 = 2π (hard spheres scatter isotropically in d = 3).

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1].
    exponent : float, optional
        γ ∈ [0, 1] (default 1).

    Raises
    ------
    InvalidArgumentError
        Naming ``restitution`` or ``exponent`` when it is out of its range.
    """

    name: ClassVar[str] = "variable_hard_spheres"
    time_name: ClassVar[str] = "t"
    dimensions: ClassVar[tuple[int, ...]] = (2, 3)
    parameters: ClassVar[tuple[KernelParameter, ...]] = (VHS_EXPONENT,)
    #: σ uniform on the sphere, independent of g (:data:`DIRECTION_LAWS`).
    direction_law: ClassVar[str] = "isotropic"

    exponent: float = 1.0

    @property
    def homogeneity(self) -> float:
        """γ: the rate |v − w|^γ is homogeneous of degree γ."""
        return self.exponent

    def rate(self, v, w, xp=np):
        """|v − w|^γ per unit t and density (1 for γ = 0; |v − w| itself for γ = 1).

        Parameters
        ----------
        v, w : array
            Velocities, shape ``(..., d)``, d = 2 or 3.
        xp : module, default numpy
            The array module.

        Returns
        -------
        array
            The rate of each pair, shape ``(...)``.

        Raises
        ------
        InvalidArgumentError
            Naming ``v`` when the last axis is not of length 2 or 3.
        """
        d = _sphere_dimension(v, w)
        g = v - w
        speed = xp.sqrt(_dot(g, g, d))
        if self.exponent == 0.0:
            return xp.ones_like(speed)
        return speed if self.exponent == 1.0 else speed**self.exponent

    def rate_bound(self, spread: float, dimension: int | None = None) -> float:
        """The spread to the power γ (the rate increases with |v − w|; the same in every d).

        Parameters
        ----------
        spread : float
            The largest |v − w|, ≥ 0.
        dimension : int, optional
            Unused.

        Returns
        -------
        float
        """
        if self.exponent == 0.0:
            return 1.0
        return float(spread) if self.exponent == 1.0 else float(spread) ** self.exponent

    def post_collision(self, v, w, xp=np, *, direction=None):
        """v′ = c + (1 − α)/4 g + (1 + α)/4 |g| σ, w′ = c − (same), c = (v + w)/2.

        Parameters
        ----------
        v, w : array
            Velocities, shape ``(..., d)``.
        xp : module, default numpy
            The array module.
        direction : array
            σ, unit vectors of shape ``(..., d)``.

        Returns
        -------
        tuple of array
            ``(v′, w′)``.

        Raises
        ------
        InvalidArgumentError
            Naming ``direction`` when it is not given, or ``v`` for vectors not of d = 2, 3.
        """
        sigma = _direction(direction)
        d = _sphere_dimension(v, w)
        g = v - w
        centre = (v + w) * 0.5
        half = g * ((1.0 - self.restitution) * 0.25) \
            + (xp.sqrt(_dot(g, g, d)) * ((1.0 + self.restitution) * 0.25))[..., None] * sigma
        return centre + half, centre - half
