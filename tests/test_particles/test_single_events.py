"""Single collisions by hand: every engine against numbers computed here from the paper's rule.

The engines and their sequential references share :mod:`particles.collision`, so agreement
between them cannot reveal an error in the rule itself.  These tests state a handful of explicit
velocities and restitution coefficients, work out the outcome in the test from the rule written
in another algebraic form,

    v_a' = ((1 − r) v_a + (1 + r) v_b) / 2,    v_b' = ((1 + r) v_a + (1 − r) v_b) / 2,

(for the vector models: the same along the collision direction n, the transverse part
unchanged), and compare to 1e-12 relative.  A change of 1e-4 in the transfer fraction moves
every outcome here by more than 1e-5, so it fails every test of this file.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from particles import Lattice, LatticeState, MDEngine, MDParams, MDState
from particles.lattice import run_clocks, thinning_bound
from particles.md.kernel import collide as md_collide
from particles.pair_schedule import collide_in_order, collide_sequential
from particles.sticky import sticky_state
from particles.ulam_kinematics import collide_vectors

RESTITUTIONS = [0.0, 0.3, 0.6, 0.95, 1.0]


def by_hand(va: float, vb: float, r: float) -> tuple[float, float]:
    """The rule of the paper, written as the weighted means it amounts to."""
    return ((1 - r) * va + (1 + r) * vb) / 2, ((1 + r) * va + (1 - r) * vb) / 2


def close(a, b):
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-14)


# -- Ulam (mean field, d = 1): explicit pairs, fast path and reference --

@pytest.mark.parametrize("r", RESTITUTIONS)
@pytest.mark.parametrize("collide", [collide_in_order, collide_sequential])
def test_ulam_one_collision_by_hand(collide, r):
    v = np.array([1.25, -0.5, 2.0, 0.0])
    out = collide(v, np.array([[0, 1]]), r)
    a, b = by_hand(1.25, -0.5, r)
    close(out, [a, b, 2.0, 0.0])
    assert v[0] == 1.25  # the input is not modified


@pytest.mark.parametrize("collide", [collide_in_order, collide_sequential])
def test_ulam_two_collisions_sharing_a_particle_by_hand(collide):
    # particle 1 collides with 0, then the result with 2: the order of the pairs is time order
    r = 0.4
    v = np.array([1.0, -1.0, 3.0])
    out = collide(v, np.array([[0, 1], [1, 2]]), r)
    a, b = by_hand(1.0, -1.0, r)
    b, c = by_hand(b, 3.0, r)
    close(out, [a, b, c])
    # momentum conserved, energy lost by (1 − r²)/4 · Δ² per collision
    assert out.sum() == pytest.approx(3.0, rel=1e-15)
    loss = (1 - r**2) / 4 * ((1.0 + 1.0) ** 2 + (by_hand(1.0, -1.0, r)[1] - 3.0) ** 2)
    assert 0.5 * (np.sum(v**2) - np.sum(out**2)) == pytest.approx(loss, rel=1e-13)


# -- Ulam in d = 2, 3: the vector rule along n --

@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
@pytest.mark.parametrize("d", [2, 3])
def test_vector_collision_by_hand(d, r):
    rng = np.random.default_rng(7)
    va = rng.normal(size=(1, d))
    vb = rng.normal(size=(1, d))
    n = rng.normal(size=(1, d))
    n /= np.linalg.norm(n)
    a0, b0 = va.copy()[0], vb.copy()[0]
    collide_vectors(va, vb, n, (1 + r) / 2)
    # decompose along n and across it: the normal parts follow the 1D rule, the rest is kept
    un = n[0]
    an, bn = by_hand(a0 @ un, b0 @ un, r)
    close(va[0], a0 - (a0 @ un) * un + an * un)
    close(vb[0], b0 - (b0 @ un) * un + bn * un)


# -- Lattice: one bond fires, both rates --

def _lattice_state(v, clocks, attempt_rate=None):
    return LatticeState(0.0, np.array(v, dtype=float), np.array(clocks, dtype=float),
                        attempt_rate=attempt_rate)


@pytest.mark.parametrize("r", RESTITUTIONS)
def test_lattice_constant_rate_one_collision_by_hand(r):
    # bond 0 ticks at τ = 0.2 and its pair approaches (1 > −1); the other clocks are far away
    engine = Lattice(4, r)
    rng = np.random.default_rng(3)
    following = 0.2 + copy.deepcopy(rng).standard_exponential(1)[0]
    assert following > 0.25  # the next tick of bond 0 falls after the window (seed chosen so)
    out = engine.advance(_lattice_state([1.0, -1.0, 0.5, 0.0], [0.2, 9, 9, 9]), 0.25, rng)
    a, b = by_hand(1.0, -1.0, r)
    close(out.velocities, [a, b, 0.5, 0.0])
    assert (out.collisions, out.attempts) == (1, 1)
    close(out.clocks, [following, 9, 9, 9])


def test_lattice_constraint_refuses_a_receding_pair_by_hand():
    # bond 1 joins −1 and 0.5: they recede, so the tick is an attempt but no collision
    out = Lattice(4, 0.5).advance(_lattice_state([1.0, -1.0, 0.5, 0.0], [9, 0.1, 9, 9]), 0.15,
                                  np.random.default_rng(3))
    close(out.velocities, [1.0, -1.0, 0.5, 0.0])
    assert (out.collisions, out.attempts) == (0, 1)
    # without the constraint the same tick collides
    out = Lattice(4, 0.5, constraint=False).advance(
        _lattice_state([1.0, -1.0, 0.5, 0.0], [9, 0.1, 9, 9]), 0.15, np.random.default_rng(3))
    a, b = by_hand(-1.0, 0.5, 0.5)
    close(out.velocities, [1.0, a, b, 0.0])


def test_lattice_relative_velocity_rate_thinning_by_hand():
    """Rate ∝ |Δ|: a tick of bond b collides iff u·R < Δ_b, u the uniform mark drawn at the tick.

    Bond 2 (0.5 → −0.5, Δ = 1) ticks alone with R = max v − min v = 2 (and its 1e-9 margin): it is
    accepted with probability 1/2; the seeds below give both outcomes."""
    v = [1.0, -1.0, 0.5, -0.5]
    bound = thinning_bound(np.array(v))
    assert bound == pytest.approx(2.0, rel=2e-9)
    engine = Lattice(4, 0.7, rate="relative_velocity")
    outcomes = set()
    for seed in range(8):
        rng = np.random.default_rng(seed)
        mark = copy.deepcopy(rng).random(1)[0]
        out = engine.advance(_lattice_state(v, [9, 9, 0.3, 9], attempt_rate=bound), 0.3001, rng)
        accepted = mark * bound < 1.0
        outcomes.add(accepted)
        if accepted:
            a, b = by_hand(0.5, -0.5, 0.7)
            close(out.velocities, [1.0, -1.0, a, b])
        else:
            close(out.velocities, v)
        assert (out.collisions, out.attempts) == (int(accepted), 1)
    assert outcomes == {True, False}


def test_lattice_relative_velocity_threshold_is_the_mark_times_the_bound():
    """A tick of bond 0 (Δ = 1.5) with R = 2 collides iff u · 2 < 1.5: marks 1e-4 either side of
    u = 3/4 (far above round-off) give both outcomes, so u · R is checked to 1e-4."""
    for u, collides in ((0.75 * (1 - 1e-4), True), (0.75 * (1 + 1e-4), False)):
        for constraint in (True, False):
            v = np.array([1.0, -0.5, 0.0, 0.0])
            clocks = np.array([0.1, 9.0, 9.0, 9.0])
            attempts, collisions, _ = run_clocks(v, clocks, 1.0, 0.75, constraint,
                                                 lambda b: np.full(b.size, 5.0),
                                                 marks=lambda b, u=u: np.full(b.size, u),
                                                 rate_bound=2.0)
            a, b = by_hand(1.0, -0.5, 0.5)  # p = 0.75: r = 0.5
            close(v, [a, b, 0.0, 0.0] if collides else [1.0, -0.5, 0.0, 0.0])
            assert (attempts, collisions) == (1, int(collides))


class _UnitWaits:
    """A Generator whose exponential waits are all 1 and whose uniform marks are all 0.9."""

    def __init__(self):
        self._rng = np.random.default_rng(0)

    def standard_exponential(self, size):
        return np.ones(size)

    def random(self, size):
        return np.full(size, 0.9)

    def __getattr__(self, name):
        return getattr(self._rng, name)


def test_lattice_relative_velocity_clocks_run_at_the_bound_by_hand():
    """Rate ∝ |Δ|: every bond's clock ticks at the common rate R, so a wait is Exp(1)/R; a state
    whose clocks ran at another rate R_old has its residual waits (clock − time) rescaled by
    R_old/R (memoryless).  With unit waits and marks 0.9 (0.9 R ≈ 1.8 > Δ = 1: rejected):
    R_old = 4, clocks (0.4, 9, 0.1, 9) become 4/R times themselves; bond 2 ticks at 0.4/R < 0.3
    and waits 1/R more, to 1.4/R; nothing else ticks before 0.3.  Round-off only: 1e-12."""
    v = [1.0, -1.0, 0.5, -0.5]
    bound = thinning_bound(np.array(v))
    out = Lattice(4, 0.7, rate="relative_velocity").advance(
        _lattice_state(v, [0.4, 9.0, 0.1, 9.0], attempt_rate=4.0), 0.3, _UnitWaits())
    close(out.clocks, np.array([1.6, 36.0, 1.4, 36.0]) / bound)
    close(out.velocities, v)
    assert (out.collisions, out.attempts, out.attempt_rate) == (0, 1, bound)


def test_lattice_vectorized_clocks_one_collision_by_hand():
    v = np.array([2.0, 0.0, 0.0, -1.0, 0.0])
    clocks = np.array([0.1, 9.0, 9.0, 0.2, 9.0])
    attempts, collisions, _ = run_clocks(v, clocks, 1.0, 0.8, True, lambda b: np.full(b.size, 5.0))
    a, b = by_hand(2.0, 0.0, 0.6)  # p = 0.8: r = 0.6
    # bond 3 joins sites 3 and 4 (−1 and 0): they recede, an attempt but no collision
    close(v, [a, b, 0.0, -1.0, 0.0])
    assert (attempts, collisions) == (2, 1)
    close(clocks, [5.1, 9.0, 9.0, 5.2, 9.0])


# -- MD: two collisions of hard rods on a ring, worked out by hand --

@pytest.mark.parametrize("method", ["fast", "reference"])
@pytest.mark.parametrize("r", [0.3, 0.6, 0.9])
def test_md_two_collisions_by_hand(method, r):
    """Three point rods on a ring of length 4: x = (0, 1, 2), v = (1, −1, 0).

    Rods 0 and 1 meet at t = 0.5 at x = 0.5.  Then rod 1 moves at v1' towards rod 2 at rest
    (gap 1.5) and meets it at t = 0.5 + 1.5/v1'; rod 0 moves left at v0' < 0 towards rod 2 across
    the seam (gap 2.5), which it reaches later.
    """
    engine = MDEngine(MDParams(n=3, density=0.75, restitution=r), method)
    state = MDState(0.0, np.array([0.0, 1.0, 2.0]), np.zeros(3), np.array([1.0, -1.0, 0.0]), 0)
    v0, v1 = by_hand(1.0, -1.0, r)
    t2 = 0.5 + 1.5 / v1
    t_seam = 0.5 + 2.5 / (0.0 - v0)
    assert t2 < t_seam
    mid = 0.5 * (0.5 + t2)
    s = engine.advance(state, mid)
    assert s.collisions == 1
    close(s.velocities, [v0, v1, 0.0])
    close(s.positions_at(mid), [0.5 + v0 * (mid - 0.5), 0.5 + v1 * (mid - 0.5), 2.0])
    after = t2 + 0.1 * (min(t_seam, t2 + 1.0) - t2)
    s = engine.advance(s, after)
    assert s.collisions == 2
    v1b, v2 = by_hand(v1, 0.0, r)
    close(s.velocities, [v0, v1b, v2])
    close(s.positions_at(after), [0.5 + v0 * (after - 0.5), 2.0 + v1b * (after - t2),
                                  2.0 + v2 * (after - t2)])


def test_md_kernel_collision_by_hand_and_the_elastic_threshold():
    a, b, elastic = md_collide(1.0, -0.5, 0.75, 0.0, False)  # p = 0.75: r = 0.5
    close([a, b], by_hand(1.0, -0.5, 0.5))
    assert not elastic
    # below the threshold δ the rods exchange their velocities (an elastic collision)
    a, b, elastic = md_collide(1.0, 0.9, 0.75, 0.2, False)
    assert (a, b, elastic) == (0.9, 1.0, True)


# -- Sticky gas: clusters merge with the mean velocity of their mass --

def test_sticky_two_then_three_particles_by_hand():
    """x = (0, 1, 4), v = (1, −1, −2) on a ring of length 100.  Particles 0 and 1 merge at
    t = 0.5 at x = 0.5 (cluster of mass 2 at rest); particle 2 reaches it at t = 1.75 (gap 3.5 at
    speed 2) and the cluster of mass 3 moves at (0·2 − 2)/3 = −2/3 from x = 0.5."""
    x0 = np.array([0.0, 1.0, 4.0])
    v0 = np.array([1.0, -1.0, -2.0])
    s = sticky_state(x0, v0, 100.0, 1.0)
    assert s.collisions == 1
    close(s.velocities, [0.0, 0.0, -2.0])
    close(np.sort(np.mod(s.positions, 100.0)), [0.5, 2.0])
    s = sticky_state(x0, v0, 100.0, 2.5)
    assert s.collisions == 2
    close(s.velocities, [-2 / 3] * 3)
    close(np.mod(s.positions, 100.0), [0.5 - 2 / 3 * (2.5 - 1.75)])
    # momentum is conserved exactly by the merged clusters
    assert float(np.sum(s.masses * s.cluster_velocities)) == pytest.approx(-2.0, rel=1e-15)
