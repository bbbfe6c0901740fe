"""The Ulam model: exactness of the round-parallel fast path, exact energy decay, the scaling
solution f(x) = 2/(π(1+x²)²) with its x⁻⁴ tail, and agreement with a sequential reference."""

import dataclasses
import math
import re

import numpy as np
import pytest

from particles.driver import simulate
from particles.pair_schedule import collide_in_order, collide_sequential, draw_pairs
from particles.ulam import Ulam, UlamReference, recentre
from particles.validation import InvalidArgumentError


def scaling_cdf(x):
    """CDF of f(x) = 2/(π(1+x²)²): 1/2 + (arctan x + x/(1+x²))/π."""
    x = np.asarray(x, dtype=float)
    return 0.5 + (np.arctan(x) + x / (1 + x * x)) / np.pi


@pytest.mark.parametrize("n, k", [(2, 50), (7, 2000), (300, 5000), (5000, 2000)])
@pytest.mark.parametrize("r", [0.0, 0.37, 1.0])
def test_fast_path_equals_sequential_loop_on_the_same_events(n, k, r):
    # Few particles and many events make long dependency chains (many rounds); many particles
    # make wide rounds.  The updates must be identical, not merely close.
    rng = np.random.default_rng(n + k)
    v = rng.standard_normal(n)
    pairs = draw_pairs(rng, n, k)
    assert np.all(pairs[:, 0] != pairs[:, 1]) and pairs.min() >= 0 and pairs.max() < n
    fast = collide_in_order(v, pairs, r)
    slow = collide_sequential(v, pairs, r)
    assert np.array_equal(fast, slow)
    assert not np.array_equal(fast, v)
    assert abs(fast.sum() - v.sum()) < 1e-12 * n


def test_scatter_max_matches_the_order_independent_fallback():
    from particles.pair_schedule import largest_occurrence, largest_occurrence_ufunc

    rng = np.random.default_rng(3)
    flat = rng.integers(0, 500, 4000).astype(np.intp)  # many repeats per particle
    occ = np.arange(4000, dtype=np.int32)
    fast = largest_occurrence(np.empty(500, np.int32), flat, occ)
    exact = largest_occurrence_ufunc(np.empty(500, np.int32), flat, occ)
    assert np.array_equal(fast, exact)
    direct = np.array([occ[flat == p].max() for p in flat])
    assert np.array_equal(exact, direct)


def test_engine_applies_the_drawn_events_exactly():
    # Replay the engine's draws (window by window: Poisson count, then pairs; the drawn pairs
    # read backwards are the events in time order) with the sequential loop.
    engine = Ulam(400, 0.6, "laplace")
    state = engine.initial_state(np.random.default_rng(5))
    rng = np.random.default_rng(9)
    replay = np.random.default_rng(9)
    after = engine.advance(state, 3.3, rng)
    v = state.velocities
    collisions = 0
    windows = engine.windows(0.0, 3.3)
    assert windows[0][0] == 0.0 and windows[-1][1] == 3.3 and len(windows) > 1
    for a, b in windows:
        k = int(replay.poisson(0.5 * engine.n * (b - a)))
        if k:
            v = collide_sequential(v, draw_pairs(replay, engine.n, k)[::-1], engine.restitution)
            collisions += k
    assert np.array_equal(after.velocities, v)
    assert after.collisions == collisions and after.time == 3.3
    assert np.array_equal(
        state.velocities, engine.initial_state(np.random.default_rng(5)).velocities
    )


def test_engine_recentres_exactly_at_the_stop_grid():
    # Past several multiples of stop_step (4 here): the engine's events replayed with the
    # sequential loop, recentred at the same grid points, must agree bit for bit.
    engine = Ulam(400, 0.6, "laplace")
    assert engine.stop_step == 4.0
    state = engine.initial_state(np.random.default_rng(5))
    rng, replay = np.random.default_rng(11), np.random.default_rng(11)
    after = engine.advance(state, 9.3, rng)
    v = state.velocities
    for a, b in engine.windows(0.0, 9.3):
        k = int(replay.poisson(0.5 * engine.n * (b - a)))
        if k:
            v = collide_sequential(v, draw_pairs(replay, engine.n, k)[::-1], engine.restitution)
        if b in (4.0, 8.0):
            recentre(v)
    assert np.array_equal(after.velocities, v)
    # Stopping at a grid point (8.0: a window boundary, recentred there either way) and going on
    # with the same generator is the same run, bit for bit: same windows, same draws.
    rng = np.random.default_rng(11)
    mid = engine.advance(state, 8.0, rng)
    assert not np.array_equal(mid.velocities, after.velocities)  # events happen in (8, 9.3]
    resumed = engine.advance(mid, 9.3, rng)
    assert np.array_equal(resumed.velocities, after.velocities)
    assert resumed.collisions == after.collisions
    # Stopping off the window grid (5.0; windows are 2 long here) splits a window, so its
    # Poisson count is drawn in two parts and the stream shifts: another realisation of the
    # same law.  This is why the driver stops only on a fixed grid.
    assert engine.window == 2.0
    rng = np.random.default_rng(11)
    off = engine.advance(engine.advance(state, 5.0, rng), 9.3, rng)
    assert not np.array_equal(off.velocities, after.velocities)


@pytest.mark.parametrize("cls", [Ulam, UlamReference])
def test_long_run_keeps_the_mean_velocity_at_round_off(cls):
    # r = 0.9: λ = 0.0475, so at τ = 1400 (λτ = 66.5) the velocities are ~e^{-66} ≈ 1e-29 of the
    # start, far below the ~1e-16 round-off of the total momentum.  Without recentring every
    # velocity approached that residue (|⟨v⟩| ≈ rms); with it the mean stays at round-off of
    # the current rms, and the rescaled velocities keep the scaling law's spread.
    n = 2000 if cls is Ulam else 200
    tau = 1400.0 if cls is Ulam else 700.0  # the reference loop is slow: λτ = 33 there
    res = simulate(cls(n, 0.9, "uniform"), [tau], 3, progress=False, snapshots=True)
    v = res.snapshots[-1]
    rms = np.sqrt(np.mean(v * v))
    assert rms < 1e-20 if cls is Ulam else rms < 1e-10
    assert abs(v.mean()) < 1e-12 * rms
    x = v / rms
    assert np.std(x) > 0.99 and np.unique(x).size == n


@pytest.mark.parametrize("cls", [Ulam, UlamReference])
def test_expected_energy_is_exactly_exp_minus_2_lambda_tau_n_over_n_minus_1(cls):
    # Exact: E(τ) = exp(-2λτ N/(N-1)) in expectation, N particles at zero momentum.  N = 10
    # makes the finite-N factor 10/9 visible: over 2000 seeds the standard error of the mean is
    # ~0.004, and the infinite-N law exp(-2λτ) is 5-11 standard errors away (asserted too, so
    # the test can tell the two apart).  Tolerance: 4 standard errors from the seed spread.  The
    # reference's loop too: its partner draw (any j ≠ i, uniformly) sets the factor N/(N−1).
    n, r = 10, 0.5
    lam = (1 - r * r) / 4
    taus = np.array([0.5, 1.0, 2.0, 4.0])
    energy = np.array([simulate(cls(n, r), taus, s, progress=False).energy for s in range(2000)])
    mean = energy.mean(axis=0)
    se = energy.std(axis=0, ddof=1) / np.sqrt(len(energy))
    exact = np.exp(-2 * lam * taus * n / (n - 1))
    assert np.all(np.abs(mean - exact) < 4 * se), (mean, exact, se)
    infinite_n = np.exp(-2 * lam * taus)
    assert np.all(np.abs(mean - infinite_n)[1:] > 4 * se[1:])


def test_fast_engine_and_sequential_reference_agree_in_distribution():
    # Same model, independent implementations (the reference draws exponential waiting times
    # and one pair at a time).  N = 50, 1000 seeds each: compare the means of E(1), E(3) and of
    # the flatness <v^4>/<v^2>^2 at τ = 3 with a two-sample z-test, |z| < 4.
    def stats(cls):
        rows = []
        for seed in range(1000):
            res = simulate(cls(50, 0.5), [1.0, 3.0], seed, progress=False)
            v = res.velocities
            rows.append([res.energy[0], res.energy[1], np.mean(v**4) / np.mean(v**2) ** 2])
        return np.array(rows)

    fast, ref = stats(Ulam), stats(UlamReference)
    z = (fast.mean(0) - ref.mean(0)) / np.sqrt(fast.var(0) / 1000 + ref.var(0) / 1000)
    assert np.all(np.abs(z) < 4), z
    # and both follow the exact energy law (4 standard errors)
    exact = np.exp(-2 * 0.1875 * np.array([1.0, 3.0]) * 50 / 49)
    for sample in (fast, ref):
        assert np.all(
            np.abs(sample[:, :2].mean(0) - exact) < 4 * sample[:, :2].std(0) / np.sqrt(1000)
        )


@pytest.mark.parametrize(
    "r, law", [(0.0, "gaussian"), (0.0, "uniform"), (0.5, "gaussian"), (0.5, "uniform")]
)
def test_late_histogram_is_the_scaling_solution_with_its_power_law_tail(r, law):
    """N = 2e5, τ = 100 (independent: sup|G - f̂| ≈ 3e-3 there for r = 0.5; r = 0 contracts faster).

    Statistic.  f is even and so are these initial laws, so |x| is compared with 2 f(|x|):
    20 bins of width 0.2 on [0, 4], after fitting one scale s (x → s x): in a finite system √E
    is set by the few largest particles of an x⁻⁴ tail, cut near X ≈ (4N/3π)^{1/3} ≈ 44 (missing
    variance 4/(πX) ≈ 3%), so E fluctuates from run to run with a heavy right tail.
    Why |x| and not x: the odd part of the histogram (x against −x) has rare large excursions.
    A particle far out in the tail (|x| up to ~130 measured) eventually collides and spreads its
    momentum over a growing family of particles of one sign (at r = 0 they carry identical
    velocities), a transient one-sided bump: over 120 runs the odd part reached χ²/bin = 35
    while the even part stayed ≤ 2.6 (seed 12, r = 0, Gaussian: odd 33 and even 1.8 at
    τ = 100; 1.0 and 1.0 at τ = 50, 3.6 and 1.5 at τ = 200).  That is finite-N dynamics, not
    the scaling law, so it is left out.
    Tolerances, measured outside CI for these four (r, law) at N = 2e5, τ = 100, seeds 1-30
    (120 runs), with exactly this code:
    * χ²/bin of |x| (binomial errors): mean 0.93, 0.98, 1.20, 1.30 for the four cases (the
      velocities of a run are not independent samples: a collision leaves two correlated
      velocities, identical ones at r = 0), standard deviation 0.45, largest 2.56.  Bound:
      overdispersion φ = 1.3 (the largest case mean) times the 5-standard-deviation bound of
      χ²/dof for 20 bins, 1.3 (1 + 5 sqrt(2/20)) = 3.36.  A law of the same variance with a
      x^-4.5 or x^-3.5 tail (Student t, ν = 3.5 or 2.5) adds 8 or 20 to χ²/bin (computed); a
      Gaussian gives ~1800 (measured), asserted > 100.
    * s: 0.956 to 1.152 (right tail from the large particles inflating E).  Bound 0.92 < s < 1.2.
    * The tail: counts of |s x| in [3, 5), [5, 8), [8, 13), [13, 30) against the exact tail
      probabilities of f (2·10³, 4·10², 10², 30 expected).  The measured mean of z² per bin
      with Poisson errors is 1.4 to 2.3 over all runs, up to 4.2 for r = 0, uniform (the same
      families of particles, now out in the tail), largest |z| 6.9.  Bound |z| < 4 with errors
      sqrt(φ_tail · expected), φ_tail = 4, i.e. |z| < 8 with Poisson errors.  A Gaussian has no
      particle beyond 5 (z = -10 in [5, 8)).
    The first 6 seeds, on which the earlier bounds (40 bins of x, φ = 1.5, |s - 1| < 0.08,
    φ_tail = 1.5) were set, were not typical: over 120 runs those bounds failed 7, 6 and 4 times.
    """
    from scipy.special import ndtr

    n = 200_000
    res = simulate(Ulam(n, r, law), [100.0], 1, progress=False)
    v = res.velocities  # (momentum: test_momentum_drift_between_recentrings_is_round_off)
    ax = np.abs(v) / np.sqrt(np.mean(v**2))
    edges = np.linspace(0.0, 4.0, 21)
    counts = np.histogram(ax, edges)[0]

    def best_chi2(cdf):
        scales = np.linspace(0.7, 1.3, 601)
        chi2 = []
        for s in scales:
            prob = 2 * np.diff(cdf(s * edges))
            expected = prob * n
            chi2.append(np.mean((counts - expected) ** 2 / (expected * (1 - prob))))
        i = int(np.argmin(chi2))
        return chi2[i], scales[i]

    chi2, s = best_chi2(scaling_cdf)
    assert 0.92 < s < 1.2, s
    assert chi2 < 1.3 * (1 + 5 * np.sqrt(2 / 20)), chi2
    assert best_chi2(ndtr)[0] > 100
    tail_edges = np.array([3.0, 5.0, 8.0, 13.0, 30.0])
    tail = np.histogram(s * ax, tail_edges)[0]
    expected = n * 2 * np.diff(scaling_cdf(tail_edges))
    z = (tail - expected) / np.sqrt(4.0 * expected)
    assert np.all(np.abs(z) < 4), (tail, expected)


def momentum_drift_and_bound(res, a, b):
    """Exact change of the total momentum between ``res.snapshots[a]`` and ``[b]`` (math.fsum:
    no summation error), and a rigorous round-off bound for it.  One collision computes
    d = fl(fl(v_a - v_b) p), then fl(v_a - d) and fl(v_b + d): the same d leaves one particle
    and enters the other, so the only change of the exact sum is the two final roundings,
    at most u (|v_a'| + |v_b'|), u = 2⁻⁵³.  Post-collision velocities are convex combinations
    of the pre-collision ones up to a relative ~5u, so |v'| ≤ M (1 + 5u)^K with M = max |v| at
    the start and K the collisions in between: |ΔP| ≤ 2 u K M (1 + 5u)^K."""
    import math

    u = 2.0**-53
    start, end = res.snapshots[a], res.snapshots[b]
    k = int(res.collisions[b] - res.collisions[a])
    drift = abs(math.fsum(end) - math.fsum(start))
    return drift, 2 * u * k * np.abs(start).max() * (1 + 5 * u) ** k, k


@pytest.mark.parametrize(
    "engine, times",
    [
        (Ulam(20_000, 0.5, "uniform"), [0.0, 3.9]),
        (Ulam(20_000, 0.5, "uniform"), [96.0, 99.5]),
        (Ulam(20_000, 0.0, "asymmetric"), [96.0, 99.5]),
        (UlamReference(300, 0.5, "uniform"), [8.0, 11.5]),
    ],
    ids=["ulam-start", "ulam-late", "ulam-r0-late", "reference"],
)
def test_momentum_drift_between_recentrings_is_round_off(engine, times):
    # The engines subtract the mean velocity at every multiple of stop_step (4), which would
    # hide any drift recorded at those times.  Here the interval (t_a, t_b] contains no such
    # point, so the snapshots show the raw collision round-off, bounded as in
    # momentum_drift_and_bound.  The bound is a worst case: measured drifts are 5e-6..4e-5 of it
    # (a random walk of K roundings, ~u sqrt(K) |v|).  Checked by mutation: v_b += d (1 + ε)
    # instead of v_b += d fails the "ulam-start" case at ε = 1e-12 (not at 1e-14: the sign of d
    # is random here, so such an error only random-walks); gross errors (a lost update) fail all.
    assert engine.next_stop(times[0]) > times[1]  # no recentring inside the interval
    res = simulate(engine, times, 1, progress=False, snapshots=True)
    drift, bound, k = momentum_drift_and_bound(res, 0, 1)
    assert k > 0.4 * engine.n * (times[1] - times[0]) and drift <= bound, (drift, bound, k)


def test_energy_and_collision_bookkeeping():
    res = simulate(Ulam(10_000, 0.2, "asymmetric"), [0.0, 1.0, 5.0], 4, progress=False)
    # Poisson number of collisions, mean N τ / 2: within 5 standard deviations.
    mean = 10_000 * 5.0 / 2
    assert abs(res.collisions[-1] - mean) < 5 * np.sqrt(mean)
    assert res.energy[0] == pytest.approx(1.0, abs=1e-14)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n": 1, "restitution": 0.5}, "n=1"),
        ({"n": 2.5, "restitution": 0.5}, "n=2.5"),
        ({"n": 2**31, "restitution": 0.5}, "n=2147483648"),
        ({"n": 10, "restitution": 1.5}, "restitution=1.5"),
        ({"n": 10, "restitution": -0.1}, "restitution=-0.1"),
        ({"n": 10, "restitution": 0.5, "initial": "cauchy"}, "initial='cauchy'"),
    ],
)
def test_bad_parameters_are_named(kwargs, match):
    with pytest.raises(InvalidArgumentError, match=match):
        Ulam(**kwargs)


def test_windows_are_a_fixed_grid():
    engine = Ulam(1_000_000, 0.5)
    assert engine.window == 2.0**-4 and engine.stop_step == 4.0
    windows = engine.windows(0.0, 1.0)
    assert len(windows) == 16 and windows[0] == (0.0, 0.0625) and windows[-1] == (0.9375, 1.0)
    assert engine.windows(0.1, 0.2) == [(0.1, 0.125), (0.125, 0.1875), (0.1875, 0.2)]
    assert Ulam(10, 0.5).window == 2.0


def test_state_from_arrays_checks_the_shape_of_each_dimension():
    # d = 1 states are (N,), d >= 2 states are (N, d); a state of the other shape is refused.
    rng = np.random.default_rng(0)
    one, two = Ulam(10, 0.5), Ulam(10, 0.5, dimension=2)
    s1, s2 = one.initial_state(rng), two.initial_state(rng)
    assert s1.velocities.shape == (10,) and s2.velocities.shape == (10, 2)
    assert np.array_equal(two.state_from_arrays(s2.to_arrays()).velocities, s2.velocities)
    with pytest.raises(ValueError, match=r"\(10, 2\)"):
        one.state_from_arrays(s2.to_arrays())
    with pytest.raises(ValueError, match=r"expected \(10, 2\)"):
        two.state_from_arrays(s1.to_arrays())


def test_driven_run_resumes_from_a_checkpoint_bit_for_bit(tmp_path):
    # The driven engine through the run driver: Ctrl-C in the 3rd advance (after the stop at
    # τ = 4), checkpoint, resume: the same run as an uninterrupted one, bit for bit.
    import dataclasses

    @dataclasses.dataclass(frozen=True)
    class Interrupting:
        inner: object
        calls: list = dataclasses.field(default_factory=list)
        name = "ulam"

        def __getattr__(self, item):
            return getattr(self.inner, item)

        def advance(self, state, until, rng):
            self.calls.append(until)
            if len(self.calls) == 3:
                rng.random(5)  # randomness consumed by the interrupted advance must not matter
                raise KeyboardInterrupt
            return self.inner.advance(state, until, rng)

    engine = Ulam(500, 0.3, driving=0.8)
    times = [1.0, 6.5, 13.5]
    reference = simulate(engine, times, 4, progress=False)
    path = tmp_path / "driven.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Interrupting(engine), times, 4, progress=False, checkpoint=path)
    resumed = simulate(engine, times, 4, progress=False, resume=path)
    assert np.array_equal(resumed.velocities, reference.velocities)
    assert np.array_equal(resumed.energy, reference.energy)
    assert resumed.collisions[-1] == reference.collisions[-1]
    # heating is on: the energy rises from 1 towards D/(pq) (1 - 1/N)^2 = 4.16
    assert reference.energy[-1] > 1.5


class _CountingRng:
    """A Generator whose Poisson draws record their means (everything else passes through)."""

    def __init__(self, seed):
        self._rng = np.random.default_rng(seed)
        self.means = []

    def poisson(self, lam, *args, **kwargs):
        self.means.append(float(lam))
        return self._rng.poisson(lam, *args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._rng, name)


@pytest.mark.parametrize("kwargs", [{}, {"dimension": 2}, {"dimension": 3}, {"driving": 0.5}])
def test_collisions_are_a_poisson_process_of_rate_n_over_two(kwargs):
    """The model: pair collisions at total rate N/2 per unit τ (each particle at rate 1).  The
    engine's window counts are Poisson draws, so the sum of their means over [τ₀, τ₁] must be
    N (τ₁ − τ₀)/2 exactly (to round-off), whatever the windows; a rate off by 0.1 % fails by
    1e-3 relative, the check is to 1e-12.  Each window's mean is N/2 times its length."""
    engine = Ulam(300, 0.6, **kwargs)
    state = engine.initial_state(np.random.default_rng(1))
    rng = _CountingRng(2)
    after = engine.advance(state, 7.3, rng)
    windows = engine.windows(0.0, 7.3)
    assert len(rng.means) == len(windows) > 1
    assert sum(rng.means) == pytest.approx(300 * 7.3 / 2, rel=1e-12)
    for mean, (a, b) in zip(rng.means, windows, strict=True):
        assert mean == pytest.approx(300 * (b - a) / 2, rel=1e-12)
    assert after.collisions > 0


def test_relative_velocity_candidates_are_a_poisson_process_of_rate_n_n_minus_1_b_over_two():
    """The hard-rod DSMC: pair (i, j) collides at rate n|v_i − v_j|/N, so that a particle collides
    at rate n⟨|v − w|⟩ over its N − 1 partners; thinned under the bound B ≥ every |v_i − v_j|,
    the N(N − 1)/2 pairs give candidates at total rate n(N − 1)B/2.  Over the first block (one
    bound, B = max v − min v with its margin) each window's Poisson mean must be that rate times
    its length, to round-off (1e-12); a rate off by 0.1 % fails by 1e-3."""
    from particles.pair_schedule import hull_bound

    for engine in (Ulam(200, 0.6, rate="relative_velocity", density=2.5),
                   UlamReference(200, 0.6, rate="relative_velocity", density=2.5)):
        state = engine.initial_state(np.random.default_rng(4))
        bound = hull_bound(state.velocities)
        assert bound == pytest.approx(np.ptp(state.velocities), rel=1e-8)
        windows = engine.thinned_windows(0.0, 50.0, bound)
        rng = _CountingRng(5)
        engine.advance(state, windows[-1][1], rng)
        assert len(rng.means) == len(windows) > 1
        for mean, (a, b) in zip(rng.means, windows, strict=True):
            assert mean == pytest.approx(2.5 * 199 * bound * (b - a) / 2, rel=1e-12)


class _NoEventsUnitKicks:
    """A Generator with no event before τ = 10⁹ and standard normals ±1 in turn (mean zero, so a
    recentring leaves them alone)."""

    def __init__(self):
        self._rng = np.random.default_rng(0)

    def exponential(self, *args, **kwargs):
        return 1e9

    def standard_normal(self, shape):
        return np.resize([1.0, -1.0], shape)

    def __getattr__(self, name):
        return getattr(self._rng, name)


def test_reference_kick_has_variance_two_d_dt_by_hand():
    """White noise of strength D (Fokker–Planck term D ∂²_v P) moves a velocity by a Gaussian of
    variance 2DΔτ over Δτ.  The reference engine with no event and unit normals ±1 must move
    v by ±√(2DΔτ): D = 0.5, Δτ = 0.01 (before the first recentring) gives ±0.1, to round-off."""
    from particles.ulam import UlamState

    engine = UlamReference(4, 0.5, driving=0.5)
    assert engine.stop_step > 0.01
    v0 = np.array([1.0, -1.0, 0.5, -0.5])
    out = engine.advance(UlamState(0.0, v0, 0), 0.01, _NoEventsUnitKicks())
    np.testing.assert_allclose(out.velocities, v0 + 0.1 * np.array([1, -1, 1, -1]), rtol=1e-14)
    assert out.collisions == 0


def test_largest_occurrence_of_a_particle_seen_only_at_index_zero():
    """Occurrence 0 is a valid largest occurrence: for flat [0, 1, 1] particle 0 appears only
    at index 0 and particle 1 last at index 2, so both functions return [0, 2, 2], whatever the
    scratch held before."""
    from particles.pair_schedule import largest_occurrence, largest_occurrence_ufunc

    flat = np.array([0, 1, 1], dtype=np.intp)
    occ = np.arange(3, dtype=np.int32)
    for fn in (largest_occurrence, largest_occurrence_ufunc):
        assert fn(np.full(4, 7, np.int32), flat, occ).tolist() == [0, 2, 2]


def test_largest_occurrence_falls_back_when_repeated_writes_land_out_of_order():
    """The fast path trusts that a fancy assignment with repeated indices keeps the last write,
    and checks it: scratch whose writes land in reverse order (the first write wins) must send
    it to the order-independent fallback, which gives the largest occurrence by hand (particle
    0 last at 3, 1 at 4, 2 at 2)."""
    from particles.pair_schedule import largest_occurrence

    class FirstWriteWins(np.ndarray):
        def __setitem__(self, index, value):
            if isinstance(index, np.ndarray) and np.ndim(value) == 1:
                index, value = index[::-1], value[::-1]
            super().__setitem__(index, value)

    flat = np.array([0, 1, 2, 0, 1], dtype=np.intp)
    occ = np.arange(5, dtype=np.int32)
    scratch = np.full(3, 9, np.int32).view(FirstWriteWins)
    scratch[flat] = occ
    assert np.asarray(scratch).tolist() == [0, 1, 2]  # the premise: first writes kept
    out = largest_occurrence(np.full(3, 9, np.int32).view(FirstWriteWins), flat, occ)
    assert np.asarray(out).tolist() == [3, 4, 2, 3, 4]


def test_event_loops_take_integer_velocities_as_floats_and_check_the_pairs():
    """Integer velocities are collided as floats (r = 0: the pair meets at its mean), and a
    ``pairs`` array not of shape (K, 2) is refused naming it and its shape."""
    for collide in (collide_in_order, collide_sequential):
        out = collide([0, 3, 7], [[0, 1]], 0.0)
        assert out.dtype == np.float64 and out.tolist() == [1.5, 1.5, 7.0]
        for bad in ([0, 1, 2], [[0, 1, 2], [1, 2, 0]]):
            shape = re.escape(str(np.shape(bad)))
            with pytest.raises(InvalidArgumentError,
                               match=rf"argument pairs='array of shape {shape}' is invalid: "
                                     r"expected shape \(K, 2\)"):
                collide([0.0, 1.0, 2.0], bad, 0.5)


@pytest.mark.parametrize("bad", [[[0, 3]], [[-1, 1]], [[1, 1]], [[0, 1], [2, 2]]])
def test_event_loops_refuse_pairs_out_of_range_or_of_one_particle(bad):
    """Indices outside 0..N−1 (N = 3: 3 and −1) and a particle paired with itself are refused
    naming ``pairs``; the boundary indices 0 and N − 1 are accepted."""
    for collide in (collide_in_order, collide_sequential):
        with pytest.raises(InvalidArgumentError,
                           match=r"argument pairs='out-of-range or i == j entries' is invalid: "
                                 r"expected pairs of 0\.\.2, i != j"):
            collide([0.0, 1.0, 2.0], bad, 0.5)
        assert collide([0.0, 1.0, 4.0], [[2, 0]], 0.0).tolist() == [2.0, 1.0, 2.0]


def test_draw_pairs_checks_its_arguments():
    """``rng`` must be a Generator, N an integer in [2, 2³¹ − 1] (int32 particle ids, both
    ends accepted), K an integer ≥ 0; each refusal names the argument and the value."""
    rng = np.random.default_rng(0)
    with pytest.raises(InvalidArgumentError,
                       match=r"argument rng='RandomState' is invalid: expected a numpy\.random\."
                             r"Generator"):
        draw_pairs(np.random.RandomState(0), 5, 1)
    with pytest.raises(InvalidArgumentError, match=r"argument n=1 is invalid"):
        draw_pairs(rng, 1, 1)
    with pytest.raises(InvalidArgumentError,
                       match=r"argument n=2147483648 is invalid: expected an integer <= "
                             r"2\*\*31 - 1 \(int32 particle ids\)"):
        draw_pairs(rng, 2**31, 1)
    with pytest.raises(InvalidArgumentError, match=r"argument k=-1 is invalid"):
        draw_pairs(rng, 5, -1)
    big = draw_pairs(rng, 2**31 - 1, 3)
    assert big.dtype == np.int32 and big.shape == (3, 2) and np.all(big[:, 0] != big[:, 1])
    two = draw_pairs(rng, 2, 50)
    assert sorted(set(map(tuple, two.tolist()))) == [(0, 1), (1, 0)]
    assert draw_pairs(rng, 5, 0).shape == (0, 2)


def test_ulam_state_round_trips_through_its_arrays_as_a_copy():
    """What a checkpoint stores and reloads: time as a float, the velocities (a copy, as
    floats), collisions as an integer; the dimension defaults to 1."""
    from particles.ulam import UlamState

    v = np.array([0.5, -1.0, 0.25, 0.25])
    arrays = UlamState(1.5, v, 7).to_arrays()
    assert set(arrays) == {"time", "velocities", "collisions"}
    back = UlamState.from_arrays(arrays, 4)  # dimension 1 unless told
    assert (back.time, back.collisions) == (1.5, 7)
    assert isinstance(back.time, float) and isinstance(back.collisions, int)
    np.testing.assert_array_equal(back.velocities, v)
    arrays["velocities"][0] = 99.0
    assert back.velocities[0] == 0.5  # a copy, not a view of the file's array
    ints = dict(arrays, velocities=np.arange(4))  # a hand-made file of integers
    assert UlamState.from_arrays(ints, 4).velocities.dtype == np.float64
    planar = UlamState(2.0, np.ones((3, 2)), 1).to_arrays()
    assert UlamState.from_arrays(planar, 3, dimension=2).velocities.shape == (3, 2)


@pytest.mark.parametrize("arrays, n, dimension, match", [
    ({"time": 1.0, "velocities": np.zeros(4)}, 4, 1,
     r"checkpoint=\"missing \['collisions'\]\".*\ban Ulam state\b"),
    ({"time": 1.0, "velocities": np.zeros(5), "collisions": 0}, 4, 1,
     r"checkpoint='velocities of shape \(5,\)'.*an Ulam state, expected \(4,\)"),
    ({"time": 1.0, "velocities": np.zeros(4), "collisions": 0}, 4, 2,
     r"checkpoint='velocities of shape \(4,\)'.*expected \(4, 2\)"),
    ({"time": 1.0, "velocities": np.zeros((4, 2)), "collisions": 0}, 4, 1,
     r"checkpoint='velocities of shape \(4, 2\)'.*expected \(4,\)"),
])
def test_ulam_state_from_arrays_refuses_an_inconsistent_state(arrays, n, dimension, match):
    from particles.ulam import UlamState

    with pytest.raises(InvalidArgumentError, match=match):
        UlamState.from_arrays(arrays, n, dimension)


def test_names_moved_out_of_the_ulam_module_say_where_they_went():
    import particles.ulam as ulam

    with pytest.raises(ImportError, match=r"particles\.ulam\.draw_pairs moved to "
                                          r"particles\.pair_schedule\.draw_pairs"):
        ulam.draw_pairs  # noqa: B018
    with pytest.raises(ImportError, match=r"particles\.ulam_kinematics\.draw_angles"):
        ulam.draw_angles  # noqa: B018
    with pytest.raises(AttributeError, match=r"'particles\.ulam' has no attribute 'nothing'"):
        ulam.nothing  # noqa: B018


def test_the_reference_loop_draws_every_pair_alike():
    """The reference picks each unordered pair with probability 1/(N(N−1)/2) per collision.
    N = 3, r = 1 (a collision exchanges the two velocities), velocities 0, 1, 2: a run with
    exactly one collision shows which pair collided.  3000 seeds to τ = 0.4 (one collision with
    probability 0.6 e^{−0.6} ≈ 0.33): each pair's count is binomial with p = 1/3 among the
    single-collision runs; tolerance 5 standard deviations."""
    engine = UlamReference(3, 1.0)
    counts = {}
    for seed in range(3000):
        rng = np.random.default_rng(seed)
        start = dataclasses.replace(engine.initial_state(rng), velocities=np.array([0.0, 1.0, 2.0]))
        end = engine.advance(start, 0.4, rng)
        if end.collisions == 1:
            pair = tuple(np.flatnonzero(end.velocities != start.velocities))
            counts[pair] = counts.get(pair, 0) + 1
    total = sum(counts.values())
    assert set(counts) == {(0, 1), (0, 2), (1, 2)}, counts
    sd = math.sqrt(total * (1 / 3) * (2 / 3))
    for pair, count in counts.items():
        assert abs(count - total / 3) < 5 * sd, (pair, counts)


def test_parameters_are_checked_and_normalised():
    """What the constructor stores is the checked value in its plain type (the recorded
    parameters and the checkpoints compare them); its refusals name the argument and value."""
    from particles.initial import get_law, law_from_characteristic

    engine = Ulam(np.int64(2), np.float32(0.5), initial=get_law("uniform"),
                  dimension=np.int64(1))  # N = 2, the smallest gas
    assert type(engine.n) is int and engine.n == 2
    assert type(engine.restitution) is float and engine.restitution == 0.5
    assert engine.initial == "uniform" and type(engine.dimension) is int
    driven = Ulam(10, 0.5, driving=np.float32(0.25), density=np.float32(1.0))
    assert type(driven.driving) is float and type(driven.density) is float
    assert Ulam(2**31 - 1, 0.5).n == 2**31 - 1  # particle ids are int32
    with pytest.raises(InvalidArgumentError, match=r"n=2147483648.*\ban integer <= 2\*\*31 - 1$"):
        Ulam(2**31, 0.5)
    no_sampler = law_from_characteristic(lambda k: np.exp(-0.5 * k * k), 1.0, name="mine")
    with pytest.raises(InvalidArgumentError, match=r"initial='mine'.*\ba law with a sampler$"):
        Ulam(10, 0.5, initial=no_sampler)
    for kwargs, match in [
        ({"dimension": 2, "driving": 0.1}, r"driving=0\.1.*\b0 when dimension > 1$"),
        ({"rate": "relative_velocity", "dimension": 2},
         r"rate='relative_velocity'.*expected 'constant' when dimension > 1$"),
        ({"rate": "relative_velocity", "driving": 0.1},
         r"rate='relative_velocity'.*expected 'constant' with driving > 0$"),
        ({"density": 2.0}, r"density=2\.0.*\b1 with rate 'constant' \(the density sets the rate "
                           r"\(n/N\)\|v_i - v_j\| of rate 'relative_velocity' only\)$"),
    ]:
        with pytest.raises(InvalidArgumentError, match=match):
            Ulam(10, 0.5, **kwargs)
    # the window (τ per batch of events) is a power of two clipped to [2⁻¹², 2]
    assert Ulam(2, 0.5).window == 2.0 and Ulam(10**9, 0.5).window == 2.0**-12
