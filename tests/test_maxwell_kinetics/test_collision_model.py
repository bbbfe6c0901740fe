"""The kinetic collision models (module ``model``): every quantity checked against values worked
out by hand here (fractions of p = (1 + r)/2 at r = 0, 0.2, 0.5, 1), not against the code."""

import math

import numpy as np
import pytest

from maxwell_kinetics.angular import ANGULAR_MODELS
from maxwell_kinetics.model import (
    KINETIC_MODELS,
    CollisionModel,
    DrivenMaxwellModel,
    MaxwellModel,
    RelativeVelocityModel,
)
from particles.collision import transfer_fraction
from particles.ulam_kinematics import ANGULAR_MODELS as PARTICLE_ANGULAR_MODELS
from particles.validation import InvalidArgumentError

#: r: (p, λ, 1 − p^s − (1 − p)^s at s = 2, 4, 6), by hand.
HAND = {
    0.0: (1 / 2, 1 / 4, (1 / 2, 7 / 8, 31 / 32)),  # 1 − 2/2^s
    0.2: (0.6, 0.24, (0.48, 0.8448, 0.949248)),  # 1 − .36 − .16, 1 − .1296 − .0256, ...
    0.5: (3 / 4, 3 / 16, (3 / 8, 87 / 128, 1683 / 2048)),  # 1 − (3^s + 1)/4^s
    1.0: (1.0, 0.0, (0.0, 0.0, 0.0)),
}


@pytest.mark.parametrize("r", sorted(HAND))
def test_p_lambda_and_moment_rates_by_hand(r):
    p, lam, rates = HAND[r]
    model = MaxwellModel(r)
    assert model.p == pytest.approx(p, rel=1e-15)
    assert model.p == transfer_fraction(r)  # the particle engines' own p, bit for bit
    assert model.complement == pytest.approx(1.0 - p, rel=1e-15)
    assert model.lam == pytest.approx(lam, rel=1e-15, abs=1e-16)
    assert model.pair_lam == pytest.approx(lam, rel=1e-15, abs=1e-16)
    assert MaxwellModel.lam_of(p) == pytest.approx(lam, rel=1e-15, abs=1e-16)
    for s, rate in zip((2, 4, 6), rates, strict=True):
        assert model.moment_rate(s) == pytest.approx(rate, rel=1e-14, abs=1e-16)
        assert MaxwellModel.rate_of(p, s) == pytest.approx(rate, rel=1e-14, abs=1e-16)
        # the |k|^{2s} coefficient in d = 1 is the moment of order 2s
        assert float(model.coefficient_rate(s / 2)) == pytest.approx(rate, rel=1e-14, abs=1e-16)
    assert model.energy_rate() == pytest.approx(2 * lam, rel=1e-15, abs=1e-16)


@pytest.mark.parametrize(("dimension", "angular", "mean"), [
    (1, "uniform", 1.0), (2, "uniform", 1 / 2), (3, "uniform", 1 / 3),
    (2, "hard", 2 / 3), (3, "hard", 1 / 2),  # 1/d and 2/(d + 1)
])
def test_angular_means_and_energy_rate(dimension, angular, mean):
    model = MaxwellModel(0.5, dimension, angular)
    assert model.law.mean == pytest.approx(mean, rel=1e-15)
    assert float(model.law.moment(1.0)) == pytest.approx(mean, rel=1e-14)
    # Λ = 2 λ ⟨η⟩ with λ = 3/16, and λ(1) of the |k|² coefficient is the same rate
    assert model.energy_rate() == pytest.approx(2 * 3 / 16 * mean, rel=1e-15)
    assert float(model.coefficient_rate(1.0)) == pytest.approx(2 * 3 / 16 * mean, rel=1e-14)
    # the quadrature's own ⟨η⟩ gives the transport speed Λ/2
    eta, weights = model.law.quadrature(4)
    assert model.transport_speed(eta, weights) == pytest.approx(3 / 16 * mean, rel=1e-14)
    # energy_rate of another dimension, as before
    assert MaxwellModel(0.5).energy_rate(dimension, angular) == pytest.approx(
        2 * 3 / 16 * mean, rel=1e-15)


def test_fourth_power_rate_in_three_dimensions_by_hand():
    # d = 3 uniform: η ~ Beta(1/2, 1), ⟨η⟩ = 1/3, ⟨η²⟩ = (1/2)(3/2)/((3/2)(5/2)) = 1/5.
    # r = 1/2: p = 3/4, c = 1 − (1/4)² = 15/16; λ(2) = 2c⟨η⟩ − c²⟨η²⟩ − p⁴⟨η²⟩
    # = 5/8 − 45/256 − 81/1280 = 247/640.
    model = MaxwellModel(0.5, 3, "uniform")
    assert float(model.coefficient_rate(2.0)) == pytest.approx(247 / 640, rel=1e-14)
    assert MaxwellModel.cross_fraction_of(model.p) == pytest.approx(15 / 16, rel=1e-15)


def test_gain_factors_by_hand():
    p = 3 / 4
    b, a = MaxwellModel.gain_scales_of(p, 0.25)
    assert (b, a) == pytest.approx((3 / 8, 7 / 8), rel=1e-15)  # √(1 − (15/16)(1/4)) = 7/8
    # the energy of the pair: b² + a² = 1 − 2λη = 1 − 3/32
    assert b * b + a * a == pytest.approx(29 / 32, rel=1e-15)
    model = MaxwellModel(0.5)
    assert model.gain_shifts(1.0) == pytest.approx((math.log(3 / 4), math.log(1 / 4)), rel=1e-15)
    assert model.gain_shifts(0.25) == pytest.approx((math.log(3 / 8), math.log(7 / 8)),
                                                    rel=1e-14)
    # p^k + (1 − p)^k = 1 − kλ: 9/16 + 1/16 and 27/64 + 1/64
    assert MaxwellModel.power_sum_of(3 / 16, 2) == pytest.approx(10 / 16, rel=1e-15)
    assert MaxwellModel.power_sum_of(3 / 16, 3) == pytest.approx(28 / 64, rel=1e-15)
    with pytest.raises(ValueError, match="k must be 2 or 3"):
        MaxwellModel.power_sum_of(3 / 16, 4)
    # the gain moments: C(n, m) p^m (1 − p)^{n−m}
    assert model.gain_moment_coefficients(2) == pytest.approx(
        np.array([[1, 0, 0], [1 / 4, 3 / 4, 0], [1 / 16, 6 / 16, 9 / 16]]), rel=1e-15)


def test_kernel_functions_of_p_work_on_traced_values():
    jax = pytest.importorskip("jax")
    with jax.enable_x64(True):
        lam = jax.jit(MaxwellModel.lam_of)(jax.numpy.float64(0.75))
    assert float(lam) == pytest.approx(3 / 16, rel=1e-15)


def test_driven_model_by_hand():
    model = DrivenMaxwellModel(0.5, driving=2.0)
    assert model.steady_energy == pytest.approx(2.0 / (3 / 16), rel=1e-15)  # D / (p(1 − p))
    assert model.moment_rates([1, 2, 3]) == pytest.approx([3 / 8, 87 / 128, 1683 / 2048],
                                                          rel=1e-14)
    # a second positional number is not taken for D: D is keyword-only, the model is 1D
    with pytest.raises(InvalidArgumentError, match="dimension=3 .*one-dimensional"):
        DrivenMaxwellModel(0.5, 3)
    with pytest.raises(TypeError):
        DrivenMaxwellModel(0.5, 1, "uniform", 2.0)


def test_the_models_are_listed_and_say_how_they_collide():
    assert KINETIC_MODELS == {"maxwell": MaxwellModel, "driven": DrivenMaxwellModel,
                              "relative_velocity": RelativeVelocityModel}
    assert [cls.fourier_closed for cls in KINETIC_MODELS.values()] == [True, True, False]
    assert MaxwellModel(0.5).rate(np.zeros(3), np.ones(3)).tolist() == [1.0, 1.0, 1.0]
    assert MaxwellModel(0.5, 2).rate(np.zeros((4, 2)), np.ones((4, 2))).shape == (4,)
    with pytest.raises(NotImplementedError, match="CollisionModel defines no collision rate"):
        CollisionModel(0.5).rate(0.0, 1.0)


def test_angular_models_are_named_once():
    assert tuple(ANGULAR_MODELS) == PARTICLE_ANGULAR_MODELS
    assert ANGULAR_MODELS == {"uniform": 0.5, "hard": 1.0}  # the Beta parameter a of η


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"restitution": 1.5}, "restitution"),
    ({"restitution": 0.5, "dimension": 4}, "dimension"),
    ({"restitution": 0.5, "dimension": 2, "angular": "soft"}, "angular"),
])
def test_bad_arguments_are_refused_by_name(kwargs, name):
    with pytest.raises(InvalidArgumentError, match=name):
        MaxwellModel(**kwargs)


def test_the_relative_velocity_rate_is_the_power_of_the_relative_speed():
    # rods: |v - w|; Maxwell (gamma = 0): 1 even at v = w; gamma = 2: the square
    v, w = np.array([0.0, 1.0, -2.0]), np.array([0.5, 1.0, 1.0])
    assert RelativeVelocityModel(0.5).rate(v, w).tolist() == [0.5, 0.0, 3.0]
    assert RelativeVelocityModel(0.5, exponent=0).rate(v, w).tolist() == [1.0, 1.0, 1.0]
    assert RelativeVelocityModel(0.5, exponent=2).rate(v, w).tolist() == [0.25, 0.0, 9.0]
    model = RelativeVelocityModel(0.5)
    assert model.p == 0.75 and model.complement == 0.25 and model.lam == 3 / 16
    # the pair keeps its momentum and loses 2 lambda g^2 of v^2 + w^2
    a, b = model.post_collision(2.0, -1.0), model.post_collision(-1.0, 2.0)
    assert a + b == 1.0 and 4.0 + 1.0 - a * a - b * b == pytest.approx(2 * 3 / 16 * 9, rel=1e-15)
    for bad in (-0.5, 2.5, float("nan"), True):
        with pytest.raises(InvalidArgumentError, match="exponent"):
            RelativeVelocityModel(0.5, exponent=bad)


def test_growth_rate_energy_and_maxwell_rod_rate_by_hand():
    # r = 1/2: p = 3/4, λ = 3/16.  g(s) = λs − 1 + p^s + (1 − p)^s vanishes at s = 2 (energy)
    # and s = 3: 3/8 − 1 + 9/16 + 1/16 = 0 and 9/16 − 1 + 27/64 + 1/64 = 0; at s = 4:
    # 3/4 − 1 + 81/256 + 1/256 = 9/128.  Tolerances: round-off of a few operations on O(1) terms.
    model = MaxwellModel(0.5)
    assert model.growth_rate(2.0) == pytest.approx(0.0, abs=1e-15)
    assert model.growth_rate(3.0) == pytest.approx(0.0, abs=1e-15)
    assert model.growth_rate(4.0) == pytest.approx(9 / 128, rel=1e-14)
    # γ(s) = −g(s); at s = 5/2: 1 − 15/32 − (3/4)^{5/2} − (1/4)^{5/2} = (16 − 9√3)/32 ≈ 0.0129,
    # a difference of O(1) terms: round-off 1e-16 of them is ~1e-14 of it
    assert model.contraction_rate(2.5) == pytest.approx((16 - 9 * math.sqrt(3)) / 32, rel=1e-13)
    # ⟨v²⟩(τ) = e^{−2λτ}: at τ = 4, e^{−3/2}
    assert model.energy(4.0) == pytest.approx(math.exp(-1.5), rel=1e-15)
    # the rate-|v − w|⁰ gas is the Maxwell gas in time n t: its energy decays at 2λ = 3/8
    assert RelativeVelocityModel(0.5, exponent=0).energy_rate() == pytest.approx(3 / 8, rel=1e-15)
    with pytest.raises(NotImplementedError, match="gamma > 0"):
        RelativeVelocityModel(0.5).energy_rate()


@pytest.mark.parametrize(("r", "beta"), [(0.0, 2.0), (0.5, 4 / 3), (1.0, 1.0)])
def test_beta_is_two_over_one_plus_r_by_hand(r, beta):
    # the paper's β = 2/(1 + r) = 1/p: 2 (r = 0), 4/3 (r = 1/2), 1 (elastic)
    assert MaxwellModel(r).beta == pytest.approx(beta, rel=1e-15)


def test_one_dimensional_mixed_moment_is_the_power_of_one_minus_c():
    # d = 1: η ≡ 1, so ⟨(1 − cη)^s⟩ = (1 − c)^s; c = 15/16 (the cross fraction at r = 1/2)
    # gives 1/16 at s = 1 and 1/256 at s = 2; c = 1/2, s = 1/2: √2/2
    law = MaxwellModel(0.5).law
    assert law.mixed_moment(15 / 16, [1.0, 2.0]) == pytest.approx([1 / 16, 1 / 256], rel=1e-15)
    assert float(law.mixed_moment(0.5, 0.5)) == pytest.approx(math.sqrt(0.5), rel=1e-15)
    # d = 3 uniform, η ~ Beta(1/2, 1) with ⟨η⟩ = 1/3: ⟨1 − cη⟩ = 1 − c/3 at s = 1
    law3 = MaxwellModel(0.5, 3).law
    assert float(law3.mixed_moment(15 / 16, 1.0)) == pytest.approx(1 - 5 / 16, rel=1e-15)
