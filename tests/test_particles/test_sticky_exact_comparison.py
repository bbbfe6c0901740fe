"""particles.sticky_comparison.ExactLawComparison: the pooled histograms of sticky-gas states
against the exact late-time laws — counting on hand-made states, the delta-method error of the tail
exponent against the scatter of repeated samples, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from particles.sticky import StickyGas, StickyParams, StickyState
from particles.sticky_comparison import EXACT_W_EDGES, ExactLawComparison
from particles.validation import InvalidArgumentError


def _state(masses, velocities, t=1.0) -> StickyState:
    """A state with the given clusters (density 1, labels in order, positions unused)."""
    masses = np.asarray(masses, dtype=np.int64)
    velocities = np.asarray(velocities, dtype=float)
    n = int(masses.sum())
    starts = np.concatenate([[0], np.cumsum(masses)[:-1]])
    x0 = np.arange(n, dtype=float)
    return StickyState(float(t), float(n), x0, np.repeat(velocities, masses), starts,
                       x0[starts], velocities, np.repeat(velocities, masses), n - masses.size)


def test_counts_on_a_hand_made_state():
    # density 1, t = 8: w = 2 v, μ = m / 4.  Clusters of masses 1, 2, 3, 40 at w = −2, 0.6, 1.8, 0
    cmp = ExactLawComparison(8.0, tail_w=[1.0, 1.9, 2.5], min_clusters=1)
    cmp.add(_state([1, 2, 3, 40], [-1.0, 0.3, 0.9, 0.0], t=8.0))
    n = 46
    vel = cmp.velocity()
    centres = 0.5 * (EXACT_W_EDGES[:-1] + EXACT_W_EDGES[1:])
    for w, m in ((-2.0, 1), (0.6, 2), (1.8, 3)):
        k = int(np.flatnonzero((EXACT_W_EDGES[:-1] <= w) & (w < EXACT_W_EDGES[1:]))[0])
        assert vel["density"][k] == pytest.approx(m / (n * 0.25))
        assert vel["density_error"][k] == pytest.approx(m / (n * 0.25))
        assert abs(centres[k] - w) <= 0.125
    assert vel["observed"].sum() == n
    assert vel["expected"].sum() == pytest.approx(n, rel=1e-9)  # the exact law is normalised
    mass = cmp.mass()
    assert mass["observed"].sum() == 4  # every cluster, the one beyond 8 M = 32 included
    assert mass["observed"][-1] >= 1 and mass["hi"][-1] == 32
    tail = cmp.tail(exact=False)
    # |w| = 2, 0.6, 1.8, 0: above 1.0 the masses 1 + 3, above 1.9 the mass 1, above 2.5 none
    np.testing.assert_allclose(tail["survival"], [4 / n, 1 / n, 0.0])
    np.testing.assert_allclose(tail["survival_error"], [math.sqrt(10) / n, 1 / n, 0.0])
    np.testing.assert_array_equal(tail["clusters_beyond"], [2, 1, 0])
    np.testing.assert_array_equal(tail["resolved"], [True, True, False])
    beta = (math.log(-math.log(1 / n)) - math.log(-math.log(4 / n))) / math.log(1.9)
    assert tail["beta"][0] == pytest.approx(beta)
    assert tail["deepest"]["w"] == pytest.approx(2.0)



def test_mass_and_velocity_scales_with_the_initial_variance_by_hand():
    # density 1, t = 8, T₀ = 1/8: M = (n² T₀ t²)^{1/3} = (64/8)^{1/3} = 2 and w = v (n t/T₀)^{1/3}
    # = 4 v.  Clusters of masses 1, 2, 3, 40 (N = 46) at v = −1, 0.3, 0.9, 0: the mass bins sit at
    # μ = m/2, each bin's density is clusters / (N/M × width in μ), the number of clusters × M/N
    # is 4 · 2/46, and E (n t)^{2/3} T₀^{−2/3} = Σ m w²/N = (16 + 2 · 1.44 + 3 · 12.96)/46.
    cmp = ExactLawComparison(8.0, variance=0.125, min_clusters=1)
    cmp.add(_state([1, 2, 3, 40], [-1.0, 0.3, 0.9, 0.0], t=8.0))
    mass = cmp.mass()
    lo, hi = mass["lo"], mass["hi"]
    np.testing.assert_allclose(mass["mu"], (lo + hi) / 4, rtol=1e-15)
    np.testing.assert_allclose(mass["density"], mass["observed"] / (23 * (hi - lo + 1) / 2),
                               rtol=1e-15)
    assert hi[-1] == 16  # masses up to 8 M, the heavier ones in the last bin
    corr = cmp.corrections()
    assert corr["clusters"]["value"][0] == pytest.approx(4 / 23, rel=1e-15)
    assert corr["energy"]["value"][0] == pytest.approx(57.76 / 46, rel=1e-14)

def test_tail_exponent_error_matches_the_scatter_of_repeated_samples():
    # Clusters of masses 1 + Poisson(2) with w Laplace-distributed: the chord β between w = 1
    # and 2 from 400 independent samples of 5000 clusters.  The delta-method error must match
    # the standard deviation over the samples; the sample std of 400 values has a relative
    # error of 1/√798 = 3.5 %, so 15 % is more than 4 of it.
    rng = np.random.default_rng(7)
    betas, errors = [], []
    for _ in range(400):
        m = 1 + rng.poisson(2.0, 5000)
        cmp = ExactLawComparison(1.0, tail_w=[1.0, 2.0], min_clusters=25)
        cmp.add(_state(m, rng.laplace(0.0, 1.0, m.size)))
        tail = cmp.tail(exact=False)
        betas.append(tail["beta"][0])
        errors.append(tail["beta_error"][0])
    ratio = np.std(betas, ddof=1) / np.mean(errors)
    assert abs(ratio - 1.0) < 0.15, ratio


def test_an_engine_state_counts_every_particle():
    engine = StickyGas(StickyParams(20_000, 1.0, "gaussian"))
    state = engine.advance(engine.initial_state(np.random.default_rng(3)), 50.0)
    cmp = ExactLawComparison(50.0)
    cmp.add(state)
    cmp.add(state)
    vel, mass = cmp.velocity(), cmp.mass()
    assert vel["observed"].sum() == 40_000
    assert mass["observed"].sum() == 2 * state.starts.size
    corr = cmp.corrections()
    e = float(np.mean(state.velocities**2)) * 50.0 ** (2.0 / 3.0)
    assert corr["energy"]["value"][0] == pytest.approx(e)
    assert corr["energy"]["value"][1] == 0.0  # two identical runs


def test_bad_input_names_the_argument():
    state = _state([1, 2], [0.1, -0.1], t=2.0)
    with pytest.raises(InvalidArgumentError, match="argument state="):
        ExactLawComparison(1.0).add(state)  # another time
    with pytest.raises(InvalidArgumentError, match="argument state="):
        ExactLawComparison(2.0).add("not a state")
    with pytest.raises(InvalidArgumentError, match="argument tail_w="):
        ExactLawComparison(1.0, tail_w=[2.0, 1.0])
    with pytest.raises(InvalidArgumentError, match="argument t="):
        ExactLawComparison(-1.0)
    with pytest.raises(InvalidArgumentError, match="argument states="):
        ExactLawComparison(1.0).velocity()


def test_merged_halves_are_the_whole():
    # two gases added to one comparison, against one gas added to each of two merged ones; the
    # sums are the same up to the order of additions (1e-12)
    from particles.sticky_comparison import exact_law_runs

    grid = [0.8, 1.2, 1.8, 2.7]
    whole = exact_law_runs(3000, [1, 2, 3], [50.0, 400.0], tail_w=grid, min_clusters=3)
    first = exact_law_runs(3000, [1], [50.0, 400.0], tail_w=grid, min_clusters=3)
    rest = exact_law_runs(3000, [2, 3], [50.0, 400.0], tail_w=grid, min_clusters=3)
    for a, b, c in zip(first, rest, whole, strict=True):
        a.merge(b)
        assert a.runs == c.runs == 3 and a.particles == c.particles
        for method in ("velocity", "mass"):
            got, want = getattr(a, method)(), getattr(c, method)()
            for key in ("observed", "expected"):
                np.testing.assert_allclose(got[key], want[key], rtol=1e-12)
            assert got["chi2"] == pytest.approx(want["chi2"], rel=1e-12)
        got, want = a.tail(exact=False), c.tail(exact=False)
        np.testing.assert_allclose(got["survival"], want["survival"], rtol=1e-12)
        assert got["deepest"] == want["deepest"]
        assert a.corrections() == c.corrections()


def test_merging_an_empty_comparison_changes_nothing_and_a_mismatch_is_named():
    cmp = ExactLawComparison(8.0, tail_w=[1.0, 1.9, 2.5], min_clusters=1)
    cmp.add(_state([1, 2, 3, 40], [-1.0, 0.3, 0.9, 0.0], t=8.0))
    before = cmp.velocity()["observed"].copy()
    cmp.merge(ExactLawComparison(8.0, tail_w=[1.0, 1.9, 2.5], min_clusters=1))
    assert np.array_equal(cmp.velocity()["observed"], before) and cmp.runs == 1
    for other in (ExactLawComparison(9.0, tail_w=[1.0, 1.9, 2.5], min_clusters=1),
                  ExactLawComparison(8.0, tail_w=[1.0, 2.0], min_clusters=1),
                  ExactLawComparison(8.0, tail_w=[1.0, 1.9, 2.5], min_clusters=2), "x"):
        with pytest.raises(InvalidArgumentError, match="other"):
            cmp.merge(other)
