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
    """The fraction p = (1 + r)/2 of the relative velocity that a collision transfers.

    p ∈ [1/2, 1] for r ∈ [0, 1]: p = 1 exchanges the velocities (elastic), p = 1/2 leaves both
    particles at their mean velocity (sticky).  p is the inverse of the paper's β.

    Parameters
    ----------
    restitution : float
        The restitution coefficient r ∈ [0, 1].

    Returns
    -------
    float
        p = (1 + r)/2.

    Raises
    ------
    particles.InvalidArgumentError
        From :func:`particles.validation.check_restitution`, if ``restitution`` is not a finite
        number in [0, 1].
    """
    return 0.5 * (1.0 + check_restitution(restitution))


def collide_scalar(va: float, vb: float, p: float) -> tuple[float, float]:
    """One collision on Python floats (the sequential references use this).

    Computes ``d = (va - vb) * p`` and returns ``(va - d, vb + d)``, the operations and their order
    shared by every engine (see the module docstring).

    Parameters
    ----------
    va, vb : float
        Velocities of the two colliding particles before the collision.
    p : float
        The transfer fraction (1 + r)/2 (:func:`transfer_fraction`).

    Returns
    -------
    tuple of float
        ``(va', vb')``, the velocities after the collision.
    """
    d = (va - vb) * p
    return va - d, vb + d


def collide_arrays(va: np.ndarray, vb: np.ndarray, p: float) -> None:
    """Collide ``va[k]`` with ``vb[k]`` for every k, in place.

    Element-wise the same floating-point operations as :func:`collide_scalar`, so that a vectorized
    engine and its sequential reference agree bit for bit.  The pairs must be disjoint: the arrays
    are the gathered velocities of distinct particles.

    Parameters
    ----------
    va, vb : numpy.ndarray
        Float arrays of the same shape, the velocities of the first and second particle of each
        pair; both are overwritten with the velocities after the collision.
    p : float
        The transfer fraction (1 + r)/2 (:func:`transfer_fraction`).
    """
    d = va - vb
    d *= p
    va -= d
    vb += d
