"""The exact sticky-gas laws on hostile input: NaN and complex points, booleans, a non-integer
or zero number of quadrature nodes, a NaN cutoff.  Each raises ``InvalidArgumentError`` naming
the argument (before: NaN returned for z = NaN, True taken as the point 1, nodes = 2.5 taken as
2, SciPy's ValueError for nodes = 0, a NumPy warning for cutoff = NaN)."""

from __future__ import annotations

import pytest

from particles import sticky_exact as se
from particles.validation import InvalidArgumentError

NAN = float("nan")


@pytest.mark.parametrize("call, name", [
    (lambda: se.chernoff_density([NAN]), "z"),
    (lambda: se.chernoff_density([1j]), "z"),
    (lambda: se.chernoff_density([0.0], cutoff=NAN), "cutoff"),
    (lambda: se.chernoff_density([0.0], nodes=True), "nodes"),
    (lambda: se.exact_mass_density(True), "mu"),
    (lambda: se.exact_velocity_density([1.0], nodes=2.5), "nodes"),
    (lambda: se.exact_velocity_density([1.0], nodes=True), "nodes"),
    (lambda: se.exact_velocity_survival([1.0], nodes=0), "nodes"),
    (lambda: se.exact_shock_density([1.0], [1j]), "b"),
    (lambda: se.exact_shock_density([NAN], [1.0]), "a"),
    (lambda: se.displacement_scale(0.0, 1.0), "density"),
    (lambda: se.displacement_scale(1.0, -1.0), "variance"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_a_non_finite_point_is_refused_with_its_value():
    """The first non-finite entry is named with its value and what was expected."""
    with pytest.raises(InvalidArgumentError) as info:
        se.exact_mass_density([1.0, float("inf"), NAN])
    assert info.value.name == "mu"
    assert str(info.value) == "argument mu=inf is invalid: expected finite real numbers"


def test_the_tail_exponent_refuses_velocities_outside_zero_to_thirty_with_the_first_one():
    """β(w) needs w > 0 and a survival that does not underflow (w ≤ 30): the first velocity
    outside is named, with its value and the range."""
    with pytest.raises(InvalidArgumentError) as info:
        se.exact_velocity_tail_exponent([1.0, -0.5, 0.0])
    assert str(info.value) == "argument w=-0.5 is invalid: expected positive velocities"
    with pytest.raises(InvalidArgumentError) as info:
        se.exact_velocity_tail_exponent([2.0, 30.0, 31.0, 40.0])  # 30 itself is allowed
    assert str(info.value) == ("argument w=31.0 is invalid: expected w <= 30.0 (the survival "
                               "underflows beyond)")
    assert info.value.name == "w"
    for f in (se.exact_velocity_survival, se.exact_velocity_tail_exponent,
              se.exact_velocity_density, se.exact_eulerian_velocity_density):
        with pytest.raises(InvalidArgumentError) as info:
            f([1.0, NAN])
        assert info.value.name == "w"


def test_extreme_but_valid_points_give_the_law_not_inf_or_nan():
    """F(μ) overflowed to inf at μ = 1e-300 (its asymptote μ^{−1/2}/√(2π) is 4e149); the tail
    exponent was −inf at w = 1e-20 (1 − S cancelled; β → 1 as w → 0, since −ln S ≈ 2 P(0) w);
    Chernoff's density was NaN at |z| = 1e308 (it is below 1e-280 beyond |z| = 10)."""
    import math

    import numpy as np

    mu = np.array([1e-300, 1e-200, 1e-12])
    np.testing.assert_allclose(se.exact_mass_density(mu), mu**-0.5 / math.sqrt(2 * math.pi),
                               rtol=1e-5)  # the next term is O(μ^{3/2}) relative
    w = np.array([1e-300, 1e-20, 1e-12, 1e-8])
    np.testing.assert_allclose(se.exact_velocity_tail_exponent(w), 1.0, atol=1e-7)
    # the two ways of −ln S agree where both are accurate (either side of the switch at 0.5)
    beta = se.exact_velocity_tail_exponent(np.array([0.49999, 0.5, 0.50001]))
    assert abs(beta[1] - beta[0]) < 1e-5 and abs(beta[2] - beta[1]) < 1e-5
    f = se.chernoff_density(np.array([1e308, -1e308, 10.5, 0.0]))
    assert f.tolist()[:3] == [0.0, 0.0, 0.0] and 0.75 < f[3] < 0.77
    assert se.CHERNOFF_REACH == 10.0
