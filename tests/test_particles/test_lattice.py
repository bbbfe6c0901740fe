"""The lattice model: exactness of the parallel clock passes, agreement with the discrete
model, the exact initial cooling rates, E ~ τ^(-1/2), the k⁻² Porod range and the
reference value."""

import math

import numpy as np
import pytest

from particles.driver import simulate
from particles.initial import get_law
from particles.lattice import (
    Lattice,
    LatticeDiscreteReference,
    LatticeState,
    run_clocks,
    run_clocks_sequential,
    thinning_bound,
)
from particles.observables import correlation, log_bin
from particles.validation import InvalidArgumentError


def per_bond_increments(table):
    """An increment source reading each bond's own pre-drawn waiting times in order."""
    used = np.zeros(table.shape[0], dtype=int)

    def increments(bonds):
        out = table[bonds, used[bonds]]
        used[bonds] += 1
        return out

    return increments


@pytest.mark.parametrize("n", [3, 4, 41, 1000])
@pytest.mark.parametrize("constraint", [True, False])
@pytest.mark.parametrize("sparse_ratio", [0, 16, 10**9])
def test_parallel_passes_equal_time_ordered_attempts(n, constraint, sparse_ratio):
    # The same continuous-time clocks (pre-drawn per bond) processed in passes of local minima,
    # and one attempt at a time in time order: identical velocities, clocks and counts.
    # sparse_ratio 0 never switches to the sparse tail passes; 10**9 switches after the first.
    rng = np.random.default_rng(n)
    table = rng.standard_exponential((n, 200))
    v0 = rng.standard_normal(n)
    c0 = rng.standard_exponential(n)
    until = 60.0
    v1, c1 = v0.copy(), c0.copy()
    attempts, collisions, passes = run_clocks(
        v1, c1, until, 0.8, constraint, per_bond_increments(table), sparse_ratio=sparse_ratio
    )
    v2, c2 = v0.copy(), c0.copy()
    ref = run_clocks_sequential(v2, c2, until, 0.8, constraint, per_bond_increments(table))
    assert (attempts, collisions) == ref
    assert np.array_equal(v1, v2) and np.array_equal(c1, c2)
    assert np.all(c1 >= until)
    assert attempts > 40 * n and passes <= attempts
    # a pass fires local minima of the clocks, no two on neighbouring bonds: at most n/2 bonds
    assert passes >= attempts / (n // 2)
    if n > 10:  # on a ring of 3 every bond touches the other two: one attempt per pass
        assert passes < attempts / 10
    assert (collisions < attempts) == constraint
    assert abs(v1.sum() - v0.sum()) < 1e-13 * n


def test_engine_state_carries_clocks_and_counts():
    engine = Lattice(500, 0.3, "uniform", constraint=True)
    res = simulate(engine, [2.0, 6.0], 1, progress=False)
    # attempts are Poisson(N τ): 5 standard deviations
    assert abs(res.extras["attempts"][-1] - 3000) < 5 * np.sqrt(3000)
    assert 0 < res.collisions[-1] < res.extras["attempts"][-1]
    assert np.all(np.abs(res.momentum) < 1e-15)


@pytest.mark.parametrize("constraint", [True, False])
def test_momentum_is_conserved_to_round_off(constraint):
    # The lattice engine never recentres, so the total momentum at τ = 50 is the raw result of
    # every collision since τ = 0.  Bound (derived in test_particles_ulam's
    # momentum_drift_and_bound): |ΔP| ≤ 2 u K max|v(0)| (1 + 5u)^K, u = 2⁻⁵³, K collisions;
    # measured drifts are ~2e-5 of it.  Checked by mutation: v_b += d (1 + ε) in run_clocks
    # fails the constrained case at ε = 1e-14 (there d > 0 in every collision, so it adds up).
    import math

    res = simulate(
        Lattice(20_000, 0.5, constraint=constraint),
        [0.0, 50.0],
        1,
        progress=False,
        snapshots=True,
    )
    u = 2.0**-53
    k = int(res.collisions[1] - res.collisions[0])
    drift = abs(math.fsum(res.snapshots[1]) - math.fsum(res.snapshots[0]))
    bound = 2 * u * k * np.abs(res.snapshots[0]).max() * (1 + 5 * u) ** k
    assert k > 3 * 10**5 and drift <= bound, (drift, bound, k)


def test_fast_engine_and_discrete_reference_agree_in_distribution():
    # The clock engine against a plain loop choosing a random bond N times per unit τ.  N = 50,
    # 1000 seeds each: means of E(1), E(2) and of the neighbour correlation C(1)/E at τ = 2,
    # two-sample z-test |z| < 4.  (The discrete loop makes exactly Nτ attempts, the clocks a
    # Poisson number; this changes E by a relative c²τ/2N ~ 1e-3, far below the 1% resolution.)
    def stats(cls):
        rows = []
        for seed in range(1000):
            res = simulate(cls(50, 0.5), [1.0, 2.0], seed, progress=False)
            v = res.velocities
            rows.append([res.energy[0], res.energy[1], correlation(v)[1] / res.energy[1]])
        return np.array(rows)

    fast, ref = stats(Lattice), stats(LatticeDiscreteReference)
    z = (fast.mean(0) - ref.mean(0)) / np.sqrt(fast.var(0) / 1000 + ref.var(0) / 1000)
    assert np.all(np.abs(z) < 4), z
    assert fast[:, 2].mean() > 0.1  # the constraint builds positive neighbour correlations


@pytest.mark.parametrize("constraint, rate", [(True, 0.5), (False, 1.0)])
def test_initial_energy_slope(constraint, rate):
    # Exact: from uncorrelated Gaussian data dE/dτ(0) = -(1-r²)/2 with the constraint and
    # -(1-r²) without.  N = 2e5, E at τ = 0.01..0.05 fitted by 1 + aτ + bτ² (E(0) = 1 exactly);
    # 24 seeds, tolerance 4 standard errors of the mean slope (measured SE ≈ 1.4% / 1.3%).
    r = 0.5
    taus = np.linspace(0.01, 0.05, 5)
    design = np.stack([taus, taus**2], axis=1)
    slopes = []
    for seed in range(24):
        engine = Lattice(200_000, r, constraint=constraint)
        energy = simulate(engine, taus, seed, progress=False).energy
        slopes.append(np.linalg.lstsq(design, energy - 1.0, rcond=None)[0][0])
    slopes = np.array(slopes)
    se = slopes.std(ddof=1) / np.sqrt(len(slopes))
    expected = -rate * (1 - r * r)
    assert abs(slopes.mean() - expected) < 4 * se, (slopes.mean(), se, expected)
    assert 4 * se < 0.1 * abs(expected)  # resolution: the other law is 100% away


def test_reference_energy_at_tau_20():
    # Reference (measured with independent code): r = 0.5, N = 2e5, unit Gaussian start,
    # E(20) = 0.0723 ± 0.0003 over 12 seeds.  Same protocol here; tolerance 4 combined
    # standard errors.
    energy = np.array(
        [simulate(Lattice(200_000, 0.5), [20.0], s, progress=False).energy[0] for s in range(12)]
    )
    se = energy.std(ddof=1) / np.sqrt(12)
    assert abs(energy.mean() - 0.0723) < 4 * np.hypot(se, 0.0003), (energy.mean(), se)


@pytest.fixture(scope="module")
def late_runs():
    """N = 1e5, r = 0.5, τ up to 512: seeds 1 and 2 with the constraint (S(k) for seed 1) and
    seed 1 without it at τ = 256."""
    taus = [32.0, 64.0, 128.0, 256.0, 512.0]
    with_c = [
        simulate(Lattice(100_000, 0.5), taus, seed, progress=False, structure_factor=seed == 1)
        for seed in (1, 2)
    ]
    without = simulate(
        Lattice(100_000, 0.5, constraint=False), [256.0], 1, progress=False, structure_factor=True
    )
    return with_c, without


def test_late_energy_decays_as_tau_to_minus_one_half(late_runs):
    # Fit the mean over seeds 1-2 of log E against log τ on τ ∈ [32, 512].  Measured outside CI
    # for this exact setting (one fit per seed, seeds 1-24): exponent -0.483 on average,
    # seed-to-seed standard deviation 0.0079, range -0.496 to -0.464; local slopes between
    # successive τ drift from about -0.47 toward -0.50 (preasymptotic), hence the mean is 0.017
    # short of -1/2.  The mean of 2 seeds has a standard deviation 0.0079/√2 = 0.0056, so
    # tolerance 0.04 = the drift 0.017 plus 4 standard deviations (a single seed would need
    # 0.017 + 4 × 0.0079 ≈ 0.05).  The homogeneous (mean-field) law would be exponential, slope
    # < -3 here; MD's t^(-2/3) would be 0.17 away.
    res, _ = late_runs
    times = res[0].times
    mean_log_e = np.mean([np.log(r.energy) for r in res], axis=0)
    slope = np.polyfit(np.log(times), mean_log_e, 1)[0]
    assert abs(slope + 0.5) < 0.04, slope


def porod_run_length(k, s):
    """Longest run of consecutive log-bins (5 per decade) whose local log-log slope of S(k) is
    within 0.4 of -2, for 0.05 < k < 2 (above the large-scale part, below the lattice cutoff)."""
    kb, sb, _ = log_bin(k, s, bins_per_decade=5)
    local = np.diff(np.log(sb)) / np.diff(np.log(kb))
    kmid = np.sqrt(kb[1:] * kb[:-1])
    good = (np.abs(local + 2) < 0.4) & (kmid > 0.05) & (kmid < 2.0)
    best = run = 0
    for g in good:
        run = run + 1 if g else 0
        best = max(best, run)
    return best


def test_porod_range_with_the_constraint_only(late_runs):
    # τ = 256, N = 1e5 (one run; a log-bin at k ~ 0.3 averages ~5000 modes, S to ~1.5%, so a
    # local slope over a factor 10^0.2 is good to ~0.05).  Measured: with the constraint the
    # local slopes are -2.1 ± 0.05 over 0.2 < k < 0.8 (4 bins in a row); without it S falls
    # steeply (slopes -3 to -10) onto a flat floor, crossing -2 at most once.
    # The window and thresholds were first set on seed 1 (the test's seed), then checked on
    # seeds 2-24 (outside CI): the run of -2 ± 0.4 bins is 4 for every seed (threshold 3), the
    # fitted slope over 0.2 < k < 0.8 is -2.13 ± 0.026 (range -2.18 to -2.08; threshold
    # |slope + 2| < 0.3, so ≥ 0.12 of margin = 4.7 standard deviations), and without the
    # constraint the run is 0 for every seed (threshold ≤ 1).
    with_c, without = late_runs
    with_c = with_c[0]
    k, s = with_c.structure[0], with_c.structure[1][3]
    assert with_c.times[3] == 256.0
    assert porod_run_length(k, s) >= 3
    fit = (k > 0.2) & (k < 0.8)
    slope = np.polyfit(np.log(k[fit]), np.log(s[fit]), 1)[0]
    assert abs(slope + 2) < 0.3, slope
    k, s = without.structure[0], without.structure[1][0]
    assert porod_run_length(k, s) <= 1


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n": 2, "restitution": 0.5}, "n=2"),
        ({"n": 10, "restitution": 2}, "restitution=2"),
        ({"n": 10, "restitution": 0.5, "initial": "nope"}, "initial='nope'"),
        ({"n": 10, "restitution": 0.5, "constraint": "yes"}, "constraint='yes'"),
    ],
)
def test_bad_parameters_are_named(kwargs, match):
    with pytest.raises(InvalidArgumentError, match=match):
        Lattice(**kwargs)


# ----------------------------------------------------------------- rate ∝ |Δ| (MD-like) variant


@pytest.mark.parametrize("n", [3, 4, 41, 1000])
@pytest.mark.parametrize("constraint", [True, False])
@pytest.mark.parametrize("sparse_ratio", [0, 16, 10**9])
def test_thinned_passes_equal_time_ordered_attempts(n, constraint, sparse_ratio):
    # Rate-|Δ| thinning: per-bond pre-drawn clock increments (Exp(1)/R) and acceptance marks
    # (uniform), processed in passes of local minima and one attempt at a time in time order:
    # identical velocities, clocks and counts.
    rng = np.random.default_rng(100 + n)
    v0 = rng.standard_normal(n)
    bound = thinning_bound(v0)
    table = rng.standard_exponential((n, 400)) / bound
    marks = rng.random((n, 400))
    c0 = rng.standard_exponential(n) / bound
    until = 60.0 / bound
    v1, c1 = v0.copy(), c0.copy()
    attempts, collisions, passes = run_clocks(
        v1, c1, until, 0.8, constraint, per_bond_increments(table), sparse_ratio=sparse_ratio,
        marks=per_bond_increments(marks), rate_bound=bound,
    )
    v2, c2 = v0.copy(), c0.copy()
    ref = run_clocks_sequential(
        v2, c2, until, 0.8, constraint, per_bond_increments(table),
        marks=per_bond_increments(marks), rate_bound=bound,
    )
    assert (attempts, collisions) == ref
    assert np.array_equal(v1, v2) and np.array_equal(c1, c2)
    assert np.all(c1 >= until)
    assert 0 < collisions < attempts and attempts > 40 * n
    assert attempts / (n // 2) <= passes <= attempts  # n/2 local minima at most per pass
    assert abs(v1.sum() - v0.sum()) < 1e-13 * n
    # thinning keeps every velocity inside the initial range (what makes the bound valid)
    assert v0.min() <= v1.min() and v1.max() <= v0.max()


def relative_velocity_gillespie(n, r, t_end_list, constraint, rng):
    """Independent reference without thinning: the exact continuous-time process in which bond
    b = (b, b+1) collides at rate Δ_b⁺ (constraint) or |Δ_b|, Δ_b = v_b − v_{b+1}: the next
    event after Exp(Σ rates), on a bond chosen with probability ∝ its rate.  Unit Gaussian
    start normalised like the engine (zero mean, ⟨v²⟩ = 1).  Returns v at each time and the
    number of collisions up to the last time."""
    v = rng.standard_normal(n)
    v -= v.mean()
    v /= np.sqrt(np.mean(v * v))
    p = 0.5 * (1 + r)
    t, out, collisions = 0.0, [], 0
    for t_end in t_end_list:
        while True:
            d = v - np.roll(v, -1)
            rates = np.maximum(d, 0.0) if constraint else np.abs(d)
            total = rates.sum()
            wait = rng.standard_exponential() / total if total > 0 else np.inf
            if t + wait >= t_end:
                t = t_end  # memoryless: the pending wait is redrawn from t_end
                break
            t += wait
            b = int(np.searchsorted(np.cumsum(rates), rng.random() * total, side="right"))
            b = min(b, n - 1)
            s = (b + 1) % n
            dv = (v[b] - v[s]) * p
            v[b] -= dv
            v[s] += dv
            collisions += 1
        out.append(v.copy())
    return out, collisions


@pytest.mark.parametrize("constraint", [True, False])
def test_thinned_engine_matches_exact_rate_process_in_distribution(constraint):
    # The engine (thinning at R = span of v, rescaled at every stop 0.5, 1, 1.5) against a
    # Gillespie loop with the exact rates.  N = 50, r = 0.5, 800 seeds each: means of E(1),
    # E(2), the neighbour correlation C(1)/E at t = 2 and collisions per particle by t = 2;
    # two-sample z-test |z| < 4 (measured |z| ≤ 1.3).  Power, checked by mutation: without
    # the clock rescaling between stops, E(2) is off by 5.0 / 6.3 combined standard errors and
    # τ(2) by 7.9 / 12 (with / without the constraint).
    n, r, seeds = 50, 0.5, 800
    times = [0.5, 1.0, 1.5, 2.0]
    engine = Lattice(n, r, constraint=constraint, rate="relative_velocity")
    fast, ref = [], []
    for seed in range(seeds):
        res = simulate(engine, times, seed, progress=False)
        v = res.velocities
        fast.append([res.energy[1], res.energy[3], correlation(v)[1] / res.energy[3],
                     2 * res.collisions[3] / n])
        vs, count = relative_velocity_gillespie(n, r, times, constraint,
                                                np.random.default_rng(10**6 + seed))
        e1, e2 = np.mean(vs[1] ** 2), np.mean(vs[3] ** 2)
        ref.append([e1, e2, correlation(vs[3])[1] / e2, 2 * count / n])
    fast, ref = np.array(fast), np.array(ref)
    z = (fast.mean(0) - ref.mean(0)) / np.sqrt(fast.var(0) / seeds + ref.var(0) / seeds)
    assert np.all(np.abs(z) < 4), z


@pytest.mark.parametrize("constraint, factor", [(True, 1.0), (False, 2.0)])
def test_relative_velocity_initial_cooling_is_md_like(constraint, factor):
    # Exact, uncorrelated Gaussian data of variance T = 1, bond rate Δ⁺ (constraint) or |Δ|,
    # Δ ~ N(0, 2T): a collision removes (1 − r²)Δ²/2 from Σv², so
    #   dT/dt = −(1 − r²)/2 ⟨Δ⁺ Δ²⟩ = −(2/√π)(1 − r²) T^{3/2}  (×2 without the constraint),
    #   dτ/dt = 2 ⟨Δ⁺⟩ = 2 √(T/π)                               (×2 without),
    # τ = 2·collisions/N, hence dT/dτ = −(1 − r²) T in both cases: MD's values at density 1
    #, twice the constant-rate lattice's −(1 − r²)T/2 per collision per particle.
    # N = 2e5, r = 0.5, t = 0.01..0.05 fitted by 1 + a t + b t² (E(0) = 1 and τ(0) = 0
    # exactly); 16 seeds, tolerance 4 standard errors of the mean slope over seeds (measured
    # SE with / without the constraint: 1.0% / 0.4% of the slope for E, 0.9% / 0.4% for τ,
    # 0.7% / 0.5% for dT/dτ; measured |z| ≤ 1.5).  Resolution: 4 SE < 10% of the slope, while
    # the constant-rate value of dT/dτ is 50% away.
    r, n = 0.5, 200_000
    ts = np.linspace(0.01, 0.05, 5)
    design = np.stack([ts, ts**2], axis=1)
    e_slopes, tau_slopes, ratios = [], [], []
    for seed in range(16):
        engine = Lattice(n, r, constraint=constraint, rate="relative_velocity")
        res = simulate(engine, ts, seed, progress=False)
        tau = 2.0 * res.collisions / n
        e_slopes.append(np.linalg.lstsq(design, res.energy - 1.0, rcond=None)[0][0])
        tau_slopes.append(np.linalg.lstsq(design, tau, rcond=None)[0][0])
        tau_design = np.stack([tau, tau**2], axis=1)
        ratios.append(np.linalg.lstsq(tau_design, res.energy - 1.0, rcond=None)[0][0])
    cases = [
        (e_slopes, -factor * 2 / np.sqrt(np.pi) * (1 - r * r)),
        (tau_slopes, factor * 2 / np.sqrt(np.pi)),
        (ratios, -(1 - r * r)),
    ]
    for slopes, expected in cases:
        slopes = np.array(slopes)
        se = slopes.std(ddof=1) / np.sqrt(len(slopes))
        assert abs(slopes.mean() - expected) < 4 * se, (slopes.mean(), se, expected)
        assert 4 * se < 0.1 * abs(expected)


class _Interrupting:
    """Wraps an engine and raises KeyboardInterrupt in its ``after``-th advance."""

    def __init__(self, inner, after):
        self.inner, self.after, self.calls = inner, after, 0

    def __getattr__(self, item):
        return getattr(self.inner, item)

    def advance(self, state, until, rng):
        self.calls += 1
        if self.calls == self.after:
            raise KeyboardInterrupt
        return self.inner.advance(state, until, rng)


def test_relative_velocity_checkpoint_resumes_bit_for_bit_and_is_its_own_run(tmp_path):
    from particles.driver import CheckpointError

    engine = Lattice(400, 0.7, "uniform", rate="relative_velocity")
    assert engine.to_dict()["rate"] == "relative_velocity"
    assert "rate" not in Lattice(400, 0.7, "uniform").to_dict()  # old checkpoints stay valid
    assert engine.time_name == "t"
    times = [1.0, 6.0, 13.0]
    reference = simulate(engine, times, 4, progress=False)
    path = tmp_path / "rv.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(_Interrupting(engine, 3), times, 4, progress=False, checkpoint=path)
    resumed = simulate(engine, times, 4, progress=False, resume=path)
    for a, b in [(reference.energy, resumed.energy), (reference.collisions, resumed.collisions),
                 (reference.velocities, resumed.velocities)]:
        assert np.array_equal(a, b)
    with pytest.raises(CheckpointError):
        simulate(Lattice(400, 0.7, "uniform"), times, 4, progress=False, resume=path)


def test_relative_velocity_rate_is_validated():
    with pytest.raises(InvalidArgumentError, match="rate='nope'"):
        Lattice(10, 0.5, rate="nope")
    with pytest.raises(InvalidArgumentError, match=r"^argument rate='relative_velocity' is "
                                                   r"invalid: expected 'constant' \(the discrete "
                                                   r"reference\)$"):
        LatticeDiscreteReference(10, 0.5, rate="relative_velocity")


def test_thinning_bound_of_one_site_and_its_refusals():
    """One velocity has no pair: R = 0.  Not a non-empty 1-D array: refused, naming ``v``."""
    assert thinning_bound([0.3]) == 0.0
    for bad, match in ((np.zeros((2, 2)), r"expected a 1-dimensional array"),
                       ([], r"expected at least 1 values")):
        with pytest.raises(InvalidArgumentError, match=r"^argument v=.*" + match) as info:
            thinning_bound(bad)
        assert info.value.name == "v"


@pytest.mark.parametrize("constraint", [True, False])
def test_discrete_reference_by_hand(constraint):
    # The discrete reference draws `round(τN) − attempts` bonds uniformly from 0..N−1 (bond b
    # joins sites b and b + 1 mod N) and collides each, under the constraint only if the left
    # site is strictly faster.  Here, by hand: the same draws, the rule as weighted means, the
    # seam bond N − 1 = (N − 1, 0), a tie (no collision under the constraint), the count.
    n, r = 5, 0.3
    engine = LatticeDiscreteReference(n, r, constraint=constraint)
    until = 3.0  # 15 attempts
    bonds = np.random.default_rng(9).integers(0, n, 15).tolist()
    assert {n - 2, n - 1} <= set(bonds)  # the last inner bond and the seam are drawn
    v0 = np.roll([1.0, 1.0, -0.5, 2.0, 0.25], bonds[0])  # the first bond drawn is a tie
    clocks = np.arange(1.0, 6.0)
    state = LatticeState(0.0, v0.copy(), clocks, 0, 0)
    v, count = v0.tolist(), 0
    for b in bonds:
        s = (b + 1) % n
        if not constraint or v[b] > v[s]:
            a, c = v[b], v[s]
            v[b], v[s] = ((1 - r) * a + (1 + r) * c) / 2, ((1 + r) * a + (1 - r) * c) / 2
            count += 1
    out = engine.advance(state, until, np.random.default_rng(9))
    np.testing.assert_allclose(out.velocities, v, rtol=1e-12, atol=1e-14)
    assert out.collisions == count and out.attempts == 15 and out.time == until
    assert count < 15 if constraint else count == 15
    np.testing.assert_array_equal(out.clocks, clocks)


def test_thinning_bound_is_never_below_the_largest_difference():
    v = np.array([0.3, -1.7, 2.9, 0.0])
    assert thinning_bound(v) >= 2.9 - (-1.7)
    assert thinning_bound(v) == pytest.approx(4.6, rel=1e-8)


@pytest.mark.parametrize("rate", ["constant", "relative_velocity"])
def test_initial_state_counts_nothing_yet(rate):
    state = Lattice(50, 0.5, rate=rate).initial_state(np.random.default_rng(3))
    assert state.time == 0.0 and state.collisions == 0 and state.attempts == 0
    assert np.all(state.clocks > 0.0) and state.clocks.shape == (50,)


def test_parameters_are_recorded_under_their_documented_names():
    # to_dict is what checkpoints and saved runs record and what resume compares
    engine = Lattice(50, 0.25, initial="uniform", constraint=False)
    d = engine.to_dict()
    assert set(d) == {"n", "restitution", "initial", "constraint", "stop_step"}
    assert (d["n"], d["restitution"], d["initial"], d["constraint"]) == (50, 0.25, "uniform",
                                                                         False)
    assert d["stop_step"] == engine.stop_step
    assert Lattice(50, 0.25, rate="relative_velocity").to_dict()["rate"] == "relative_velocity"


def test_advance_to_the_same_time_is_a_no_op_and_backwards_is_refused():
    engine = Lattice(20, 0.5)
    state = engine.advance(engine.initial_state(np.random.default_rng(1)), 1.0,
                           np.random.default_rng(2))
    same = engine.advance(state, 1.0, np.random.default_rng(3))
    np.testing.assert_array_equal(same.velocities, state.velocities)
    assert same.collisions == state.collisions
    with pytest.raises(InvalidArgumentError, match=r"until=0\.5.*a time >= 1\.0"):
        engine.advance(state, 0.5, np.random.default_rng(3))


def test_rate_relative_velocity_advance_refuses_a_state_without_attempt_rate():
    """A rate-|Δ| engine given a constant-rate state (no ``attempt_rate``) refuses it, naming
    the argument, what it got and what it needs, and leaves the state untouched."""
    engine = Lattice(20, 0.5, rate="relative_velocity")
    constant = Lattice(20, 0.5).initial_state(np.random.default_rng(1))
    assert constant.attempt_rate is None
    before = constant.velocities.copy()
    with pytest.raises(InvalidArgumentError,
                       match=r"argument state='a state without attempt_rate' is invalid: "
                             r"expected a rate-\|Δ\| state"):
        engine.advance(constant, 1.0, np.random.default_rng(2))
    np.testing.assert_array_equal(constant.velocities, before)


def test_rate_relative_velocity_gas_of_equal_velocities_never_collides():
    """All velocities equal: every pair's rate |Δ| is 0, so no bond ever collides.  The advance
    returns the state at ``until`` with the velocities, counts and attempt rate unchanged, and
    every pending clock at or after ``until`` (none due before it)."""
    engine = Lattice(8, 0.5, rate="relative_velocity")
    v = np.full(8, 0.3)
    clocks = np.array([0.1, 0.5, 2.0, 3.5, 0.2, 9.0, 1.5, 0.05])
    state = LatticeState(0.0, v, clocks, collisions=5, attempts=7, attempt_rate=1.25)
    out = engine.advance(state, 3.0, np.random.default_rng(0))
    assert out.time == 3.0
    np.testing.assert_array_equal(out.velocities, v)
    np.testing.assert_array_equal(out.clocks, np.maximum(clocks, 3.0))
    assert (out.collisions, out.attempts, out.attempt_rate) == (5, 7, 1.25)
    # the input state is not modified
    np.testing.assert_array_equal(state.clocks, [0.1, 0.5, 2.0, 3.5, 0.2, 9.0, 1.5, 0.05])


def _lattice_arrays(n=4, time=1.0, rate=None):
    arrays = {"time": np.array(time), "velocities": np.arange(n, dtype=float),
              "clocks": np.full(n, time + 0.5), "collisions": np.array(3),
              "attempts": np.array(9)}
    if rate is not None:
        arrays["attempt_rate"] = np.array(rate)
    return arrays


def test_lattice_state_from_arrays_round_trip_and_copies():
    arrays = _lattice_arrays(rate=2.5)
    state = LatticeState.from_arrays(arrays, 4)
    assert (state.time, state.collisions, state.attempts, state.attempt_rate) == (1.0, 3, 9, 2.5)
    assert isinstance(state.collisions, int) and isinstance(state.attempts, int)
    np.testing.assert_array_equal(state.velocities, arrays["velocities"])
    np.testing.assert_array_equal(state.clocks, arrays["clocks"])
    arrays["velocities"][0] = 99.0
    arrays["clocks"][0] = 99.0
    assert state.velocities[0] == 0.0 and state.clocks[0] == 1.5  # copies, not views
    assert LatticeState.from_arrays(_lattice_arrays(), 4).attempt_rate is None
    # a cold rate-|Δ| gas has a bound below 1: any finite R > 0 loads
    assert LatticeState.from_arrays(_lattice_arrays(rate=0.25), 4).attempt_rate == 0.25
    # a clock exactly at the state's time is pending, not past
    at_time = _lattice_arrays()
    at_time["clocks"][2] = 1.0
    assert LatticeState.from_arrays(at_time, 4).clocks[2] == 1.0
    back = LatticeState.from_arrays(state.to_arrays(), 4)
    assert back.to_arrays().keys() == state.to_arrays().keys()
    # integer arrays (a hand-made file) become the documented float arrays
    ints = _lattice_arrays()
    ints["velocities"], ints["clocks"] = np.arange(4), np.full(4, 2)
    loaded = LatticeState.from_arrays(ints, 4)
    assert loaded.velocities.dtype == loaded.clocks.dtype == np.float64


@pytest.mark.parametrize("change, match", [
    (lambda a: a.pop("clocks"), r"checkpoint=\"missing \['clocks'\]\".*expected a lattice state$"),
    (lambda a: a.update(velocities=np.zeros(5)),
     r"checkpoint='velocities \(5,\) / clocks \(4,\)'.*expected \(4,\)"),
    (lambda a: a.update(clocks=np.zeros(3)),
     r"checkpoint='velocities \(4,\) / clocks \(3,\)'.*expected \(4,\)"),
    (lambda a: a["clocks"].__setitem__(1, 0.999), r"checkpoint='clocks'.*>= time=1\.0"),
    (lambda a: a["clocks"].__setitem__(1, np.inf), r"checkpoint='clocks'.*finite"),
    (lambda a: a["clocks"].__setitem__(1, np.nan), r"checkpoint='clocks'"),
    (lambda a: a.update(attempt_rate=np.array(0.0)),
     r"checkpoint='attempt_rate=0\.0'.*expected a finite number > 0$"),
    (lambda a: a.update(attempt_rate=np.array(-1.0)), r"checkpoint='attempt_rate=-1\.0'"),
    (lambda a: a.update(attempt_rate=np.array(np.inf)), r"checkpoint='attempt_rate=inf'"),
    (lambda a: a.update(attempt_rate=np.array(np.nan)), r"checkpoint='attempt_rate=nan'"),
])
def test_lattice_state_from_arrays_refuses_an_inconsistent_state(change, match):
    arrays = _lattice_arrays()
    change(arrays)
    with pytest.raises(InvalidArgumentError, match=match):
        LatticeState.from_arrays(arrays, 4)


def test_lattice_state_from_arrays_refuses_a_state_of_the_other_rate():
    """The engine's state_from_arrays checks the rate as well as LatticeState's checks."""
    with_rate, without = _lattice_arrays(rate=2.0), _lattice_arrays()
    assert Lattice(4, 0.5, rate="relative_velocity").state_from_arrays(with_rate).attempt_rate \
        == 2.0
    assert Lattice(4, 0.5).state_from_arrays(without).attempt_rate is None
    with pytest.raises(InvalidArgumentError,
                       match=r"checkpoint='attempt_rate=2\.0'.*rate='constant'"):
        Lattice(4, 0.5).state_from_arrays(with_rate)
    with pytest.raises(InvalidArgumentError,
                       match=r"checkpoint='attempt_rate=None'.*rate='relative_velocity'"):
        Lattice(4, 0.5, rate="relative_velocity").state_from_arrays(without)
    with pytest.raises(InvalidArgumentError, match=r"expected \(5,\)"):
        Lattice(5, 0.5).state_from_arrays(without)


def test_constrained_attempts_between_equal_velocities_are_not_collisions():
    """With the constraint a bond collides only if its pair approaches, Δ = v_b − v_{b+1} > 0:
    in a gas of equal velocities every attempt finds Δ = 0, so none counts as a collision and
    the velocities stay exactly as they were (without the constraint every attempt counts)."""
    for constraint, counted in ((True, False), (False, True)):
        v = np.full(6, 0.7)
        clocks = np.random.default_rng(3).standard_exponential(6)
        table = np.random.default_rng(4).standard_exponential((6, 100))
        attempts, collisions, _ = run_clocks(v, clocks, 5.0, 0.5, constraint,
                                             per_bond_increments(table))
        assert attempts > 6
        assert collisions == (attempts if counted else 0)
        np.testing.assert_array_equal(v, np.full(6, 0.7))


def test_lattice_parameters_are_checked_and_normalised():
    """What the constructor stores is the checked value in its plain type (the recorded
    parameters and the checkpoints compare them); its refusals name the argument and value."""
    from particles.initial import law_from_characteristic

    engine = Lattice(np.int64(3), np.float32(0.5))  # a ring of 3, the smallest lattice
    assert type(engine.n) is int and engine.n == 3
    assert type(engine.restitution) is float and engine.restitution == 0.5
    with pytest.raises(InvalidArgumentError, match=r"^argument n=2 is invalid"):
        Lattice(2, 0.5)
    no_sampler = law_from_characteristic(lambda k: np.exp(-0.5 * k * k), 1.0, name="mine")
    with pytest.raises(InvalidArgumentError, match=r"^argument initial='mine' is invalid: "
                                                   r"expected a law with a sampler$"):
        Lattice(10, 0.5, initial=no_sampler)
    named = Lattice(10, 0.5, initial=get_law("uniform"), constraint=np.bool_(False))
    assert named.initial == "uniform" and named.constraint is False
    with pytest.raises(InvalidArgumentError,
                       match=r"^argument constraint=1 is invalid: expected True or False$"):
        Lattice(10, 0.5, constraint=1)
    with pytest.raises(InvalidArgumentError, match=r"^argument rate='fast' is invalid: "
                                                   r"expected a registered kernel: 'constant', "
                                                   r"'relative_velocity'$"):
        Lattice(10, 0.5, rate="fast")


def test_expected_events_is_the_documented_estimate():
    """N t attempts at constant rate; with rate |Δ| the clocks tick at the velocity range,
    about 2√(2 ln N) at t = 0: N t · 2√(2 ln N)."""
    assert Lattice(1000, 0.5).expected_events(3.0, 5) == (3000.0, "attempts")
    events, unit = Lattice(1000, 0.5, rate="relative_velocity").expected_events(3.0, 5)
    assert unit == "attempts"
    assert events == pytest.approx(3000.0 * 2.0 * math.sqrt(2.0 * math.log(1000.0)), rel=1e-15)
