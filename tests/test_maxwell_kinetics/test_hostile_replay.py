"""Hostile arguments to the Solution methods, the relative-velocity solvers and the bin
integrals: each is refused by name (InvalidArgumentError), never a TypeError, IndexError,
ValueError, RuntimeError or MemoryError from deep inside, and never a silent nan."""

import math

import numpy as np
import pytest

from maxwell_kinetics import solve
from particles.validation import InvalidArgumentError


@pytest.fixture(scope="module")
def sol():
    return solve(0.5, "gaussian", tau=[1.0, 2.0], resolution="coarse", progress=False)


@pytest.mark.parametrize("tau_index", [True, np.bool_(False), 1.5, "0", 1.0])
def test_tau_index_must_be_an_integer(sol, tau_index):
    with pytest.raises(InvalidArgumentError) as err:
        sol.evaluate([0.0, 1.0], tau_index=tau_index)
    assert err.value.name == "tau_index"


def test_tau_index_of_numpy_integer_is_taken(sol):
    assert np.array_equal(sol.evaluate([1.0], tau_index=np.int64(0)),
                          sol.evaluate([1.0], tau_index=0))


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"s": float("nan")}, "s"), ({"s": float("inf")}, "s"), ({"s": True}, "s"),
    ({"s": 2.5 + 1j}, "s"), ({"s": "a"}, "s"),
    ({"s": 2.5, "q_low": float("nan")}, "q_low"), ({"s": 2.5, "q_low": 1e9}, "q_low"),
    ({"s": 2.5, "q_low": "a"}, "q_low"), ({"s": 2.5, "q_low": True}, "q_low"),
])
def test_fourier_distance_refuses_by_name(sol, kwargs, name):
    with pytest.raises(InvalidArgumentError) as err:
        sol.fourier_distance(tau_index=0, **kwargs)
    assert err.value.name == name


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"max_steps": 0}, "max_steps"), ({"max_steps": 1.5}, "max_steps"),
    ({"max_steps": True}, "max_steps"), ({"grid": "fine"}, "grid"),
])
def test_solve_boltzmann_refuses_by_name_before_the_work(kwargs, name):
    from maxwell_kinetics import solve_boltzmann

    with pytest.raises(InvalidArgumentError) as err:
        solve_boltzmann(0.5, [1.0], **kwargs)
    assert err.value.name == name


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"tolerance": -1.0}, "tolerance"), ({"tolerance": float("nan")}, "tolerance"),
    ({"max_iterations": True}, "max_iterations"), ({"max_iterations": -1}, "max_iterations"),
    ({"max_iterations": 2.5}, "max_iterations"), ({"relaxation": float("nan")}, "relaxation"),
    ({"relaxation": -5.0}, "relaxation"), ({"grid": (241, 12.0)}, "grid"),
])
def test_scaling_state_refuses_by_name_before_the_work(kwargs, name):
    from maxwell_kinetics import scaling_state

    with pytest.raises(InvalidArgumentError) as err:
        scaling_state(0.5, **kwargs)
    assert err.value.name == name


def test_a_half_width_no_grid_can_cover_is_named_itself():
    # Before: half_width 1e9 was reported as points=201 "at least 8000000001 points", beyond
    # the 1601 points allowed: the value to change is the half-width.
    from maxwell_kinetics.velocity_grid import (
        MAX_POINTS,
        MAX_SPACING,
        VelocityGrid,
        initial_values,
    )

    with pytest.raises(InvalidArgumentError) as err:
        initial_values("gaussian", VelocityGrid(201, 1e9))
    widest = MAX_SPACING * (MAX_POINTS - 1) / 2
    assert err.value.name == "half_width" and f"a half-width <= {widest:g}" in str(err.value)
    # within reach of the points allowed, the points are still what is named
    with pytest.raises(InvalidArgumentError) as err:
        initial_values("gaussian", VelocityGrid(201, 100.0))
    assert err.value.name == "points"


def test_a_time_beyond_the_hard_rod_solvers_reach_is_refused_before_the_work():
    # Before: solve --rate relative_velocity --t 1e24 ran for minutes (the integration stalls
    # once the thermal scale falls below ~1e-18) and gamma = 0 to n t = 1e5 would have run a
    # million steps before failing.
    import time

    from maxwell_kinetics.inelastic_boltzmann import (
        SMALLEST_SCALE,
        check_reach,
        solve_boltzmann,
    )
    from maxwell_kinetics.model import RelativeVelocityModel
    from maxwell_kinetics.velocity_grid import default_grid

    start = time.perf_counter()
    for exponent, t in ((1.0, 1e24), (0.5, 1e12), (0.0, 1e5)):
        with pytest.raises(InvalidArgumentError) as err:
            solve_boltzmann(0.5, [1.0, t], exponent=exponent)
        assert err.value.name == "t" and "a last time t <= " in str(err.value)
    assert time.perf_counter() - start < 5.0  # refused before any compilation
    # The reach of gamma = 1 at r = 0.5, n = 1: Haff's law from a Gaussian,
    # s = 1/(1 + lam n kappa t/2), lam = 3/16, kappa = 8/sqrt(pi).
    model = RelativeVelocityModel(0.5, exponent=1.0)
    rate = 0.5 * (3.0 / 16.0) * 8.0 / math.sqrt(math.pi)
    reach = (1.0 / SMALLEST_SCALE - 1.0) / rate
    check_reach(model, 1.0, 0.999 * reach, default_grid(1.0), 10**6)
    with pytest.raises(InvalidArgumentError):
        check_reach(model, 1.0, 1.001 * reach, default_grid(1.0), 10**6)
    # gamma = 0: the step estimate against max_steps (30 steps per unit n t on the default
    # grid, whose stiffness max|c|/h is 40/0.2 = 200)
    maxwell = RelativeVelocityModel(0.5, exponent=0.0)
    check_reach(maxwell, 1.0, 16.0, default_grid(0.0), 500)
    with pytest.raises(InvalidArgumentError, match="max_steps = 500"):
        check_reach(maxwell, 1.0, 17.0, default_grid(0.0), 500)


def test_the_reach_estimate_follows_the_solved_cooling():
    """Haff's estimate of the thermal scale that check_reach uses, against the solve: hard rods,
    r = 0.5, t = 1000 from a Gaussian (the kurtosis moves from 3 to 3.48, so the estimate,
    made with the Gaussian's <|v - w|^3>, is within a few per cent, not exact)."""
    from maxwell_kinetics.inelastic_boltzmann import solve_boltzmann

    solution = solve_boltzmann(0.5, [1000.0])
    s = math.sqrt(solution.energy[-1])
    predicted = 1.0 / (1.0 + 0.5 * (3.0 / 16.0) * 8.0 / math.sqrt(math.pi) * 1000.0)
    assert abs(s / predicted - 1.0) < 0.1, (s, predicted)


def test_a_density_at_too_many_points_is_refused_before_the_work():
    # Before: Solution.density(x=...) had no estimate on the number of points (10⁶ points at
    # |x| <= 5 took 114 s on a loaded machine; the time is nodes x points).
    import time

    from maxwell_kinetics.velocity import (
        MAX_QUADRATURE_SECONDS,
        SECONDS_PER_NODE_VALUE,
        check_quadrature,
        quadrature_nodes,
    )

    nodes = quadrature_nodes(35.0, 5e4)
    most = MAX_QUADRATURE_SECONDS / (SECONDS_PER_NODE_VALUE * nodes)
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError, match=r"at most .* values at this largest \|x\|"):
        check_quadrature(35.0, np.full(int(1.01 * most) + 1, 5e4), "x")
    assert check_quadrature(35.0, np.full(int(0.99 * most), 5e4), "x") == nodes
    assert time.perf_counter() - start < 5.0
    solution = solve(0.5, tau=[1.0], resolution="coarse", progress=False)
    q_max = solution.resolution.q_max
    too_many = int(1.01 * MAX_QUADRATURE_SECONDS
                   / (SECONDS_PER_NODE_VALUE * quadrature_nodes(q_max, 5e4))) + 1
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError) as err:
        solution.density(x=np.full(too_many, 5e4))
    assert err.value.name == "x" and time.perf_counter() - start < 5.0
