"""Tests written to kill wrong constants of 0.1 % that passed the whole suite before,
each derived by hand or exactly, never from a number read off a run:

* ``test_hard_rod_scaling_state_is_normalised``: the hard-rod scaling state's conditions
  ∫F = 1, ⟨c⟩ = 0, ⟨c²⟩ = 1 (``scaling_state``, maxwell_kinetics/inelastic_boltzmann.py)
  solved with ⟨c²⟩ = 1.001; checked by the trapezoid rule of ``numpy`` on the returned F, to
  1e-12, not by the state's own ``moment``.
* ``test_collisions_per_particle_of_the_elastic_gas``: the collision count τ(t) behind the
  rate/correlation split (``collisions_per_particle``, comparisons/_rate_vs_correlations.py)
  0.1 % off; checked at r = 1 against τ = 2nt/√π times the grid's quadrature factor
  1 − h²/24 − h⁴/960, derived by hand (Euler–Maclaurin at the kink of |v − w|).
* ``test_rescaled_rows_have_zero_mean_and_unit_variance``: ``analysis.rescaled`` (every
  comparison's kurtosis) with its mean or its variance 0.1 % off (or the variance with N − 1);
  checked exactly: ⟨x⟩ = 0, ⟨x²⟩ = 1 per row to round-off, x = ±1 for two particles, affine
  invariance.
* ``testkurtosis_sampling_error_*``: the delta-method σ of the sample kurtosis
  (``kurtosis_sampling_error``, comparisons/_rate_vs_correlations.py) 0.1 % off; checked on a
  sample with the Gaussian moments 3, 15, 105 (var ψ = 24, σ = √(24/(NR)) exactly) and on
  integer samples against var ψ = m₈ − 4m₄m₆ + 4m₄³ − m₄² in exact rationals (the Gaussian is
  blind to the coefficient 2 of ψ: Cov(ψ, x²) = 0 there).

The two solver tests compile the solver on the grids that the existing tests use (61 points on
±6 for the scaling state, 101 on ±6 for the solution: test_inelastic_boltzmann.py and
comparisons/test_rate_vs_correlations.py), so in a full run they reuse those compilations; alone,
each spends ~5 s compiling and well under a second computing.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy import optimize, special

from maxwell_kinetics.app.comparisons import collisions_per_particle, kurtosis_sampling_error
from maxwell_kinetics.app.comparisons.analysis import rescaled
from maxwell_kinetics.inelastic_boltzmann import scaling_state, solve_boltzmann
from maxwell_kinetics.velocity_grid import VelocityGrid

EPS = np.finfo(float).eps

# ------------------------------------------------------------------- 3. the scaling state


def test_hard_rod_scaling_state_is_normalised():
    """F of the hard-rod scaling state at r = 0.9 on 61 points of [−6, 6] (the grid of the
    existing stationarity test): the trapezoid rule (``numpy.trapezoid`` on nodes built here,
    not the solver's ``grid_sum`` nor ``moment``) gives ∫F = 1, ∫cF = 0, ∫c²F = 1 to 1e-12.
    The trapezoid rule differs from the solver's sum h Σ F_i c_i^k by h(F₀c₀^k + F_N c_N^k)/2,
    ~1e-15·36·0.1 with F ~ 1e-15 at ±6; Newton stops at a residual ≤ 1e-11 with the three
    conditions as equations of the least-squares system, met to round-off."""
    state = scaling_state(0.9, grid=VelocityGrid(61, 6.0), relaxation=20.0)
    assert state.residual <= 1e-11
    c = np.linspace(-6.0, 6.0, 61)
    np.testing.assert_allclose(state.grid.c, c, rtol=0, atol=1e-14)
    F = np.asarray(state.F)
    assert np.max(np.abs(F[[0, -1]])) < 1e-12  # the state fits on the grid
    assert np.trapezoid(F, c) == pytest.approx(1.0, abs=1e-12)
    assert np.trapezoid(c * F, c) == pytest.approx(0.0, abs=1e-12)
    assert np.trapezoid(c * c * F, c) == pytest.approx(1.0, abs=1e-12)


# ------------------------------------------------------- 4. collisions per particle at r = 1


def test_collisions_per_particle_of_the_elastic_gas():
    """At r = 1 from the unit Gaussian the law does not change, and each particle collides at
    rate n⟨|v − w|⟩ = n·E|N(0, 2)| = 2n/√π: τ(t) = 2nt/√π exactly.

    On the grid (spacing h = 0.12, 101 points on ±6, the comparisons' small grid) the solver's
    ⟨|v − w|⟩ is h² Σᵢⱼ FᵢFⱼ|cᵢ − cⱼ| = h Σ_d |dh| k_h(dh), k_h(x) = h Σᵢ F(cᵢ)F(cᵢ − x) = the
    N(0, 2) density k to spectral accuracy: the trapezoid rule of |x| k(x), whose kink at the
    node 0 costs (Euler–Maclaurin, both sides) −(h²/6)k(0) + (h⁴/120)k''(0) + O(h⁶), with
    k(0) = 1/(2√π), k''(0) = −k(0)/2.  Relative to 2/√π: 1 − h²/24 − h⁴/960 (6.00216e-4 below 1
    at h = 0.12).  Tolerance 1e-7: the O(h⁶) term (~2e-10) and the cut at ±6 (mass 2e-9 outside,
    each at |v − w| ≲ 7: ~1e-8).  The trapezoid rule in t of a constant rate is exact, so every
    saved time (unequal steps here) has the same ratio; two densities check the factor n."""
    grid = VelocityGrid(101, 6.0)
    h = grid.h
    assert h == pytest.approx(0.12, rel=1e-15)
    factor = 1.0 - h * h / 24.0 - h**4 / 960.0
    t = np.array([0.0, 0.3, 1.0, 2.5])
    for n in (1.0, 2.5):
        solution = solve_boltzmann(1.0, t, density=n, grid=grid)
        tau = collisions_per_particle(solution)
        assert tau[0] == 0.0
        exact = 2.0 * n * t[1:] / math.sqrt(math.pi)
        np.testing.assert_allclose(tau[1:] / exact, factor, rtol=0, atol=1e-7)


# ------------------------------------------------------------------------- 5. rescaled


def test_rescaled_rows_have_zero_mean_and_unit_variance():
    """``rescaled`` maps each row (last axis) to x = (v − ⟨v⟩)/√⟨(v − ⟨v⟩)²⟩: shape kept,
    ⟨x⟩ = 0 and ⟨x²⟩ = 1 (the population variance, divisor N) per row, to round-off; any row of
    two distinct values becomes ±1 exactly; x is invariant under v → av + b (a > 0) and changes
    sign for a < 0; rows do not mix.

    Round-off: subtracting a mean of size |b| leaves errors ~ε|b| per element, i.e. ε|b|/s in x
    (s the row's spread); the bound used is 64ε(1 + |b|/s), and 64ε for ⟨x²⟩ − 1 (one division
    by a square root computed from the same numbers)."""
    rng = np.random.default_rng(47)
    shape = (3, 4, 257)
    offsets = rng.choice([-1e3, -7.5, 0.0, 3.0, 250.0], size=shape[:2])[..., None]
    scales = 10.0 ** rng.uniform(-6, 6, size=shape[:2])[..., None]
    laws = [rng.standard_normal(shape), rng.exponential(size=shape),
            rng.uniform(-1, 1, size=shape) ** 3]
    for z in laws:
        v = offsets + scales * z
        x = rescaled(v)
        assert x.shape == v.shape
        spread = scales * np.std(z, axis=-1, keepdims=True)
        bound = 64 * EPS * (1.0 + np.abs(offsets) / spread)
        worst_mean = float(np.max(np.abs(np.mean(x, axis=-1, keepdims=True)) / bound))
        assert worst_mean <= 1.0, f"<x> off by {worst_mean:.3g} times its round-off bound"
        worst_var = float(np.max(np.abs(np.mean(x * x, axis=-1) - 1.0)))
        assert worst_var <= 64 * EPS, f"<x^2> - 1 = {worst_var:.3g}"
        np.testing.assert_allclose(rescaled(-2.0 * v + 5.0), -x, rtol=0, atol=1e-9)
        np.testing.assert_allclose(rescaled(v[1, 2]), x[1, 2], rtol=0, atol=1e-15)
    two = rescaled(np.array([[3.0, -1.0], [0.5, 2.5], [-7.0, 1e6]]))
    np.testing.assert_array_equal(two, [[1.0, -1.0], [-1.0, 1.0], [-1.0, 1.0]])
    three = rescaled(np.array([-1.0, 0.0, 1.0]))  # ⟨v²⟩ = 2/3: x = ∓√(3/2), 0
    np.testing.assert_allclose(three, [-math.sqrt(1.5), 0.0, math.sqrt(1.5)], rtol=1e-15)


# ------------------------------------------------------- 6. the kurtosis's sampling error


def _gaussian_moment_sample(m: int) -> np.ndarray:
    """2m values ±z_j whose normalised moments ⟨x⁴⟩, ⟨x⁶⟩, ⟨x⁸⟩ (⟨x²⟩ = 1) are the Gaussian
    3, 15, 105 to round-off: z = q(1 + a q² + b q⁴ + c q⁶), q the half-normal quantiles, with
    (a, b, c) solved for (the three equations are scale-free)."""
    q = math.sqrt(2.0) * special.erfinv((np.arange(1, m + 1) - 0.5) / m)

    def values(p):
        return q * (1.0 + p[0] * q**2 + p[1] * q**4 + p[2] * q**6)

    def defects(p):
        y = values(p) ** 2
        m2 = np.mean(y)
        return [np.mean(y**2) / m2**2 - 3.0, np.mean(y**3) / m2**3 - 15.0,
                np.mean(y**4) / m2**4 - 105.0]

    solved = optimize.root(defects, [0.0, 0.0, 0.0], method="hybr", tol=1e-15)
    assert solved.success
    z = values(solved.x)
    return np.concatenate([-z[::-1], z])


def _exact_psi_variance(sample) -> Fraction:
    """var ψ, ψ = (x⁴ − m₄) − 2m₄(x² − 1), x the centred sample scaled to ⟨x²⟩ = 1, in exact
    rationals for an integer sample symmetric about 0: with m_k = M_k/M₂^{k/2} (M_k the central
    moments), ⟨ψ⟩ = 0 and ⟨ψ²⟩ = m₈ − 4m₄m₆ + 4m₄³ − m₄² (expand the square, ⟨x²⟩ = 1)."""
    values = [Fraction(int(s)) for s in sample]
    n = len(values)
    assert sum(values) == 0

    def central(k):
        return sum(x**k for x in values) / n

    m2 = central(2)
    m4, m6, m8 = central(4) / m2**2, central(6) / m2**3, central(8) / m2**4
    return m8 - 4 * m4 * m6 + 4 * m4**3 - m4**2


def testkurtosis_sampling_error_is_24_over_n_for_gaussian_moments():
    """For a law with the Gaussian moments, var ψ = 105 − 4·3·15 + 4·27 − 9 = 24, so the
    delta-method error of the mean kurtosis of R runs of N particles is √(R·24/N)/R = √(24/(NR)),
    the textbook 24/N.  A sample whose own moments are Gaussian (to round-off) makes this exact;
    the shift 5 and scale 3 of the rows show that it is computed on the rescaled velocities."""
    sample = _gaussian_moment_sample(500)
    n = sample.size
    x = sample / math.sqrt(np.mean(sample**2))
    for k, expected in ((4, 3.0), (6, 15.0), (8, 105.0)):
        assert math.fsum(x**k) / n == pytest.approx(expected, rel=1e-12)
    runs = 3
    snapshots = np.empty((runs, 2, n))
    for r in range(runs):
        for j in range(2):
            snapshots[r, j] = 5.0 + 3.0 * np.roll(sample, 17 * r + j)  # same moments
    sigma = kurtosis_sampling_error(snapshots)
    assert sigma.shape == (2,)
    np.testing.assert_allclose(sigma, math.sqrt(24.0 / (n * runs)), rtol=1e-10)


def testkurtosis_sampling_error_on_integer_samples_in_exact_arithmetic():
    """Symmetric integer samples (non-Gaussian: there the coefficient 2 of ψ matters) against
    var ψ in exact rationals (:func:`_exact_psi_variance`); R = 2 runs of unequal var ψ:
    σ = √((var ψ₁ + var ψ₂)/N)/2."""
    half = [np.array([1, 2, 2, 5]), np.array([1, 1, 3, 4, 9, 0, 0, 2])]
    rows = [np.concatenate([-h, h]) for h in half]
    rows[0] = np.tile(rows[0], 2)  # both rows of N = 16
    n = rows[0].size
    assert rows[1].size == n
    variances = [_exact_psi_variance(row) for row in rows]
    assert variances[0] != variances[1]
    for row, var in zip(rows, variances, strict=True):
        sigma = kurtosis_sampling_error(row.astype(float)[None, None, :])
        assert sigma[0] == pytest.approx(math.sqrt(float(var / n)), rel=1e-12)
    both = np.stack([rows[0], rows[1]]).astype(float)[:, None, :]
    expected = math.sqrt(float((variances[0] + variances[1]) / n)) / 2.0
    assert kurtosis_sampling_error(both)[0] == pytest.approx(expected, rel=1e-12)
