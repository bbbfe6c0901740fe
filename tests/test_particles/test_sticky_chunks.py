"""The sticky gas as K chunks against the single-process engine on the same initial state."""

import numpy as np
import pytest

import particles.sticky_chunks as sc
from particles.driver import simulate
from particles.observables import DEFAULT_EDGES, correlation, rescaled_histogram, structure_factor
from particles.sticky import StickyGas, StickyParams, sticky_state
from particles.sticky_observables import cluster_mass_distribution, total_momentum
from particles.validation import InvalidArgumentError

N, K = 20000, 5
TIMES = [0.0, 0.5, 5.0, 50.0, 500.0, 5000.0, 1e5]


def single_engine_on_the_chunks_draw(params, seed, chunks, times=TIMES):
    """The exact state of the whole ring from the K chunks' initial data, by the engine."""
    parts = [sc.chunk_initial(params, seed, k, chunks) for k in range(chunks)]
    x0 = np.concatenate([p[0] for p in parts])
    v0 = np.concatenate([p[1] for p in parts])
    assert np.all(np.diff(x0) >= 0) and x0[0] >= 0 and x0[-1] < params.length
    return [sticky_state(x0, v0, params.length, t) for t in times]


@pytest.mark.parametrize("edge", [1, sc.EDGE])
def test_chunks_equal_the_engine_on_the_same_initial_state(monkeypatch, edge):
    # edge = 1: a pooled block reaches past one block at most junctions, so the retry with 4x
    # the edge is exercised (the result must not depend on it).
    monkeypatch.setattr(sc, "EDGE", edge)
    params = StickyParams(N, 1.0)
    states = single_engine_on_the_chunks_draw(params, 3, K)
    res = sc.simulate_chunks(params, TIMES, 3, K)
    assert res.clusters.tolist() == [s.starts.size for s in states]
    assert res.collisions.tolist() == [s.collisions for s in states]
    np.testing.assert_allclose(res.energy, [np.mean(s.velocities**2) for s in states],
                               rtol=1e-12)
    kurtosis = [np.mean(s.velocities**4) / np.mean(s.velocities**2) ** 2 for s in states]
    np.testing.assert_allclose(res.kurtosis, kurtosis, rtol=1e-10)
    np.testing.assert_allclose(res.momentum, [total_momentum(s) for s in states], atol=1e-9)
    m, count = cluster_mass_distribution(states[-1])
    assert res.masses.tolist() == m.tolist() and res.mass_counts.tolist() == count.tolist()
    hist = rescaled_histogram(states[-1].velocities, DEFAULT_EDGES)
    assert np.abs(res.histogram.count - hist.count).sum() <= 2  # v0 differs in round-off only
    assert res.histogram.samples == N
    assert states[-1].starts[0] > 0 or states[-2].starts[0] > 0  # a cluster across the seam
    if edge == 1:
        assert res.edge > 1  # the retry happened


def test_one_chunk_is_the_single_process_engine():
    params = StickyParams(3000, 2.0, "uniform")
    res = sc.simulate_chunks(params, [1.0, 10.0, 100.0], 7, 1, structure_factor=True)
    run = simulate(StickyGas(params), [1.0, 10.0, 100.0], 7, progress=False,
                   structure_factor="last")
    assert np.array_equal(res.energy, run.energy)
    assert np.array_equal(res.kurtosis, run.kurtosis)
    assert res.to_dict()["kurtosis"] == run.summary()["kurtosis"]
    assert np.array_equal(res.histogram.count, run.histogram.count)
    assert res.clusters.tolist() == run.extras["clusters"].astype(int).tolist()
    assert np.array_equal(res.k, run.structure[0]) and np.array_equal(res.S, run.structure[1][-1])


@pytest.mark.parametrize("last", [0.0, 5.0, 50.0, 1e5])
def test_the_structure_factor_of_the_chunks_is_the_engines(monkeypatch, last):
    # S(k) and C(r) at the last time from the chunks' clusters, against the engine's velocities
    # on the same initial state: at t = 0 (every particle its own cluster), at times with
    # hundreds of clusters and at 1e5 (a few clusters, one across the seam).  The velocities
    # agree to round-off (a cluster's Σ v / m summed in another order), so S to 1e-9.
    monkeypatch.setattr(sc, "EDGE", 4)  # small edges: interior and joined clusters both occur
    params = StickyParams(N, 1.0)
    times = [t for t in TIMES if t < last] + [last]
    state = single_engine_on_the_chunks_draw(params, 5, K, times)[-1]
    res = sc.simulate_chunks(params, times, 5, K, structure_factor=True)
    k, s = structure_factor(state.velocities)
    assert np.array_equal(res.k, k)
    np.testing.assert_allclose(res.S, s, rtol=1e-9, atol=1e-12 * s.max())
    c = correlation(state.velocities)[: N // 2 + 1]
    np.testing.assert_allclose(res.C, c, rtol=0, atol=1e-9 * c[0])
    assert res.to_dict()["S"] == res.S.tolist()


def test_the_velocity_field_of_clusters_wraps_through_label_zero():
    # clusters of the labels {8, 9, 0, 1}, {2, 3, 4}, {5, 6, 7} given in any order
    v = sc.velocity_field(10, [5, 8, 2], [3, 4, 3], [3.0, -8.0, 1.5])
    assert v.tolist() == [-2.0, -2.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, -2.0, -2.0]
    with pytest.raises(ValueError, match="N = 11"):
        sc.velocity_field(11, [5, 8, 2], [3, 4, 3], [3.0, -8.0, 1.5])


def test_a_structure_factor_beyond_the_memory_is_refused(monkeypatch):
    monkeypatch.setattr(sc, "available_memory", lambda: 2.0 * sc.SPECTRUM_BYTES * 5999)
    with pytest.raises(InvalidArgumentError, match="structure_factor"):
        sc.simulate_chunks(StickyParams(6000, 1.0), [1.0], 0, 2, structure_factor=True)
    # exactly within half the memory: runs
    monkeypatch.setattr(sc, "available_memory", lambda: 2.0 * sc.SPECTRUM_BYTES * 6000)
    assert sc.simulate_chunks(StickyParams(6000, 1.0), [1.0], 0, 2,
                              structure_factor=True).S.size == 3001


def _ring(params, seed, chunks):
    """The chunks' initial data concatenated, and each chunk's velocities."""
    parts = [sc.chunk_initial(params, seed, k, chunks) for k in range(chunks)]
    return (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
            [p[1] for p in parts])


def test_one_chunk_draws_the_single_engines_initial_state_bit_for_bit():
    params = StickyParams(1001, 0.5, "laplace")
    x, v = sc.chunk_initial(params, 9, 0, 1)
    state = StickyGas(params).initial_state(np.random.default_rng(9))
    assert np.array_equal(x, state.positions) and np.array_equal(v, state.velocities)


def test_the_chunks_initial_state_is_normalised_over_the_whole_ring_not_per_chunk():
    # K = 4 chunks of N = 1001: the chunks' raw draws (spacings, velocities), put end to end,
    # are normalised as the single engine normalises its N values: positions L S_j / T (the
    # order statistics of N uniforms), velocities by the engine's own initial_velocities (its
    # shift and scale replayed on the same raw numbers): equal to round-off.
    from particles.driver import initial_velocities

    params = StickyParams(1001, 0.5)
    x, v, per_chunk = _ring(params, 3, 4)
    raw = [sc._chunk_draw(params, 3, k, 4) for k in range(4)]
    # the documented seeding: chunk k draws its spacings, then its velocities, from the k-th
    # child of SeedSequence(seed).spawn(K) (the last chunk one spacing more)
    for k, (gaps_k, v_k) in enumerate(raw):
        rng = np.random.default_rng(np.random.SeedSequence(3).spawn(4)[k])
        n_k = [251, 250, 250, 250][k]
        assert np.array_equal(gaps_k, rng.standard_exponential(n_k + (k == 3)))
        assert np.array_equal(v_k, rng.standard_normal(n_k))
    gaps = np.concatenate([r[0] for r in raw])
    assert gaps.size == 1002
    s = np.cumsum(gaps)
    np.testing.assert_allclose(x, params.length * s[:-1] / s[-1], rtol=1e-13)
    assert np.all(np.diff(x) >= 0) and x[0] >= 0 and x[-1] < params.length

    class Replay(np.random.Generator):  # the gaussian law's sampler calls standard_normal(n)
        def standard_normal(self, n):
            return np.concatenate([r[1] for r in raw])

    replay = Replay(np.random.PCG64(0))
    np.testing.assert_allclose(v, initial_velocities("gaussian", 1001, replay), rtol=1e-13,
                               atol=1e-15)
    # the ring: mean 0 and <v^2> = 1 to round-off ...
    assert abs(v.mean()) < 1e-15 and np.mean(v * v) == pytest.approx(1.0, rel=1e-14)
    # ... and no chunk by itself: its mean and energy keep their fluctuations, of order
    # 1/sqrt(250) = 0.06 and sqrt(2/250) = 0.09 (seed 3: each is > 1e-3 in some chunk)
    assert max(abs(c.mean()) for c in per_chunk) > 1e-3
    assert max(abs(np.mean(c * c) - 1.0) for c in per_chunk) > 1e-3


def test_the_chunks_initial_law_is_the_engines_above_the_chunk_scale():
    # K = 2 chunks of N = 1000 on a ring of L = 1000, over 200 seeds.  The engine's law: the
    # number of particles on the first half of the ring is Binomial(1000, 1/2), variance 250;
    # the momentum of the first 500 labels, of N exchangeable velocities with sum 0 and
    # sum of squares N, has variance n(N - n)/(N - 1) = 250.25.  Normalising each chunk by
    # itself (or placing exactly 500 particles on each half) makes either variance 0.  The
    # sample variance of 200 near-Gaussian values has a relative standard deviation
    # sqrt(2/199) = 0.10: tolerance +-40 % (4 sigma).
    params = StickyParams(1000, 1.0)
    counts, momenta = [], []
    for seed in range(200):
        x, v, _ = _ring(params, seed, 2)
        counts.append(np.count_nonzero(x < 500.0))
        momenta.append(v[:500].sum())
    assert np.var(counts, ddof=1) / 250.0 == pytest.approx(1.0, abs=0.4)
    assert np.var(momenta, ddof=1) / 250.25 == pytest.approx(1.0, abs=0.4)


def test_chunks_of_two_particles_keep_the_initial_law():
    # K = N/2: per-chunk normalisation made every velocity +-1; over the ring, |v| takes N
    # distinct values (a continuous law)
    params = StickyParams(100, 1.0)
    _, v, _ = _ring(params, 1, 50)
    assert np.unique(np.abs(v)).size == 100 and np.ptp(np.abs(v)) > 1.0


def test_chunks_give_the_engines_energy_decay():
    # E(t = 10) of N = 1000 over 40 seeds, K = 1 (the engine) against K = 50 chunks of 20
    # particles.  One seed's E scatters by about 10 % (measured sd 0.010 at E = 0.095), so the
    # difference of the two means has a standard error of about 0.0023, computed below from
    # the samples; they must agree within 4 of it.  (Per-chunk normalisation gave E = 0.062,
    # 35 % low, about 14 of these errors.)
    params = StickyParams(1000, 1.0)
    one = np.array([sc.simulate_chunks(params, [10.0], s, 1).energy[-1] for s in range(40)])
    many = np.array([sc.simulate_chunks(params, [10.0], s, 50).energy[-1]
                     for s in range(100, 140)])
    error = np.sqrt(one.var(ddof=1) / 40 + many.var(ddof=1) / 40)
    assert error < 0.004
    assert abs(one.mean() - many.mean()) < 4 * error


def test_a_dask_cluster_gives_the_same_numbers_bit_for_bit():
    distributed = pytest.importorskip("distributed")
    params = StickyParams(6000, 1.0)
    here = sc.simulate_chunks(params, [1.0, 30.0, 900.0], 11, 4, structure_factor=True)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = sc.simulate_chunks(params, [1.0, 30.0, 900.0], 11, 4, client=client,
                                   structure_factor=True)
    for key in ("energy", "momentum", "clusters", "S", "C"):
        assert np.array_equal(getattr(here, key), getattr(there, key)), key
    assert np.array_equal(here.histogram.count, there.histogram.count)


@pytest.mark.parametrize("chunks", [0, -1, 3001, 2.5, True, "x"])
def test_bad_chunks_are_named(chunks):
    with pytest.raises(InvalidArgumentError, match="chunks"):
        sc.simulate_chunks(StickyParams(6000, 1.0), [1.0], 0, chunks)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"seed": -1}, "seed"), ({"seed": True}, "seed"), ({"seed": 1.5}, "seed"),
        ({"seed": "1"}, "seed"), ({"seed": None}, "seed"),
        ({"times": [True]}, "t"), ({"times": [1.0, float("nan")]}, "t"),
        ({"structure_factor": "yes"}, "structure_factor"), ({"structure_factor": 1},
                                                            "structure_factor"),
        ({"bins": [1.0, 0.0]}, "bins"), ({"bins": [0.0, float("nan")]}, "bins"),
        ({"bins": [-np.inf, 0.0, 1.0]}, "bins"), ({"bins": "x"}, "bins"),
        ({"client": "x"}, "client"), ({"progress": 5}, "progress"),
    ],
)
def test_bad_arguments_are_named_before_any_work(kwargs, name):
    args = {"times": [1.0], "seed": 0, **kwargs}
    with pytest.raises(InvalidArgumentError) as err:
        sc.simulate_chunks(StickyParams(100, 1.0), args.pop("times"), args.pop("seed"), 2,
                           **args)
    assert err.value.name == name
