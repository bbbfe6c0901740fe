"""Tests written to kill wrong constants of 0.1 % that passed the whole suite before,
each derived by hand or exactly, never from a number read off a run:

* ``test_md_initial_points_fill_the_whole_reduced_ring``: MD's initial points drawn on 99.9 % of
  the reduced ring (``MDEngine.initial_state``, particles/md/engine.py) instead of all of it; the
  gap across the seam is then ≥ 0.1 % of the ring, which uniform points leave with probability
  ~1e-20 at N = 50 000 (the test's threshold: p = 1e-9 per seed, exact law of that gap).
* ``test_lattice_first_clocks_are_unit_exponentials_over_the_rate``: the lattice's first clocks
  of the rate-|Δ| variant drawn at rate 1.001 R (``Lattice.initial_state``, particles/lattice.py)
  instead of R; checked exactly by replaying the same seed: clocks = E/R, E the unit
  exponentials drawn right after the velocities, R = (max v − min v)(1 + margin) by hand.
* ``test_one_thinned_dsmc_candidate_by_hand``: one candidate of the hard-rod DSMC (the Ulam
  engine with ``rate="relative_velocity"``, particles/ulam.py and particles/pair_schedule.py)
  traced by hand: the Poisson mean n(N − 1)BΔt/2, the pair, the mark U, the decision
  U·B < |v_a − v_b| with the velocities set 1e-4 (relative) on either side of the threshold,
  and the collision rule v_a − p g, v_b + p g; a 0.1 % change of the bound, of the acceptance
  or of p fails it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from particles.driver import initial_velocities
from particles.lattice import RATE_BOUND_MARGIN, Lattice
from particles.md import MDEngine, MDParams
from particles.ulam import Ulam, UlamState

# ----------------------------------------------------------------------------- 1. MD positions

#: Seeds and N of the MD check.
MD_SEEDS = range(5)
MD_N = 50_000
#: Per-seed false-alarm probability of the seam-gap check.
SEAM_P = 1e-9


def _seam_gap_survival(u: float, n: int) -> float:
    """P(G > u·L) for the gap G = L − max + min across the seam (the point 0) of n independent
    uniform points on [0, L): G/L ~ Beta(2, n − 1) (the spacing that covers a fixed point), so
    P(G/L > u) = (1 − u)^n + n u (1 − u)^(n−1)."""
    return (1.0 - u) ** n + n * u * (1.0 - u) ** (n - 1)


def _seam_gap_threshold(n: int, p: float) -> float:
    """The u with P(G/L > u) = p (bisection of the decreasing survival function)."""
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _seam_gap_survival(mid, n) > p:
            lo = mid
        else:
            hi = mid
    return hi


def test_md_initial_points_fill_the_whole_reduced_ring():
    """The initial points are N sorted uniform draws on the reduced ring [0, L − Nσ).  With σ > 0
    the reduced length is computed here by hand, L − Nσ = N/n − Nσ.

    Seam gap: G = (L − Nσ) − max x + min x.  Uniform points leave G > u(L − Nσ) with probability
    (1 − u)^N + N u (1 − u)^(N−1); the threshold u* solves that = 1e-9 (u* ≈ 23.8/N = 4.8e-4 at
    N = 50 000; five seeds: family-wise false alarm 5e-9).  Points spread over 99.9 % of the
    ring have G ≥ 1e-3 (L − Nσ) > u*(L − Nσ) for every seed.

    KS: the points scaled by L − Nσ against U(0, 1), p-value ≥ 1e-4 for each seed (five seeds:
    family-wise 5e-4); it catches a wrong law, not the 0.1 % shrink (that would need N ~ 4e6)."""
    density, sigma = 0.8, 0.25
    reduced = MD_N / density - MD_N * sigma  # L − Nσ by hand
    u_star = _seam_gap_threshold(MD_N, SEAM_P)
    assert 20.0 / MD_N < u_star < 30.0 / MD_N  # ≈ 23.8/N: e^{−s}(1 + s) = 1e-9
    assert u_star < 1e-3  # the planted shrink (1e-3 of the ring) is beyond it
    engine = MDEngine(MDParams(MD_N, density, 0.9, rod_length=sigma))
    for seed in MD_SEEDS:
        state = engine.initial_state(np.random.default_rng(seed))
        x = np.asarray(state.positions)
        assert state.time == 0.0 and np.all(state.t_last == 0.0)
        assert np.all(np.diff(x) >= 0.0)  # sorted
        assert x[0] >= 0.0 and x[-1] < reduced
        gap = reduced - x[-1] + x[0]
        assert gap <= u_star * reduced, (seed, gap / reduced, u_star)
        assert stats.kstest(x / reduced, "uniform").pvalue >= 1e-4, seed


# -------------------------------------------------------------------------- 2. lattice clocks


@pytest.mark.parametrize("seed", [0, 1, 7])
def test_lattice_first_clocks_are_unit_exponentials_over_the_rate(seed):
    """``initial_state`` draws the velocities (:func:`particles.driver.initial_velocities`),
    then N unit exponentials E; the clocks are E (constant rate) or E/R (rate-|Δ|, R the bound
    (max v − min v)(1 + margin) ≥ every |v_i − v_j|).  Replaying the same seed gives E and the
    velocities exactly, so the clocks must equal E/R bit for bit, and the generator must end in
    the same state (no other draws).  A clock rate of 1.001 R changes every clock by 1e-3."""
    n = 1000
    for rate in ("constant", "relative_velocity"):
        engine = Lattice(n, 0.7, rate=rate)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        replay = np.random.default_rng(seed)
        v = initial_velocities("gaussian", n, replay)
        e = replay.standard_exponential(n)
        np.testing.assert_array_equal(state.velocities, v)
        assert rng.bit_generator.state == replay.bit_generator.state
        assert state.time == 0.0 and state.collisions == 0 and state.attempts == 0
        if rate == "constant":
            assert state.attempt_rate is None
            np.testing.assert_array_equal(state.clocks, e)
            continue
        assert 0.0 < RATE_BOUND_MARGIN <= 1e-6  # ulp-level cover, not a change of the rate
        bound = float(v.max() - v.min()) * (1.0 + RATE_BOUND_MARGIN)
        assert state.attempt_rate == bound
        assert bound >= np.max(np.abs(np.diff(np.sort(v)))) and bound >= v.max() - v.min()
        np.testing.assert_array_equal(state.clocks, e / bound)


# ------------------------------------------------------------------- 7. one DSMC candidate


def _replay_window(seed: int, n: int, mean: float):
    """The draws of one sub-window of the thinned Ulam engine, in its documented order: the
    Poisson count K, the first particles (integers in [0, N)), the second ones (integers in
    [0, N − 1), shifted past the first), then K uniform marks."""
    rng = np.random.default_rng(seed)
    k = int(rng.poisson(mean))
    a = rng.integers(0, n, k, dtype=np.int32)
    b = rng.integers(0, n - 1, k, dtype=np.int32)
    b += b >= a
    marks = rng.random(k)
    return k, a, b, marks


def test_one_thinned_dsmc_candidate_by_hand():
    """N = 3 particles at v = (1, x, −1), density n = 2, r = 1/2 (p = 3/4), advanced to
    t = 1/4.  The bound B = (max − min)(1 + 1e-9) = 2(1 + 1e-9) does not depend on x, so neither
    do the draws.  Candidate rate n(N − 1)B/2 = 2B ≈ 4 per unit t, aiming at min(25 000, N) = 3
    per sub-window: h = 2^round(log2(3/4)) = 1 > 1/4, so [0, 1/4] is one sub-window (and no
    recentring: the stop step is 2^round(log2(4/n)) = 2).  Poisson mean 2B/4 = B/2.

    For seeds whose window holds exactly one candidate, on a pair (a, b) with mark U: if the pair
    is (0, 2) (|g| = 2 ≥ U·B always) it collides; otherwise x is chosen so that
    |g| = U·B·(1 ± 1e-4), just above or just below the threshold, and the candidate collides iff
    the sign is +.  A collision gives v_a − p g, v_b + p g (g = v_a − v_b); the time is 1/4 and
    the count of collisions 1 or 0."""
    n_particles, density, r, until = 3, 2.0, 0.5, 0.25
    p = (1.0 + r) / 2.0
    engine = Ulam(n_particles, r, rate="relative_velocity", density=density)
    assert engine.stop_step == 2.0 ** round(math.log2(4.0 / density))
    bound = 2.0 * (1.0 + 1e-9)
    assert engine.thinned_windows(0.0, until, bound) == [(0.0, until)]
    mean = 0.5 * density * (n_particles - 1) * bound * until
    seen = {"accepted": 0, "rejected": 0, "always": 0}
    for seed in range(60):
        k, a, b, marks = _replay_window(seed, n_particles, mean)
        if k != 1:
            continue
        ia, ib, u = int(a[0]), int(b[0]), float(marks[0])
        cases = [(None, True)] if {ia, ib} == {0, 2} else [(+1e-4, True), (-1e-4, False)]
        for eps, accept in cases:
            if eps is None:
                v = np.array([1.0, 0.25, -1.0])
                seen["always"] += 1
            else:
                # |g| = U·B(1 + eps): for (0, 1) |g| = 1 − x, for (1, 2) |g| = 1 + x
                g_abs = u * bound * (1.0 + eps)
                x = 1.0 - g_abs if 0 in (ia, ib) else g_abs - 1.0
                v = np.array([1.0, x, -1.0])
                assert abs(abs(v[ia] - v[ib]) / (u * bound) - 1.0 - eps) < 1e-9
                seen["accepted" if accept else "rejected"] += 1
            # the hull bound of this v is the one assumed above
            assert float(v.max() - v.min()) * (1.0 + 1e-9) == bound
            start = UlamState(0.0, v.copy(), 0)
            out = engine.advance(start, until, np.random.default_rng(seed))
            expected = v.copy()
            if accept:
                g = v[ia] - v[ib]
                expected[ia], expected[ib] = v[ia] - p * g, v[ib] + p * g
            assert out.time == until
            assert out.collisions == int(accept), (seed, eps)
            np.testing.assert_allclose(out.velocities, expected, rtol=0, atol=1e-15)
            if not accept:
                np.testing.assert_array_equal(out.velocities, v)
    assert seen["accepted"] >= 3 and seen["rejected"] >= 3 and seen["always"] >= 1, seen


def test_dsmc_candidate_count_has_the_hand_mean():
    """The number of candidates in a sub-window of length Δt is Poisson with the hand mean
    μ = n(N − 1)BΔt/2.  N = 2 particles at v = (1, −1) (B = 2(1 + 1e-9), every candidate of the
    first pair accepted: |g| = 2 > U·B), density n = 2: μ = B·Δt, one sub-window while Δt < 1
    (h = 2^round(log2(2/B)) = 1, stop step 2).  For a seed, μ* is where the replayed count
    ``rng.poisson(μ)`` (the window's first draw) jumps from 0 to 1, found by bisection; then a run
    to Δt = μ*(1 − 1e-4)/B has no collision and one to μ*(1 + 1e-4)/B at least one.  A candidate
    rate 0.1 % off moves the jump by 1e-3 and fails one side."""
    n_particles, density = 2, 2.0
    engine = Ulam(n_particles, 0.5, rate="relative_velocity", density=density)
    bound = 2.0 * (1.0 + 1e-9)
    per_time = 0.5 * density * (n_particles - 1) * bound  # μ per unit Δt
    v = np.array([1.0, -1.0])
    checked = 0
    for seed in range(10):
        def count(mu, seed=seed):
            return int(np.random.default_rng(seed).poisson(mu))

        lo, hi = 0.0, 0.999 * per_time  # a jump with Δt < 1
        if count(hi) == 0:
            continue
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if count(mid) == 0 else (lo, mid)
        if hi < 0.05 * per_time:
            continue
        below, above = hi * (1 - 1e-4) / per_time, hi * (1 + 1e-4) / per_time
        assert engine.thinned_windows(0.0, above, bound) == [(0.0, above)]
        out = engine.advance(UlamState(0.0, v.copy(), 0), below, np.random.default_rng(seed))
        assert out.collisions == 0 and out.time == below
        np.testing.assert_array_equal(out.velocities, v)
        out = engine.advance(UlamState(0.0, v.copy(), 0), above, np.random.default_rng(seed))
        assert out.collisions >= 1 and out.time == above, seed
        checked += 1
    assert checked >= 3
