"""The shared initial laws: zero mean, unit variance, and characteristic functions that match
their samplers."""

import numpy as np
import pytest

from particles.initial import LAWS, get_law, law_from_characteristic
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("name", sorted(LAWS))
def test_phi_derivatives_give_zero_mean_unit_variance(name):
    law = get_law(name)
    h = 1e-3
    phi = law.phi(np.array([-h, 0.0, h]))
    assert phi[1] == pytest.approx(1.0, abs=1e-15)
    mean = ((phi[2] - phi[0]) / (2j * h)).real  # phi'(0) = i E[v]
    second = -((phi[2] - 2 * phi[1] + phi[0]) / h**2).real  # phi''(0) = -E[v^2]
    assert abs(mean) < 1e-6
    assert second == pytest.approx(1.0, abs=1e-5)


@pytest.mark.parametrize("name", sorted(LAWS))
def test_sampler_matches_characteristic_function(name):
    # n = 4e5 samples: the empirical characteristic function has standard error
    # <= 1/sqrt(n) = 1.6e-3 per component; 5 sigma = 8e-3.
    law = get_law(name)
    n = 400_000
    v = law.sample(np.random.default_rng(1), n)
    assert abs(v.mean()) < 5 / np.sqrt(n)
    assert v.var() == pytest.approx(1.0, abs=5 * np.sqrt(np.var(v**2) / n))
    k = np.array([0.5, 1.0, 2.0])
    empirical = np.exp(1j * np.outer(k, v)).mean(axis=1)
    assert np.max(np.abs(empirical - law.phi(k))) < 8e-3
    assert np.mean(v**3) == pytest.approx(law.skewness, abs=5 * np.sqrt(np.var(v**3) / n))


def test_unknown_law_lists_names():
    with pytest.raises(InvalidArgumentError, match="initial='cauchy'.*asymmetric, bimodal"):
        get_law("cauchy")


def test_user_law_is_rescaled_to_unit_variance():
    law = law_from_characteristic(lambda k: np.exp(-2.0 * k**2), variance=4.0)
    assert law.phi(np.array([1.0]))[0] == pytest.approx(np.exp(-0.5))


@pytest.mark.parametrize(
    "phi, match",
    [
        (lambda k: 0.5 * np.exp(-(k**2)), "phi\\(0\\)"),
        (lambda k: np.where(np.abs(k) > 5, np.nan, np.exp(-(k**2))), "finite"),
    ],
)
def test_bad_user_law(phi, match):
    with pytest.raises(InvalidArgumentError, match=match):
        law_from_characteristic(phi, variance=1.0)


@pytest.mark.parametrize("name", sorted(LAWS))
def test_cdf_matches_the_sampler(name):
    # Kolmogorov distance of 2e5 samples to the law's CDF: its 99.9 % quantile is
    # 1.95/sqrt(n) = 4.4e-3 for a continuous law (Kolmogorov distribution)
    law = get_law(name)
    n = 200_000
    x = np.sort(law.sample(np.random.default_rng(7), n))
    F = law.cdf(x)
    ecdf_hi = np.arange(1, n + 1) / n
    distance = max(np.max(ecdf_hi - F), np.max(F - (ecdf_hi - 1.0 / n)))
    assert distance < 1.95 / np.sqrt(n)
    assert law.cdf(np.array([-1e9]))[0] == 0.0 and law.cdf(np.array([1e9]))[0] == 1.0
