"""The causal-depth count of particles/md/analysis.py (the bound quoted in benchmarks/README.md,
"How much parallelism there is"), on hand-made states whose collisions are known."""

import numpy as np
import pytest

from particles.md import MDEngine, MDParams, MDState
from particles.md import analysis as bench


def state(x, v):
    x = np.array(x, float)
    return MDState(0.0, x, np.zeros_like(x), np.array(v, float), 0)


def test_two_independent_inelastic_collisions_take_one_round():
    # pairs (0, 1) and (2, 3) meet at t = 0.5, 50 apart; the next contact is at t = 50.5
    params = MDParams(4, 0.04, 0.5)
    out = bench.causal_depth(params, state([0, 1, 50, 51], [1, -1, 1, -1]), 10.0)
    assert out["collisions"] == 2 and out["depth"] == 1 and out["per_round"] == 2.0
    assert out["inelastic"] == 2 and out["ghost_depth"] == 1
    assert out["replay_matches_reference"]


def test_newtons_cradle_is_a_chain_of_two_and_has_no_inelastic_round():
    # elastic: 0 hits 1 at t = 1, 1 hits 2 at t = 2 (the same particle 1: two rounds); as ghosts
    # the one carrier passes through both, so no inelastic collision and no round
    params = MDParams(3, 0.03, 1.0)
    out = bench.causal_depth(params, state([0, 1, 2], [1, 0, 0]), 10.0)
    assert out["collisions"] == 2 and out["depth"] == 2
    assert out["inelastic"] == 0 and out["ghost_depth"] == 0


def recount(record, n):
    """Depth by brute force: a collision's level is one more than the largest level of the
    earlier collisions that share a particle with it."""
    levels = []
    for k, (_, b) in enumerate(record):
        pair = {b, (b + 1) % n}
        before = [levels[m] for m in range(k) if pair & {record[m][1], (record[m][1] + 1) % n}]
        levels.append(1 + max(before, default=0))
    return max(levels)


@pytest.mark.parametrize("delta", [0.0, 0.3])
def test_depth_agrees_with_a_brute_force_count_on_a_random_gas(delta):
    params = MDParams(200, 1.0, 0.7, delta=delta)
    s0 = MDEngine(params).initial_state(np.random.default_rng(3))
    block = np.full(params.n, -1)
    block[10:20] = 0
    out = bench.causal_depth(params, s0, 3.0, block)
    rec = MDEngine(params, "reference", record=True)
    rec.advance(s0, 3.0)
    assert out["collisions"] == len(rec.record) > 100
    assert out["depth"] == recount(rec.record, params.n) > 1
    inside = sum(10 <= b < 19 for _, b in rec.record)
    assert out["in_blocks"] == inside > 0 and out["in_blocks_elastic"] <= inside
    assert out["replay_matches_reference"]
    if delta == 0.0:
        # no elastic exchange: carriers never move, the ghost graph is the full graph
        assert out["inelastic"] == out["collisions"] and out["ghost_depth"] == out["depth"]
        assert out["in_blocks_elastic"] == 0
    else:
        assert 0 < out["inelastic"] < out["collisions"]
        assert 0 < out["ghost_depth"] < out["depth"]


def test_cluster_anatomy_by_hand_with_gaps_and_spans_of_exactly_delta():
    # δ = 1/2, six point rods on a ring of length 6.  Gaps 0.25, 0.5, 1.25, 0.5, 1.5 and 2 (the
    # wrap): a gap below δ joins two rods, a gap of exactly δ does not, so the clusters are
    # {0, 1} and four single rods.  Velocities 0, 0.1, 0.2, 0.3, 0.49, 1: the first five span
    # 0.49 < δ, one soft block of 5; with 0.5 instead of 0.49 the span is exactly δ and the
    # block stops at 4 rods.
    params = MDParams(6, 1.0, 0.5, delta=0.5)
    x = [0.0, 0.25, 0.75, 2.0, 2.5, 4.0]
    out, block = bench.cluster_anatomy(params, state(x, [0.0, 0.1, 0.2, 0.3, 0.49, 1.0]))
    assert out["cluster_sizes"] == [2, 1, 1, 1, 1]
    assert out["soft_blocks"] == [5, 1] and out["particles_in_soft_blocks_of_5_or_more"] == 5
    assert block.tolist() == [0, 0, 0, 0, 0, -1]
    out, block = bench.cluster_anatomy(params, state(x, [0.0, 0.1, 0.2, 0.3, 0.5, 1.0]))
    assert out["soft_blocks"] == [4, 1, 1] and out["particles_in_soft_blocks_of_5_or_more"] == 0
    assert block.tolist() == [-1] * 6
