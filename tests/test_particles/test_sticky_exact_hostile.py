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
