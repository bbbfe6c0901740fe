"""The sticky gas as K chunks against the single-process engine on the same initial state."""

import numpy as np
import pytest

import particles.sticky_chunks as sc
from particles.driver import simulate
from particles.observables import DEFAULT_EDGES, correlation, rescaled_histogram, structure_factor
from particles.sticky import (
    StickyGas,
    StickyParams,
    cluster_mass_distribution,
    sticky_state,
    total_momentum,
)
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


def test_the_chunks_draw_is_stratified_and_standardised():
    params = StickyParams(1001, 0.5)
    bounds = sc.chunk_bounds(1001, 4)
    assert bounds.tolist() == [0, 251, 501, 751, 1001]
    for k in range(4):
        x, v = sc.chunk_initial(params, 0, k, 4)
        lo, hi = params.length * bounds[k] / 1001, params.length * bounds[k + 1] / 1001
        assert x.size == bounds[k + 1] - bounds[k] and lo <= x[0] and x[-1] < hi
        assert abs(v.mean()) < 1e-15 and np.mean(v * v) == pytest.approx(1.0, rel=1e-14)
    # the positions are uniform order statistics: pooled over 200 seeds (50 000 positions of
    # one chunk), a Kolmogorov–Smirnov test of uniformity on the arc at the 1e-3 level
    from scipy.stats import kstest

    params = StickyParams(1000, 1.0)
    x = np.concatenate([sc.chunk_initial(params, s, 1, 4)[0] for s in range(200)])
    assert kstest((x - 250.0) / 250.0, "uniform").pvalue > 1e-3
    assert np.all(np.diff(sc.chunk_initial(params, 0, 2, 4)[0]) > 0)


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
