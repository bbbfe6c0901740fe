"""The sequential reference of the hard-rod MD: a binary heap over the N pair predictions.

``method="reference"``: a plain sequential loop, a binary heap (``heapq``) over the N pair
predictions with lazy invalidation, ties broken by the pair index.  Pure Python floats (IEEE
double): the operations of :mod:`particles.md.kernel`, in the same order as the light-cone engine,
so in non-chaotic settings the two agree bit for bit (tested).
"""

from __future__ import annotations

import heapq

import numpy as np

from .kernel import collide, collision_time
from .state import MDState

__all__ = ["advance_reference"]


def advance_reference(engine, state: MDState, until: float):
    """Every collision of ``state`` up to ``until`` in (time, pair) order; returns the arrays
    (positions, t_last, velocities) and the collision count of the state at ``until``.

    This is the sequential reference engine: one heap of predicted collision times, one collision
    at a time, with the kernel's formulas (:mod:`particles.md.kernel`).  It is normally called
    through ``MDEngine.advance`` with ``method="reference"``.

    Parameters
    ----------
    engine : particles.MDEngine
        The engine: its ``params``, its inelastic-collapse watch and its ``record`` list.
    state : particles.MDState
        The state to advance (not modified).
    until : float
        The physical time to advance to.

    Returns
    -------
    tuple
        ``(positions, t_last, velocities, collisions)``: three float arrays of shape ``(N,)``
        and the total collision count (int).
    """
    params = engine.params
    n = params.n
    lr = params.reduced_length
    p = params.p
    delta = params.delta
    elastic_only = params.restitution == 1.0
    x = state.positions.tolist()
    tl = state.t_last.tolist()
    v = state.velocities.tolist()
    count = int(state.collisions)
    last = n - 1
    streak = [0] * n
    dt_tiny, limit, detail = engine.collapse_watch()
    record = engine.record

    ctime = [collision_time(x, tl, b, v[b], b + 1, v[b + 1], lr) for b in range(last)]
    ctime.append(collision_time(x, tl, last, v[last], 0, v[0], lr))
    version = [0] * n
    heap = [(c, b, 0) for b, c in enumerate(ctime) if c <= until]
    heapq.heapify(heap)
    while heap:
        c, b, ver = heapq.heappop(heap)
        if ver != version[b]:
            continue
        i = b
        j = b + 1 if b < n - 1 else 0
        # collapse watch: time advance of each particle since its previous collision
        for k in (i, j):
            if c - tl[k] <= dt_tiny:
                streak[k] += 1
            else:
                streak[k] = 0
        if streak[i] >= limit or streak[j] >= limit:
            involved = [k for k in range(n) if streak[k] > 0]
            engine.raise_collapse(c, involved, count, detail)
        vi = v[i]
        vj = v[j]
        xc = x[i] + vi * (c - tl[i])
        x[i] = xc
        x[j] = xc - lr if j == 0 else xc
        tl[i] = c
        tl[j] = c
        v[i], v[j], _ = collide(vi, vj, p, delta, elastic_only)
        count += 1
        if record is not None:
            record.append((c, b))
        for bb in (b - 1 if b > 0 else n - 1, b, b + 1 if b < n - 1 else 0):
            k = bb + 1 if bb < last else 0
            cc = collision_time(x, tl, bb, v[bb], k, v[k], lr)
            if cc != ctime[bb] or bb == b:
                version[bb] += 1
                ctime[bb] = cc
                if cc <= until:
                    heapq.heappush(heap, (cc, bb, version[bb]))
    return np.array(x), np.array(tl), np.array(v), count
