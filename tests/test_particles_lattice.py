"""The lattice model: exactness of the parallel clock passes, agreement with the discrete
model, the exact initial cooling rates, E ~ τ^(-1/2), the k⁻² Porod range and the SPEC
reference value."""

import numpy as np
import pytest

from particles.driver import simulate
from particles.lattice import (
    Lattice,
    LatticeDiscreteReference,
    run_clocks,
    run_clocks_sequential,
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
    # SPEC §3: from uncorrelated Gaussian data dE/dτ(0) = -(1-r²)/2 with the constraint and
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
    # SPEC §3 (measured with independent code): r = 0.5, N = 2e5, unit Gaussian start,
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
