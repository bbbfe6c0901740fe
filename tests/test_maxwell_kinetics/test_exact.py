"""The exact results of the 1D model (module ``exact``), checked independently of the solvers."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from maxwell_kinetics.exact import f_density, f_hat, moment_hierarchy, rescaled_moments
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.stationary import stationary_residual


def _f_hat_with_derivative(q, derivative):
    q = np.abs(q)
    return (1.0 + q) * np.exp(-q) if derivative == 0 else -q * np.exp(-q)


@pytest.mark.parametrize("r", [0.0, 0.3, 0.5, 0.9, 0.99, 0.999])
def test_f_hat_is_stationary(r):
    # λ q f' − f + f(pq) f((1−p)q) = e^{-q}[−λq² − 1 − q + (1 + pq)(1 + (1−p)q)] = 0 because
    # λ = p(1 − p).  The terms are O(1), so the residual is round-off (measured <= 3e-16).
    q = np.linspace(0.0, 40.0, 4001)
    assert np.max(np.abs(stationary_residual(_f_hat_with_derivative, r, q))) <= 2e-15


def test_gaussian_is_not_stationary():
    # The check above can fail: e^{-q²/2} leaves an O(0.1) residual.
    def gauss(q, derivative):
        return np.exp(-0.5 * q * q) if derivative == 0 else -q * np.exp(-0.5 * q * q)

    q = np.linspace(0.0, 10.0, 101)
    assert np.max(np.abs(stationary_residual(gauss, 0.5, q))) > 1e-2


@pytest.mark.parametrize("k", [0.0, 0.3, 1.0, 2.5, 7.0])
def test_f_density_is_the_inverse_transform_of_f_hat(k):
    # ∫ e^{ikx} f(x) dx = 2 ∫_0^∞ cos(kx) f(x) dx; QUADPACK's Fourier (QAWF) rule for k > 0.
    # Its error estimate is ~1e-12 or better here; 1e-10 is its default requested accuracy.
    if k == 0.0:
        value = 2.0 * quad(f_density, 0.0, np.inf, epsabs=1e-13)[0]
    else:
        value = 2.0 * quad(f_density, 0.0, np.inf, weight="cos", wvar=k)[0]
    assert value == pytest.approx(float(f_hat(k)), abs=1e-10)


def test_f_density_unit_variance_and_tail():
    var = 2.0 * quad(lambda x: x * x * f_density(x), 0.0, np.inf, epsabs=1e-13)[0]
    assert var == pytest.approx(1.0, abs=1e-10)  # QUADPACK on a smooth x^-2 integrand
    x = np.array([1e3, 1e4])
    # f = (2/π) x^-4 (1 - 2/x² + 3/x⁴ - ...): the x⁻⁴ tail; the next term, 4/x⁶ <= 4e-18, and
    # round-off are far below 1e-12.
    expected = 1.0 - 2.0 / x**2 + 3.0 / x**4
    assert f_density(x) * x**4 * math.pi / 2 == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_energy_decays_as_exp_minus_two_lambda_tau(r):
    model = MaxwellModel(r)
    tau = np.array([0.5, 1.0, 5.0, 20.0])
    M = moment_hierarchy(model, [1.0, 0.0, 1.0], tau)
    # The hierarchy is integrated at rtol 1e-12 (DOP853); 1e-9 leaves room for accumulation.
    np.testing.assert_allclose(M[:, 2], np.exp(-2.0 * model.lam * tau), rtol=1e-9)
    np.testing.assert_allclose(M[:, 0], 1.0, rtol=1e-12)
    np.testing.assert_allclose(M[:, 1], 0.0, atol=1e-15)


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_skewness_is_conserved(r):
    # Zero mean: dM3/dτ = −a₃ M3 and a₃ = 3λ, so M3 / M2^{3/2} is constant.  Asymmetric law,
    # E[x³] = 2.  Tolerance as above.
    model = MaxwellModel(r)
    tau = np.array([1.0, 10.0, 50.0])
    R = rescaled_moments(model, [1.0, 0.0, 1.0, 2.0], tau)
    np.testing.assert_allclose(R[:, 3], 2.0, rtol=1e-9)


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_fourth_moment_closed_form(r):
    # dM4/dτ = −a₄ M4 + 6 λ² M2², M2 = e^{−2λτ}:
    # M4 = e^{−a₄τ} [M4(0) + 6 λ² (e^{(a₄ − 4λ)τ} − 1) / (a₄ − 4λ)].  Gaussian start, M4(0) = 3.
    model = MaxwellModel(r)
    lam, a4 = model.lam, model.moment_rate(4)
    tau = np.array([0.5, 2.0, 10.0, 40.0])
    M = moment_hierarchy(model, [1.0, 0.0, 1.0, 0.0, 3.0], tau)
    exact = np.exp(-a4 * tau) * (3.0 + 6 * lam**2 * np.expm1((a4 - 4 * lam) * tau) / (a4 - 4 * lam))
    np.testing.assert_allclose(M[:, 4], exact, rtol=1e-9)
    # Multiscaling: a₄ < 2a₂, so the rescaled fourth moment grows without bound.
    kurt = rescaled_moments(model, [1.0, 0.0, 1.0, 0.0, 3.0], tau)[:, 4]
    assert np.all(np.diff(kurt) > 0)


def test_moment_hierarchy_at_tau_zero_one_and_integer_input():
    # τ = 0 alone returns the initial moments, one row per time; τ = 1 is integrated (the
    # energy M₂ = e^{−2p(1−p)τ} M₂(0) at zero mean: dM₂/dτ = −M₂ + (p² + (1 − p)²) M₂).
    model = MaxwellModel(0.4)
    at0 = moment_hierarchy(model, [1, 0, 2], [0, 0])
    assert at0.dtype == float and at0.shape == (2, 3) and at0.tolist() == [[1, 0, 2]] * 2
    M = moment_hierarchy(model, [1.0, 0.0, 2.0], [0.5, 1.0])
    lam = model.p * (1 - model.p)
    np.testing.assert_allclose(M[:, 2], 2.0 * np.exp(-2 * lam * np.array([0.5, 1.0])),
                               rtol=1e-10)
    # integers are read as floats: x² of a large integer does not wrap around
    big = 2**33
    assert f_density(np.array([big]))[0] == pytest.approx(2 / (math.pi * float(big) ** 4),
                                                          rel=1e-12)
