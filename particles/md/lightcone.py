"""The fast path of the hard-rod MD: the light-cone scheme (``method="fast"``).

Velocities stay in [v_min, v_max] forever (collisions make convex combinations), so a pending
collision at (c_a, X_a) cannot influence anything outside the cone X_a + [v_min, v_max] (t − c_a).
A prediction (c_b, X_b) is *safe* when it is earlier than both neighbouring pairs' predictions and
no other pending collision's cone reaches it: v_max c_b − X_b < min_{a<b} (v_max c_a − X_a)
and X_b − v_min c_b < min_{a>b} (X_a − v_min c_a), prefix and suffix minima by
``np.minimum.accumulate`` (the ring enters as one extra lap, + L_r). All safe collisions are
processed in one NumPy pass. The globally earliest collision is always safe, so the scheme never
stalls; so is the earliest, in (time, index) order, of a *tie group* (candidates within a few cone
margins of each other, e.g. a cluster with zero gaps) that no candidate outside the group reaches,
so isolated clusters each fire one collision per pass. Only collisions earlier than a moving
horizon H are candidates; a later collision (c_a > H ≥ c_b) cannot reach an earlier one, so
leaving it out is exact, and it keeps a pass at O(candidates) instead of O(N). When a pass fires
only a handful of collisions (a clustered gas, where a few hot clusters carry long causal chains)
the rest of the slab runs in the scalar heap loop on the same data, which is exact as well: it is
the reference restricted to the events before H (a pass costs about as much as 100 scalar
collisions). In a clustered gas nearly all collisions run there, and most of them in *zero-gap
bursts*: a cluster collapses to one floating-point point, and every collision that reaches it
triggers a cascade of collisions at one time and place.  The scalar loop runs such a cascade as a
sort of the block's velocities (``_burst``: the heap's order, without the heap).  See
``benchmarks/README.md`` for the measured costs.

Floating-point traps of the scheme (those of a single pair are handled in
:mod:`particles.md.kernel`):

* simultaneous collisions: the sequential heap orders ties by pair index, the fast scheme lets a
  pair fire only if it precedes both neighbours in (time, index) order, and within a tie group
  only the group's earliest in that order;
* the cone tests carry a relative round-off margin (``_CONE_MARGIN``); erring on "unsafe" costs
  only parallelism.
"""

from __future__ import annotations

import heapq
import math
import time as _time
from bisect import bisect_right
from itertools import accumulate

import numpy as np

from .kernel import collide_many, collision_time, collision_times
from .state import MDState

__all__ = ["advance_fast"]

# Relative round-off margin of the light-cone tests (in units of the largest key magnitude).
_CONE_MARGIN = 64 * np.finfo(float).eps
# Candidates closer than this many cone margins form one tie group (see ``advance_fast``).
_GROUP_GAP = 1024.0
# Cost model of the fast path's choice between a vectorised pass and the scalar loop, in units of
# one plain scalar collision (~1.7 µs): the cost of a pass per candidate (fitted: 0.1-0.6 µs,
# about 0.25 µs, i.e. 0.15 units) and of a collision in a zero-gap burst (0.15-0.5 µs with its
# share of the burst's fixed cost, taken as 0.15 units); the fixed cost of a pass (~80 µs,
# about 47 units) is the engine's ``sequential_below`` (default 64).  See benchmarks/README.md.
_PASS_PER_CANDIDATE = 0.15
_BURST_COST = 0.15
# The scalar fallback works on lazy dict views of the arrays, and on lists of the whole state
# from N / _FULL_COPY_RATIO collisions on (or at once with more than that many candidates).
_FULL_COPY_RATIO = 4


class _Lazy(dict):
    """A dict view of a NumPy array that copies an entry to a Python scalar on first use."""

    __slots__ = ("array",)

    def __init__(self, array):
        super().__init__()
        self.array = array

    def __missing__(self, k):
        value = self.array[k].item()
        self[k] = value
        return value

    def write_back(self):
        if self:
            idx = np.fromiter(self.keys(), dtype=np.int64, count=len(self))
            self.array[idx] = np.fromiter(self.values(), dtype=self.array.dtype, count=len(self))


def _sequential_slab(engine, x, tl, v, c, streak, cand, horizon, count):
    """Process, in time order, every collision up to ``horizon`` starting from the candidate
    pairs ``cand`` (all pairs with c ≤ horizon), with scalar Python floats: the reference loop.

    The loop starts on lazy dict views of the arrays (only the particles touched are loaded:
    cheap for the sparse tail of a slab, a few collisions) and switches to plain lists of the
    whole state once it has processed N / ``_FULL_COPY_RATIO`` collisions (a hot cluster's long
    chain, where list access is about twice as fast and pays for the copy).  Either way the
    results are written back to the arrays.  Returns the number of collisions processed.
    """
    params = engine.params
    n = params.n
    lr = params.reduced_length
    p = params.p
    delta = params.delta
    elastic_only = params.restitution == 1.0
    dt_tiny, limit, detail = engine.collapse_watch()
    record = engine.record
    inf = math.inf
    full = cand.size * _FULL_COPY_RATIO >= n
    if full:
        X, TL, V, ST, C = x.tolist(), tl.tolist(), v.tolist(), streak.tolist(), c.tolist()
        switch_at = -1
    else:
        X, TL, V, ST, C = _Lazy(x), _Lazy(tl), _Lazy(v), _Lazy(streak), _Lazy(c)
        switch_at = n // _FULL_COPY_RATIO

    # Heap entries (time, pair); an entry is live while C[pair] still equals its time (a pair
    # re-predicted to the very same time keeps one live entry: equal keys are processed once,
    # after which C[pair] = inf).  Ties pop in pair order, as in the reference.
    heap = [(C[b], b) for b in cand.tolist()]
    heapq.heapify(heap)
    ctx = (n - 1, lr, p, delta, elastic_only, dt_tiny, limit, record, horizon)  # for _burst
    pop = heapq.heappop
    push = heapq.heappush
    last = n - 1
    done = 0
    elastic = 0
    while heap:
        if 0 <= switch_at <= done:
            for store in (X, TL, V, ST, C):
                store.write_back()
            X, TL, V, ST, C = x.tolist(), tl.tolist(), v.tolist(), streak.tolist(), c.tolist()
            full = True
            switch_at = -1
        cb, b = pop(heap)
        if cb != C[b]:
            continue
        i = b
        j = b + 1 if b < last else 0
        ti = TL[i]
        tj = TL[j]
        if ti == cb and j != 0:
            # a zero-gap burst: particle i already collided at this very time and place
            burst = _burst(ctx, X, TL, V, ST, C, heap, b, cb, False)
            if burst is not None:
                done += burst[0]
                elastic += burst[1]
                engine.stats["burst"] += burst[0]
                continue
        si = ST[i] + 1 if cb - ti <= dt_tiny else 0
        sj = ST[j] + 1 if cb - tj <= dt_tiny else 0
        ST[i] = si
        ST[j] = sj
        if si >= limit or sj >= limit:
            involved = [k for k in (range(n) if full else ST.keys()) if ST[k] > 0]
            engine.raise_collapse(cb, involved, count + done, detail)
        vi = V[i]
        vj = V[j]
        xc = X[i] + vi * (cb - ti)
        X[i] = xc
        X[j] = xc - lr if j == 0 else xc
        TL[i] = cb
        TL[j] = cb
        # kernel.collide, written out for speed (a call would be paid on every collision)
        # kernel copy: collide (begin)
        d = vi - vj
        if elastic_only or d < delta:
            V[i] = vj
            V[j] = vi
            elastic += 1
            vi, vj = vj, vi
        else:
            pd = p * d
            a = vi - pd
            e = vj + pd
            a = min(max(a, vj), vi)
            e = min(max(e, vj), vi)
            if a > e:
                a, e = e, a
            V[i] = a
            V[j] = e
            vi = a
            vj = e
        # kernel copy: collide (end)
        done += 1
        if record is not None:
            record.append((cb, b))
        C[b] = inf  # the pair separates (v_i' <= v_j'); its popped entry was the live one
        # New predictions of the two neighbouring pairs: kernel.collision_time written out for
        # speed, with the fresh data of i and j (X[i] = xc, TL[i] = TL[j] = cb).
        bb = b - 1 if b > 0 else last  # left pair (h, i), h = bb
        # kernel copy: collision_time, left pair (h, i) with h = bb (begin)
        vh = V[bb]
        if vh > vi:
            th = TL[bb]
            tt = th if th > cb else cb
            xh = X[bb] + vh * (tt - th)
            xi = xc + vi * (tt - cb)
            if i == 0:
                xi = xi + lr
            g = xi - xh
            if g < 0.0:
                g = 0.0
            cl = tt + g / (vh - vi)
        else:
            cl = inf
        # kernel copy: collision_time, left pair (h, i) with h = bb (end)
        k = j + 1 if j < last else 0  # right pair (j, k), index j
        # kernel copy: collision_time, right pair (j, k) (begin)
        vk = V[k]
        if vj > vk:
            tk = TL[k]
            tt = tk if tk > cb else cb
            xj = X[j] + vj * (tt - cb)
            xk = X[k] + vk * (tt - tk)
            if k == 0:
                xk = xk + lr
            g = xk - xj
            if g < 0.0:
                g = 0.0
            cr = tt + g / (vj - vk)
        else:
            cr = inf
        # kernel copy: collision_time, right pair (j, k) (end)
        if (cl == cb or cr == cb) and j != 0:
            # a neighbouring pair is due at this very time: a burst may follow
            burst = _burst(ctx, X, TL, V, ST, C, heap, b, cb, True)
            done += burst[0]
            elastic += burst[1]
            engine.stats["burst"] += burst[0]
            continue
        if cl != C[bb]:
            C[bb] = cl
            if cl <= horizon:
                push(heap, (cl, bb))
        if cr != C[j]:
            C[j] = cr
            if cr <= horizon:
                push(heap, (cr, j))
    if full:
        x[:] = X
        tl[:] = TL
        v[:] = V
        streak[:] = ST
        c[:] = C
    else:
        for store in (X, TL, V, ST, C):
            store.write_back()
    engine.stats["elastic"] += elastic
    return done


def _burst(ctx, X, TL, V, ST, C, heap, b, t, fired):
    """All collisions at time ``t`` of the *block* that grows from pair ``b`` = (i, i + 1):
    consecutive particles that sit at exactly the same point at time t and have collided
    there.  Either i has collided at t already and pair b was just popped (``fired`` False), or
    the caller has just processed pair b's collision and found a neighbouring pair due at t
    (``fired`` True).  The collisions are processed in the heap loop's (time, pair) order on a
    local list of velocities, and the state and the heap are left as the heap loop would leave
    them.  ``ctx`` holds the slab's constants.  Returns (collisions, elastic ones), or None if
    it processed none and the caller still has to process pair b.

    Exactness.  For two particles at the same point, both last updated at t, the prediction
    formula gives c = t if v_i > v_j and inf otherwise, so inside the block the pending pairs at
    time t are exactly the inversions v_k > v_{k+1}.  Pair b was the smallest pending (t, pair),
    so no pair left of it is pending.  Firing the smallest pending pair k leaves none left of
    k − 1, so the next smallest is k − 1 if it became an inversion, and otherwise the first
    pending pair right of k: a gnome sort, which visits the collisions in the heap's order.  An
    elastic collision at k starts a run that the gnome would do one swap at a time: v_{k+1}
    moves left past every larger velocity of the sorted w[0..k] (each difference is at most the
    first one, so each swap is elastic too); it is done by one bisection and a slice move.
    At the ends of the block, a neighbour at the same point, last updated at t, joins without a
    collision; otherwise the boundary pair is predicted by the heap loop's formula, and if it
    is due at t it is the next pending pair when the sort reaches that end (the heap would pop
    it then too): its collision moves both particles to the left one's point, so the newcomer
    joins if that is the block's point (always on the right; on the left the burst hands back
    to the heap loop if not).  Positions and t_last of block particles do not change.
    Collisions elsewhere at time t involve other particles and commute with the block.

    The collapse watch: each burst collision is one without time advance for both particles
    (a newcomer's first one is judged by its own time advance), so a particle's streak grows by
    the number of collisions of its two pairs, counted as a difference array ``dh`` and added
    by :func:`_burst_flush`.  No streak can reach the limit while (largest streak in the block)
    + (collisions so far) stays below it; there the burst hands back to the heap loop, which
    checks every collision.
    """
    last, lr, p, delta, elastic_only, dt_tiny, limit, record, horizon = ctx
    xb = X[b]
    lo = hi = b  # the block is particles lo .. hi, w[q] the velocity of lo + q
    w = [V[b]]
    s = [ST[b]]  # streaks at entry (or at joining)
    dh = [0]  # collisions of local pair q = (lo + q, lo + q + 1): dh[0] + ... + dh[q]
    k = m = 0  # m: local pairs 0 .. m - 1
    done = 0
    elastic = 0
    tb = C[b]
    C[b] = math.inf  # its heap entry was just popped
    if fired:  # the caller has processed the collision of pair b: go on after it
        hi = b + 1
        w.append(V[hi])
        s.append(ST[hi])
        dh.append(0)
        m = 1
    budget = limit - 1 - max(s)  # collisions that certainly leave every streak below the limit

    look_left = fired  # after a collision of the block's first pair
    while True:
        if look_left:  # the block's first velocity changed: the pair on its left
            look_left = False
            h = lo - 1 if lo > 0 else last
            if h == hi:
                break
            if lo > 0 and TL[h] == t and X[h] == xb:
                sh = ST[h]  # at the block's point already: it joins without a collision
                join = False
            elif not collision_time(X, TL, h, V[h], lo, w[0], lr) <= t:
                k = 1
                continue
            else:
                # the left boundary pair is due now, so it is the next pending pair; its
                # collision moves both particles to h's position: h joins if that is the
                # block's point
                if lo == 0:
                    break
                th = TL[h]
                if X[h] + V[h] * (t - th) != xb:
                    break
                sh = ST[h] if t - th <= dt_tiny else -1
                join = True
            if limit - 1 - sh < budget:
                budget = limit - 1 - sh
            if join:
                if done >= budget:
                    break
                X[h] = xb
                TL[h] = t
            w.insert(0, V[h])
            s.insert(0, sh)
            dh.insert(0, 0)
            lo = h
            m += 1
            # next: the new first pair if it is due (a newcomer's always is), else past the
            # pair just fired
            k = 0 if join or w[0] > w[1] else 2
            continue
        if k == m:  # at the right end: extend, join or stop
            r = hi + 1 if hi < last else 0
            if r == 0 or r == lo:
                break  # the seam (or the whole ring): the heap loop takes over if it is due
            if TL[r] == t and X[r] == xb:
                sr = ST[r]
                join = False
            elif collision_time(X, TL, hi, w[m], r, V[r], lr) <= t:
                # the boundary pair is due now: its collision brings r to the block's point
                sr = ST[r] if t - TL[r] <= dt_tiny else -1
                join = True
            else:
                break
            if limit - 1 - sr < budget:
                budget = limit - 1 - sr
            if done >= budget:
                break
            if join:
                X[r] = xb
                TL[r] = t
            w.append(V[r])
            s.append(sr)
            dh.append(0)
            hi = r
            m += 1
            continue
        vi = w[k]
        vj = w[k + 1]
        if not vi > vj:
            k += 1
            continue
        if done >= budget:
            break
        d = vi - vj
        if elastic_only or d < delta:
            # An elastic run: vj moves left past every larger velocity of the sorted w[0..k],
            # one swap each (the gnome's next collisions, pairs k, k - 1, ..., stop, done at
            # once).  Each is elastic: w[q] - vj <= vi - vj = d < delta (IEEE subtraction is
            # monotone).
            stop = bisect_right(w, vj, 0, k)
            if done + k + 1 - stop > budget:
                # only as many as the streak budget allows: vj stops short (pair stop - 1 stays
                # an inversion) and the next check hands back to the heap loop
                stop = k + 1 - (budget - done)
            run = k + 1 - stop
            w[stop + 1 : k + 2] = w[stop : k + 1]
            w[stop] = vj
            dh[stop] += 1
            dh[k + 1] -= 1
            done += run
            elastic += run
            if record is not None:
                record.extend([(t, lo + q) for q in range(k, stop - 1, -1)])
            if done >= budget:
                break
            if stop:
                k += 1  # pairs stop .. k are sorted now
            else:
                look_left = True
            continue
        # inelastic: kernel.collide written out (min(max(a, vj), vi) as two comparisons, which
        # keep a unless the other operand is strictly beyond it, as min and max do)
        # kernel copy: collide, inelastic branch (begin)
        pd = p * d
        a = vi - pd
        e = vj + pd
        if vj > a:
            a = vj
        if vi < a:
            a = vi
        if vj > e:
            e = vj
        if vi < e:
            e = vi
        if a > e:
            a, e = e, a
        # kernel copy: collide, inelastic branch (end)
        w[k] = a
        w[k + 1] = e
        dh[k] += 1
        dh[k + 1] -= 1
        done += 1
        if record is not None:
            record.append((t, lo + k))
        if k:
            k = k - 1 if w[k - 1] > w[k] else k + 1
        else:
            look_left = True
    # The sort is finished, or a boundary pair is due that the block cannot absorb, or a streak
    # might reach the limit: the heap loop goes on from the state written back here.
    if done == 0 and not fired:
        C[b] = tb
        return None
    _burst_flush(X, TL, V, ST, C, heap, t, horizon, lo, hi, w, s, dh, lr, last)
    return done, elastic


def _burst_flush(X, TL, V, ST, C, heap, t, horizon, lo, hi, w, s, dh, lr, last):
    """Write a burst's block back (velocities; streaks grown by the collisions of each particle's
    two pairs) and leave predictions and heap entries as the heap loop would: inner pairs
    pending at t where they are inversions (none once the sort has finished), the two boundary
    pairs predicted from the final velocities.  Returns None."""
    inf = math.inf
    push = heapq.heappush
    m = hi - lo
    hits = list(accumulate(dh))  # collisions of each local pair
    streaks = [a + b + c for a, b, c in zip(s, [0, *hits[:-1]], hits, strict=True)]
    if type(V) is list:
        V[lo : hi + 1] = w
        ST[lo : hi + 1] = streaks
    else:
        for q in range(m + 1):
            V[lo + q] = w[q]
            ST[lo + q] = streaks[q]
    for q in range(m):
        if w[q] > w[q + 1]:
            if C[lo + q] != t:
                C[lo + q] = t
                push(heap, (t, lo + q))
        else:
            C[lo + q] = inf
    h = lo - 1 if lo > 0 else last
    cc = collision_time(X, TL, h, V[h], lo, w[0], lr)
    if cc != C[h]:
        C[h] = cc
        if cc <= horizon:
            push(heap, (cc, h))
    r = hi + 1 if hi < last else 0
    cc = collision_time(X, TL, hi, w[m], r, V[r], lr)
    if cc != C[hi]:
        C[hi] = cc
        if cc <= horizon:
            push(heap, (cc, hi))


def advance_fast(engine, state: MDState, until: float):
    """Every collision of ``state`` up to ``until`` by the light-cone scheme (module docstring);
    returns the arrays (positions, t_last, velocities) and the collision count at ``until``.

    Parameters
    ----------
    engine : particles.MDEngine
        The engine: its ``params`` and its inelastic-collapse watch.
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
    x = state.positions.copy()
    tl = state.t_last.copy()
    v = state.velocities.copy()
    count = int(state.collisions)
    streak = np.zeros(n, dtype=np.int64)
    dt_tiny, limit, detail = engine.collapse_watch()
    record = engine.record
    target = engine.target_candidates
    seq_below = engine.sequential_below
    stats = engine.stats

    allpairs = np.arange(n)
    c = collision_times(x, tl, v, allpairs, lr)
    # horizon width, adapted so that about ``target`` collisions are candidates per slab
    width = None
    while True:
        cmin = c.min()
        if not cmin <= until:
            break
        vmax = float(v.max())
        vmin = float(v.min())
        if width is None:
            sample = c[np.isfinite(c)]
            k = min(target, sample.size) - 1
            width = float(np.partition(sample, k)[k] - cmin) if k > 0 else 0.0
        horizon = min(cmin + width, until)
        cand = np.flatnonzero(c <= horizon)
        stats["slabs"] += 1
        done_in_slab = 0
        while cand.size:
            stats["passes"] += 1
            cc = c[cand]
            # local minimum in (time, index) order among the neighbouring pairs
            left = cand - 1
            left[left < 0] = n - 1
            right = cand + 1
            right[right == n] = 0
            cl = c[left]
            cr = c[right]
            safe = ((cc < cl) | ((cc == cl) & (cand < left))) & (
                (cc < cr) | ((cc == cr) & (cand < right))
            )
            if cand.size > 1:
                xc = x[cand] + v[cand] * (cc - tl[cand])
                kl = vmax * cc - xc
                kr = xc - vmin * cc
                tol = _CONE_MARGIN * (
                    (abs(vmax) + abs(vmin)) * np.abs(cc).max() + np.abs(xc).max() + lr
                )
                pre = np.empty_like(kl)
                pre[0] = np.inf
                np.minimum.accumulate(kl[:-1], out=pre[1:])
                np.minimum(pre, kl.min() + lr, out=pre)
                suf = np.empty_like(kr)
                suf[-1] = np.inf
                suf[:-1] = np.minimum.accumulate(kr[:0:-1])[::-1]
                np.minimum(suf, kr.min() + lr, out=suf)
                cone = (kl < pre - tol) & (kr < suf - tol)
                # Ties: zero gaps in a cluster give several pending collisions at one time and
                # place; their keys agree within ``tol``, so the cone test blocks all of them
                # (only the global earliest used to fire: one collision per pass for the whole
                # gas).  Tie groups: runs of consecutive candidates within ``_GROUP_GAP * tol``
                # of each other.  The earliest of a group in (time, index) order is safe when
                # no candidate outside its group reaches it (the cone test against the prefix
                # minimum up to the group's start and the suffix minimum after its end): the
                # other members come later in (time, index) order, so they (and all their
                # consequences) run after it in the sequential order as well.
                brk = np.abs(np.diff(xc)) > _GROUP_GAP * tol
                if not brk.all():
                    k = cc.size
                    starts = np.flatnonzero(np.concatenate(([True], brk)))
                    gid = np.cumsum(np.concatenate(([0], brk)))
                    first = np.minimum.reduceat(
                        np.where(cc == np.minimum.reduceat(cc, starts)[gid], np.arange(k), k),
                        starts,
                    )
                    ends = np.append(starts[1:], k) - 1
                    g_ok = (kl[first] < pre[starts] - tol) & (kr[first] < suf[ends] - tol)
                    cone[first[g_ok]] = True
                safe &= cone
            safe[np.argmin(cc)] = True  # the earliest collision is always safe
            ev = cand[safe]
            tev = cc[safe]
            # -- collisions -----------------------------------------------------------
            i = ev
            j = ev + 1
            seam = j == n
            j[seam] = 0
            vi = v[i]
            vj = v[j]
            # collapse watch
            dti = tev - tl[i]
            dtj = tev - tl[j]
            stats["vectorised"] += ev.size
            stats["vectorised_zero_dt"] += int(np.count_nonzero(np.minimum(dti, dtj) <= 0.0))
            si = np.where(dti <= dt_tiny, streak[i] + 1, 0)
            sj = np.where(dtj <= dt_tiny, streak[j] + 1, 0)
            streak[i] = si
            streak[j] = sj
            if si.max() >= limit or sj.max() >= limit:
                bad = np.flatnonzero((si >= limit) | (sj >= limit))[0]
                engine.raise_collapse(
                    tev[bad],
                    np.flatnonzero(streak > 0),
                    count + bad,
                    detail,
                )
            xcol = x[i] + vi * dti
            x[i] = xcol
            if seam.any():
                xj = xcol.copy()
                xj[seam] -= lr
                x[j] = xj
            else:
                x[j] = xcol
            tl[i] = tev
            tl[j] = tev
            a, e, el = collide_many(vi, vj, p, delta, elastic_only)
            stats["elastic"] += int(np.count_nonzero(el))
            v[i] = a
            v[j] = e
            count += ev.size
            if record is not None:
                record.extend(zip(tev.tolist(), ev.tolist(), strict=True))
            done_in_slab += ev.size
            # -- new predictions for the pairs touching changed particles ---------------
            # the pair itself now separates (v_i' <= v_j' by construction): no prediction
            c[ev] = np.inf
            aff = np.concatenate((ev - 1, ev + 1))
            aff[aff < 0] += n
            aff[aff >= n] -= n
            c[aff] = collision_times(x, tl, v, aff, lr)
            # candidates: the unfired ones and the new predictions inside the horizon
            rest = cand[~safe]
            newc = aff[c[aff] <= horizon]
            if newc.size:
                cand = np.unique(np.concatenate((rest, newc)))
                cand = cand[c[cand] <= horizon]
            else:
                cand = rest
            # Cost model, in units of one plain scalar collision: a pass costs seq_below +
            # _PASS_PER_CANDIDATE * candidates, a collision of the scalar loop 1 if plain and
            # _BURST_COST in a zero-gap burst, at the burst fraction seen so far (in passes:
            # collisions with no time advance for one particle).  The slab goes to the scalar
            # loop once that is cheaper for the collisions this pass fired.
            burst_like = (stats["burst"] + stats["vectorised_zero_dt"]) / (
                stats["sequential"] + stats["vectorised"]
            )
            scalar = 1.0 - (1.0 - _BURST_COST) * burst_like
            pass_cost = seq_below + _PASS_PER_CANDIDATE * cand.size if seq_below else 0.0
            if ev.size * scalar < pass_cost and cand.size:
                # little parallelism left: finish the slab with the scalar event loop
                t_seq = _time.perf_counter()
                done = _sequential_slab(engine, x, tl, v, c, streak, cand, horizon, count)
                stats["sequential_seconds"] += _time.perf_counter() - t_seq
                count += done
                done_in_slab += done
                stats["sequential"] += done
                cand = cand[:0]
        # adapt the horizon width to the number of collisions that fitted in the slab
        if done_in_slab > 0 and width > 0:
            width *= min(2.0, max(0.5, target / done_in_slab))
        elif width == 0.0:
            width = None
    return x, tl, v, count
