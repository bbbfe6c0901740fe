"""One large sticky gas computed as K chunks of the ring, in one process or on Dask.

The N labels of the ring are cut into K chunks of consecutive labels (the first N mod K chunks
one label longer).  Chunk k draws its own raw data from the child seed
``SeedSequence(seed, spawn_key=(k,))`` (the k-th child of ``SeedSequence(seed).spawn(K)``; the
single engine's stream ``default_rng(seed)`` is the root's, independent of every child): n_k
exponential spacings (one more for the last chunk) and then n_k velocities of the law.  The
child depends on k only, not on K: runs of one seed with different K share the beginnings of
their chunks' streams, so they are correlated, not independent, samples; use other seeds to
compare K.  The
initial state is the single engine's law, normalised over the whole ring, never chunk by chunk:

* positions: with T the sum of all N + 1 spacings and S_j the sum of the first j + 1, particle j
  sits at x_j = L S_j / T, so the N positions are the order statistics of N independent uniforms
  on [0, L), as the engine's ``sort(uniform(0, L, N))`` (their numbers on the chunks' arcs
  fluctuate as the engine's do);
* velocities: each chunk returns Σ v and its Σ (v − v̄_k)² about its own mean (n_k, Σ v and
  Σ v² in a numerically stable form); the client forms the ring's mean μ and ⟨(v − μ)²⟩ and
  sends back one shift and scale, v ← (v − μ)/√⟨(v − μ)²⟩: the engine's own normalisation of its
  N velocities (:func:`particles.driver.initial_velocities`).  The ring's Σ v is 0 and its ⟨v²⟩
  is 1 up to round-off; a chunk's own momentum and energy fluctuate, as they do in the engine,
  and so do the momentum fluctuations on scales above a chunk that drive E ∝ t^{−2/3}.

This costs one pass over the chunks (:func:`chunk_moments`) before the first time.  K = 1 is the
single-process engine itself (:class:`particles.sticky.StickyGas` run by
:func:`particles.driver.simulate`), same draw, same numbers; K > 1 has the same law, not the
same numbers.

At each output time t every chunk computes the isotonic regression of its free-streamed
positions x_j + v_j t (:mod:`particles.sticky`): a block of the ring's regression is a union of
whole blocks of the chunks, and two monotone sequences regress to themselves except for one
block pooled across their junction.  So only blocks near the junctions (and the seam) can
change.  Each chunk returns its first and last ``edge`` blocks and, for the blocks between them
(its *interior*), only sums: their number, Σ m u² and the counts of their masses (u a cluster's
velocity, m its mass).  Its first and last interior blocks come along as *sentinels*.  The
client joins the edge blocks by one weighted isotonic regression and pools the seam; if a pooled
block reached a sentinel, the interior was not out of reach after all, and the time is computed
again with 4× the edge.  The final histogram of x = v/√E needs E: a second pass counts each
chunk's interior velocities on its bins.  With ``structure_factor`` the same pass also returns
the interior clusters (first label, mass, Σ v); this process lays them out with the joined
clusters as the per-particle velocity field v_j and takes S(k) = |v̂(k)|²/N, v̂(k) = Σ_j v_j
e^{−ikj}, and C(r) as the single engine does (:func:`particles.observables.structure_factor`):
the spectrum has N/2 + 1 values, so it costs :data:`SPECTRUM_BYTES` bytes a particle here.

Every sum over chunks is taken on the client in chunk order, so the result for a given
(seed, K) does not depend on the number of workers or on where the tasks ran.  A task recomputes
its chunk from the seed (nothing is held on the workers between tasks): the memory of a worker
is that of one chunk, about 70 bytes a particle.
"""

from __future__ import annotations

import math
import time as _time

import numpy as np

from .budget import available_memory, format_bytes
from .driver import initial_velocities
from .initial import get_law
from .observables import histogram_from_counts
from .sticky import StickyParams, period_regression, pool_junction
from .validation import InvalidArgumentError, check_count, check_times

__all__ = ["ChunkedResult", "chunk_bounds", "chunk_initial", "chunk_moments", "check_chunks",
           "ring_normalisation", "simulate_chunks", "velocity_field"]

#: Blocks sent from each end of a chunk at first (multiplied by 4 while a pooled block reaches
#: past them).
EDGE = 64


def check_chunks(chunks, n: int) -> int:
    """``chunks`` as an integer in [1, N/2]: every chunk holds at least two particles.

    Parameters
    ----------
    chunks : int
        The number of chunks K asked for.
    n : int
        The number of particles N.

    Returns
    -------
    int
        K.

    Raises
    ------
    InvalidArgumentError
        Naming ``chunks`` when it is not an integer in [1, N/2].
    """
    try:
        k = check_count(chunks, "chunks", 1)
    except InvalidArgumentError:
        raise InvalidArgumentError("chunks", chunks, f"an integer in [1, N/2 = {n // 2}]") from None
    if k > n // 2:
        raise InvalidArgumentError("chunks", chunks, f"an integer in [1, N/2 = {n // 2}]")
    return k


def chunk_bounds(n: int, chunks: int) -> np.ndarray:
    """First labels of the K chunks, with N appended (the first N mod K chunks one longer).

    Parameters
    ----------
    n : int
        The number of particles N.
    chunks : int
        The number of chunks K.

    Returns
    -------
    numpy.ndarray
        K + 1 int64 labels: chunk k holds the labels ``bounds[k]`` … ``bounds[k + 1]`` − 1.
    """
    size, extra = divmod(int(n), int(chunks))
    lengths = np.full(int(chunks), size, dtype=np.int64)
    lengths[:extra] += 1
    return np.concatenate([[0], np.cumsum(lengths)])


def _chunk_draw(params: StickyParams, seed: int, k: int, chunks: int):
    """Chunk k's raw draw from its child seed: its exponential spacings (n_k, or n_k + 1 for the
    last chunk) and n_k velocities of the law, neither shifted nor scaled."""
    bounds = chunk_bounds(params.n, chunks)
    nk = int(bounds[k + 1] - bounds[k])
    rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(k),)))
    gaps = rng.standard_exponential(nk + (k == chunks - 1))
    return gaps, get_law(params.initial).sample(rng, nk)


def chunk_moments(params_dict: dict, seed: int, k: int, chunks: int) -> dict:
    """Chunk k's sums for the ring's normalisation (:func:`ring_normalisation`).

    Parameters
    ----------
    params_dict : dict
        The gas's ``StickyParams.to_dict()``.
    seed : int
        The run's seed.
    k, chunks : int
        The chunk's index and the number of chunks K.

    Returns
    -------
    dict
        ``n`` (n_k), ``gaps`` (the sum of its spacings, as the running sum that places its
        particles computes it), ``sum`` (Σ v of its raw velocities) and ``m2`` (Σ (v − v̄_k)²,
        v̄_k = Σ v / n_k).
    """
    params = StickyParams(**params_dict)
    gaps, v = _chunk_draw(params, seed, k, chunks)
    s1 = float(np.add.reduce(v))
    v -= s1 / v.size
    v *= v
    np.cumsum(gaps, out=gaps)  # the running sum chunk_initial places the particles with
    return {"n": int(v.size), "gaps": float(gaps[-1]), "sum": s1, "m2": float(np.add.reduce(v))}


def ring_normalisation(moments, n: int, initial="gaussian") -> list[tuple]:
    """The one shift and scale of the whole ring from its chunks' :func:`chunk_moments`.

    Parameters
    ----------
    moments : list of dict
        :func:`chunk_moments` of chunks 0 … K − 1, in chunk order.
    n : int
        N.
    initial : str
        The law's name (named in the error).

    Returns
    -------
    list of tuple
        Per chunk ``(offset, total, mu, scale)``: the sum of the spacings of the chunks before
        it, the sum T of all N + 1 spacings, the ring's mean velocity μ and
        1/√⟨(v − μ)²⟩ over the N raw velocities.

    Raises
    ------
    InvalidArgumentError
        Naming ``initial`` when the N raw velocities have zero variance.
    """
    offsets, total = [], 0.0
    for m in moments:  # a running sum: the last position of a chunk is the next one's offset
        offsets.append(total)
        total += m["gaps"]
    mu = math.fsum(m["sum"] for m in moments) / n
    m2 = math.fsum(m["m2"] for m in moments) + math.fsum(
        m["n"] * (m["sum"] / m["n"] - mu) ** 2 for m in moments)
    e = m2 / n
    if not e > 0.0:
        raise InvalidArgumentError("initial", initial, "a law with non-zero variance")
    scale = 1.0 / math.sqrt(e)
    return [(off, total, mu, scale) for off in offsets]


def chunk_initial(params: StickyParams, seed: int, k: int, chunks: int, norm=None):
    """The initial positions and velocities of chunk ``k`` of ``chunks``, normalised over the
    whole ring (module docstring).

    Particle j of the chunk (global label b_k + j) sits at x = L (offset + S_j)/T, S_j the
    running sum of the chunk's spacings, and its velocity is (v − μ)·scale, with ``norm`` =
    (offset, T, μ, scale) of :func:`ring_normalisation`.  K = 1 is the single engine's draw:
    ``default_rng(seed)``, N sorted uniforms on [0, L), then the velocities.

    Parameters
    ----------
    params : particles.sticky.StickyParams
        The gas.
    seed : int
        The run's seed.
    k, chunks : int
        The chunk's index and the number of chunks K.
    norm : tuple, optional
        This chunk's ``(offset, total, mu, scale)`` of :func:`ring_normalisation`; by default
        computed here from every chunk's draw (a pass over the whole ring).

    Returns
    -------
    x, v : numpy.ndarray
        The chunk's positions (nondecreasing, in [0, L)) and velocities.
    """
    n, length = params.n, params.length
    if chunks == 1:
        rng = np.random.default_rng(seed)
        x = np.sort(rng.uniform(0.0, length, n))
        return x, initial_velocities(params.initial, n, rng)
    if norm is None:
        pd = params.to_dict()
        norm = ring_normalisation([chunk_moments(pd, seed, j, chunks) for j in range(chunks)],
                                  n, params.initial)[k]
    offset, total, mu, scale = norm
    x, v = _chunk_draw(params, seed, k, chunks)
    np.cumsum(x, out=x)
    x = x[: v.size]
    x += offset
    x *= length / total
    np.minimum(x, np.nextafter(length, 0.0), out=x)  # x < L despite the rounding of L/T
    v -= mu
    v *= scale
    return x, v


def _chunk_blocks(params: StickyParams, seed, k, chunks, norm, t):
    x, v = chunk_initial(params, seed, k, chunks, norm)
    first = int(chunk_bounds(params.n, chunks)[k])
    if t == 0.0:
        nk = x.size
        return (np.arange(nk, dtype=np.int64), x - params.length, np.ones(nk), v.copy(), first,
                float(np.add.reduce(v)))
    blocks, means, weights = period_regression(x, v, params.length, t)
    vsums = np.add.reduceat(v, blocks)
    return (blocks.astype(np.int64), means.copy(), weights.copy(), vsums, first,
            float(np.add.reduce(v)))  # labels as int64: a chunk's first label is added to them


def _interior(nb: int, edge: int):
    """Indices of the edge blocks and of the two sentinels, and the interior slice (None when a
    chunk has too few blocks to have an interior)."""
    if nb <= 2 * edge + 2:
        return np.arange(nb), np.zeros(nb, dtype=np.int8), None
    idx = np.concatenate([np.arange(edge + 1), np.arange(nb - edge - 1, nb)])
    flags = np.zeros(idx.size, dtype=np.int8)
    flags[edge] = flags[edge + 1] = 1
    return idx, flags, slice(edge, nb - edge)


def chunk_summary(params_dict: dict, seed: int, k: int, chunks: int, norm, t: float,
                  edge: int) -> dict:
    """One chunk at time ``t``: its edge blocks and sentinels (label starts, means of
    x + vt − L, masses, velocity sums, sentinel flags), its interior sums and Σ v (``norm``:
    the chunk's entry of :func:`ring_normalisation`)."""
    params = StickyParams(**params_dict)
    blocks, means, weights, vsums, first, momentum = _chunk_blocks(params, seed, k, chunks, norm,
                                                                   t)
    idx, flags, inner = _interior(blocks.size, edge)
    out = {"starts": blocks[idx] + first, "means": means[idx], "weights": weights[idx],
           "vsums": vsums[idx], "flags": flags, "momentum": momentum,
           "count": 0, "energy": 0.0, "fourth": 0.0,
           "masses": (np.zeros(0, np.int64), np.zeros(0, np.int64))}
    if inner is not None:
        w, s = weights[inner], vsums[inner]
        out["count"] = int(w.size)
        out["energy"] = float(np.add.reduce(s * s / w))
        u = s / w  # the cluster's velocity, carried by its w particles
        out["fourth"] = float(np.add.reduce(w * (u * u) ** 2))
        out["masses"] = np.unique(w.astype(np.int64), return_counts=True)
    return out


def chunk_last(params_dict: dict, seed: int, k: int, chunks: int, norm, t: float, edge: int,
               v0: float, edges, field: bool = False) -> dict:
    """The second pass at the last time ``t`` over chunk ``k``'s interior clusters.

    Parameters
    ----------
    params_dict : dict
        The gas's ``StickyParams.to_dict()``.
    seed : int
        The run's seed (the chunk draws from its child seed).
    k, chunks : int
        This chunk's index and the number of chunks.
    norm : tuple
        The chunk's ``(offset, total, mu, scale)`` of :func:`ring_normalisation`.
    t : float
        The last output time (physical time).
    edge : int
        The edge the join used at ``t`` (the interior is what lies between the edges).
    v0 : float
        √E at ``t``: the histogram counts x = v/v0.
    edges : array_like
        The histogram's bin edges in x.
    field : bool
        Also return the interior clusters themselves, for the velocity field of S(k).

    Returns
    -------
    dict
        ``counts``: the interior particles' counts on ``edges`` (int64); with ``field``,
        ``starts`` (global first labels), ``masses`` and ``vsums`` (Σ v) of the interior
        clusters.
    """
    params = StickyParams(**params_dict)
    blocks, _, weights, vsums, first, _ = _chunk_blocks(params, seed, k, chunks, norm, t)
    _, _, inner = _interior(blocks.size, edge)
    out = {"counts": np.zeros(len(edges) - 1, dtype=np.int64)}
    if field:
        out.update(starts=np.zeros(0, np.int64), masses=np.zeros(0), vsums=np.zeros(0))
    if inner is None:
        return out
    w = weights[inner]
    u = vsums[inner] / w
    count, _ = np.histogram(u / v0, bins=edges, weights=w)
    out["counts"] = np.rint(count).astype(np.int64)
    if field:
        out.update(starts=blocks[inner] + first, masses=w.copy(), vsums=vsums[inner].copy())
    return out


def velocity_field(n: int, starts, masses, vsums) -> np.ndarray:
    """The per-particle velocities v_i, i = 0 … N − 1, of clusters given by their first labels,
    masses and momenta Σ v, in any order; a cluster may wrap through label 0 (the seam's).

    Parameters
    ----------
    n : int
        The number of particles N.
    starts : array_like of int
        Each cluster's first label.
    masses : array_like
        Each cluster's mass (number of particles); they sum to N.
    vsums : array_like
        Each cluster's total momentum.

    Returns
    -------
    numpy.ndarray
        v of shape (N,): label i carries its cluster's velocity Σ v / m.

    Raises
    ------
    ValueError
        If the masses do not sum to N.
    """
    order = np.argsort(starts, kind="stable")
    m = np.asarray(masses)[order].astype(np.int64)
    u = np.asarray(vsums)[order] / m
    first = int(np.asarray(starts)[order[0]])
    run = np.repeat(u, m)  # labels first, first + 1, … (mod N), in order
    if run.size != n:
        raise ValueError(f"the clusters hold {run.size} particles, not N = {n}")
    return np.roll(run, first)


def _spectrum_of(v: np.ndarray) -> dict:
    """S(k) and C(r), r = 0 … ⌊N/2⌋, of the per-particle velocities ``v``, as the single
    engine's ``simulate sticky --structure-factor`` gives them."""
    from .observables import correlation, structure_factor

    k, s = structure_factor(v)
    return {"k": k, "S": s, "C": correlation(v)[: v.size // 2 + 1]}


def _single(params, times, seed, edges, start, structure_factor) -> ChunkedResult:
    """K = 1: the single-process engine, run by the driver."""
    from .driver import simulate
    from .sticky import StickyGas
    from .sticky_observables import cluster_mass_distribution

    run = simulate(StickyGas(params), times, seed, progress=False, bins=edges)
    clusters = run.extras["clusters"].astype(np.int64)
    m, mass_counts = cluster_mass_distribution(run.final_state)
    spectrum = _spectrum_of(run.final_state.velocities) if structure_factor else {}
    return ChunkedResult(
        params=params.to_dict(), seed=int(seed), chunks=1, times=times, energy=run.energy,
        kurtosis=run.kurtosis,
        momentum=run.extras["total_momentum"], clusters=clusters, collisions=run.collisions,
        masses=m, mass_counts=mass_counts, histogram=run.histogram, edge=None,
        seconds=_time.perf_counter() - start, **spectrum,
    )


#: Bytes per particle that S(k) and C(r) take on the client: the velocity field (8), its
#: half-spectrum (8) and the correlation (8).
SPECTRUM_BYTES = 24


class _Reached(Exception):
    """A pooled block reached a chunk's interior: ask again with a larger edge."""


def _join(parts: list[dict], length: float):
    """The ring's clusters among the edge blocks: (masses, velocity sums, first labels) of the
    clusters that are not interior sentinels.  Raises :class:`_Reached` when a sentinel was
    pooled."""
    from scipy.optimize import isotonic_regression

    means = np.concatenate([p["means"] for p in parts])
    weights = np.concatenate([p["weights"] for p in parts])
    vsums = np.concatenate([p["vsums"] for p in parts])
    starts = np.concatenate([p["starts"] for p in parts])
    flags = np.concatenate([p["flags"] for p in parts]).astype(np.int64)
    fit = isotonic_regression(means, weights=weights)
    b = fit.blocks[:-1]
    sizes = np.diff(fit.blocks)
    flagged = np.add.reduceat(flags, b)
    if np.any((flagged > 0) & (sizes > 1)):
        raise _Reached
    bm, bw = fit.x[b], np.add.reduceat(weights, b)
    bv = np.add.reduceat(vsums, b)
    bs = starts[b]
    i, j, _ = pool_junction(bm, bw, length)
    if j > 0:
        if np.any(flagged[i:]) or np.any(flagged[:j]):
            raise _Reached
        keep = np.flatnonzero(flagged[j:i] == 0) + j
        masses = np.append(bw[keep], bw[i:].sum() + bw[:j].sum())
        sums = np.append(bv[keep], bv[i:].sum() + bv[:j].sum())
        firsts = np.append(bs[keep], bs[i])  # the seam's cluster starts at block i
    else:
        keep = np.flatnonzero(flagged == 0)
        masses, sums, firsts = bw[keep], bv[keep], bs[keep]
    return masses, sums, firsts


class ChunkedResult:
    """The outputs of :func:`simulate_chunks`.

    Parameters
    ----------
    **fields
        The attributes below, by name.

    Attributes
    ----------
    params : dict
        The gas's parameters (``StickyParams.to_dict()``).
    seed, chunks : int
        The run's seed and number of chunks K.
    times : numpy.ndarray
        The output times t (physical time).
    energy : numpy.ndarray
        ⟨v²⟩ per particle at each time.
    kurtosis : numpy.ndarray
        ⟨v⁴⟩/⟨v²⟩² at each time (NaN where every velocity is 0).
    momentum : numpy.ndarray
        Σ v at each time (zero up to round-off).
    clusters, collisions : numpy.ndarray
        The number of clusters and N − clusters at each time.
    masses, mass_counts : numpy.ndarray
        The cluster-mass distribution at the last time: the masses present and how many
        clusters have each.
    histogram : particles.observables.Histogram or None
        Particles' x = v/√E at the last time (None when E = 0).
    edge : int or None
        The largest edge the joins used (None for K = 1).
    seconds : float
        Wall time of the run.
    k, S, C : numpy.ndarray
        Only with ``structure_factor``: k = 2πm/N, S(k) = |v̂(k)|²/N with v̂(k) = Σ_j v_j e^{−ikj}
        over the labels j at the last time (:func:`particles.observables.structure_factor`),
        and C(r) for r = 0 … ⌊N/2⌋ (:func:`particles.observables.correlation`).
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)

    def to_dict(self) -> dict:
        """The outputs as JSON-ready values (lists and numbers).

        Returns
        -------
        dict
            ``model``, ``params``, ``seed``, ``chunks``, ``t``, ``energy``, ``kurtosis`` (null
            where undefined), ``momentum``,
            ``clusters``, ``collisions``, ``mass_distribution`` (``m``, ``count``),
            ``histogram``, ``edge``, ``seconds``; and ``k``, ``S``, ``C`` when S(k) was asked.
        """
        out = {
            "model": "sticky", "params": self.params, "seed": self.seed, "chunks": self.chunks,
            "t": self.times.tolist(), "energy": self.energy.tolist(),
            "kurtosis": [float(k) if math.isfinite(k) else None for k in self.kurtosis],
            "momentum": self.momentum.tolist(), "clusters": self.clusters.tolist(),
            "collisions": self.collisions.tolist(),
            "mass_distribution": {"m": self.masses.tolist(), "count": self.mass_counts.tolist()},
            "histogram": None if self.histogram is None else self.histogram.to_dict(),
            "edge": self.edge, "seconds": self.seconds,
        }
        for key in ("k", "S", "C"):
            if key in self.__dict__:
                out[key] = self.__dict__[key].tolist()
        return out


def simulate_chunks(params: StickyParams, times, seed: int, chunks: int, *, client=None,
                    bins=None, progress=None, structure_factor: bool = False) -> ChunkedResult:
    """The sticky gas of ``params`` at ``times`` as ``chunks`` chunks (module docstring).

    Parameters
    ----------
    params : particles.sticky.StickyParams
        The gas (N, the ring's length L, the initial velocity law).
    times : array_like
        Output times t (physical time), nondecreasing, finite, ≥ 0.
    seed : int
        The seed; chunk k draws from ``SeedSequence(seed).spawn(chunks)[k]`` (K = 1: the
        single engine's ``default_rng(seed)``); the initial state is normalised over the whole
        ring (module docstring).
    chunks : int
        K, in [1, N/2].
    client : distributed.Client, optional
        Runs the chunk tasks; None runs them here, one after another.  The result does not
        depend on it.
    bins : array_like, optional
        The histogram's edges in x = v/√E (default
        :data:`particles.observables.DEFAULT_EDGES`).
    progress : callable, optional
        ``progress(done, total)`` after each time.
    structure_factor : bool
        Also compute S(k) and C(r) at the last time.  The chunks return their clusters (first
        label, mass, momentum) and this process builds the velocity field and its FFT:
        :data:`SPECTRUM_BYTES` bytes a particle here, refused when that exceeds half the
        memory available.

    Returns
    -------
    ChunkedResult

    Raises
    ------
    InvalidArgumentError
        For a ``params`` that is not a StickyParams, bad ``times`` (booleans included),
        ``seed`` (an integer >= 0), ``chunks`` or ``bins``, a ``structure_factor`` that is
        not a bool or does not fit in memory, a ``client`` without ``submit`` and ``gather``,
        or a ``progress`` that is not callable.
    """
    from .observables import DEFAULT_EDGES, rescaled_histogram

    if not isinstance(params, StickyParams):
        raise InvalidArgumentError("params", params, "a StickyParams")
    if (np.asarray(times).dtype == bool if isinstance(times, np.ndarray) else any(
            isinstance(t, (bool, np.bool_))
            for t in (times if isinstance(times, (list, tuple)) else [times]))):
        raise InvalidArgumentError("t", times, "times, not booleans")
    times = check_times(times, "t")
    seed = check_count(seed, "seed", 0)  # as the single engine's driver checks it
    chunks = check_chunks(chunks, params.n)
    if not isinstance(structure_factor, bool):
        raise InvalidArgumentError("structure_factor", structure_factor, "True or False")
    if client is not None and not (hasattr(client, "submit") and hasattr(client, "gather")):
        raise InvalidArgumentError("client", client, "a distributed.Client or None")
    if progress is not None and not callable(progress):
        raise InvalidArgumentError("progress", progress, "a callable progress(done, total)")
    # the histogram's edges, checked as the single engine checks them
    edges = rescaled_histogram(np.array([1.0, -1.0]), DEFAULT_EDGES if bins is None
                               else bins).edges
    pd = params.to_dict()
    n = params.n
    if structure_factor:
        need, have = SPECTRUM_BYTES * n, available_memory()
        if need > have / 2:
            raise InvalidArgumentError(
                "structure_factor", True,
                f"S(k) for N = {n} needs {format_bytes(need)} in this process; "
                f"{format_bytes(have)} available (at most half may be used)")
    start = _time.perf_counter()
    if chunks == 1:
        return _single(params, times, seed, edges, start, structure_factor)

    def run(fn, *args, norms=None):
        extra = [() if norms is None else (norms[k],) for k in range(chunks)]
        if client is None:
            return [fn(pd, seed, k, chunks, *extra[k], *args) for k in range(chunks)]
        futures = [client.submit(fn, pd, seed, k, chunks, *extra[k], *args, pure=False)
                   for k in range(chunks)]
        return client.gather(futures)  # in chunk order

    norms = ring_normalisation(run(chunk_moments), n, params.initial)

    energy, momentum, clusters, kurtosis = [], [], [], []
    edge = EDGE
    for step, t in enumerate(times):
        while True:
            parts = run(chunk_summary, float(t), edge, norms=norms)
            try:
                masses, sums, firsts = _join(parts, params.length)
                break
            except _Reached:
                edge *= 4
        e_sum = math.fsum([p["energy"] for p in parts]) + math.fsum(sums * sums / masses)
        energy.append(e_sum / n)
        joined = sums / masses
        fourth = (math.fsum([p["fourth"] for p in parts])
                  + math.fsum(masses * (joined * joined) ** 2)) / n
        kurtosis.append(fourth / energy[-1] ** 2 if energy[-1] > 0.0 else math.nan)
        momentum.append(math.fsum([p["momentum"] for p in parts]))
        clusters.append(sum(p["count"] for p in parts) + masses.size)
        if progress is not None:
            progress(step + 1, len(times))
    # the last time: the mass distribution and the histogram of x = v/√E
    values = np.concatenate([p["masses"][0] for p in parts] + [masses.astype(np.int64)])
    counts = np.concatenate([p["masses"][1] for p in parts] + [np.ones(masses.size, np.int64)])
    m, inverse = np.unique(values, return_inverse=True)
    mass_counts = np.bincount(inverse, weights=counts).astype(np.int64)
    histogram, spectrum = None, {}
    if energy[-1] > 0.0 or structure_factor:
        v0 = math.sqrt(energy[-1]) if energy[-1] > 0.0 else 1.0
        rows = run(chunk_last, float(times[-1]), edge, v0, edges, bool(structure_factor),
                   norms=norms)
        if energy[-1] > 0.0:
            count = np.sum([r["counts"] for r in rows], axis=0)
            extra, _ = np.histogram(sums / masses / v0, bins=edges, weights=masses)
            count = count + np.rint(extra).astype(np.int64)
            histogram = histogram_from_counts(edges, count, n, v0)
        if structure_factor:
            v = velocity_field(
                n, np.concatenate([r["starts"] for r in rows] + [firsts]),
                np.concatenate([r["masses"] for r in rows] + [masses]),
                np.concatenate([r["vsums"] for r in rows] + [sums]))
            del rows
            spectrum = _spectrum_of(v)
    clusters = np.array(clusters, dtype=np.int64)
    return ChunkedResult(
        params=pd, seed=int(seed), chunks=chunks, times=times, energy=np.array(energy),
        kurtosis=np.array(kurtosis), momentum=np.array(momentum), clusters=clusters,
        collisions=n - clusters, masses=m,
        mass_counts=mass_counts, histogram=histogram, edge=edge,
        seconds=_time.perf_counter() - start, **spectrum,
    )
