"""Tails of d-dimensional inelastic Maxwell models: closed forms against quadrature, the tail
root against exact values and against a direct scan, multiscaling rates, argument checks."""

import numpy as np
import pytest
from scipy import integrate, stats

from maxwell_kinetics.angular import angular_law
from maxwell_kinetics.tails import (
    decay_rate,
    eta_moment,
    growth_rate,
    mixed_moment,
    moment_rates,
    tail_exponent,
)
from particles.validation import InvalidArgumentError


def beta_density_expectation(a, b, func):
    """⟨func(η)⟩ for η ~ Beta(a, b) by adaptive quadrature, independent of the closed forms.
    The substitution η = sin²θ removes the integrable endpoint singularities of the density."""
    dist = stats.beta(a, b)

    def integrand(theta):
        eta = np.sin(theta) ** 2
        jac = 2 * np.sin(theta) * np.cos(theta)
        return func(eta) * dist.pdf(eta) * jac

    return integrate.quad(integrand, 0, np.pi / 2, epsabs=1e-13, epsrel=1e-12, limit=200)[0]


@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
@pytest.mark.parametrize("s", [0.5, 1.0, 1.5, 2.7, 6.0])
def test_closed_forms_match_quadrature(dimension, angular, s):
    law = angular_law(dimension, angular)
    assert law.a == {"uniform": 0.5, "hard": 1.0}[angular] and law.b == (dimension - 1) / 2
    expected = beta_density_expectation(law.a, law.b, lambda e: e**s)
    assert eta_moment(law, s) == pytest.approx(expected, rel=1e-9)
    for c in (0.0, 0.3, 0.75, 1.0):
        expected = beta_density_expectation(law.a, law.b, lambda e, c=c: (1 - c * e) ** s)
        assert mixed_moment(law, c, s) == pytest.approx(expected, rel=1e-9, abs=1e-13)


@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
def test_angular_laws_are_those_of_random_directions(dimension, angular):
    # Monte Carlo from the geometry, not from the Beta law: n uniform on the sphere, k̂ = e_1;
    # "hard" weights each n by |ĝ·n| (ĝ = k̂ here: the law of η is the same by Bobylev's
    # reflection).  ⟨η⟩ and ⟨η²⟩ from 4e5 samples: standard errors ≤ 1e-3, tolerance 5e-3.
    rng = np.random.default_rng(7)
    n = rng.standard_normal((400_000, dimension))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    eta = n[:, 0] ** 2
    weight = np.sqrt(eta) if angular == "hard" else np.ones_like(eta)
    law = angular_law(dimension, angular)
    for s in (1, 2):
        mc = np.sum(weight * eta**s) / np.sum(weight)
        assert mc == pytest.approx(eta_moment(law, s), abs=5e-3)


@pytest.mark.parametrize("dimension", [1, 2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
@pytest.mark.parametrize("r", [0.0, 0.3, 0.8, 1.0])
def test_energy_rate_is_lambda_of_one(dimension, angular, r):
    p = (1 + r) / 2
    # ⟨η⟩ = ⟨cos²⟩ = 1/d for uniform directions; |cos|-weighted: ⟨|cos|³⟩/⟨|cos|⟩ = 2/(d + 1)
    mean_eta = 1.0 / dimension if angular == "uniform" else 2.0 / (dimension + 1)
    assert decay_rate(dimension, r, angular) == pytest.approx(2 * p * (1 - p) * mean_eta, 1e-14)
    assert growth_rate(dimension, r, 1.0, angular) == pytest.approx(
        decay_rate(dimension, r, angular), rel=1e-12, abs=1e-15
    )


@pytest.mark.parametrize("angular", ["uniform", "hard"])
@pytest.mark.parametrize("r", [0.0, 0.2, 0.5, 0.9, 0.999])
def test_one_dimension_has_s_star_three_halves_for_every_r(angular, r):
    t = tail_exponent(1, r, angular)
    assert t.s == pytest.approx(1.5, abs=1e-10)
    # the exact r = 0 scaling density, f ∝ x⁻⁴: d + 2s* = 1 + 3 = 4
    assert t.exponents == pytest.approx({"density": 4.0, "speed": 4.0, "component": 4.0})


def test_hard_model_in_two_dimensions_at_r0_has_s_star_two():
    # Exact: ⟨η⟩ = 2/3, ⟨η²⟩ = 8/15, p = q = 1/2, c = 3/4:
    # λ(1) = 1/3, λ(2) = 2c⟨η⟩ − c²⟨η²⟩ − ⟨η²⟩/16 = 1 − 3/10 − 1/30 = 2/3 = 2 λ(1).
    t = tail_exponent(2, 0.0, "hard")
    assert t.s == pytest.approx(2.0, abs=1e-10)
    assert t.exponents["speed"] == pytest.approx(5.0)
    assert t.exponents["density"] == pytest.approx(6.0)
    assert growth_rate(2, 0.0, 2.0, "hard") == pytest.approx(2 / 3, rel=1e-13)
    # the uniform model gives no exponent 5 at r = 0 in 2D
    u = tail_exponent(2, 0.0, "uniform")
    assert 2.1 < u.s < 2.2 and abs(u.exponents["speed"] - 5.0) > 0.25


@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_tail_root_is_the_only_sign_change_above_one(dimension, angular, r):
    # Independent of the bracket logic: scan F(s) = λ(s) − s λ(1) on a fine grid.
    t = tail_exponent(dimension, r, angular)
    lam1 = t.decay_rate
    s = np.linspace(1.0 + 1e-3, 3 * t.s, 3001)
    f = growth_rate(dimension, r, s, angular) - s * lam1
    changes = np.nonzero(np.diff(np.sign(f)))[0]
    assert changes.size == 1
    assert s[changes[0]] <= t.s <= s[changes[0] + 1]
    assert abs(growth_rate(dimension, r, t.s, angular) - t.s * lam1) < 1e-12
    assert t.exponents["density"] == pytest.approx(dimension + 2 * t.s)
    assert t.exponents["component"] == t.exponents["speed"] == pytest.approx(1 + 2 * t.s)


def test_tail_root_grows_as_collisions_become_elastic():
    s = [tail_exponent(3, r, "uniform").s for r in (0.0, 0.5, 0.9, 0.99)]
    assert np.all(np.diff(s) > 0) and s[-1] > 100


@pytest.mark.parametrize("dimension", [1, 2, 3])
def test_moment_rates_multiscale_above_the_tail_root(dimension):
    r, angular = 0.3, "hard"
    t = tail_exponent(dimension, r, angular)
    n = np.arange(1, 9)
    rates = moment_rates(dimension, r, n, angular)
    normal = n * t.decay_rate
    below = n < t.s
    assert np.allclose(rates[below], normal[below], rtol=1e-13)
    assert np.all(rates[~below] < normal[~below])
    assert np.allclose(rates[~below], growth_rate(dimension, r, n[~below], angular))


def test_moment_rates_in_one_dimension_match_the_moment_hierarchy():
    # Exact: the leading rate of M_{2n} is a_{2n} = 1 − p^{2n} − q^{2n}, and M_{2n} also
    # inherits n·a_2 from products of lower moments.
    r = 0.4
    p, q = 0.7, 0.3
    n = np.arange(1, 6)
    expected = np.minimum(1 - p ** (2 * n) - q ** (2 * n), n * (1 - p * p - q * q))
    assert np.allclose(moment_rates(1, r, n), expected, rtol=1e-14)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: tail_exponent(4, 0.5), "dimension=4"),
        (lambda: tail_exponent(True, 0.5), "dimension=True"),
        (lambda: tail_exponent(2, 0.5, "soft"), "angular='soft'"),
        (lambda: tail_exponent(2, 1.2), "restitution=1.2"),
        (lambda: tail_exponent(2, float("nan")), "restitution=nan"),
        (lambda: tail_exponent(2, 1.0), "restitution=1.0"),
        (lambda: tail_exponent(1, 1.0), "restitution=1.0"),
        (lambda: decay_rate(0, 0.5), "dimension=0"),
        (lambda: moment_rates(2, 0.5, [0, 1]), "orders"),
        (lambda: moment_rates(2, 0.5, [1.5]), "orders"),
    ],
)
def test_bad_arguments_are_named(call, match):
    with pytest.raises(InvalidArgumentError, match=match):
        call()


def test_elastic_rates_are_accepted():
    assert decay_rate(3, 1.0) == 0.0
    assert np.all(moment_rates(2, 1.0, [1, 2, 3]) <= 1e-15)
