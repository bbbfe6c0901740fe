"""``solve(kernel, initial, times, method)``: one entry point for every kernel and method, and the
old spellings (a restitution, the Fourier keywords) giving the same numbers bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import (
    FourierScheme,
    VelocitySpace,
    fixed_point,
    linear_decay_rates,
    solve,
    steady_state,
)
from maxwell_kinetics.inelastic_boltzmann import scaling_state, solve_boltzmann
from maxwell_kinetics.solver import solve_fourier
from maxwell_kinetics.velocity_grid import VelocityGrid
from particles.kernels import ConstantRate, RelativeVelocity
from particles.validation import InvalidArgumentError

GRID = VelocityGrid(81, 6.0)


@pytest.fixture(scope="module")
def fourier():
    return solve_fourier(0.5, "uniform", tau=[0.5, 2.0], resolution="coarse", progress=False)


@pytest.mark.parametrize("call", [
    lambda: solve(0.5, "uniform", tau=[0.5, 2.0], resolution="coarse", progress=False),
    lambda: solve(0.5, "uniform", [0.5, 2.0], "coarse", progress=False),
    lambda: solve(ConstantRate(0.5), "uniform", [0.5, 2.0], FourierScheme("coarse"),
                  progress=False),
    lambda: solve(ConstantRate(0.5), "uniform", tau=[0.5, 2.0], resolution="coarse",
                  progress=False),
], ids=["old keywords", "positional resolution", "kernel and method", "kernel and keywords"])
def test_every_spelling_of_a_fourier_solve_gives_the_same_numbers(fourier, call):
    sol = call()
    assert sol.time_name == "tau"
    np.testing.assert_array_equal(sol.G, fourier.G)
    np.testing.assert_array_equal(sol.tau, fourier.tau)


def test_a_velocity_space_solve_is_the_hard_rod_solver_bit_for_bit():
    direct = solve_boltzmann(0.5, [0.0, 0.5], grid=GRID, density=2.0)
    for sol in (solve(RelativeVelocity(0.5), "gaussian", [0.0, 0.5], VelocitySpace(GRID),
                      density=2.0),
                solve(RelativeVelocity(0.5), t=[0.0, 0.5], method=VelocitySpace(grid=GRID),
                      density=2.0)):
        assert sol.time_name == "t"
        np.testing.assert_array_equal(sol.F, direct.F)
        np.testing.assert_array_equal(sol.log_scale, direct.log_scale)
    # the kernel as the first argument of the velocity-space functions, old spelling kept
    np.testing.assert_array_equal(
        solve_boltzmann(RelativeVelocity(0.5, 0.5), [0.0, 0.5], grid=GRID).F,
        solve_boltzmann(0.5, [0.0, 0.5], exponent=0.5, grid=GRID).F)
    np.testing.assert_array_equal(solve_boltzmann(restitution=0.5, t=[0.0, 0.5], grid=GRID).F,
                                  solve_boltzmann(0.5, [0.0, 0.5], grid=GRID).F)


@pytest.mark.parametrize("call, name, words", [
    (lambda: solve(RelativeVelocity(0.5), "gaussian", tau=[1.0]), "tau",
     "counts physical time t"),
    (lambda: solve(0.5, "gaussian", t=[1.0]), "t", "collisions per particle tau"),
    (lambda: solve(0.5, "gaussian", [1.0], tau=[1.0]), "tau", "the times once"),
    (lambda: solve(ConstantRate(0.5), "gaussian", [1.0], VelocitySpace()), "method",
     "'constant' is not one"),
    (lambda: solve(RelativeVelocity(0.5), "gaussian", [1.0], "coarse"), "method",
     "'relative_velocity' does not"),
    (lambda: solve(RelativeVelocity(0.5), "gaussian", [1.0], FourierScheme()), "method",
     "Fourier scheme carries"),
    (lambda: solve(0.5, "gaussian", [1.0], density=2.0), "density", "no density"),
    (lambda: solve(0.5, "gaussian", [1.0], FourierScheme(), dimension=2), "dimension",
     "with a method object"),
    (lambda: solve(0.5, "gaussian", [1.0], "coarse", resolution="fine"), "resolution",
     "once"),
    (lambda: solve(0.5, "gaussian", [1.0], method=3), "method", "FourierScheme or"),
    (lambda: solve(ConstantRate, "gaussian", [1.0]), "kernel", "not the class"),
    (lambda: solve(1.5), "restitution", "[0, 1]"),
    (lambda: solve(RelativeVelocity(0.5)), "t", "no default times"),
    (lambda: solve_boltzmann(RelativeVelocity(0.5), [1.0], exponent=0.5), "exponent",
     "no exponent with a kernel"),
    (lambda: solve_boltzmann(ConstantRate(0.5), [1.0]), "kernel", "power of |v - w|"),
    (lambda: solve_boltzmann(0.5, [1.0], restitution=0.5), "restitution", "no restitution"),
    (lambda: fixed_point(RelativeVelocity(0.5)), "kernel", "scaling_state"),
    (lambda: steady_state(RelativeVelocity(0.5), 1.0), "kernel", "scaling_state"),
])
def test_what_a_method_cannot_carry_is_refused_by_name_before_any_work(call, name, words):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name and words in str(info.value)


def test_the_old_keyword_of_the_first_argument_names_the_new_form():
    for keyword in ("restitution", "r"):
        with pytest.raises(TypeError, match=r"solve\(kernel, initial, times, method\)"):
            solve(**{keyword: 0.5})
    with pytest.raises(TypeError, match="unexpected keyword argument 'q_max'"):
        solve(0.5, q_max=3)


def test_the_stationary_solvers_take_the_maxwell_kernel():
    np.testing.assert_array_equal(fixed_point(ConstantRate(0.5), n=24).G,
                                  fixed_point(0.5, n=24).G)
    kernel, number = steady_state(ConstantRate(0.3), 2.0), steady_state(0.3, 2.0)
    assert (kernel.variance, kernel.kurtosis) == (number.variance, number.kurtosis)
    assert linear_decay_rates(ConstantRate(0.5), n=32).rates == linear_decay_rates(0.5, n=32).rates
    grid = VelocityGrid(81, 8.0)
    assert (scaling_state(RelativeVelocity(0.5), grid=grid, relaxation=20.0).kurtosis
            == scaling_state(0.5, grid=grid, relaxation=20.0).kurtosis)


def test_a_velocity_space_solve_on_the_command_line_saves_and_plots(tmp_path, capsys):
    import json

    from maxwell_kinetics.app.cli import main
    from maxwell_kinetics.boltzmann_solution import BoltzmannSolution

    save, plot = tmp_path / "rods.npz", tmp_path / "rods.png"
    assert main(["solve", "--kernel", "relative_velocity", "-r", "0.5", "--t", "0,0.5",
                 "--points", "81", "--half-width", "6", "--save", str(save), "--plot",
                 str(plot), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    loaded = BoltzmannSolution.load(save)
    direct = solve_boltzmann(0.5, [0.0, 0.5], grid=GRID)
    np.testing.assert_array_equal(loaded.F, direct.F)
    assert out["energy"] == direct.energy.tolist()
    assert out["moments"]["4"] == direct.moments((2, 4, 6)).raw()[:, 1].tolist()
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_one_dimensional_solve_reports_no_angular_model(capsys):
    import json

    from maxwell_kinetics.app.cli import main

    assert main(["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["dimension"] == 1 and out["angular"] is None and out["angular_rule"] is None
