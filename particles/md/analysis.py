"""How much parallelism a window of the hard-rod MD holds: its causal depth and its clusters.

Analysis tools for the benchmarks (``benchmarks/md.py --causal-depth``, the bound quoted in
``benchmarks/README.md``, "How much parallelism there is"): :func:`causal_depth` replays a window
of the reference engine and counts the fewest rounds any exact parallel scheme needs;
:func:`cluster_anatomy` describes the clusters of a state.
"""

from __future__ import annotations

import numpy as np

from .engine import MDEngine, MDParams, MDState
from .kernel import collide

__all__ = ["causal_depth", "cluster_anatomy"]


def causal_depth(params: MDParams, state: MDState, until: float, block=None) -> dict:
    """How many collisions of [state.time, until] an *ideal* exact parallel scheme runs at once.

    The reference runs the window with ``record=True``; its collisions are then replayed in
    order.  A collision's time and outcome depend on the states of its two particles, i.e. on
    their previous collisions, so every exact scheme must run it in a later round than those:
    its *level* is 1 + the larger level of its two particles' previous collisions, and the
    largest level (the depth) is the fewest rounds any exact scheme needs, even one that knew the
    whole future.  collisions / depth bounds the average number of collisions per vectorised
    pass from above (the light-cone scheme's own count is ``--critical-path``).

    The same replay with elastic exchanges as *ghosts* (identical particles swapping velocities
    are velocity carriers passing through each other): an inelastic collision depends only on
    the previous inelastic collisions of its two carriers; ``ghost_depth`` is the depth of that
    dependency graph (elastic exchanges cost no round).  The replay recomputes the velocities
    with the kernel's formulas and checks them against the reference's end state.

    ``block`` (optional, an int per particle, −1 for none) marks groups of particles, e.g. the
    soft blocks of :func:`cluster_anatomy`; ``in_blocks`` counts the collisions of two particles
    of one group, and ``in_blocks_elastic`` those of them that were elastic.

    Parameters
    ----------
    params : particles.MDParams
        The run's parameters.
    state : particles.MDState
        The state at the start of the window.
    until : float
        The physical time at the end of the window.
    block : numpy.ndarray or None, optional
        An int group label per particle (−1 for none), e.g. the second value returned by
        :func:`cluster_anatomy`; None (default) puts no particle in a group.

    Returns
    -------
    dict
        ``collisions``, ``depth``, ``per_round`` (collisions / depth), ``inelastic``,
        ``ghost_depth``, ``ghost_per_round`` (inelastic / ghost_depth), ``in_blocks``,
        ``in_blocks_elastic`` and ``replay_matches_reference`` (bool).
    """
    engine = MDEngine(params, "reference", record=True)
    end = engine.advance(state, until)
    n, p, delta = params.n, params.p, params.delta
    elastic_only = params.restitution == 1.0
    v = state.velocities.tolist()
    level = [0] * n  # level of each particle's last collision
    carrier = list(range(n))  # which velocity carrier each particle holds
    ghost_level = [0] * n  # level of each carrier's last inelastic collision
    group = [-1] * n if block is None else block.tolist()
    depth = ghost_depth = inelastic = in_blocks = in_blocks_elastic = 0
    for _, b in engine.record:
        i, j = b, (b + 1 if b < n - 1 else 0)
        lv = max(level[i], level[j]) + 1
        level[i] = level[j] = lv
        depth = max(depth, lv)
        inside = group[i] >= 0 and group[i] == group[j]
        in_blocks += inside
        v[i], v[j], elastic = collide(v[i], v[j], p, delta, elastic_only)
        if elastic:
            in_blocks_elastic += inside
            carrier[i], carrier[j] = carrier[j], carrier[i]
            continue
        inelastic += 1
        ci, cj = carrier[i], carrier[j]
        gl = max(ghost_level[ci], ghost_level[cj]) + 1
        ghost_level[ci] = ghost_level[cj] = gl
        ghost_depth = max(ghost_depth, gl)
    count = len(engine.record)
    return {
        "collisions": count,
        "depth": depth,
        "per_round": count / max(depth, 1),
        "inelastic": inelastic,
        "ghost_depth": ghost_depth,
        "ghost_per_round": inelastic / max(ghost_depth, 1),
        "in_blocks": in_blocks,
        "in_blocks_elastic": in_blocks_elastic,
        "replay_matches_reference": bool(np.array_equal(np.array(v), end.velocities)),
    }


def cluster_anatomy(params: MDParams, state: MDState) -> tuple[dict, np.ndarray]:
    """Clusters at the state's time: runs of particles with gaps below δ (``cluster_sizes``, the
    five largest) and, in label order from particle 0, maximal runs of neighbours whose velocities
    span less than δ (``soft_blocks``, the five largest, and the particles in runs of ≥ 5).  Every
    collision inside such a run is an elastic exchange, whatever the order.  Also returns the
    run of ≥ 5 each particle belongs to (−1 for none), for :func:`causal_depth`.

    Parameters
    ----------
    params : particles.MDParams
        The run's parameters (N, δ, reduced ring length).
    state : particles.MDState
        The state to analyse.

    Returns
    -------
    tuple of (dict, numpy.ndarray)
        The dict has ``cluster_sizes`` and ``soft_blocks`` (lists of the five largest sizes)
        and ``particles_in_soft_blocks_of_5_or_more`` (int); the array of shape ``(N,)`` gives
        each particle's run of ≥ 5 (−1 for none).
    """
    x = state.positions_at()
    v = state.velocities
    gaps = np.diff(np.append(x, x[0] + params.reduced_length))
    cuts = np.flatnonzero(gaps >= params.delta)
    sizes = np.diff(np.append(cuts, cuts[0] + params.n)) if cuts.size else np.array([params.n])
    soft, i = [], 0
    block = np.full(params.n, -1)
    while i < params.n:
        lo = hi = v[i]
        j = i + 1
        while j < params.n and max(hi, v[j]) - min(lo, v[j]) < params.delta:
            lo, hi = min(lo, v[j]), max(hi, v[j])
            j += 1
        if j - i >= 5:
            block[i:j] = len(soft)
        soft.append(j - i)
        i = j
    soft = np.array(soft)
    return {
        "cluster_sizes": np.sort(sizes)[::-1][:5].tolist(),
        "soft_blocks": np.sort(soft)[::-1][:5].tolist(),
        "particles_in_soft_blocks_of_5_or_more": int(soft[soft >= 5].sum()),
    }, block
