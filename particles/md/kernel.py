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
    """Predicted collision time of the neighbour pair (i, j) (j = i + 1, or j = 0 at the seam)
    if i and j had the velocities ``vi`` and ``vj``: ``math.inf`` unless vi > vj.

    ``x`` and ``t_last`` are indexable stores (lists, dicts, arrays) of the lazily stored
    positions and their times; ``lr`` is the reduced ring length L_r.  Times in units of t.

    Parameters
    ----------
    x, t_last : indexable
        Stored positions and their times.
    i, j : int
        The pair.
    vi, vj : float
        Their velocities.
    lr : float
        The reduced ring length.

    Returns
    -------
    float
        The collision time, or ``math.inf``.
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
    """:func:`collision_time` of the pairs ``pairs`` (indices b of pairs (b, b + 1), the seam
    pair N − 1 is (N − 1, 0)) with their current velocities ``v``, as an array (inf where the
    pair is not approaching); ``pairs`` is not modified.

    Parameters
    ----------
    x, tl, v : numpy.ndarray
        Stored positions, their times and the velocities.
    pairs : numpy.ndarray
        Pair indices b.
    lr : float
        The reduced ring length.

    Returns
    -------
    numpy.ndarray
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
    """Velocities (v_i', v_j') of the pair after its collision, and whether it was elastic
    (``elastic_only``, i.e. r = 1, or Δ = v_i − v_j < δ): then an exact swap; otherwise the rule
    of :func:`particles.collision.collide_scalar` with p = (1 + r)/2 and the separation guard.

    Parameters
    ----------
    vi, vj : float
        The pair's velocities.
    p : float
        (1 + r)/2.
    delta : float
        δ.
    elastic_only : bool
        r = 1.

    Returns
    -------
    tuple
        (v_i', v_j', elastic).
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
    """:func:`collide` element-wise on arrays: (v_i', v_j', elastic mask).  The inputs are not
    modified (with ``elastic_only`` the outputs are the inputs, swapped).

    Parameters
    ----------
    vi, vj : numpy.ndarray
        The pairs' velocities (not changed).
    p, delta, elastic_only
        As for :func:`collide`.

    Returns
    -------
    tuple of numpy.ndarray
        (v_i', v_j', elastic mask).
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
