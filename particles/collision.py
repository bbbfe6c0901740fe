"""The collision rule of every particle model, in one place.

A colliding pair (a, b) with Δ = v_a − v_b becomes

    v_a' = v_a − p Δ,    v_b' = v_b + p Δ,    p = (1 + r) / 2,

r ∈ [0, 1] the restitution coefficient.  Momentum is conserved exactly in exact arithmetic; the
pair loses (1 − r²) Δ²/4 of kinetic energy ½(v_a² + v_b²).  The floating-point operations are
always, in this order: ``d = (v_a - v_b) * p``, ``v_a - d``, ``v_b + d``; the vectorized engines
and their sequential references use the same operations, so they agree bit for bit.
"""

from __future__ import annotations

import numpy as np

from .validation import check_restitution

__all__ = ["transfer_fraction", "collide_scalar", "collide_arrays"]


def transfer_fraction(restitution) -> float:
    """p = (1 + r)/2 ∈ [1/2, 1] for r ∈ [0, 1] (the inverse of the paper's β).

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1].

    Returns
    -------
    float
        p.
    """
    return 0.5 * (1.0 + check_restitution(restitution))


def collide_scalar(va: float, vb: float, p: float) -> tuple[float, float]:
    """One collision on Python floats (the sequential references use this).

    v_a' = v_a − pΔ, v_b' = v_b + pΔ with Δ = v_a − v_b.

    Parameters
    ----------
    va, vb : float
        The two velocities.
    p : float
        (1 + r)/2.

    Returns
    -------
    tuple of float
        The new velocities.
    """
    d = (va - vb) * p
    return va - d, vb + d


def collide_arrays(va: np.ndarray, vb: np.ndarray, p: float) -> None:
    """Collide ``va[k]`` with ``vb[k]`` for every k, in place (element-wise the same operations
    as :func:`collide_scalar`).

    Parameters
    ----------
    va, vb : numpy.ndarray
        The velocities, changed in place.
    p : float
        (1 + r)/2.
    """
    d = va - vb
    d *= p
    va -= d
    vb += d
