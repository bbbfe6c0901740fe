"""Moments read from a solution (Solution.moments, Solution.kurtosis) against the exact moment
equations.

The reference is derived here from the collision rule, independently of the solver and of the
moment hierarchy code: with G(x) = 1 + C₁x² + C₂x⁴ + …, C₁ = −1/2, and the gain
⟨G(q√(1 − aη)) G(pq√η)⟩ (a = 1 − (1 − p)², p = (1 + r)/2, Λ = 2p(1 − p)⟨η⟩), the q⁴ terms give

    dC₂/dτ = ρ C₂ + (p²/4)(⟨η⟩ − a⟨η²⟩),   ρ = 2Λ − 1 + ⟨(1 − aη)²⟩ + p⁴⟨η²⟩,

so C₂(τ) = C∞ + (1/8 − C∞) e^{ρτ} from the Gaussian's 1/8.  ⟨η⟩, ⟨η²⟩ are the moments of the
angular law: d = 1: η ≡ 1 (ρ = 9/128 = 0.0703125 at r = 0.5, so
⟨x⁴⟩ = 24 C₂ = −3 + 6e^{0.0703125τ}); d = 2 uniform: Beta(1/2, 1/2), 1/2 and 3/8; d = 3 uniform:
Beta(1/2, 1), 1/3 and 1/5.  The speed kurtosis is K = ⟨|v|⁴⟩/⟨|v|²⟩² = 24 C₂/(⟨cos⁴θ⟩ d²)
with ⟨cos⁴θ⟩ = 1, 3/8, 1/5 in d = 1, 2, 3.

Tolerance 1e-7 relative at the default grid (what a user is promised); measured: ≤ 2.5e-8.
"""

import math
import re

import numpy as np
import pytest

from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.scaling_tails import series_coefficients
from maxwell_kinetics.solver import solve
from particles.initial import law_from_characteristic
from particles.validation import InvalidArgumentError

COS4 = {1: 1.0, 2: 3.0 / 8.0, 3: 1.0 / 5.0}


def exact_kurtosis(d, r, eta1, eta2, tau):
    p = (1 + r) / 2
    a = 1 - (1 - p) ** 2
    lam = 2 * p * (1 - p) * eta1
    rho = 2 * lam - 1 + (1 - 2 * a * eta1 + a * a * eta2) + p**4 * eta2
    c_inf = -0.25 * p * p * (eta1 - a * eta2) / rho
    c2 = c_inf + (0.125 - c_inf) * np.exp(rho * np.asarray(tau))
    return 24 * c2 / (COS4[d] * d * d)


def test_one_dimensional_kurtosis_is_the_closed_form():
    taus = [10.0, 50.0]
    sol = solve(0.5, "gaussian", taus)
    closed = -3 + 6 * np.exp(0.0703125 * np.array(taus))
    np.testing.assert_allclose(exact_kurtosis(1, 0.5, 1.0, 1.0, taus), closed, rtol=1e-13)
    np.testing.assert_allclose(sol.kurtosis, closed, rtol=1e-7)
    m = sol.moments()
    assert m.orders == (2, 4, 6) and m.values.shape == (2, 3)
    np.testing.assert_array_equal(m.values[:, 0], 1.0)  # ⟨x²⟩ = 1: the rescaling's unit
    np.testing.assert_array_equal(m.values, m.component)  # d = 1: one component
    assert all(r == ("", "", "") for r in m.reasons)


@pytest.mark.parametrize(
    "d, angular, r, eta1, eta2, taus",
    [
        (2, "uniform", 0.5, 0.5, 3 / 8, [10.0, 50.0, 100.0, 200.0]),
        (2, "uniform", 0.2, 0.5, 3 / 8, [10.0, 40.0, 60.0, 100.0, 200.0]),
        (3, "uniform", 0.5, 1 / 3, 1 / 5, [10.0, 50.0, 200.0]),  # the compile of test_speed_density
    ],
)
def test_kurtosis_in_two_and_three_dimensions_follows_the_moment_equation(
        d, angular, r, eta1, eta2, taus):
    sol = solve(r, "gaussian", taus, dimension=d, angular=angular)
    np.testing.assert_allclose(sol.kurtosis, exact_kurtosis(d, r, eta1, eta2, taus), rtol=1e-7)
    m = sol.moments(orders=(2, 4))
    np.testing.assert_allclose(m.values[:, 0], d, rtol=1e-15)  # ⟨|v|²⟩/v₀² = d
    np.testing.assert_allclose(m.component[:, 1], m.values[:, 1] * COS4[d], rtol=1e-14)


def test_sixth_moments_lie_within_their_error_estimates():
    # ⟨|v|⁶⟩ of d = 2 uniform r = 0.5 against the exact hierarchy's C₃ (the q⁶ terms of the same
    # expansion; maxwell_kinetics.scaling_tails.rescaled_coefficients integrates it).  Measured:
    # the actual error is at most 2.7x the window's error estimate plus the solver's own
    # (≤ 1e-7 at these τ); bound 5x + 1e-6.
    from maxwell_kinetics.scaling_tails import rescaled_coefficients

    taus = [10.0, 50.0, 100.0]
    sol = solve(0.5, "gaussian", taus, dimension=2)
    m = sol.moments(orders=(6,))
    exact = -720 * rescaled_coefficients(2, 0.5, taus, 3)[:, 3] / (5.0 / 16.0)
    err = np.abs(m.values[:, 0] / exact - 1)
    assert np.all(err <= 5 * m.errors[:, 0] / m.values[:, 0] + 1e-6), (err, m.errors)


def test_a_divergent_moment_is_nan_with_its_reason():
    # Started from the scaling solution f̂ = (1 + |k|) e^{−|k|} itself (a density ∝ 1/(1 + x²)²):
    # ⟨x⁴⟩ is infinite, w = G − e^{−q²/2} ∝ |q|³.
    law = law_from_characteristic(lambda k: f_hat(np.abs(k)), 1.0, "scaling")
    sol = solve(0.5, law, [1.0, 5.0])
    m = sol.moments()
    assert np.all(m.values[:, 0] == 1.0)
    assert np.all(np.isnan(m.values[:, 1:])) and np.all(np.isnan(sol.kurtosis))
    for row in m.reasons:
        assert row[0] == "" and "not analytic to order 4" in row[1]
        beta = float(re.search(r"\|q\|\^([0-9.]+)", row[1]).group(1))
        assert abs(beta - 3.0) < 0.1, row[1]  # the |q|³ of f̂


def test_a_moment_grown_beyond_the_grid_is_nan_not_a_number():
    # d = 2, r = 0.2 at τ = 200: ⟨|v|⁶⟩ grows as e^{(3Λ − λ(3))τ} toward its divergence in the
    # scaling limit (2s* < 6); the |q|^{2s*} term covers the range the grid resolves.
    sol = solve(0.2, "gaussian", [200.0], dimension=2)
    m = sol.moments()
    assert np.isfinite(m.values[0, 1]) and np.isnan(m.values[0, 2]) and m.reasons[0][2]
    assert m.to_dict()["values"][0][2] is None


@pytest.mark.parametrize("orders", [3, (2, 5), (0,), (-2,), (2.0,), (True,), ("4",), ()])
def test_bad_orders_are_named(orders):
    sol = solve(0.5, "gaussian", [1.0], "coarse")
    with pytest.raises(InvalidArgumentError, match="orders") as info:
        sol.moments(orders=orders)
    assert "even positive integers" in str(info.value)


def test_series_coefficients_window_is_automatic_or_refused():
    # d = 2, r = 0.2, τ = 40: the old default window q ∈ (0.01, 0.1) gave C₂ biased by −9.9e-5.
    sol = solve(0.2, "gaussian", [10.0, 40.0], dimension=2)
    exact = exact_kurtosis(2, 0.2, 0.5, 3 / 8, [10.0, 40.0]) / 16  # K = 16 C₂ in d = 2
    for k in range(2):
        assert series_coefficients(sol, k, 2)[0] == pytest.approx(exact[k], rel=1e-7)
    with pytest.raises(InvalidArgumentError, match="window") as info:
        series_coefficients(sol, 1, 2, window=(0.01, 0.1))
    assert "halves differs" in str(info.value)
    # at τ = 10 the same window is analytic enough and is used as asked
    c = series_coefficients(sol, 0, 2, window=(0.01, 0.1))
    assert c[0] == pytest.approx(exact[0], rel=1e-5)
    assert math.isfinite(c[0])
