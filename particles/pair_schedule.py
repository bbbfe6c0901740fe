"""The pair scheduler of the Ulam engine: the random pairs of a window's events, the round
schedule that fires them in parallel, and the fast and reference loops over a list of events (in
1D, and in d = 2, 3 with the kinematics of :mod:`particles.ulam_kinematics`).

Exact vectorized scheme.  τ is cut into windows on a fixed grid of step ``window``
(a power of two, so grid points are exact floats) and at the requested times.  For a window of
length Δτ we draw the number of events K ~ Poisson(N Δτ / 2) and the K pairs; event times inside
a window are never needed, only their order.  The events are then fired in rounds: in each round
every remaining event that is the earliest remaining event of *both* its particles fires (all
such events touch disjoint particles, and no earlier event can touch them), and is removed.  This
applies exactly the updates of a sequential loop over the same events, in an order that differs
only by swapping events on disjoint particles, so the velocities agree bit for bit
(:func:`collide_in_order` against :func:`collide_sequential`).

"Earliest remaining event of each particle" is a scatter-max of the occurrence index: the events
are stored in *reverse* time order as an interleaved int32 array ``[a_0, b_0, a_1, b_1, ...]``
and a single fancy assignment ``first[pairs] = arange(2K)`` leaves, for each particle, the
largest occurrence index written to it.  NumPy applies repeated indices in order in practice, but
does not promise it, so the result is checked (every occurrence must see an index ≥ its own) and
recomputed with ``np.maximum.at`` if the check ever fails.

Collision rate ∝ |v_i − v_j| (the Ulam DSMC, :class:`particles.ulam.Ulam` with
``rate="relative_velocity"``): the events are candidates, drawn at a uniformized rate with a bound
B ≥ every |v_i − v_j| (:func:`hull_bound`), each with a uniform mark U; a candidate collides iff
U·B < |v_i − v_j| when it fires (:func:`fire_rounds_thinned`, against the loop
:func:`thin_sequential`).  A rejected candidate changes nothing but still waits for the earlier
candidates of its particles, whose outcome decides its own.  :func:`thinned_windows` cuts time
into the blocks (one bound each) and sub-windows of the scheme.
"""

from __future__ import annotations

import math

import numpy as np

from .collision import collide_arrays, collide_scalar, transfer_fraction
from .driver.engine import next_grid_point
from .kernels import ConstantRate, defines_rate
from .sphere_kernels import DIRECTION_LAWS
from .ulam_kinematics import (
    AngularDraws,
    as_complex,
    check_angular,
    collide_complex,
    collide_pairs_vectors,
    plane_transfer,
    subset_draws,
)
from .validation import InvalidArgumentError, check_count

__all__ = [
    "ulam_carries",
    "kernel_bound",
    "draw_pairs",
    "fire_rounds_thinned",
    "thin_sequential",
    "hull_bound",
    "thinned_windows",
    "collide_in_order",
    "collide_sequential",
    "collide_in_order_vectors",
    "collide_sequential_vectors",
]


def draw_pairs(rng: np.random.Generator, n: int, k: int) -> np.ndarray:
    """``k`` independent uniformly random ordered pairs (i, j), i ≠ j, of ``n`` particles, as an
    int32 array of shape (k, 2).

    Parameters
    ----------
    rng : numpy.random.Generator
        The random generator.
    n : int
        The number of particles N ≥ 2.
    k : int
        The number of pairs.

    Returns
    -------
    numpy.ndarray
        int32 array of shape ``(k, 2)``.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``rng``) if it is not a ``numpy.random.Generator``; (``n``) if it is not an
        integer in [2, 2³¹ − 1]; (``k``) if it is not an integer >= 0.
    """
    if not isinstance(rng, np.random.Generator):
        raise InvalidArgumentError("rng", type(rng).__name__, "a numpy.random.Generator")
    n = check_count(n, "n", 2)
    if n > 2**31 - 1:
        raise InvalidArgumentError("n", n, "an integer <= 2**31 - 1 (int32 particle ids)")
    return draw_pairs_unchecked(rng, n, check_count(k, "k", 0))


def draw_pairs_unchecked(rng: np.random.Generator, n: int, k: int) -> np.ndarray:
    """:func:`draw_pairs` without the checks (the engine's own arguments)."""
    pairs = np.empty((k, 2), dtype=np.int32)
    pairs[:, 0] = rng.integers(0, n, k, dtype=np.int32)
    second = rng.integers(0, n - 1, k, dtype=np.int32)
    second += second >= pairs[:, 0]
    pairs[:, 1] = second
    return pairs


def largest_occurrence(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """For each entry of ``flat`` (particle ids), the largest ``occ`` among the entries with the
    same particle.  One fancy assignment (the last write wins), verified; exact fallback."""
    first[flat] = occ
    own = first[flat]
    if not np.all(own >= occ):  # pragma: no cover - NumPy did not write in order
        own = largest_occurrence_ufunc(first, flat, occ)
    return own


def largest_occurrence_ufunc(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """The same with ``np.maximum.at`` (order-independent, ~10x slower)."""
    first[flat] = -1
    np.maximum.at(first, flat, occ)
    return first[flat]


def _rounds(reversed_pairs: np.ndarray, first: np.ndarray, occurrence: np.ndarray):
    """The round schedule of the events of ``reversed_pairs`` ((K, 2) int32, C-contiguous,
    **last event first**): yields, round by round, ``(fired, fire)`` where ``fire`` masks the
    events still pending that fire now (each is the earliest pending event of both its
    particles) and ``fired`` = [a_0, b_0, a_1, …] their particles, all distinct.  ``first`` is
    int32 scratch of size N, ``occurrence`` is ``arange(≥ 2K, dtype=int32)``.  The caller
    applies the round before asking for the next (``fire`` is reused afterwards)."""
    packed = reversed_pairs.view(np.int64).reshape(-1)  # one int64 per event: cheap compaction
    while packed.size:
        m = packed.size
        # a_0, b_0, a_1, b_1, ... (reverse time order); intp indices index ~2x faster than int32
        flat = packed.view(np.int32).astype(np.intp)
        occ = occurrence[: 2 * m]
        own = largest_occurrence(first, flat, occ)
        # Event r (occurrences 2r, 2r+1) fires iff it is the earliest of both its particles.
        own_is_first = own == occ
        fire = own_is_first[0::2]
        fire &= own_is_first[1::2]
        # np.compress, not packed[fire]: boolean indexing is ~5x slower on random masks.
        fired = np.compress(fire, packed).view(np.int32).astype(np.intp)
        yield fired, fire
        np.logical_not(fire, out=fire)
        packed = np.compress(fire, packed)


def fire_rounds(
    v: np.ndarray, reversed_pairs: np.ndarray, p: float, first: np.ndarray, occurrence: np.ndarray
) -> int:
    """Apply the events of ``reversed_pairs`` to ``v`` in place, round by round (:func:`_rounds`).
    Returns the number of rounds."""
    rounds = 0
    for fired, _ in _rounds(reversed_pairs, first, occurrence):
        vv = v[fired]
        vv2 = vv.reshape(-1, 2)
        collide_arrays(vv2[:, 0], vv2[:, 1], p)
        v[fired] = vv
        rounds += 1
    return rounds


def fire_rounds_with_rows(v, reversed_pairs, first, occurrence, collide) -> int:
    """:func:`fire_rounds` for events that carry data: ``collide(v, fired, rows)`` applies the
    events of rows ``rows`` of ``reversed_pairs`` (particles ``fired`` = [a_0, b_0, a_1, …], all
    distinct)."""
    rows = np.arange(len(reversed_pairs), dtype=np.intp)
    rounds = 0
    for fired, fire in _rounds(reversed_pairs, first, occurrence):
        collide(v, fired, np.compress(fire, rows))
        rows = np.compress(~fire, rows)
        rounds += 1
    return rounds


def fire_rounds_plane(w, reversed_pairs, transfer, first, occurrence) -> int:
    """d = 2: :func:`fire_rounds` on complex velocities ``w`` (N,) with one complex factor
    per event (``transfer``, rows as ``reversed_pairs``;
    :func:`~particles.ulam_kinematics.plane_transfer`).  A gather, the rule and a scatter of
    16-byte elements per round; the factors of the pending events are compacted alongside the
    pairs."""
    rounds = 0
    for fired, fire in _rounds(reversed_pairs, first, occurrence):
        vv = np.take(w, fired)
        collide_complex(vv[0::2], vv[1::2], np.compress(fire, transfer))
        w[fired] = vv
        transfer = np.compress(~fire, transfer)
        rounds += 1
    return rounds


#: Relative margin of the thinning bound over max v − min v (covers ulp-level round-off of the
#: collisions, which could otherwise put a velocity an ulp outside the hull).
HULL_BOUND_MARGIN = 1e-9

#: Sub-windows per thinning block: the bound (max v − min v, one pass over N velocities) is
#: recomputed once per block, not once per sub-window.
BLOCK_WINDOWS = 8


def ulam_carries(kernel) -> bool:
    """Whether the ``ulam`` model runs a kernel class: the constant rate (its windows of
    Poisson pairs), a kernel defined in d = 1 that writes out its rate and rate bound (the
    thinned DSMC of :func:`fire_rounds_thinned`), or one with its rate, bound and a direction
    law (:data:`particles.sphere_kernels.DIRECTION_LAWS`: the DSMC of d = 2, 3,
    :class:`particles.hard_sphere_dsmc.SphereDSMC`).

    Parameters
    ----------
    kernel : type
        A kernel class of :mod:`particles.kernels`.

    Returns
    -------
    bool
    """
    if kernel.name == ConstantRate.name:
        return True
    spheres = getattr(kernel, "direction_law", None) in DIRECTION_LAWS
    return defines_rate(kernel) and (1 in kernel.dimensions or spheres)


def kernel_bound(kernel, spread: float) -> float:
    """``kernel.rate_bound(spread)``, refused unless a finite number ≥ 0 (a kernel of the
    user's is never trusted blindly: NaN would draw no candidates, silently).

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        The kernel.
    spread : float
        The largest |v − w| concerned.

    Returns
    -------
    float

    Raises
    ------
    InvalidArgumentError
        Naming ``rate`` (the engines' argument for the kernel), with the bound received.
    """
    bound = kernel.rate_bound(spread)
    if not 0.0 <= bound < math.inf:
        raise InvalidArgumentError("rate", kernel, f"a kernel whose rate_bound is a finite "
                                   f"number >= 0 (got {bound!r} at spread {spread!r})")
    return bound


def power_of_two_near(x: float) -> float:
    """The power of two nearest to ``x`` > 0 in log scale, 2^e with e clipped to [−1000, 1000]."""
    if not x < math.inf:
        return 2.0**1000
    return 2.0 ** min(1000, max(-1000, round(math.log2(x))))


def hull_bound(v: np.ndarray) -> float:
    """Thinning bound (max v − min v)(1 + ``HULL_BOUND_MARGIN``) of 1D velocities ``v``: it is
    ≥ every |v_i − v_j| now and at all later times, since an inelastic collision (and the
    recentring) keeps both velocities inside the pair's hull, so the hull of all velocities never
    grows.

    Parameters
    ----------
    v : numpy.ndarray
        Velocities (N,), finite.

    Returns
    -------
    float
        The bound (0 when all velocities are equal).
    """
    return float(v.max() - v.min()) * (1.0 + HULL_BOUND_MARGIN)


def thinned_windows(start: float, until: float, rate: float, stop_step: float,
                    target: int) -> list[tuple[float, float]]:
    """The sub-windows of one thinning block of the Ulam DSMC (rate ∝ |v_i − v_j|), which begins
    at ``start`` with candidate rate ``rate`` = n(N − 1)B/2 per unit t: the sub-window length h is
    the power of two with ``rate``·h ≈ ``target`` candidates (at least 2⁻³⁰ of ``start``, so the
    grid stays representable); the block ends at the first of the next multiple of
    ``BLOCK_WINDOWS``·h, the next multiple of ``stop_step`` and ``until``; it is cut at the
    multiples of h.  A function of (``start``, the bound) only, so a run stopped at the same
    points draws the same windows (resume bit for bit).

    Parameters
    ----------
    start, until : float
        The block's start and the time to reach (t).
    rate : float
        The candidate rate ≥ 0 (0: no candidates, one window to the block's end).
    stop_step : float
        The driver's stop grid (a power of two).
    target : int
        Candidates aimed at per sub-window.

    Returns
    -------
    list of tuple of float
        The consecutive sub-windows ``(a, b)``, from ``start`` to the block's end.
    """
    h = power_of_two_near(target / rate) if rate > 0.0 else math.inf
    if start > 0.0:
        h = max(h, 2.0 ** (math.frexp(start)[1] - 30))
    end = min(until, next_grid_point(start, stop_step))
    if math.isfinite(h):
        end = min(end, next_grid_point(start, BLOCK_WINDOWS * h))
    cuts = [start]
    t = start
    while math.isfinite(h):
        t = next_grid_point(t, h)
        if t >= end:
            break
        cuts.append(t)
    cuts.append(end)
    return list(zip(cuts[:-1], cuts[1:], strict=True))


def fire_rounds_thinned(v, reversed_pairs, marks, bound, p, first, occurrence, rate) -> int:
    """:func:`fire_rounds` for thinned candidates (the collision rate of a pair is
    ``rate(v_a, v_b)``, the kernel's): candidate row k (``reversed_pairs[k]``, last
    candidate first) collides iff ``marks[k] * bound < rate(v_a, v_b)`` at the moment it fires,
    ``marks`` uniform on [0, 1), ``bound`` ≥ the rate of every pair (so the acceptance
    probability is rate/``bound``); a rejected candidate changes nothing.  A candidate fires
    when it is the earliest pending candidate of both its particles, so it sees the velocities
    of the sequential loop (:func:`thin_sequential`) and takes the same decision, bit for bit.

    Parameters
    ----------
    v : numpy.ndarray
        Velocities (N,), modified in place.
    reversed_pairs : numpy.ndarray
        int32 (K, 2), C-contiguous, the candidates in reverse time order.
    marks : numpy.ndarray
        (K,) uniform marks on [0, 1), row k for candidate k.
    bound : float
        The thinning bound.
    p : float
        The transfer fraction (1 + r)/2.
    first, occurrence : numpy.ndarray
        Scratch of :func:`_rounds`.
    rate : callable, optional
        ``rate(va, vb)`` → the pairs' rates, arrays in and out (a kernel's
        :meth:`~particles.kernels.Kernel.rate`; this module writes no rate itself).

    Returns
    -------
    int
        The number of accepted candidates (collisions).

    Raises
    ------
    InvalidArgumentError
        Naming ``rate``, when a fired pair's ``rate`` passes ``bound`` (its acceptance
        probability would pass 1: the kernel's bound does not hold).
    """
    accepted = 0
    for fired, fire in _rounds(reversed_pairs, first, occurrence):
        vv = np.take(v, fired)
        g = rate(vv[0::2], vv[1::2])
        if g.size and not g.max() <= bound:  # the acceptance rate/bound would pass 1
            raise InvalidArgumentError("rate", f"a pair's rate {g.max()!r}",
                                       f"a kernel whose rate stays <= its bound {bound!r}")
        threshold = np.compress(fire, marks)
        marks = np.compress(~fire, marks)  # the marks of the candidates still pending
        threshold *= bound
        hit = np.flatnonzero(threshold < g)  # accepted: ~⟨|g|⟩/bound of them
        if hit.size:
            ia, ib = np.take(fired[0::2], hit), np.take(fired[1::2], hit)
            va, vb = np.take(v, ia), np.take(v, ib)
            collide_arrays(va, vb, p)
            v[ia] = va
            v[ib] = vb
            accepted += int(hit.size)
    return accepted


def thin_sequential(v, reversed_pairs, marks, bound, p, rate) -> tuple[int, float]:
    """Reference of :func:`fire_rounds_thinned`: a Python loop over the candidates in time order
    (row K − 1 first, row 0 last), on ``v`` (N,) in place: candidate k collides iff
    ``marks[k] * bound < rate(v_a, v_b)`` (:func:`~particles.collision.collide_scalar`).

    Parameters
    ----------
    v : numpy.ndarray
        Velocities (N,), modified in place.
    reversed_pairs : numpy.ndarray
        (K, 2) particle indices, the candidates in reverse time order.
    marks : numpy.ndarray
        (K,) uniform marks on [0, 1).
    bound : float
        The thinning bound.
    p : float
        The transfer fraction (1 + r)/2.
    rate : callable, optional
        ``rate(va, vb)`` → the pair's rate, on floats (a kernel's
        :meth:`~particles.kernels.Kernel.rate`).

    Returns
    -------
    tuple of (int, float)
        The number of accepted candidates, and the largest rate/``bound`` seen at a
        candidate (≤ 1 when the bound holds; 0 without candidates).
    """
    w = v.tolist()
    m = marks.tolist()
    accepted = 0
    largest = 0.0
    for k in range(len(reversed_pairs) - 1, -1, -1):
        a, b = int(reversed_pairs[k, 0]), int(reversed_pairs[k, 1])
        g = float(rate(w[a], w[b]))
        largest = max(largest, g / bound)
        if m[k] * bound < g:
            w[a], w[b] = collide_scalar(w[a], w[b], p)
            accepted += 1
    v[:] = w
    return accepted, largest


def _check_events(v, pairs, restitution):
    p = transfer_fraction(restitution)
    v = np.array(v, dtype=float)  # a copy
    pairs = np.asarray(pairs)
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise InvalidArgumentError("pairs", f"array of shape {pairs.shape}", "shape (K, 2)")
    if pairs.size and (
        pairs.min() < 0 or pairs.max() >= v.size or np.any(pairs[:, 0] == pairs[:, 1])
    ):
        raise InvalidArgumentError(
            "pairs", "out-of-range or i == j entries", f"pairs of 0..{v.size - 1}, i != j"
        )
    return v, pairs, p


def collide_in_order(v, pairs, restitution) -> np.ndarray:
    """Fast path: apply the collisions ``pairs[0], pairs[1], …`` (time order) to a copy of ``v``
    with the round-parallel scheme; returns the new velocities.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)``; not modified (a copy is used).
    pairs : array_like of int
        The collisions in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        The velocities after the K collisions, shape ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``pairs`` (wrong shape, out-of-range or i = j entries) or ``restitution``.
    """
    v, pairs, p = _check_events(v, pairs, restitution)
    reversed_pairs = np.ascontiguousarray(pairs[::-1], dtype=np.int32)
    first = np.empty(v.size, dtype=np.int32)
    occurrence = np.arange(2 * len(pairs), dtype=np.int32)
    fire_rounds(v, reversed_pairs, p, first, occurrence)
    return v


def collide_sequential(v, pairs, restitution) -> np.ndarray:
    """Reference: a plain Python loop over ``pairs`` in time order, on a copy of ``v``.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)``; not modified (a copy is used).
    pairs : array_like of int
        The collisions in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        The velocities after the K collisions, shape ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`collide_in_order`.
    """
    v, pairs, p = _check_events(v, pairs, restitution)
    out = v.tolist()
    for a, b in pairs.tolist():
        out[a], out[b] = collide_scalar(out[a], out[b], p)
    return np.array(out, dtype=float)


def _check_vector_events(v, pairs, restitution, draws, angular):
    p = transfer_fraction(restitution)
    v = np.array(v, dtype=float, order="C")  # a C-contiguous copy (scatter_rows needs it)
    if v.ndim != 2 or v.shape[1] < 2:
        raise InvalidArgumentError("v", f"array of shape {v.shape}", "shape (N, d), d >= 2")
    angular = check_angular(angular)
    pairs = np.asarray(pairs)
    _check_events(np.zeros(v.shape[0]), pairs, restitution)
    k = (len(pairs),)
    if v.shape[1] == 2:
        bad = draws.sine is None or np.shape(draws.sine) != k
    else:
        bad = (draws.z is None or draws.z.shape != (len(pairs), v.shape[1])) or (
            angular == "hard" and (draws.eta is None or draws.eta.shape != k)
        )
    if bad:
        raise InvalidArgumentError("draws", "arrays of other shapes", "one draw per event")
    return v, pairs, p, angular


def collide_in_order_vectors(v, pairs, restitution, draws: AngularDraws, angular="uniform"):
    """Fast path in d dimensions: apply the events ``pairs[k]`` with angular ``draws`` row k, in
    time order k = 0, 1, …, to a copy of ``v`` (N, d); returns the new velocities.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``, d ≥ 2; not modified (a copy is used).
    pairs : array_like of int
        The events in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].
    draws : AngularDraws
        The angular variables of the K events (:func:`~particles.ulam_kinematics.draw_angles`), row
        k for event k.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``, the law of the collision direction.

    Returns
    -------
    numpy.ndarray
        The velocities after the K events, shape ``(N, d)``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``v``, ``pairs``, ``restitution``, ``angular`` or ``draws`` when out of domain
        or of the wrong shape.
    """
    v, pairs, p, angular = _check_vector_events(v, pairs, restitution, draws, angular)
    k = len(pairs)
    reversed_pairs = np.ascontiguousarray(pairs[::-1], dtype=np.int32)
    reversed_draws = subset_draws(draws, np.arange(k - 1, -1, -1))
    first = np.empty(v.shape[0], dtype=np.int32)
    occurrence = np.arange(2 * k, dtype=np.int32)
    if v.shape[1] == 2:
        transfer = plane_transfer(reversed_draws.sine, p)
        fire_rounds_plane(as_complex(v), reversed_pairs, transfer, first, occurrence)
        return v

    def collide(w, fired, rows):
        collide_pairs_vectors(w, fired, subset_draws(reversed_draws, rows), angular, p)

    fire_rounds_with_rows(v, reversed_pairs, first, occurrence, collide)
    return v


def collide_sequential_vectors(v, pairs, restitution, draws: AngularDraws, angular="uniform"):
    """Reference: a Python loop over the events in time order, one event at a time.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``, d ≥ 2; not modified (a copy is used).
    pairs : array_like of int
        The events in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].
    draws : AngularDraws
        The angular variables of the K events (:func:`~particles.ulam_kinematics.draw_angles`), row
        k for event k.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``, the law of the collision direction.

    Returns
    -------
    numpy.ndarray
        The velocities after the K events, shape ``(N, d)``.

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`collide_in_order_vectors`.
    """
    v, pairs, p, angular = _check_vector_events(v, pairs, restitution, draws, angular)
    if v.shape[1] == 2:
        w = as_complex(v)
        for k, (a, b) in enumerate(pairs.astype(np.intp)):
            pair = w[[a, b]]
            collide_complex(pair[0:1], pair[1:2], plane_transfer(draws.sine[k : k + 1], p))
            w[[a, b]] = pair
        return v
    for k, (a, b) in enumerate(pairs.astype(np.intp)):
        row = np.array([k], dtype=np.intp)
        collide_pairs_vectors(v, np.array([a, b]), subset_draws(draws, row), angular, p)
    return v
