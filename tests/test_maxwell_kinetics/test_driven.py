"""The driven 1D Maxwell model: exact cumulants, the moment equations, the steady characteristic
function (tree expansion against the series and the functional equation) and its density (FFT:
moments, tail slope and amplitude from the pole at k = −i/√D)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from maxwell_kinetics.driven import (
    characteristic_function,
    cumulants,
    moments,
    steady_kurtosis,
    steady_state,
    steady_variance,
    tail_amplitude,
)
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
@pytest.mark.parametrize("D", [0.3, 2.0])
def test_cumulants_give_variance_and_kurtosis(r, D):
    p = (1 + r) / 2
    q = 1 - p
    k2, k4, k6 = cumulants(r, D, 3)
    assert k2 == pytest.approx(D / (p * q), rel=1e-14) == steady_variance(r, D)
    assert k4 == pytest.approx(12 * D**2 / (1 - p**4 - q**4), rel=1e-14)
    assert k6 == pytest.approx(720 * D**3 / (3 * (1 - p**6 - q**6)), rel=1e-14)
    # kurtosis from the cumulants against the steady state of the moment equations (the other
    # derivation: dM4/dτ = −(1 − p⁴ − q⁴)M4 + 12 D M2 + 6p²q² M2²)
    m2, m4 = moments(1e4, r, D)
    assert m2 == pytest.approx(k2, rel=1e-12)
    assert m4 / m2**2 == pytest.approx(3 + k4 / k2**2, rel=1e-12)
    assert steady_kurtosis(r, D) == pytest.approx(3 + k4 / k2**2, rel=1e-14)


@pytest.mark.parametrize("r", [0.0, 0.6])
@pytest.mark.parametrize("D", [0.0, 0.5])
def test_moment_solution_solves_the_moment_equations(r, D):
    p = (1 + r) / 2
    q = 1 - p

    def rhs(t, m):
        m2, m4 = m
        return [
            2 * D - 2 * p * q * m2,
            -(1 - p**4 - q**4) * m4 + 12 * D * m2 + 6 * (p * q) ** 2 * m2**2,
        ]

    taus = np.linspace(0, 12, 25)
    ref = solve_ivp(rhs, (0, 12), [1.7, 9.0], t_eval=taus, rtol=1e-12, atol=1e-14, method="DOP853")
    m2, m4 = moments(taus, r, D, 1.7, 9.0)
    assert np.allclose(m2, ref.y[0], rtol=1e-9) and np.allclose(m4, ref.y[1], rtol=1e-9)


def test_free_cooling_moments_follow_the_undriven_hierarchy():
    # Exact with D = 0: M2 = e^{−2pqτ}; M4/M2² grows (multiscaling: a4 < 2 a2).
    r = 0.2
    p = 0.6
    tau = np.array([0.0, 1.0, 10.0, 40.0])
    m2, m4 = moments(tau, r, 0.0, 1.0, 3.0)
    assert np.allclose(m2, np.exp(-2 * p * (1 - p) * tau), rtol=1e-14)
    assert np.all(np.diff(m4 / m2**2) > 0)


@pytest.mark.parametrize("r", [0.0, 0.5, 0.95])
def test_tree_expansion_matches_the_series_where_it_converges(r):
    # For D k² < 1 the series converges; 400 terms reach round-off for D k² ≤ 0.8.
    D = 0.7
    p = (1 + r) / 2
    k = np.linspace(0.0, math.sqrt(0.8 / D), 50)
    j = np.arange(1, 401, dtype=float)
    a = 1 - p ** (2 * j) - (1 - p) ** (2 * j)
    series = np.array([np.sum((-1) ** j * (D * kk * kk) ** j / (j * a)) for kk in k])
    assert np.allclose(np.log(characteristic_function(k, r, D)), series, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("r", [0.0, 0.3, 0.8])
def test_steady_characteristic_function_solves_the_steady_equation(r):
    # (1 + Dk²) P̂(k) = P̂(pk) P̂(qk) at large k, with each side evaluated separately (so with
    # different expansion trees: the truncation depends on the largest k of the call).
    D = 1.3
    p = (1 + r) / 2
    for k in (0.9, 3.0, 11.0, 40.0):
        lhs = math.log1p(D * k * k) + math.log(characteristic_function(np.array([k]), r, D)[0])
        rhs = sum(
            math.log(characteristic_function(np.array([x]), r, D)[0]) for x in (p * k, (1 - p) * k)
        )
        assert lhs == pytest.approx(rhs, abs=1e-12 * max(1.0, abs(rhs)))


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_density_has_the_exact_moments(r):
    D = 0.7
    st = steady_state(r, D)
    v, P = st.velocity, st.density
    dv = v[1] - v[0]
    assert np.allclose(np.diff(v), dv)
    assert P.min() > -1e-15
    assert P.sum() * dv == pytest.approx(1.0, abs=1e-12)
    m2 = np.sum(v * v * P) * dv
    m4 = np.sum(v**4 * P) * dv
    assert m2 == pytest.approx(st.variance, rel=1e-10)
    assert m4 / m2**2 == pytest.approx(st.kurtosis, rel=1e-10)
    assert np.sum(v * P) * dv == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("r, x_range, tol", [(0.0, (12.0, 24.0), 1e-5), (0.5, (15.0, 27.0), 5e-3)])
def test_density_tail_is_exp_minus_v_over_sqrt_d(r, x_range, tol):
    # Simple poles of P̂ at k = ±i/√D: ln P(v) = ln(R/√D) − |v|/√D + corrections from the next
    # singularity, at k = i/(p√D): relative size ~ e^{−(1/p − 1)|v|/√D} (·|v| at r = 0, where the
    # poles of P̂(pk) and P̂(qk) coincide).  r = 0: ~20 e^{−12} ≈ 1e-4 in P at x = 12, slope
    # error ~1e-5; r = 0.5: e^{−5} in P, slope error ~ e^{−5}/3 ≈ 2e-3.
    D = 0.7
    st = steady_state(r, D)
    x = st.velocity / math.sqrt(D)
    sel = (x >= x_range[0]) & (x <= x_range[1])
    slope = np.polyfit(st.velocity[sel], np.log(st.density[sel]), 1)[0]
    assert slope == pytest.approx(-1 / math.sqrt(D), rel=tol)
    # the same on the negative side (P is even)
    sel_neg = (x <= -x_range[0]) & (x >= -x_range[1])
    slope_neg = np.polyfit(st.velocity[sel_neg], np.log(st.density[sel_neg]), 1)[0]
    assert slope_neg == pytest.approx(1 / math.sqrt(D), rel=tol)
    if r == 0.0:  # amplitude from the residue: e^{|v|/√D} P √D → R, within ~20 e^{−20} at x = 20
        i = np.argmin(np.abs(x - 20.0))
        amp = math.exp(x[i]) * st.density[i] * math.sqrt(D)
        assert amp == pytest.approx(tail_amplitude(r), rel=1e-6)


def test_density_scales_with_sqrt_d():
    a, b = steady_state(0.3, 1.0), steady_state(0.3, 4.0)
    assert np.allclose(b.velocity, 2 * a.velocity) and np.allclose(b.density, a.density / 2)


@pytest.mark.parametrize(
    "args, match",
    [
        ((0.5, -1.0), "driving=-1.0"),
        ((0.5, float("inf")), "driving=inf"),
        ((0.5, "x"), "driving='x'"),
        ((0.5, 0.0), "cools to rest"),
        ((1.0, 0.5), "restitution=1.0"),
        ((1.2, 0.5), "restitution=1.2"),
    ],
)
def test_bad_arguments_are_named(args, match):
    with pytest.raises(InvalidArgumentError, match=match):
        steady_state(*args)


def test_moments_refuse_elastic_collisions():
    # r = 1: the rates 2pq and 2pq(2 − pq) vanish (no dissipation), outside the solution's form.
    with pytest.raises(InvalidArgumentError, match="restitution=1.0"):
        moments(1.0, 1.0, 0.0)
    with pytest.raises(InvalidArgumentError, match="driving=-0.1"):
        moments(1.0, 0.5, -0.1)
