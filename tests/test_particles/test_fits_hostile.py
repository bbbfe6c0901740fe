"""The particle-side fits and decay laws on hostile input.

``velocity_tail_exponent`` fitted a line through repeated points: with |v| taking three values
in the tail its 25 quantile points are only 2 distinct abscissae, and it returned β = 0.92 with
a standard error of 4e-16.  Haff's law took NaN or a boolean restitution and returned NaN."""

from __future__ import annotations

import numpy as np
import pytest

from particles.md.observables import haff_energy, haff_time, initial_cooling_rate
from particles.sticky import velocity_tail_exponent
from particles.validation import InvalidArgumentError

NAN = float("nan")


def test_a_tail_of_two_distinct_points_is_not_fitted():
    v = np.repeat([0.1, 3.0, 4.0, 5.0], [98900, 600, 400, 100]).astype(float)
    with pytest.raises(InvalidArgumentError, match="2 distinct points") as info:
        velocity_tail_exponent(v)
    assert info.value.name == "v"


def test_a_gaussian_tail_is_still_fitted():
    # 1e5 Gaussian velocities: 25 distinct tail points; the local slope of ln(-ln P) against
    # ln w over P in [1e-5, 1e-2] is below the asymptotic 2 (it tends to 2 only as w -> inf);
    # it must be finite with a positive error
    beta, err, (lo, hi) = velocity_tail_exponent(np.random.default_rng(0).normal(size=100_000))
    assert 1.0 < beta < 2.0 and 0.0 < err < 0.2 and 2.0 < lo < hi


@pytest.mark.parametrize("call, name", [
    (lambda: velocity_tail_exponent([NAN] * 20), "v"),
    (lambda: velocity_tail_exponent([1j] * 20), "v"),
    (lambda: velocity_tail_exponent(np.zeros(20)), "v"),  # E = 0: w was NaN
    (lambda: velocity_tail_exponent(np.ones(1000), quantiles=(True, 1e-2)), "quantiles"),
    (lambda: velocity_tail_exponent(np.ones(1000), quantiles=0.1), "quantiles"),
    (lambda: haff_time(NAN, 1.0), "restitution"),
    (lambda: haff_time(True, 1.0), "restitution"),
    (lambda: haff_time(0.5, 0.0), "density"),
    (lambda: haff_energy([1.0, NAN], 0.5, 1.0), "t"),
    (lambda: haff_energy(-1.0, 0.5, 1.0), "t"),
    (lambda: haff_energy(1.0, 0.5, 1.0, t0_energy=-1.0), "t0_energy"),
    (lambda: initial_cooling_rate(0.5j, 1.0), "restitution"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_md_observables_check_their_state_and_time():
    from particles.md import MDEngine, MDParams, collisions_per_particle, profile_x, rod_positions

    params = MDParams(10, 1.0, 0.5)
    state = MDEngine(params).initial_state(np.random.default_rng(0))
    for call, name in [
        (lambda: rod_positions(state, params, NAN), "t"),  # gave NaN positions
        (lambda: rod_positions(state, params, 1j), "t"),  # TypeError
        (lambda: profile_x(state, params, True), "t"),  # was taken as t = 1
        (lambda: profile_x(None, params), "state"),  # AttributeError
        (lambda: rod_positions(state, MDParams(12, 1.0, 0.5)), "params"),  # another N
        (lambda: collisions_per_particle(None), "state"),
    ]:
        with pytest.raises(InvalidArgumentError) as info:
            call()
        assert info.value.name == name
    assert rod_positions(state, params).shape == (10,)


def test_engine_helpers_check_their_arguments():
    from particles.lattice import thinning_bound
    from particles.ulam import draw_pairs

    rng = np.random.default_rng(0)
    for call, name in [
        (lambda: thinning_bound(np.array([NAN, 1.0])), "v"),  # returned NaN
        (lambda: thinning_bound(np.array([1j, 2.0])), "v"),
        (lambda: draw_pairs(rng, 1, 3), "n"),  # ValueError "high <= 0" from NumPy
        (lambda: draw_pairs(rng, 10, True), "k"),
        (lambda: draw_pairs(5, 10, 3), "rng"),
    ]:
        with pytest.raises(InvalidArgumentError) as info:
            call()
        assert info.value.name == name
    pairs = draw_pairs(rng, 10, 1000)
    assert pairs.shape == (1000, 2) and np.all(pairs[:, 0] != pairs[:, 1])
    assert thinning_bound([-1.0, 2.0]) == pytest.approx(3.0)  # a list: AttributeError before


def test_sticky_state_checks_its_inputs():
    from particles.sticky import sticky_state

    x = np.linspace(0.5, 9.5, 10)
    v = np.random.default_rng(1).normal(size=10)
    for call, name in [
        (lambda: sticky_state(np.r_[x[:-1], NAN], v, 10.0, 1.0), "x0"),  # NaN positions out
        (lambda: sticky_state(x, np.r_[v[:-1], NAN], 10.0, 1.0), "v0"),
        (lambda: sticky_state(x, v, NAN, 1.0), "length"),
        (lambda: sticky_state(x, v, 10.0, NAN), "t"),  # a state at time NaN
        (lambda: sticky_state(x, v, 10.0, True), "t"),  # taken as t = 1
        (lambda: sticky_state(x, v, 10.0, 1j), "t"),  # TypeError
        (lambda: sticky_state(x[::-1], v, 10.0, 1.0), "x0"),  # unsorted: a wrong state
        (lambda: sticky_state(x + 20.0, v, 10.0, 1.0), "x0"),  # outside the ring
        (lambda: sticky_state(x, v[:-1], 10.0, 1.0), "v0"),  # broadcasting ValueError
    ]:
        with pytest.raises(InvalidArgumentError) as info:
            call()
        assert info.value.name == name
    assert sticky_state(x, v, 10.0, 1.0).time == 1.0
