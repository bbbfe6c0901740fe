"""Velocity-space inversion G(q) -> P(x) against exact densities (the project's conventions)."""

import math

import numpy as np
import pytest

from maxwell_kinetics.exact import f_density, f_hat
from maxwell_kinetics.stationary import fixed_point
from maxwell_kinetics.velocity import density_at, inverse_transform, invert, tail_exponent
from particles.initial import get_law
from particles.validation import InvalidArgumentError

PERIOD = 1000.0


def _alias(x, period, terms=200):
    """Σ_{n≠0} f(x + nL): the exact aliasing error of the trapezoid sum (Poisson summation)."""
    n = np.concatenate([np.arange(-terms, 0), np.arange(1, terms + 1)])
    return f_density(x[:, None] + period * n[None, :]).sum(axis=1)


def test_inverting_f_hat_gives_f():
    x, P = inverse_transform(f_hat, q_max=50.0, period=PERIOD)
    near = np.abs(x) <= 10.0
    err = P[near] - f_density(x[near])
    # The accuracy target; measured 1.38e-12.
    assert np.max(np.abs(err)) <= 1e-8
    # The whole error is the alias of the x^-4 tail (≈ 1.3e-12 here): after removing it, what is
    # left is round-off (measured ~1e-16; f_hat(51) ~ 4e-21 makes truncation negligible).
    assert np.max(np.abs(err - _alias(x[near], PERIOD))) <= 1e-14


def test_grid_conventions():
    x, P = inverse_transform(f_hat, q_max=50.0, period=PERIOD)
    m = x.size
    assert m == 2**14  # smallest power of two with M dq / 2 >= 50, dq = 2π/1000
    assert np.all(np.diff(x) > 0)
    assert x[0] == pytest.approx(-PERIOD / 2) and x[m // 2] == 0.0
    assert x[1] - x[0] == pytest.approx(PERIOD / m)
    # Trapezoid sum over one period of P is exactly G(0) = 1 (the q = 0 DFT mode).
    assert P.sum() * (x[1] - x[0]) == pytest.approx(1.0, abs=1e-13)


def test_sign_convention_with_asymmetric_law():
    # P̂(k) = ∫ e^{ikv} P(v) dv with the shifted exponential, density e^{-(x+1)} on x > -1:
    # the wrong sign would put the mass on x < 1 instead.
    law = get_law("asymmetric")
    x, P = inverse_transform(law.phi, q_max=50.0, period=PERIOD)
    dx = x[1] - x[0]
    assert np.sum(P[x < -1.5]) * dx < 1e-2
    assert np.sum(x * P) * dx == pytest.approx(0.0, abs=1e-2)


@pytest.mark.parametrize("q_max, measured", [(50.0, 4.5e-3), (400.0, 1.5e-3)])
def test_asymmetric_law_away_from_the_jump(q_max, measured):
    # G ~ i e^{-iq}/q decays only like 1/q: the truncation at q_c leaves ≈ sin(q_c (x+1)) /
    # (π q_c (x+1)), bounded by 1/(π q_c d) at distance d from the jump at x = -1.
    # Measured max errors at d >= 0.5, |x| <= 10: 4.5e-3 (q_c = 51.5), 1.5e-3 (q_c = 411.8).
    law = get_law("asymmetric")
    x, P = inverse_transform(law.phi, q_max=q_max, period=PERIOD)
    q_c = math.pi * x.size / PERIOD
    exact = np.where(x > -1.0, np.exp(-(x + 1.0)), 0.0)
    for d in (0.5, 1.0, 2.0, 5.0):
        sel = (np.abs(x + 1.0) >= d) & (np.abs(x) <= 10.0)
        assert np.max(np.abs(P[sel] - exact[sel])) <= 1.0 / (math.pi * q_c * d)
    sel = (np.abs(x + 1.0) >= 0.5) & (np.abs(x) <= 10.0)
    assert np.max(np.abs(P[sel] - exact[sel])) == pytest.approx(measured, rel=0.05)


def test_gaussian():
    x, P = inverse_transform(lambda q: np.exp(-0.5 * q * q))
    # Gaussian: no aliasing or truncation above round-off (measured 1.1e-16).
    assert np.max(np.abs(P - np.exp(-0.5 * x * x) / math.sqrt(2 * math.pi))) <= 1e-15


def test_density_at_matches_exact_and_fft():
    xx = np.linspace(-10.0, 10.0, 401)
    # Gauss–Legendre quadrature has no aliasing: round-off only (measured 9e-16).
    assert np.max(np.abs(density_at(f_hat, xx) - f_density(xx))) <= 1e-14
    x, P = inverse_transform(f_hat)
    sel = np.abs(x) <= 10
    # The FFT differs from it only by the alias of the tail (≈ 1.3e-12).
    assert np.max(np.abs(density_at(f_hat, x[sel]) - P[sel])) <= 2e-12


def test_tail_exponent_is_minus_four():
    # The local slope of f is -4x²/(1+x²); a finite window therefore fits slightly above -4.
    # FFT grid, window [20, 100] (x ≪ L/2 = 500, alias relative size (100/900)^4 = 1.5e-4):
    # measured slope -3.99771, against -3.99783 for the exact density on the same points.
    x, P = inverse_transform(f_hat, period=PERIOD)
    slope = tail_exponent(x, P, (20.0, 100.0))
    assert slope == pytest.approx(-4.0, abs=5e-3)
    assert slope == pytest.approx(tail_exponent(x, f_density(x), (20.0, 100.0)), abs=5e-4)
    # Quadrature (no aliasing), window [30, 300]: measured -3.999258 vs -3.999257 exact.
    xt = np.geomspace(30.0, 300.0, 40)
    slope = tail_exponent(xt, density_at(f_hat, xt), (30.0, 300.0))
    assert slope == pytest.approx(-4.0, abs=1e-3)
    assert slope == pytest.approx(tail_exponent(xt, f_density(xt), (30.0, 300.0)), abs=1e-5)


def test_fixed_point_inverted():
    # The whole chain: fixed point (error 9e-13 in G) -> velocity density within 1e-8 of f.
    fp = fixed_point(0.5)
    x, P = invert(fp, q_max=fp.q_max)
    sel = np.abs(x) <= 10
    assert np.max(np.abs(P[sel] - f_density(x[sel]))) <= 1e-8
    xs, Ps = invert(fp, q_max=fp.q_max, x=[0.0, 1.0, 5.0])
    assert np.max(np.abs(Ps - f_density(xs))) <= 1e-8


def test_bad_input():
    with pytest.raises(InvalidArgumentError, match="G="):
        inverse_transform(3.0)
    with pytest.raises(InvalidArgumentError, match="finite values"):
        inverse_transform(lambda q: np.full_like(q, np.nan))
    with pytest.raises(InvalidArgumentError, match="period=-1"):
        inverse_transform(f_hat, period=-1.0)
    with pytest.raises(InvalidArgumentError, match="x="):
        density_at(f_hat, [0.0, np.inf])
    with pytest.raises(InvalidArgumentError, match="window"):
        tail_exponent([1.0, 2.0], [1.0, 0.5], (2.0, 1.0))
    with pytest.raises(InvalidArgumentError, match="P"):
        tail_exponent([1.0, 2.0, 3.0], [1.0, -0.5, 0.1], (1.0, 3.0))
