"""Ulam with rate="relative_velocity": DSMC of the homogeneous hard-rod Boltzmann equation in time
t at density n (a pair (i, j) collides at rate (n/N)|v_i − v_j|).  One collision by hand; the
fast rounds equal the sequential reference bit for bit; checkpoint and resume bit for bit;
momentum kept to round-off; the exact finite-N expectations of the collision count and of the
energy loss rate; the thinning bound holds at every candidate."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from particles.driver import simulate
from particles.kernels import RelativeVelocity
from particles.models import get_model
from particles.pair_schedule import fire_rounds_thinned, thin_sequential
from particles.ulam import Ulam, UlamReference
from particles.validation import InvalidArgumentError

#: The hard-rod rate |v - w| of the thinning, as the engine passes it (the kernel's own).
HARD_RODS = RelativeVelocity(0.5).rate


def _pair_sums(v: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Σ_{i<j}|v_i − v_j|, Σ_{i<j}|v_i − v_j|³ and, per particle, Σ_j |v_i − v_j| (sorted
    prefix sums: O(N log N); (b − a)³ = b³ − 3b²a + 3ba² − a³ summed over a before b)."""
    order = np.argsort(v)
    x = v[order]
    n = x.size
    k = np.arange(n)
    s1 = np.concatenate(([0.0], np.cumsum(x)[:-1]))  # Σ_{i<k} x_i
    s2 = np.concatenate(([0.0], np.cumsum(x**2)[:-1]))
    s3 = np.concatenate(([0.0], np.cumsum(x**3)[:-1]))
    first = float(np.sum(k * x - s1))
    third = float(np.sum(k * x**3 - 3 * x**2 * s1 + 3 * x * s2 - s3))
    total = x.sum()
    per_sorted = (k * x - s1) + ((total - s1 - x) - (n - 1 - k) * x)
    per = np.empty(n)
    per[order] = per_sorted
    return first, third, per


def test_pair_sums_match_brute_force():
    v = np.random.default_rng(0).standard_normal(60)
    g = np.abs(v[:, None] - v[None, :])
    first, third, per = _pair_sums(v)
    assert first == pytest.approx(g.sum() / 2, rel=1e-12)
    assert third == pytest.approx((g**3).sum() / 2, rel=1e-10)
    np.testing.assert_allclose(per, g.sum(axis=1), rtol=1e-12)


def test_one_window_of_candidates_by_hand():
    # Candidates in time order (0, 1), (1, 2), (0, 2) with marks 0.5, 0.9, 0.05, bound B = 2,
    # r = 0.5 (p = 3/4); accepted iff mark·B < |g|.  Worked by hand in exact binary fractions:
    # (0, 1): |g| = 1.5 > 1.0, accepted: d = 1.125, v = (-0.125, 0.625, 0.25);
    # (1, 2): |g| = 0.375 < 1.8, rejected;
    # (0, 2): |g| = 0.375 > 0.1, accepted: d = -0.28125, v = (0.15625, 0.625, -0.03125).
    v = np.array([1.0, -0.5, 0.25])
    reversed_pairs = np.array([[0, 2], [1, 2], [0, 1]], dtype=np.int32)  # last candidate first
    marks = np.array([0.05, 0.9, 0.5])
    expected = [0.15625, 0.625, -0.03125]
    slow = v.copy()
    accepted, largest = thin_sequential(slow, reversed_pairs, marks, 2.0, 0.75, HARD_RODS)
    assert slow.tolist() == expected and accepted == 2 and largest == 0.75
    fast = v.copy()
    first, occurrence = np.empty(3, np.int32), np.arange(6, dtype=np.int32)
    assert fire_rounds_thinned(fast, reversed_pairs, marks, 2.0, 0.75, first, occurrence,
                               HARD_RODS) == 2
    assert fast.tolist() == expected


def test_acceptance_is_the_mark_times_the_bound_below_the_relative_speed():
    # One candidate (0, 1), |g| = 1.5, bound B = 2: accepted iff mark · 2 < 1.5, i.e. mark < 3/4.
    # Marks 1e-4 either side of 3/4 (far above round-off, 1e-16) give both outcomes, so the
    # threshold mark · B is checked to 1e-4: a bound or a mark scaled by 1.001 flips one of them.
    # Accepted at r = 0.5 (p = 3/4): d = p g = 1.125, v = (−0.125, 0.625).
    for mark, expected in ((0.75 * (1 - 1e-4), [-0.125, 0.625]), (0.75 * (1 + 1e-4), [1.0, -0.5])):
        marks = np.array([mark])
        pairs = np.array([[0, 1]], dtype=np.int32)
        slow = np.array([1.0, -0.5])
        accepted, largest = thin_sequential(slow, pairs, marks, 2.0, 0.75, HARD_RODS)
        assert slow.tolist() == expected and accepted == int(expected[0] != 1.0)
        assert largest == 0.75
        fast = np.array([1.0, -0.5])
        first, occurrence = np.empty(2, np.int32), np.arange(2, dtype=np.int32)
        assert fire_rounds_thinned(fast, pairs, marks, 2.0, 0.75, first, occurrence,
                                   HARD_RODS) == accepted
        assert fast.tolist() == expected


def _engines(cls, **kw):
    return cls(300, 0.4, "laplace", rate="relative_velocity", **kw)


@pytest.mark.parametrize("density", [1.0, 3.0])
def test_fast_path_equals_sequential_reference_bit_for_bit(density):
    # Through several thinning blocks and two recentrings (stop_step = 4/n rounded to a power
    # of two), then on from the middle: the same run, bit for bit.
    fast, ref = _engines(Ulam, density=density), _engines(UlamReference, density=density)
    state = fast.initial_state(np.random.default_rng(5))
    until = 2.3 * fast.stop_step
    a = fast.advance(state, until, np.random.default_rng(9))
    b = ref.advance(state, until, np.random.default_rng(9))
    assert a.collisions == b.collisions > 300
    assert np.array_equal(a.velocities, b.velocities)
    assert a.time == b.time == until
    rng = np.random.default_rng(9)
    mid = fast.advance(state, 2 * fast.stop_step, rng)
    assert np.array_equal(fast.advance(mid, until, rng).velocities, a.velocities)


def test_checkpoint_and_resume_are_bit_for_bit(tmp_path):
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

    engine = Ulam(2000, 0.7, rate="relative_velocity", density=2.0)
    assert engine.time_name == "t" and engine.stop_step == 2.0
    times = [0.5, 3.3, 7.0]
    reference = simulate(engine, times, 4, progress=False)
    path = tmp_path / "dsmc.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Interrupting(engine), times, 4, progress=False, checkpoint=path)
    resumed = simulate(engine, times, 4, progress=False, resume=path)
    assert np.array_equal(resumed.velocities, reference.velocities)
    assert np.array_equal(resumed.energy, reference.energy)
    assert np.array_equal(resumed.collisions, reference.collisions)
    assert np.array_equal(resumed.kurtosis, reference.kurtosis)
    assert reference.params["rate"] == "relative_velocity" and reference.params["density"] == 2.0


def test_momentum_is_kept_to_round_off_between_recentrings():
    # No multiple of stop_step (4) in (0.1, 3.9]: the raw drift of Σv over the collisions,
    # bounded by 2 u K max|v| (1 + 5u)^K (each collision moves the same d out of one particle
    # and into the other; only the two final roundings change the exact sum).
    engine = Ulam(20_000, 0.5, "uniform", rate="relative_velocity")
    res = simulate(engine, [0.1, 3.9], 3, progress=False, snapshots=True)
    u = 2.0**-53
    k = int(res.collisions[1] - res.collisions[0])
    drift = abs(math.fsum(res.snapshots[1]) - math.fsum(res.snapshots[0]))
    assert k > 20_000
    assert drift <= 2 * u * k * np.abs(res.snapshots[0]).max() * (1 + 5 * u) ** k


@pytest.mark.parametrize("density, scale", [(1.0, 1.0), (2.5, 1.0), (1.0, 0.05)])
def test_collision_count_is_n_times_the_mean_relative_speed(density, scale):
    # r = 1 in 1D exchanges the two velocities: the multiset of velocities, hence the total
    # rate R = (n/N) Σ_{i<j}|v_i − v_j|, stays fixed (to round-off), so the number of
    # collisions to t is exactly Poisson(R t): tolerance 4 sqrt(R t).  A cold gas (velocities
    # × 0.05: every |v_i − v_j| and the thinning bound below 1) collides by the same law, over a
    # time 1/0.05 as long.
    n_particles, t = 20_000, 1.0 / scale
    engine = Ulam(n_particles, 1.0, rate="relative_velocity", density=density)
    state = engine.initial_state(np.random.default_rng(21))
    state = dataclasses.replace(state, velocities=scale * state.velocities)
    v = state.velocities
    assert scale == 1.0 or np.ptp(v) < 1.0
    pair_sum, _, per = _pair_sums(v)
    expected = density / n_particles * pair_sum * t
    count = engine.advance(state, t, np.random.default_rng(22)).collisions
    assert abs(count - expected) < 4 * math.sqrt(expected), (count, expected)
    # Per particle per unit t, 2·count/(N t) estimates n (1/N) Σ_j |v_i − v_j|, whose N → ∞
    # value for a Gaussian of temperature T = ⟨v²⟩ is n⟨|v − w|⟩ = 2n sqrt(T/π).  Tolerance:
    # 4 standard errors, the Poisson one of the count plus that of the U-statistic
    # (1/(N(N − 1)))Σ_{i≠j}|v_i − v_j| of the drawn sample, 2 sd(h₁)/sqrt(N) with
    # h₁(v_i) = (1/(N − 1)) Σ_j |v_i − v_j| estimated from the sample.
    T = float(np.mean(v * v))
    per_particle = 2.0 * count / (n_particles * t)
    gaussian = 2.0 * density * math.sqrt(T / math.pi)
    h1 = per / (n_particles - 1)
    se = density * math.hypot(
        2.0 * math.sqrt(expected) / (n_particles * t) / density,
        2.0 * h1.std() / math.sqrt(n_particles),
    )
    finite_n = (n_particles - 1) / n_particles  # each particle has N − 1 partners
    assert abs(per_particle - finite_n * gaussian) < 4 * se, (per_particle, gaussian, se)


def test_expected_energy_loss_rate_is_the_pair_sum_of_cubed_relative_speeds():
    # From one state, R short independent runs of length t: E[ΔE]/t → dE/dt =
    # −(1 − r²)/4 · n · (1/N²) Σ_{i≠j}|v_i − v_j|³ (each collision removes (1 − r²)/2 · g²/N of
    # E = (1/N)Σv², at rate (n/N)|g| per pair).  Tolerance: 4 standard errors of the mean of
    # the R samples of ΔE/t.  The O(t) bias (the rate changes as the gas cools during t) is
    # relative ≈ (3/4)(1 − r²) · 2K/N ≈ 1e-3 with K ≈ 12 collisions per run: 0.1 of a standard
    # error (~1 %), so it cannot decide the outcome.
    n_particles, r, density, replicas = 20_000, 0.5, 1.5, 1500
    engine = Ulam(n_particles, r, rate="relative_velocity", density=density)
    state = engine.initial_state(np.random.default_rng(31))
    v0 = state.velocities
    _, cubes, _ = _pair_sums(v0)
    rate = -(1 - r * r) / 4 * density * 2.0 * cubes / n_particles**2
    t = 1e-3
    e0 = float(np.mean(v0 * v0))
    rng = np.random.default_rng(32)
    changes = np.array([np.mean(engine.advance(state, t, rng).velocities ** 2) - e0
                        for _ in range(replicas)]) / t
    se = changes.std(ddof=1) / math.sqrt(replicas)
    assert abs(changes.mean() - rate) < 4 * se, (changes.mean(), rate, se)
    assert se < 0.05 * abs(rate)  # the test resolves the rate to a few per cent


@pytest.mark.parametrize("r", [0.0, 0.6, 1.0])
def test_thinning_bound_holds_at_every_candidate(r):
    # The reference's loop sees every candidate's |g| before its decision: |g|/B must never
    # exceed 1 (acceptance probability ≤ 1), with B recomputed (tightened) block by block as the
    # gas cools.
    seen = []

    @dataclasses.dataclass(frozen=True)
    class Probe(UlamReference):
        def _thin_window(self, v, pairs, marks, bound, p, kernel):
            accepted, largest = thin_sequential(v, pairs, marks, bound, p, kernel.rate)
            seen.append((largest, bound))
            return accepted

    engine = Probe(400, r, "uniform", rate="relative_velocity", density=4.0)
    engine.advance(engine.initial_state(np.random.default_rng(1)), 3.0,
                   np.random.default_rng(2))
    largest = np.array([s[0] for s in seen])
    bounds = np.array([s[1] for s in seen])
    assert len(seen) >= 10 and largest.max() <= 1.0
    assert largest.max() > 0.9  # candidates near the bound are met: the check is not vacuous
    if r < 1.0:
        assert bounds[-1] < 0.5 * bounds[0]  # tightened as the gas cools


def test_time_convention_and_bad_input():
    constant = Ulam(50, 0.5)
    assert constant.time_name == "tau" and "rate" not in constant.to_dict()
    dsmc = Ulam(50, 0.5, rate="relative_velocity", density=0.25)
    assert dsmc.time_name == "t" and dsmc.stop_step == 16.0
    # The event budget counts candidates, and bounds them: the candidates to t have mean at
    # most n(N − 1)B₀t/2, B₀ the initial hull bound (the hull never grows).  Checked on the
    # hull of 10⁶ unit-Gaussian velocities (about 10), at two densities and times.
    from particles.pair_schedule import hull_bound

    big = Ulam(1_000_000, 0.5, rate="relative_velocity")
    b0 = hull_bound(big.initial_state(np.random.default_rng(4)).velocities)
    for engine in (big, Ulam(1_000_000, 0.5, rate="relative_velocity", density=3.0)):
        for t in (0.5, 40.0):
            estimate, unit = engine.expected_events(t, 1)
            assert unit == "candidates"
            assert estimate >= 0.5 * engine.density * (engine.n - 1) * b0 * t
            assert estimate <= 2.0 * 0.5 * engine.density * (engine.n - 1) * b0 * t  # not loose
    for kwargs, match in [
        ({"rate": "hard"}, "rate='hard'"),
        ({"rate": "relative_velocity", "density": 0.0}, "density=0.0"),
        ({"rate": "relative_velocity", "density": -2.0}, "density=-2.0"),
        ({"rate": "relative_velocity", "density": math.inf}, "density=inf"),
        ({"rate": "relative_velocity", "density": math.nan}, "density=nan"),
        ({"density": 2.0}, "density=2.0"),
        ({"rate": "relative_velocity", "dimension": 2}, "rate='relative_velocity'"),
        ({"rate": "relative_velocity", "driving": 0.1}, "rate='relative_velocity'"),
    ]:
        with pytest.raises(InvalidArgumentError, match=match):
            Ulam(50, 0.5, **kwargs)


def test_the_catalogue_builds_it_for_the_ensembles():
    engine = get_model("ulam").build({"n": 40, "restitution": 0.5,
                                      "rate": "relative_velocity", "density": 2.0})
    assert isinstance(engine, Ulam) and engine.density == 2.0 and engine.time_name == "t"
    assert get_model("ulam").time_names == ("tau", "t")


def _direct_loop(v, density, p, until, rng):
    """An independent exact simulation: no windows, no thinning.  Total rate
    R = (n/N)Σ_{i<j}|v_i − v_j| from the current velocities, an Exp(R) wait, the pair drawn with
    probability ∝ |v_i − v_j|, one collision; until the next wait passes ``until``."""
    v = v.copy()
    n = v.size
    upper = np.triu_indices(n, 1)
    t, count = 0.0, 0
    while True:
        g = np.abs(v[:, None] - v[None, :])[upper]
        total = density / n * g.sum()
        if total == 0.0:
            return v, count
        t += rng.exponential(1.0 / total)
        if t >= until:
            return v, count
        k = min(int(np.searchsorted(np.cumsum(g), rng.random() * g.sum(), side="right")),
                g.size - 1)
        i, j = upper[0][k], upper[1][k]
        d = (v[i] - v[j]) * p
        v[i] -= d
        v[j] += d
        count += 1


def test_the_engine_agrees_in_law_with_a_direct_exact_loop():
    # N = 12, r = 0.3, n = 2, to t = 1.5 (about 12 collisions, the energy down to ~0.15, through
    # several thinning blocks and a stop): the mean energy and the mean collision count of R
    # runs of each, from the same initial state, agree within 4 combined standard errors
    # (measured: se 0.15 on a count of 11.7, so a rate wrong by 5 % would fail).
    engine = Ulam(12, 0.3, "uniform", rate="relative_velocity", density=2.0)
    state = engine.initial_state(np.random.default_rng(40))
    replicas, until = 600, 1.5
    rng = np.random.default_rng(41)
    fast = [engine.advance(state, until, rng) for _ in range(replicas)]
    fast_e = np.array([np.mean(s.velocities**2) for s in fast])
    fast_k = np.array([s.collisions for s in fast], dtype=float)
    rng = np.random.default_rng(42)
    direct = [_direct_loop(state.velocities, 2.0, engine.p, until, rng) for _ in range(replicas)]
    direct_e = np.array([np.mean(v**2) for v, _ in direct])
    direct_k = np.array([k for _, k in direct], dtype=float)
    for a, b in ((fast_e, direct_e), (fast_k, direct_k)):
        se = math.hypot(a.std(ddof=1), b.std(ddof=1)) / math.sqrt(replicas)
        assert abs(a.mean() - b.mean()) < 4 * se, (a.mean(), b.mean(), se)
    assert fast_k.mean() > 8 and fast_e.mean() < 0.5  # the runs did collide and cool


def test_a_run_in_t_is_labelled_t_with_its_kurtosis():
    pytest.importorskip("xarray")
    run = simulate(Ulam(300, 0.5, rate="relative_velocity"), [0.5, 1.0], 1, progress=False)
    ds = run.to_xarray()
    assert np.array_equal(ds["t"].values, run.times) and "tau" not in ds.coords
    assert np.array_equal(ds["kurtosis"].values, run.kurtosis)
    v = run.velocities
    assert run.kurtosis[-1] == pytest.approx(np.mean(v**4) / np.mean(v**2) ** 2, rel=1e-12)


def test_thinning_windows_bound_and_powers_of_two_by_hand():
    """The thinning's window machinery, by hand.

    * The bound is ≥ every |v_i − v_j| (not merely close to the hull's width): a bound below
      the widest pair's speed would accept that pair with probability > 1.
    * ``power_of_two_near``: the nearest power of two in log scale (3 → 4, 0.7 → 0.5), the
      exponent clipped to [−1000, 1000] (1e308 → 2¹⁰⁰⁰, 1e-310 → 2⁻¹⁰⁰⁰), ∞ → 2¹⁰⁰⁰.
    * ``thinned_windows(start, until, rate, stop_step, target)``: rate 0.5 and 64 candidates
      aimed at give h = 2⁷; from 0 the block ends at 8h = 1024 (the stop grid and ``until`` are
      further), cut at the multiples of h: eight windows of 128, none empty.  Rate 0 (equal
      velocities): one window to the block's end.  A huge rate gives windows of 2⁻⁴⁰ from 0, but
      from a start s = m·2^e (½ ≤ m < 1) none shorter than 2^(e − 30): from 0.5, 2⁻³⁰."""
    from particles.pair_schedule import hull_bound, power_of_two_near, thinned_windows

    v = np.random.default_rng(3).standard_normal(50)
    assert hull_bound(v) >= np.max(np.abs(v[:, None] - v[None, :]))
    assert hull_bound(v) <= np.ptp(v) * (1.0 + 1e-8)
    assert hull_bound(np.array([-1.0, 2.0])) >= 3.0
    assert [power_of_two_near(x) for x in (3.0, 0.7, 1.0, 1e308, 1e-310, math.inf)] == [
        4.0, 0.5, 1.0, 2.0**1000, 2.0**-1000, 2.0**1000]
    windows = thinned_windows(0.0, 4096.0, 0.5, 4096.0, 64)
    assert windows == [(128.0 * k, 128.0 * (k + 1)) for k in range(8)]
    assert thinned_windows(0.0, 3.0, 0.0, 4.0, 64) == [(0.0, 3.0)]
    tiny = 2.0**-40
    windows = thinned_windows(0.0, 1.0, 64 / tiny, 1.0, 64)
    assert windows == [(tiny * k, tiny * (k + 1)) for k in range(8)]
    first = thinned_windows(0.5, 1.0, 64 / tiny, 1.0, 64)[0]
    assert first == (0.5, 0.5 + 2.0**-30)
