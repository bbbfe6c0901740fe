"""The two formulas of the hard-rod MD, each written once: the pair's predicted collision time
and the collision with its separation guard, in a scalar and an array form.

Both engines (:mod:`particles.md.reference`, :mod:`particles.md.lightcone`) use these functions;
where a hot scalar loop writes one out by hand for speed (the scalar heap loop and the zero-gap
burst of the light-cone engine, which would pay a Python call on every collision), the copy sits
between ``# kernel copy: NAME (begin)`` and ``(end)`` comments, and
``tests/test_particles/test_md_kernel.py`` executes the very lines of each copy against the
kernel on many random and edge-case inputs, bit for bit.  The array forms give element-wise the
bits of the scalar forms (tested likewise).

Prediction.  Pair (i, j), j = i + 1 or j = 0 at the seam (the partner seen at x_0 + L_r), stored
lazily (position x at the particle's own last-update time t_last): both are moved to the later of
their two t_last, tt, the gap g = x_j − x_i is taken, and the pair collides at tt + g / (v_i − v_j)
if it approaches (v_i > v_j), never otherwise.  A gap that round-off made negative is treated as
zero (the pair collides at once).

Collision.  Δ = v_i − v_j; an elastic collision (r = 1 or Δ < δ) swaps the two velocities
exactly; otherwise the rule of :mod:`particles.collision` (``collide_scalar`` /
``collide_arrays``: d = Δ p, v_i − d, v_j + d) followed by the separation guard: after an
inelastic collision the pair must separate, so the two new velocities are clipped to the old
interval [v_j, v_i] and swapped if round-off left them approaching.  The clip is
``min(max(a, v_j), v_i)`` with Python's semantics in both forms: a is kept unless the other
operand is strictly beyond it (NumPy's ``np.maximum`` returns its second operand on a tie, so
that -0.0 and 0.0 would come out differently).
"""

from __future__ import annotations

import math

import numpy as np

from ..collision import collide_arrays, collide_scalar

__all__ = ["collision_time", "collision_times", "collide", "collide_many"]


def collision_time(x, t_last, i: int, vi: float, j: int, vj: float, lr: float) -> float:
    """Predicted collision time of the neighbour pair (i, j) with velocities ``vi`` and ``vj``.

    Both rods are moved to the later of their two last-update times, tt, and the pair collides at
    tt + g / (vi − vj) if it approaches (vi > vj); a gap g made negative by round-off counts as
    zero.  At the seam (j = 0) the partner is seen at x_0 + L_r.

    Parameters
    ----------
    x, t_last : sequence of float
        Indexable stores (lists, dicts, arrays) of the lazily stored positions and the times
        at which they were stored.
    i : int
        Index of the left rod.
    vi : float
        Velocity of rod i.
    j : int
        Index of the right rod: i + 1, or 0 at the seam.
    vj : float
        Velocity of rod j.
    lr : float
        The reduced ring length L_r (ring length minus N times the rod length).

    Returns
    -------
    float
        The collision time, in units of physical time t; ``math.inf`` unless vi > vj.
    """
    if not vi > vj:
        return math.inf
    ti = t_last[i]
    tj = t_last[j]
    tt = ti if ti > tj else tj
    xi = x[i] + vi * (tt - ti)
    xj = x[j] + vj * (tt - tj)
    if j == 0:
        xj = xj + lr
    g = xj - xi
    if g < 0.0:
        g = 0.0
    return tt + g / (vi - vj)


def collision_times(x, tl, v, pairs, lr):
    """:func:`collision_time` of many pairs at once, with the rods' current velocities.

    Element-wise the same bits as the scalar form.

    Parameters
    ----------
    x, tl : numpy.ndarray
        Lazily stored positions of the N rods and the times at which they were stored.
    v : numpy.ndarray
        Current velocities of the N rods.
    pairs : numpy.ndarray
        Integer indices b of the pairs (b, b + 1); the seam pair N − 1 is (N − 1, 0).  Not
        modified.
    lr : float
        The reduced ring length L_r.

    Returns
    -------
    numpy.ndarray
        Float array of the shape of ``pairs``: the collision times (inf where the pair is not
        approaching).
    """
    n = x.shape[0]
    i = pairs
    j = pairs + 1
    seam = j == n
    j[seam] = 0
    vi = v[i]
    vj = v[j]
    ti = tl[i]
    tj = tl[j]
    app = vi > vj
    tt = np.maximum(ti, tj)
    xi = x[i] + vi * (tt - ti)
    xj = x[j] + vj * (tt - tj)
    if seam.any():
        xj[seam] = xj[seam] + lr
    g = xj - xi
    np.maximum(g, 0.0, out=g)
    dv = np.where(app, vi - vj, 1.0)
    c = tt + g / dv
    c[~app] = np.inf
    return c


def collide(vi: float, vj: float, p: float, delta: float, elastic_only: bool):
    """Velocities of a pair after its collision, with the separation guard.

    An elastic collision (``elastic_only``, i.e. r = 1, or Δ = vi − vj < δ) swaps the two
    velocities exactly; otherwise the rule of :func:`particles.collision.collide_scalar` is
    applied, the new velocities are clipped to [vj, vi] and swapped if round-off left them
    approaching.

    Parameters
    ----------
    vi, vj : float
        Velocities of the left and right rod before the collision.
    p : float
        The transfer fraction (1 + r)/2.
    delta : float
        The threshold δ ≥ 0: a collision with relative velocity below δ is elastic.
    elastic_only : bool
        True when r = 1 (every collision is a swap).

    Returns
    -------
    tuple of (float, float, bool)
        ``(vi', vj', elastic)``.
    """
    d = vi - vj
    if elastic_only or d < delta:
        return vj, vi, True
    a, e = collide_scalar(vi, vj, p)
    a = min(max(a, vj), vi)
    e = min(max(e, vj), vi)
    if a > e:
        a, e = e, a
    return a, e, False


def collide_many(vi: np.ndarray, vj: np.ndarray, p: float, delta: float, elastic_only: bool):
    """:func:`collide` element-wise on arrays, with the same bits.

    The inputs are not modified (with ``elastic_only`` the outputs are the inputs, swapped).

    Parameters
    ----------
    vi, vj : numpy.ndarray
        Velocities of the left and right rods of the pairs, same shape.
    p : float
        The transfer fraction (1 + r)/2.
    delta : float
        The threshold δ ≥ 0 below which a collision is elastic.
    elastic_only : bool
        True when r = 1.

    Returns
    -------
    tuple of numpy.ndarray
        ``(vi', vj', elastic)``: the new velocities and a boolean mask of the elastic
        collisions, each of the shape of ``vi``.
    """
    if elastic_only:
        return vj, vi, np.ones(vi.shape, dtype=bool)
    d = vi - vj
    a = vi.copy()
    e = vj.copy()
    collide_arrays(a, e, p)  # the rule of particles.collision, in place
    # min(max(a, vj), vi) as Python computes it: a is kept unless vj (then vi) is strictly
    # beyond it (np.maximum / np.minimum return the second operand on a tie, which differs
    # from Python's min and max on signed zeros)
    for w in (a, e):
        np.copyto(w, vj, where=vj > w)
        np.copyto(w, vi, where=vi < w)
    flip = a > e
    if flip.any():
        a, e = np.where(flip, e, a), np.where(flip, a, e)
    el = d < delta
    if el.any():
        a = np.where(el, vj, a)
        e = np.where(el, vi, e)
    return a, e, el
