"""The fixed-point solver against the exact scaling solution, and the linearised decay rates
against the contraction rates γ(s) of the 1D model."""

import json
import math

import numpy as np
import pytest

from maxwell_kinetics.app.cli import main
from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.linear_rates import (
    linear_decay_rates,
    linearised_operator,
    weighted_operator,
)
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.stationary import fixed_point
from particles.validation import InvalidArgumentError

RESTITUTIONS = [0.0, 0.3, 0.5, 0.9, 0.99]


@pytest.mark.parametrize("r", RESTITUTIONS)
def test_fixed_point_recovers_f_hat(r):
    fp = fixed_point(r)
    # The accuracy target.  Measured max errors at n = 64: 6.1e-13 (r = 0), 8.8e-13 (0.3),
    # 9.2e-13 (0.5), 3.0e-12 (0.9), 2.0e-11 (0.99); the floor is round-off amplified by the
    # conditioning of the collocation (it grows with n and as r -> 1).
    assert fp.max_error <= 1e-10
    assert fp.converged
    # Newton converges quadratically from e^{-q^2/2}: measured 7 steps (r = 0, 0.3) and 6
    # (r = 0.5, 0.9, 0.99).
    assert fp.iterations <= 10
    # Collocation residual at the nodes and through the interpolant off the nodes: round-off
    # (terms are O(1); measured <= 8e-16 at the nodes and <= 2e-15 on the fine grid).
    assert fp.residual <= 1e-14
    assert fp.check_residual <= 1e-13
    # The callable is even and accurate between nodes.
    q = np.linspace(-39.0, 39.0, 777)
    assert np.max(np.abs(fp(q) - f_hat(q))) <= 1e-10
    assert np.array_equal(fp(q), fp(-q))


def test_fixed_point_does_not_depend_on_the_start():
    # A start with the wrong decay (algebraic) and the wrong curvature at 0.
    a = fixed_point(0.5, initial=lambda q: 1.0 / (1.0 + q * q))
    b = fixed_point(0.5)
    assert a.converged and a.max_error <= 1e-10
    # Both are the same discrete solution, up to Newton's round-off floor (1e-12 measured).
    assert np.max(np.abs(a.G - b.G)) <= 1e-11


def test_fixed_point_error_falls_spectrally_with_n():
    ns = [16, 24, 32, 40, 48]
    errors = [fixed_point(0.5, n=n).max_error for n in ns]
    # Measured: 2.8e-2, 3.5e-4, 1.6e-7, 9.1e-12, 2.2e-14 (gains 78, 2245, 17250, then 406 at the
    # round-off floor).  The gain per +8 in degree grows: super-geometric convergence, as for an
    # entire function.
    # An algebraic method O(n^-k) would gain (24/16)^k: k > 9 to reach 50 at the first step,
    # and the gain would shrink with n, not grow.
    ratios = [errors[i] / errors[i + 1] for i in range(len(ns) - 1)]
    assert all(ratio >= 50 for ratio in ratios), (errors, ratios)
    assert ratios[1] > ratios[0]  # accelerating, not algebraic
    assert errors[-1] <= 1e-12


def test_near_elastic_still_converges_but_loses_accuracy():
    # r -> 1: the Jacobian tends to the degenerate operator (condition ~ (1 - r)^-2).
    # Measured at n = 64: max error 2.0e-11 (r = 0.99), 3.4e-9 (r = 0.999, 19 Gauss-Newton
    # iterations).
    fp = fixed_point(0.999)
    assert fp.converged
    assert 1e-11 < fp.max_error <= 1e-7


@pytest.mark.parametrize("bad", [1.0, 1.5, -0.1, float("nan"), "x"])
def test_fixed_point_rejects_bad_restitution(bad):
    with pytest.raises(InvalidArgumentError, match="restitution"):
        fixed_point(bad)


def test_fixed_point_rejects_bad_resolution():
    with pytest.raises(InvalidArgumentError, match="n=4"):
        fixed_point(0.5, n=4)
    with pytest.raises(InvalidArgumentError, match="q_max=-1"):
        fixed_point(0.5, q_max=-1.0)


@pytest.mark.parametrize("r", [0.0, 0.5, 0.9])
def test_linearised_operator_exact_eigenfunctions(r):
    # L(q f') = 0 (scale invariance) and L(q f) = λ q f (velocity shift): exact identities.
    # Measured max residuals <= 1e-15: the collocation is exact on these modes up to round-off
    # of O(1) terms times the O(λ q) <= 10 transport factor, hence 1e-14.
    lam = MaxwellModel(r).lam
    q, L = linearised_operator(r)
    scale = -q * q * np.exp(-q)  # q f_hat'(q)
    shift = q * f_hat(q)
    assert np.max(np.abs(L @ scale)) <= 1e-14
    assert np.max(np.abs(L @ shift - lam * shift)) <= 1e-14


def test_weighted_operator_is_the_linearisation():
    # The scale mode u = q f' in the weighted variable w = u / q^σ is annihilated, except in the
    # first |ln(1-p)| of the log grid where the truncation below q_min is felt.
    r, sigma = 0.5, 2.4
    y, A = weighted_operator(r, sigma, math.exp(-10.0), 40.0, 160)
    q = np.exp(y)
    w = -(q ** (2.0 - sigma)) * np.exp(-q)
    away = y >= -10.0 - math.log(1.0 - 0.75) + 1e-9
    # Relative to max|w| = e^4 = 55: measured 1.3e-15 (round-off of the spectral derivative of a
    # smooth function resolved by n = 160); 1e-13 leaves room for the n² growth of round-off.
    assert np.max(np.abs((A @ w)[away])) <= 1e-13 * np.max(np.abs(w))
    assert np.max(np.abs((A @ w)[~away])) > 1e-3 * np.max(np.abs(w))  # the cut-off matters there


def test_decay_rates_approach_max_gamma_from_above():
    r = 0.5
    rates = [linear_decay_rates(r, q_min=math.exp(-ell), n=128) for ell in (20.0, 40.0, 80.0)]
    slowest = [lr.rates[0] for lr in rates]
    lr = rates[-1]
    # γ(s) for s in {2.25, 2.5, 2.75} <= γ* = max γ: every d_s bound is weaker than γ*.
    assert all(g <= lr.gamma_star for g in lr.gamma.values())
    assert 2.0 < lr.s_star < 3.0
    assert lr.gamma_star == pytest.approx(0.0129409, abs=1e-7)  # direct maximisation
    # Monotone approach from the side of faster decay: measured 0.014165, 0.013255, 0.013020.
    assert slowest[0] > slowest[1] > slowest[2] > lr.gamma_star
    # Finite-domain law: rate - γ* ≈ g''(s*) π²/(2 ℓ²).  Measured ratio 0.988 at ℓ = 80; an
    # effective length ℓ + δ with δ <= 1 keeps the ratio in [(80/81)², 1] = [0.975, 1].
    ratio = (slowest[2] - lr.gamma_star) / (lr.predicted_slowest - lr.gamma_star)
    assert 0.975 <= ratio <= 1.0
    # The k-th rate follows k²: (rate_2 - γ*) / (rate_1 - γ*) = 4 (measured 4.0002 at ℓ = 80);
    # the effective-length correction cancels in the ratio, the quartic term of g at s* does not
    # (relative size ~ g''''/g'' (π/ℓ)² ~ 1e-3), hence 1 %.
    second = (lr.rates[1] - lr.gamma_star) / (lr.rates[0] - lr.gamma_star)
    assert second == pytest.approx(4.0, rel=0.01)


def test_finite_domain_prediction_uses_the_curvature_of_g_at_its_extremum():
    # r = 1/2: g(s) = (3/16) s − 1 + (3/4)^s + (1/4)^s, written out here.  s* is where g' = 0
    # and the prediction is γ* + g''(s*) π²/(2ℓ²); g' and g'' by central differences of step
    # 1e-3 (truncation ~1e-7 of g'', round-off 1e-16/1e-6 = 1e-10), hence 1e-6 relative.  The
    # top of g is flat: s* is found to ~1e-6 (g changes by less than round-off there), so
    # g'(s*) ≈ g''(s*) δs ≈ 0.1 δs is checked to 1e-7.
    def g(s):
        return 3 / 16 * s - 1 + 0.75**s + 0.25**s

    ell = 20.0
    lr = linear_decay_rates(0.5, q_min=math.exp(-ell), n=16, count=1)
    s, h = lr.s_star, 1e-3
    assert (g(s + h) - g(s - h)) / (2 * h) == pytest.approx(0.0, abs=1e-7)
    assert lr.gamma_star == pytest.approx(-g(s), rel=1e-9)
    curvature = (g(s + h) - 2 * g(s) + g(s - h)) / h**2
    assert (lr.predicted_slowest - lr.gamma_star) * 2 * ell**2 / math.pi**2 == pytest.approx(
        curvature, rel=1e-6)


@pytest.mark.parametrize("r", [0.0, 0.9, 0.99])
def test_decay_rates_other_restitutions(r):
    lr = linear_decay_rates(r, q_min=math.exp(-80.0), n=128)
    # Measured ratio (rate - γ*)/(formula - γ*) at ℓ = 80: 0.990 (r = 0), 0.977 (0.9),
    # 0.961 (0.99: the delay ln(1/(1-p)) = 5.3 lengthens the boundary layer, δ ≈ 1.6).
    ratio = (lr.rates[0] - lr.gamma_star) / (lr.predicted_slowest - lr.gamma_star)
    assert 0.95 <= ratio <= 1.0
    assert max(lr.gamma.values()) <= lr.gamma_star < lr.rates[0]


def test_decay_rates_independent_of_weight_and_resolution():
    # On the truncated domain the weight is a similarity: eigenvalues do not depend on σ.
    # Measured relative differences 5e-9 (σ = 2.35) and 1.2e-7 (σ = 2.6) at ℓ = 40 (round-off
    # amplified by the non-normality, larger as σ moves away from s* = 2.46), and 4.6e-5 between
    # n = 96 and n = 192 (algebraic convergence: the cut-off at q_min makes w only piecewise
    # smooth).
    base = linear_decay_rates(0.5, q_min=math.exp(-40.0), n=192)
    for sigma in (2.35, 2.6):
        other = linear_decay_rates(0.5, sigma=sigma, q_min=math.exp(-40.0), n=192)
        assert other.rates[0] == pytest.approx(base.rates[0], rel=1e-6)
    coarse = linear_decay_rates(0.5, q_min=math.exp(-40.0), n=96)
    assert coarse.rates[0] == pytest.approx(base.rates[0], rel=1e-4)


def test_decay_rates_reject_bad_input():
    with pytest.raises(InvalidArgumentError, match="sigma=3.5"):
        linear_decay_rates(0.5, sigma=3.5)
    with pytest.raises(InvalidArgumentError, match="q_min=2"):
        linear_decay_rates(0.5, q_min=2.0)
    with pytest.raises(InvalidArgumentError, match="restitution=1"):
        linear_decay_rates(1.0)


def test_cli_fixed_point_json(capsys):
    assert main(["fixed-point", "--restitution", "0.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"restitution", "max_error", "residual", "iterations", "decay_rates",
                        "gamma", "seconds"}
    assert out["restitution"] == 0.5
    assert out["max_error"] <= 1e-10
    assert list(out["gamma"]) == ["2.25", "2.5", "2.75"]
    assert out["gamma"]["2.5"] == pytest.approx(MaxwellModel(0.5).contraction_rate(2.5))
    assert len(out["decay_rates"]) == 3
    assert out["decay_rates"][0] > max(out["gamma"].values())


@pytest.mark.parametrize("bad", ["1", "1.5", "nan", "abc"])
def test_cli_fixed_point_bad_restitution(bad, capsys):
    assert main(["fixed-point", "--restitution", bad, "--json"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"restitution='{bad}'" in captured.err


# -- d = 2, 3 ---------------------------------------------------------------------------------


def test_isotropic_path_with_the_single_node_eta_1_is_the_one_dimensional_fixed_point():
    # The NumPy Jacobian of d >= 2 against the JAX one of d = 1 on the same equation (η ≡ 1).
    from maxwell_kinetics.stationary import isotropic_fixed_point

    one = fixed_point(0.5, n=64)
    iso = isotropic_fixed_point(MaxwellModel(0.5), [1.0], [1.0], 64, 40.0, None, 1e-13, 50)
    assert iso.converged
    assert np.max(np.abs(iso.G - one.G)) < 1e-12
    assert np.max(np.abs(iso.G - f_hat(iso.q))) < 1e-10


@pytest.mark.parametrize(("d", "angular", "r"), [(2, "uniform", 0.5), (3, "hard", 0.5)])
def test_isotropic_fixed_point_has_the_exact_fourth_moment(d, angular, r):
    # The stationary hierarchy (scaling_tails module docstring) gives C₂ of G = 1 − q²/2 + C₂q⁴
    # + … exactly when s* > 2: C₂ = K(2, 1) C₁² / (λ(2) − 2λ(1)), C₁ = −1/2.  From the fixed
    # point: (G − 1 + q²/2)/q⁴ fitted on q ∈ [0.03, 0.4] by C₂ + c q² + A q^{2s*−4} + c' q⁴,
    # s* from tail_exponent.  Measured relative errors 5.8e-7 (2D uniform) and 8.9e-8 (3D hard).
    from maxwell_kinetics.scaling_tails import gain_coefficient
    from maxwell_kinetics.tails import growth_rate, tail_exponent

    fp = fixed_point(r, dimension=d, angular=angular)
    assert fp.converged and fp.residual < 1e-12 and fp.check_residual < 1e-12
    assert fp.dimension == d and fp.angular == angular and math.isnan(fp.max_error)
    assert fp(0.0) == pytest.approx(1.0, abs=1e-14)
    lam = growth_rate(d, r, np.array([0.0, 1.0, 2.0]), angular)
    exact = gain_coefficient(d, r, 2, 1, angular) * 0.25 / (lam[2] - 2.0 * lam[1])
    q = np.geomspace(0.03, 0.4, 40)
    beta = 2.0 * tail_exponent(d, r, angular).s - 4.0
    basis = np.stack([np.ones_like(q), q**2, q**beta, q**4], axis=1)
    c2 = np.linalg.lstsq(basis, (fp(q) - 1.0 + 0.5 * q * q) / q**4, rcond=None)[0][0]
    assert c2 == pytest.approx(exact, rel=1e-5)


def test_isotropic_fixed_point_arguments():
    with pytest.raises(InvalidArgumentError, match="dimension"):
        fixed_point(0.5, dimension=4)
    with pytest.raises(InvalidArgumentError, match="angular"):
        fixed_point(0.5, dimension=2, angular="soft")
    with pytest.raises(InvalidArgumentError, match="angular_nodes"):
        fixed_point(0.5, dimension=2, angular_nodes=0)
    with pytest.raises(InvalidArgumentError, match="restitution"):
        fixed_point(1.0, dimension=3)


def test_fixed_point_cli_in_two_dimensions(capsys):
    assert main(["fixed-point", "-r", "0.5", "--dimension", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["dimension"] == 2 and out["angular"] == "uniform" and out["converged"]
    assert out["residual"] < 1e-12
    # no closed form and no linearisation around f̂ in d >= 2
    assert out["max_error"] is None and out["decay_rates"] is None


@pytest.mark.parametrize(("argv", "named"), [
    (["--dimension", "4"], "dimension=4"),
    (["--dimension", "2", "--angular", "soft"], "angular='soft'"),
    (["--dimension", "two"], "dimension='two'"),
])
def test_fixed_point_cli_refuses_bad_models(argv, named, capsys):
    assert main(["fixed-point", "-r", "0.5", *argv]) == 2
    captured = capsys.readouterr()
    assert named in captured.err and captured.out == ""
