"""The d-dimensional and the driven Ulam models (particles.ulam): the round-parallel fast
path against a one-event-at-a-time loop on the same draws (bit for bit), the law of the
"hard" collision directions, the exact energy decay with its finite-N factor, momentum
conservation, agreement in distribution with an independent reference (rejection sampling,
global heating), and the driven steady state against the exact theory of
maxwell_kinetics.driven."""

import dataclasses
import math
import re

import numpy as np
import pytest
from scipy import stats

from maxwell_kinetics.driven import moments, steady_kurtosis, steady_variance
from maxwell_kinetics.tails import decay_rate
from particles.collision import collide_scalar
from particles.driver import simulate
from particles.pair_schedule import collide_in_order_vectors, collide_sequential_vectors, draw_pairs
from particles.ulam import Ulam, UlamReference, recentre
from particles.ulam_kinematics import (
    AngularDraws,
    collide_complex,
    collide_vectors,
    collision_directions,
    draw_angles,
    plane_transfer,
)
from particles.validation import InvalidArgumentError

ANGULAR = ("uniform", "hard")


def energy(v):
    """⟨|v|²⟩ per particle (all components)."""
    return float(np.mean(np.sum(np.reshape(v, (v.shape[0], -1)) ** 2, axis=1)))


@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
@pytest.mark.parametrize("n, k", [(2, 40), (7, 1500), (3000, 2000)])
def test_vector_fast_path_equals_sequential_loop(dimension, angular, n, k):
    rng = np.random.default_rng(n + k + dimension)
    v = rng.standard_normal((n, dimension))
    pairs = draw_pairs(rng, n, k)
    draws = draw_angles(rng, k, dimension, angular)
    fast = collide_in_order_vectors(v, pairs, 0.3, draws, angular)
    slow = collide_sequential_vectors(v, pairs, 0.3, draws, angular)
    assert np.array_equal(fast, slow)
    assert not np.array_equal(fast, v)
    assert np.allclose(fast.sum(0), v.sum(0), atol=1e-12 * n)
    assert energy(fast) < energy(v)


@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("angular, a", [("uniform", 0.5), ("hard", 1.0)])
def test_law_of_eta_is_beta(dimension, angular, a):
    # KS test of η = (ĝ·n)² against Beta(a, (d−1)/2), 2e5 events with random g.  For the exact
    # law the p-value is uniform; we require p > 1e-4 (one fixed seed).  Power: the other
    # model's Beta law is rejected with p < 1e-10.
    rng = np.random.default_rng(dimension)
    k = 200_000
    g = rng.standard_normal((k, dimension)) * rng.exponential(1.0, (k, 1))
    n = collision_directions(g, draw_angles(rng, k, dimension, angular), angular)
    assert np.allclose(np.sum(n * n, axis=1), 1.0, atol=1e-14)
    g_hat = g / np.linalg.norm(g, axis=1, keepdims=True)
    eta = np.sum(n * g_hat, axis=1) ** 2
    b = (dimension - 1) / 2
    assert stats.kstest(eta, stats.beta(a, b).cdf).pvalue > 1e-4
    assert stats.kstest(eta, stats.beta(1.5 - a, b).cdf).pvalue < 1e-10
    if dimension == 3:
        # the direction of n around ĝ is uniform: azimuth in a fixed frame ⟂ ĝ (KS, same rule)
        e1 = np.cross(g_hat, [1.0, 0.0, 0.0])
        e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
        e2 = np.cross(g_hat, e1)
        phi = np.arctan2(np.sum(n * e2, axis=1), np.sum(n * e1, axis=1))
        assert stats.kstest(phi, stats.uniform(-np.pi, 2 * np.pi).cdf).pvalue > 1e-4


@pytest.mark.parametrize("dimension, angular", [(2, "uniform"), (2, "hard"), (3, "hard")])
def test_directions_match_rejection_sampling(dimension, angular):
    # The construction against n uniform on the sphere, accepted with probability |ĝ·n| for
    # "hard" (always for "uniform"), for one fixed g: two-sample KS on each component of n,
    # 5e4 samples each, p > 1e-4.  In 2D this also checks that the side of ĝ that n falls on
    # is fair, which the law of η alone does not see.
    rng = np.random.default_rng(4 + dimension)
    g = np.array([[0.3, -1.2, 0.5][:dimension]])
    k = 50_000
    built = collision_directions(
        np.repeat(g, k, 0), draw_angles(rng, k, dimension, angular), angular
    )
    built *= np.sign(built @ g[0])[:, None]  # n and −n are the same collision
    z = rng.standard_normal((4 * k, dimension))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    cos = z @ (g[0] / np.linalg.norm(g[0]))
    accept = np.abs(cos) if angular == "hard" else 1.0
    kept = z[rng.random(4 * k) < accept][:k]
    kept *= np.sign(kept @ g[0])[:, None]
    for c in range(dimension):
        assert stats.ks_2samp(built[:, c], kept[:, c]).pvalue > 1e-4


def test_complex_rule_is_the_vector_rule():
    # d = 2 in complex numbers: for any unit n at angle φ from ĝ (n = ĝ e^{iφ}),
    # (g·n) n = g cos φ e^{iφ} = (g + ḡ n²)/2.  Checked for arbitrary g and n against
    # collide_vectors, to round-off (1e-14 of the speeds, ~50 ulp).  Then plane_transfer(s)
    # is p cos φ e^{iφ} with sin φ = s, cos φ ≥ 0 (−n is the same collision), and the engine's
    # rule collides along collision_directions (whose law the tests above check).
    rng = np.random.default_rng(11)
    m, p = 10_000, 0.35
    va = rng.standard_normal((m, 2)) * rng.exponential(1.0, (m, 1))
    vb = rng.standard_normal((m, 2))
    n = rng.standard_normal((m, 2))
    n /= np.linalg.norm(n, axis=1, keepdims=True)

    def as_complex(x):
        return x[:, 0] + 1j * x[:, 1]

    def both_rules(along, transfer):
        expect_a, expect_b = va.copy(), vb.copy()
        collide_vectors(expect_a, expect_b, along, p)
        ca, cb = as_complex(va), as_complex(vb)
        collide_complex(ca, cb, transfer)
        scale = 1e-14 * (np.abs(as_complex(va)) + np.abs(as_complex(vb)))
        assert np.all(np.abs(ca - as_complex(expect_a)) <= scale)
        assert np.all(np.abs(cb - as_complex(expect_b)) <= scale)
        return as_complex(va) - ca, scale

    g, nc = as_complex(va - vb), as_complex(n)
    e_phi = nc * np.conj(g) / np.abs(g)  # n / ĝ
    delta, scale = both_rules(n, p * e_phi.real * e_phi)
    assert np.all(np.abs(delta - p * (g + np.conj(g) * nc**2) / 2) <= scale)
    s = rng.uniform(-1.0, 1.0, m)
    phi = np.arcsin(s)
    assert np.allclose(plane_transfer(s, p), p * np.cos(phi) * np.exp(1j * phi), rtol=0, atol=1e-15)
    for angular in ANGULAR:
        draws = draw_angles(rng, m, 2, angular)
        both_rules(collision_directions(va - vb, draws, angular), plane_transfer(draws.sine, p))


def test_zero_relative_velocity_leaves_the_pair_unchanged():
    v = np.array([[1.0, 2.0, 3.0], [1.0, 2.0, 3.0], [0.0, 0.0, 0.0]])
    draws = AngularDraws(np.array([[0.3, 0.4, 0.1]]), np.array([0.5]))
    out = collide_in_order_vectors(v, [[0, 1]], 0.0, draws, "hard")
    assert np.array_equal(out, v)
    out = collide_in_order_vectors(v[:, :2], [[0, 1]], 0.0, AngularDraws(None, sine=[0.6]))
    assert np.array_equal(out, v[:, :2])
    n = collision_directions(np.zeros((1, 2)), AngularDraws(None, sine=np.array([0.6])), "hard")
    assert np.allclose(n, [[0.8, 0.6]])


def test_draws_of_the_wrong_shape_are_refused():
    v = np.zeros((4, 2))
    with pytest.raises(InvalidArgumentError, match="draws"):
        collide_in_order_vectors(v, [[0, 1]], 0.5, AngularDraws(np.ones((1, 2))))
    with pytest.raises(InvalidArgumentError, match="draws"):
        collide_in_order_vectors(v, [[0, 1]], 0.5, AngularDraws(None, sine=np.ones(2)))
    with pytest.raises(InvalidArgumentError, match="draws"):
        collide_in_order_vectors(np.zeros((4, 3)), [[0, 1]], 0.5, AngularDraws(None))


def test_engine_applies_the_drawn_events_exactly():
    # Replay the engine's draws (per window: Poisson count, pairs, angular draws; rows read
    # backwards are the events in time order) with the sequential loop, recentring at 4.
    engine = Ulam(300, 0.4, "uniform", dimension=2, angular="hard")
    state = engine.initial_state(np.random.default_rng(5))
    assert state.velocities.shape == (300, 2)
    assert np.allclose(state.velocities.mean(0), 0, atol=1e-15)
    assert np.allclose(np.mean(state.velocities**2, axis=0), 1.0)
    rng, replay = np.random.default_rng(9), np.random.default_rng(9)
    after = engine.advance(state, 5.3, rng)
    v = state.velocities
    collisions = 0
    for a, b in engine.windows(0.0, 5.3):
        k = int(replay.poisson(0.5 * engine.n * (b - a)))
        if k:
            pairs = draw_pairs(replay, engine.n, k)
            draws = draw_angles(replay, k, 2, "hard")
            draws = AngularDraws(None, sine=draws.sine[::-1])
            v = collide_sequential_vectors(v, pairs[::-1], 0.4, draws, "hard")
            collisions += k
        if b == 4.0:
            recentre(v)
    assert np.array_equal(after.velocities, v) and after.collisions == collisions
    # stopping on the stop grid and going on is the same run
    rng = np.random.default_rng(9)
    resumed = engine.advance(engine.advance(state, 4.0, rng), 5.3, rng)
    assert np.array_equal(resumed.velocities, after.velocities)
    back = engine.state_from_arrays(after.to_arrays())
    assert np.array_equal(back.velocities, after.velocities)


def test_driven_engine_applies_kicks_and_events_exactly():
    # Replay with a Python loop: per window the Poisson count, pairs, sorted times, two normals
    # per event; kick each particle for the time since its last kick, then collide; at the
    # stop grid (4) every particle is brought to the grid time, then recentred; final kick.
    engine = Ulam(200, 0.3, "laplace", driving=0.7)
    d2 = 2 * 0.7
    state = engine.initial_state(np.random.default_rng(1))
    rng, replay = np.random.default_rng(2), np.random.default_rng(2)
    after = engine.advance(state, 6.5, rng)
    v = state.velocities.tolist()
    last = [0.0] * engine.n
    for a, b in engine.windows(0.0, 6.5):
        k = int(replay.poisson(0.5 * engine.n * (b - a)))
        if k:
            pairs = draw_pairs(replay, engine.n, k)
            times = np.sort(replay.uniform(a, b, k))[::-1]
            kicks = replay.standard_normal((k, 2))
            for row in range(k - 1, -1, -1):
                i, j = int(pairs[row, 0]), int(pairs[row, 1])
                t = float(times[row])
                vi = v[i] + math.sqrt(d2 * (t - last[i])) * float(kicks[row, 0])
                vj = v[j] + math.sqrt(d2 * (t - last[j])) * float(kicks[row, 1])
                last[i] = last[j] = t
                v[i], v[j] = collide_scalar(vi, vj, engine.p)
        if b == 4.0:
            xi = replay.standard_normal(engine.n)
            arr = np.array(v) + np.sqrt(d2 * (4.0 - np.array(last))) * xi
            recentre(arr)
            v, last = arr.tolist(), [4.0] * engine.n
    arr = np.array(v) + np.sqrt(d2 * (6.5 - np.array(last))) * replay.standard_normal(engine.n)
    assert np.array_equal(after.velocities, arr)


@pytest.mark.parametrize(
    "dimension, angular", [(2, "uniform"), (2, "hard"), (3, "uniform"), (3, "hard")]
)
@pytest.mark.parametrize("cls", [Ulam, UlamReference])
def test_expected_energy_decays_with_the_finite_n_rate(dimension, angular, cls):
    # ⟨|v|²⟩(τ) = ⟨|v|²⟩(0) e^{−Λτ N/(N−1)}, Λ = 2pq⟨η⟩ (derivation: particles.ulam.Ulam).
    # N = 5, 600 seeds: standard error of the mean ratio ~0.01; tolerance 4 standard errors.
    # The infinite-N law e^{−Λτ} must be distinguishable at τ = 4 (asserted, > 4 s.e.).  The
    # reference too: its partner draw (any j ≠ i, uniformly) sets the rate N/(N−1).
    n, r = 5, 0.2
    lam = decay_rate(dimension, r, angular)
    taus = [1.0, 2.0, 4.0]
    engine = cls(n, r, dimension=dimension, angular=angular)
    rows = []
    for seed in range(600):
        rng = np.random.default_rng(seed)
        s = engine.initial_state(rng)
        e0 = energy(s.velocities)
        row = []
        for t in taus:
            s = engine.advance(s, t, rng)
            row.append(energy(s.velocities) / e0)
        rows.append(row)
    rows = np.array(rows)
    mean, se = rows.mean(0), rows.std(0, ddof=1) / np.sqrt(len(rows))
    exact = np.exp(-lam * np.array(taus) * n / (n - 1))
    assert np.all(np.abs(mean - exact) < 4 * se), (mean, exact, se)
    assert abs(mean[-1] - math.exp(-lam * 4.0)) > 4 * se[-1]


@pytest.mark.parametrize("dimension, angular", [(2, "hard"), (3, "uniform")])
def test_momentum_drift_is_round_off(dimension, angular):
    # Between stop-grid points (no recentring in (0, 3.9]) the total momentum changes only by
    # the final roundings of v_a − δ and v_b + δ: per component at most u(|v_a'| + |v_b'|) per
    # collision, and every speed stays below S = √(Σ|v|²(0)) (Σ|v|² never grows, up to
    # round-off), so |ΔP_c| ≤ 2uKS (slack ×2 for the round-off of S).
    engine = Ulam(5000, 0.5, dimension=dimension, angular=angular)
    rng = np.random.default_rng(3)
    s0 = engine.initial_state(rng)
    s1 = engine.advance(s0, 3.9, rng)
    k = s1.collisions - s0.collisions
    assert k > 0.4 * 5000 * 3.9
    bound = 2 * 2 * 2.0**-53 * k * math.sqrt(np.sum(s0.velocities**2))
    for c in range(dimension):
        drift = abs(math.fsum(s1.velocities[:, c]) - math.fsum(s0.velocities[:, c]))
        assert drift <= bound, (drift, bound)


def _reference_stats(cls, kwargs, tau, seeds):
    rows = []
    for seed in range(seeds):
        engine = cls(**kwargs)
        rng = np.random.default_rng(seed)
        s = engine.advance(engine.initial_state(rng), tau, rng)
        v = s.velocities.reshape(s.velocities.shape[0], -1)
        sq = np.sum(v * v, axis=1)
        rows.append([sq.mean(), np.mean(sq * sq) / sq.mean() ** 2])
    return np.array(rows)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"n": 40, "restitution": 0.3, "dimension": 2, "angular": "hard"},
        {"n": 40, "restitution": 0.3, "dimension": 2, "angular": "uniform"},
        {"n": 40, "restitution": 0.3, "dimension": 3, "angular": "uniform"},
        {"n": 40, "restitution": 0.3, "driving": 0.5, "initial": "uniform"},
    ],
    ids=["2d-hard", "2d-uniform", "3d-uniform", "driven"],
)
def test_fast_engine_and_independent_reference_agree_in_distribution(kwargs):
    # The reference draws exponential waiting times, "hard" directions by rejection and heats
    # every particle over each waiting time.  400 seeds each; means of E and of the flatness
    # ⟨|v|⁴⟩/⟨|v|²⟩² at τ = 3 compared by a two-sample z-test, |z| < 4.
    fast = _reference_stats(Ulam, kwargs, 3.0, 400)
    ref = _reference_stats(UlamReference, kwargs, 3.0, 400)
    z = (fast.mean(0) - ref.mean(0)) / np.sqrt(fast.var(0) / 400 + ref.var(0) / 400)
    assert np.all(np.abs(z) < 4), z


def test_driven_finite_n_steady_energy():
    # Centred steady energy D (N−1)²/(pq N²) (particles.ulam.Ulam): N = 5 makes the factor
    # 0.64 visible.  120 seeds, energies at τ = 24, 28, …, 96 (recentred stop points; the
    # energy relaxes at rate 2pq N/(N−1) ≈ 0.68, so samples 4 apart are nearly independent);
    # the per-seed averages give the standard error; tolerance 4 standard errors, and the
    # infinite-N value D/(pq) must be > 4 s.e. away.
    n, r, drive = 5, 0.4, 0.5
    p = 0.7
    engine = Ulam(n, r, driving=drive)
    taus = np.arange(24.0, 97.0, 4.0)
    per_seed = [simulate(engine, taus, seed, progress=False).energy.mean() for seed in range(120)]
    mean, se = np.mean(per_seed), np.std(per_seed, ddof=1) / np.sqrt(len(per_seed))
    exact = drive / (p * (1 - p)) * (n - 1) ** 2 / n**2
    assert abs(mean - exact) < 4 * se, (mean, exact, se)
    assert abs(mean - drive / (p * (1 - p))) > 4 * se


@pytest.mark.parametrize("r", [0.0, 0.6])
def test_driven_steady_variance_and_kurtosis(r):
    # N = 1e4 (finite-N corrections O(1/N) = 1e-4, negligible), from a Gaussian of variance 1,
    # sampled at τ = 40, 44, …, 120 (M2 and M4 relax at rates 2pq ≥ 0.32 and 2pq(2 − pq):
    # e^{−0.32·40} ≈ 3e-6).  Standard errors from the spread of 12 seeds' averages; tolerance
    # 4 s.e. (Student t with 11 degrees of freedom: false alarm ~0.2 %; with only 6 seeds the
    # s.e. estimate was too noisy: seeds 0-5 at r = 0.6, τ ≤ 80, N = 2e4 gave 5.7 s.e., while 48
    # other seeds gave 3.5231 ± 0.0028 against 3.5217).  The s.e. must be small enough to tell
    # the kurtosis from a Gaussian's 3.
    drive = 0.4
    engine = Ulam(10_000, r, driving=drive)
    taus = np.arange(40.0, 121.0, 4.0)
    m2, kurt = [], []
    for seed in range(12):
        res = simulate(engine, taus, seed, progress=False, snapshots=True)
        v = res.snapshots
        m2.append(np.mean(v**2, axis=1).mean())
        kurt.append((np.mean(v**4, axis=1) / np.mean(v**2, axis=1) ** 2).mean())
    for values, exact in ((m2, steady_variance(r, drive)), (kurt, steady_kurtosis(r))):
        mean, se = np.mean(values), np.std(values, ddof=1) / np.sqrt(len(values))
        assert abs(mean - exact) < 4 * se, (mean, exact, se)
    assert steady_kurtosis(r) - 3 > 8 * np.std(kurt, ddof=1) / np.sqrt(12)


def test_driven_transient_moments_follow_the_moment_equations():
    # From a Gaussian (M2 = 1, M4 = 3), the exact M2(τ), M4(τ) of maxwell_kinetics.driven.moments.
    # N = 1e5, 4 seeds: the relative standard error of M4 is ~√(M8/M4² − 1)/√(4N) ≈ 0.5 %;
    # tolerance 4 s.e. from the seed spread (finite-N corrections ~1e-5).
    r, drive = 0.5, 1.5
    taus = np.array([0.5, 1.0, 3.0])
    engine = Ulam(100_000, r, driving=drive)
    m2, m4 = [], []
    for seed in range(4):
        res = simulate(engine, taus, seed, progress=False, snapshots=True)
        m2.append(np.mean(res.snapshots**2, axis=1))
        m4.append(np.mean(res.snapshots**4, axis=1))
    exact2, exact4 = moments(taus, r, drive, 1.0, 3.0)
    for sample, exact in ((np.array(m2), exact2), (np.array(m4), exact4)):
        se = sample.std(0, ddof=1) / 2
        assert np.all(np.abs(sample.mean(0) - exact) < 4 * se + 1e-12), (sample.mean(0), exact)


def test_default_keywords_keep_the_one_dimensional_engine():
    a = Ulam(300, 0.6, "laplace")
    b = Ulam(300, 0.6, "laplace", dimension=1, angular="hard", driving=0.0)
    assert a.to_dict() == b.to_dict()
    assert set(a.to_dict()) == {"n", "restitution", "initial", "window"}
    rng_a, rng_b = np.random.default_rng(1), np.random.default_rng(1)
    va = a.advance(a.initial_state(rng_a), 5.0, rng_a).velocities
    vb = b.advance(b.initial_state(rng_b), 5.0, rng_b).velocities
    assert np.array_equal(va, vb)
    assert Ulam(10, 0.5, dimension=2).to_dict()["dimension"] == 2
    assert Ulam(10, 0.5, driving=0.3).to_dict()["driving"] == 0.3


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"dimension": 4}, "dimension=4"),
        ({"dimension": True}, "dimension=True"),
        ({"dimension": 2, "angular": "soft"}, "angular='soft'"),
        ({"driving": -0.5}, "driving=-0.5"),
        ({"driving": float("nan")}, "driving=nan"),
        ({"driving": 0.5, "dimension": 2}, "driving=0.5"),
    ],
)
def test_bad_parameters_are_named(kwargs, match):
    with pytest.raises(InvalidArgumentError, match=match):
        Ulam(10, 0.5, **kwargs)


@pytest.mark.parametrize("d", [2, 3])
def test_fortran_ordered_input_is_handled(d):
    rng = np.random.default_rng(2)
    v = np.asfortranarray(rng.standard_normal((50, d)))
    pairs = draw_pairs(rng, 50, 200)
    draws = draw_angles(rng, 200, d, "hard")
    fast = collide_in_order_vectors(v, pairs, 0.5, draws, "hard")
    slow = collide_sequential_vectors(np.ascontiguousarray(v), pairs, 0.5, draws, "hard")
    assert np.array_equal(fast, slow) and not np.array_equal(fast, v)


@pytest.mark.parametrize("d", [2, 3])
def test_d_dimensional_runs_go_through_the_driver(tmp_path, d):
    # energy ⟨|v|²⟩ and |⟨v⟩| recorded per time, histogram of one component, checkpoint and
    # resume bit for bit; S(k) is refused (it belongs to d = 1)
    from particles.driver import RunResult, simulate

    engine = Ulam(2000, 0.5, dimension=d)
    full = simulate(engine, [0.5, 1.0, 2.0], 3, progress=False)
    v = full.velocities
    assert v.shape == (2000, d)
    assert full.energy[-1] == float(np.mean(np.einsum("ij,ij->i", v, v)))
    assert full.momentum[-1] < 1e-12 and full.histogram.samples == 2000
    ckpt = tmp_path / "c.npz"
    simulate(engine, [0.5, 1.0, 2.0], 3, progress=False, checkpoint=ckpt)
    again = simulate(engine, [0.5, 1.0, 2.0], 3, progress=False, resume=ckpt)
    assert np.array_equal(again.velocities, v) and np.array_equal(again.energy, full.energy)
    full.save(tmp_path / "r.npz")
    assert np.array_equal(RunResult.load(tmp_path / "r.npz").velocities, v)
    with pytest.raises(InvalidArgumentError, match="structure_factor"):
        simulate(engine, [1.0], 3, progress=False, structure_factor=True)


@pytest.mark.parametrize(("d", "angular"), [(2, "uniform"), (2, "hard"), (3, "uniform")])
def test_component_kurtosis_follows_the_exact_moment_hierarchy(d, angular):
    # At r = 0 the fourth moment moves far from the Gaussian 3; the exact isotropic hierarchy
    # (maxwell_kinetics.scaling_tails.rescaled_coefficients) gives ⟨x⁴⟩/⟨x²⟩² = 24 C₂(τ) for
    # one rescaled component.  N = 2·10⁵, every component pooled, 6 seeds; tolerance 4 standard
    # errors of the seed mean (Student t, 5 dof: two-sided 1 %).  This checks the law of the
    # collision rule and of its angle draws as a whole, not bit for bit.
    from maxwell_kinetics.scaling_tails import rescaled_coefficients

    taus = [1.0, 3.0]
    exact = 24.0 * rescaled_coefficients(d, 0.0, taus, n_max=2, angular=angular)[:, 2]
    rows = []
    for seed in range(6):
        engine = Ulam(200_000, 0.0, dimension=d, angular=angular)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        row = []
        for tau in taus:
            state = engine.advance(state, tau, rng)
            x = state.velocities.ravel()
            row.append(np.mean(x**4) / np.mean(x**2) ** 2)
        rows.append(row)
    rows = np.array(rows)
    se = rows.std(axis=0, ddof=1) / math.sqrt(rows.shape[0])
    assert np.all(np.abs(rows.mean(axis=0) - exact) < 4 * se)
    assert exact[-1] - 3.0 > 0.25  # far from Gaussian: the test has something to see


@pytest.mark.parametrize("d, angular", [(2, "uniform"), (3, "uniform"), (3, "hard")])
def test_no_events_leave_the_velocities_unchanged(d, angular):
    """K = 0 events: both loops return an unchanged copy (the fast path's reversed draws are
    empty too, not a row read from the end)."""
    rng = np.random.default_rng(3)
    v = rng.normal(size=(5, d))
    draws = draw_angles(rng, 0, d, angular)
    for collide in (collide_in_order_vectors, collide_sequential_vectors):
        out = collide(v, np.empty((0, 2), dtype=np.int32), 0.4, draws, angular)
        np.testing.assert_array_equal(out, v)
        assert out is not v


def _vector_events(d, angular, k=3, seed=4):
    rng = np.random.default_rng(seed)
    return (rng.normal(size=(4, d)), np.array([[0, 1], [2, 3], [1, 2]][:k]),
            draw_angles(rng, k, d, angular))


@pytest.mark.parametrize("d", [2, 3])
def test_vector_loops_take_integer_velocities_as_floats(d):
    v, pairs, draws = _vector_events(d, "uniform")
    v_int = np.arange(4 * d).reshape(4, d) * 3
    for collide in (collide_in_order_vectors, collide_sequential_vectors):
        out = collide(v_int, pairs, 0.3, draws)
        assert out.dtype == np.float64
        np.testing.assert_array_equal(out, collide(v_int.astype(float), pairs, 0.3, draws))


def test_vector_loops_default_to_the_uniform_law():
    for d in (2, 3):
        v, pairs, draws = _vector_events(d, "uniform")
        for collide in (collide_in_order_vectors, collide_sequential_vectors):
            np.testing.assert_array_equal(collide(v, pairs, 0.3, draws),
                                          collide(v, pairs, 0.3, draws, "uniform"))


@pytest.mark.parametrize("collide", [collide_in_order_vectors, collide_sequential_vectors])
def test_vector_loops_refuse_bad_velocities_and_draws(collide):
    v, pairs, draws = _vector_events(3, "hard")
    for bad in (v[:, 0], v[:, :1]):
        shape = re.escape(str(bad.shape))
        with pytest.raises(InvalidArgumentError,
                           match=rf"argument v='array of shape {shape}' is invalid: "
                                 r"expected shape \(N, d\), d >= 2"):
            collide(bad, pairs, 0.3, draws, "hard")
    wrong_draws = r"argument draws='arrays of other shapes' is invalid: expected one draw per event"
    for bad in (dataclasses.replace(draws, eta=None), dataclasses.replace(draws, eta=draws.eta[:2]),
                dataclasses.replace(draws, z=draws.z[:2])):
        with pytest.raises(InvalidArgumentError, match=wrong_draws):
            collide(v, pairs, 0.3, bad, "hard")
    v2, pairs2, draws2 = _vector_events(2, "uniform")
    with pytest.raises(InvalidArgumentError, match=wrong_draws):
        collide(v2, pairs2, 0.3, dataclasses.replace(draws2, sine=draws2.sine[:2]))
    with pytest.raises(InvalidArgumentError, match=r"argument pairs=.*expected shape \(K, 2\)"):
        collide(v, pairs[:, :1], 0.3, draws, "hard")


def test_plane_rounds_count_and_row_scatter_in_the_plane():
    """The round loops return their number of rounds: events (0, 1) then (1, 2) share a
    particle (2 rounds), (0, 1) and (2, 3) do not (1 round), no events 0 rounds.  And the row
    scatter of (N, 2) arrays (one complex per row) writes exactly the given rows."""
    from particles.pair_schedule import fire_rounds, fire_rounds_plane, fire_rounds_with_rows
    from particles.ulam_kinematics import scatter_rows

    for pairs, rounds in (([[0, 1], [1, 2]], 2), ([[0, 1], [2, 3]], 1), (np.empty((0, 2)), 0)):
        reversed_pairs = np.ascontiguousarray(np.asarray(pairs)[::-1], dtype=np.int32)
        k = len(reversed_pairs)

        def scratch(k=k):
            return np.empty(4, np.int32), np.arange(2 * k, dtype=np.int32)

        transfer = plane_transfer(np.zeros(k), 0.5)
        assert fire_rounds_plane(np.arange(4, dtype=complex), reversed_pairs, transfer,
                                 *scratch()) == rounds
        assert fire_rounds(np.arange(4.0), reversed_pairs, 0.5, *scratch()) == rounds
        assert fire_rounds_with_rows(np.arange(4.0), reversed_pairs, *scratch(),
                                     lambda v, fired, rows: None) == rounds
    v = np.arange(10, dtype=float).reshape(5, 2)
    scatter_rows(v, np.array([3, 0]), np.array([[-1.0, -2.0], [-3.0, -4.0]]))
    np.testing.assert_array_equal(v, [[-3, -4], [2, 3], [4, 5], [-1, -2], [8, 9]])


def test_angular_draws_hold_only_what_their_law_uses():
    """As documented by AngularDraws: d = 3 "uniform" draws only the normals (no η), "hard"
    also η (K,); d = 2 only sin φ (K,)."""
    rng = np.random.default_rng(0)
    uniform3, hard3 = draw_angles(rng, 4, 3, "uniform"), draw_angles(rng, 4, 3, "hard")
    assert uniform3.z.shape == (4, 3) and uniform3.eta is None and uniform3.sine is None
    assert hard3.z.shape == (4, 3) and hard3.eta.shape == (4,) and hard3.sine is None
    for angular in ("uniform", "hard"):
        plane = draw_angles(rng, 4, 2, angular)
        assert plane.z is None and plane.eta is None and plane.sine.shape == (4,)


def test_angular_draws_are_the_quantiles_of_their_laws():
    """Each draw is the quantile of its law at the engine's own uniform u, so the law's CDF at the
    draw gives u back (to round-off, 1e-12), a check at every draw with no sampling error.

    d = 3 "hard": η = (ĝ·n)² ~ Beta(1, (d − 1)/2) = Beta(1, 1) (density ∝ |cos θ| sin θ),
    CDF 1 − (1 − η)^{(d−1)/2} = η (scipy's Beta CDF here); d = 2 "uniform": φ uniform on
    [−π/2, π/2] with sin φ = cos(π u), i.e. arccos(sin φ)/π = u; d = 2 "hard": density
    ∝ |cos φ| dφ = |d sin φ|, sin φ = 2u − 1."""
    k = 1000
    replay = np.random.default_rng(5)
    replay.standard_normal((k, 3))  # z is drawn first
    u = replay.random(k)
    eta = draw_angles(np.random.default_rng(5), k, 3, "hard").eta
    np.testing.assert_allclose(stats.beta(1.0, 1.0).cdf(eta), u, rtol=1e-12, atol=1e-14)
    u = np.random.default_rng(6).random(k)
    sine = draw_angles(np.random.default_rng(6), k, 2, "uniform").sine
    np.testing.assert_allclose(np.arccos(sine) / np.pi, u, rtol=1e-12, atol=1e-12)
    sine = draw_angles(np.random.default_rng(6), k, 2, "hard").sine
    np.testing.assert_allclose((sine + 1) / 2, u, rtol=1e-12, atol=1e-14)


def test_hard_direction_in_three_dimensions_by_hand():
    """g = (2, 0, 0), z = (5, 3, 0), η = 0.36: ĝ = x̂, the part of z across ĝ is ŷ, so
    n = √η x̂ + √(1 − η) ŷ = (0.6, 0.8, 0); its (ĝ·n)² is η."""
    draws = AngularDraws(np.array([[5.0, 3.0, 0.0]]), np.array([0.36]))
    n = collision_directions(np.array([[2.0, 0.0, 0.0]]), draws, "hard")
    np.testing.assert_allclose(n, [[0.6, 0.8, 0.0]], rtol=0, atol=1e-15)


@pytest.mark.parametrize("cls, kwargs", [
    (Ulam, {}),
    (UlamReference, {}),
    (Ulam, {"dimension": 2}),
    (Ulam, {"driving": 0.5}),
    (UlamReference, {"driving": 0.5}),
    (UlamReference, {"dimension": 2, "angular": "hard"}),
])
def test_collisions_are_counted_from_the_state_onwards(cls, kwargs):
    """The pair collisions of an advance are a Poisson count of mean Nτ/2 (τ: collisions per
    particle), added to the state's own count.  N = 40 over τ = 30 (through seven stop points):
    mean 600, tolerance 5 standard deviations (√600 ≈ 24.5) on one draw."""
    n, tau = 40, 30.0
    engine = cls(n, 0.5, **kwargs)
    rng = np.random.default_rng(5)
    start = dataclasses.replace(engine.initial_state(rng), collisions=10_000)
    end = engine.advance(start, tau, rng)
    counted = end.collisions - 10_000
    assert abs(counted - n * tau / 2) < 5 * math.sqrt(n * tau / 2), counted
    # the event budget's estimate is that mean (the driver refuses runs beyond the budget)
    assert engine.expected_events(tau, 1) == (n * tau / 2, "collisions")


def test_the_driven_reference_heats_every_particle_and_recentres_at_the_stop_points():
    """Elastic (r = 1) and driven: collisions keep the energy, the noise adds 2D per unit τ to
    each particle's ⟨v²⟩, and the recentring at the stop point τ = 4 removes the mean's square,
    of expectation 2D·4/N.  At τ = 6: E⟨v²⟩ − ⟨v²⟩(0) = 2D·6 − 2D·4/N = 5.9 (D = 1/2, N = 40).
    300 seeds; the per-seed increments give the standard error (~0.08); tolerance 5 of them.
    At τ = 8, a stop point, the mean velocity is zero to round-off."""
    n, drive = 40, 0.5
    engine = UlamReference(n, 1.0, driving=drive)
    gains, means = [], []
    for seed in range(300):
        rng = np.random.default_rng(seed)
        s0 = engine.initial_state(rng)
        s6 = engine.advance(s0, 6.0, rng)
        gains.append(np.mean(s6.velocities**2) - np.mean(s0.velocities**2))
        means.append(abs(engine.advance(s6, 8.0, rng).velocities.mean()))
    mean, se = np.mean(gains), np.std(gains, ddof=1) / math.sqrt(len(gains))
    exact = 2 * drive * 6.0 - 2 * drive * 4.0 / n
    assert abs(mean - exact) < 5 * se, (mean, exact, se)
    assert max(means) < 1e-13, max(means)


def test_recentring_removes_each_components_mean():
    """Recentring subtracts the mean velocity, component by component in d ≥ 2, in place."""
    rng = np.random.default_rng(2)
    for shape, shift in [((50,), 3.0), ((50, 2), np.array([3.0, -7.0])),
                         ((50, 3), np.array([1.0, 2.0, -4.0]))]:
        base = rng.standard_normal(shape)
        base -= base.mean(axis=0)
        v = base + shift
        recentre(v)
        np.testing.assert_allclose(v.mean(axis=0), 0.0, atol=1e-14)
        np.testing.assert_allclose(v, base, atol=1e-14)


@pytest.mark.parametrize("kwargs", [{}, {"dimension": 2}, {"dimension": 3, "angular": "hard"},
                                    {"driving": 0.5}])
def test_the_engine_recentres_at_its_stop_points(kwargs):
    """At a stop point (a multiple of ``stop_step``) the mean velocity is zero to round-off in
    every component, whatever the noise and the collisions added."""
    engine = Ulam(200, 0.5, **kwargs)
    rng = np.random.default_rng(8)
    state = engine.initial_state(rng)
    state = dataclasses.replace(state, velocities=state.velocities + 0.5)  # a moving gas
    end = engine.advance(state, 2 * engine.stop_step, rng)
    assert np.all(np.abs(np.mean(end.velocities, axis=0)) < 1e-13)


@pytest.mark.parametrize("cls", [Ulam, UlamReference])
def test_advance_to_the_state_time_is_a_no_op(cls):
    engine = cls(30, 0.5)
    rng = np.random.default_rng(1)
    state = engine.advance(engine.initial_state(rng), 1.0, rng)
    same = engine.advance(state, 1.0, rng)
    assert same.time == 1.0 and same.collisions == state.collisions
    np.testing.assert_array_equal(same.velocities, state.velocities)
    with pytest.raises(InvalidArgumentError, match=r"^argument until=0\.5 is invalid: expected "
                                                   r"a time >= 1\.0$"):
        engine.advance(state, 0.5, rng)


def test_memory_estimate_covers_the_two_copies_of_the_velocities():
    """An advance holds the state it was given and the new one: two arrays of d float64 per
    particle at least, which the estimate used by the memory budget must cover in every d."""
    for d in (1, 2, 3):
        engine = Ulam(100, 0.5, dimension=d)
        assert engine.memory_per_particle() >= 2 * 8 * d


def test_parameters_are_recorded_under_their_documented_names():
    """``to_dict`` (recorded with every result, compared on resume) names what sets the random
    stream: the 1D keys, plus dimension and angular law, driving, or the relative-velocity rate's
    density and sub-window sizes (no fixed window then)."""
    from particles.pair_schedule import BLOCK_WINDOWS

    base = Ulam(100, 0.5).to_dict()
    assert set(base) == {"n", "restitution", "initial", "window"}
    assert Ulam(100, 0.5, dimension=2, angular="hard").to_dict() == {
        **base, "dimension": 2, "angular": "hard"}
    assert Ulam(100, 0.5, driving=0.25).to_dict() == {**base, "driving": 0.25}
    dsmc = Ulam(100, 0.5, rate="relative_velocity", density=2.0).to_dict()
    assert dsmc == {"n": 100, "restitution": 0.5, "initial": base["initial"],
                    "rate": "relative_velocity", "density": 2.0, "target_events": 100,
                    "block_windows": BLOCK_WINDOWS}
    assert Ulam(50_000, 0.5, rate="relative_velocity").to_dict()["target_events"] == 25_000
