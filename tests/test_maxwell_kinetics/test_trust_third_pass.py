"""Hostile input to the library, third pass: every refusal is an InvalidArgumentError naming the
argument and showing the value received, raised before any expensive work."""

from __future__ import annotations

import os

import numpy as np
import pytest

from maxwell_kinetics import compile_cache
from maxwell_kinetics import inelastic_boltzmann as ib
from maxwell_kinetics import velocity_grid as vg
from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.grid import RESOLUTIONS
from maxwell_kinetics.kinetic_histogram import band_limited_density
from maxwell_kinetics.solution import Solution
from particles.initial import get_law
from particles.validation import InvalidArgumentError


def _no_work(*args, **kwargs):
    raise AssertionError("the relaxation started instead of being refused")


@pytest.fixture
def no_relaxation(monkeypatch):
    monkeypatch.setattr(ib, "tables_for", _no_work)


def test_a_relaxation_past_the_integrators_steps_is_refused_first(no_relaxation):
    with pytest.raises(InvalidArgumentError, match=r"relaxation=100000\.0.*time steps"):
        ib.scaling_state(0.5, relaxation=1e5)


def test_a_relaxation_of_more_than_a_day_is_refused_unless_forced(no_relaxation):
    grid = vg.VelocityGrid(1601, 12.0)
    with pytest.raises(InvalidArgumentError, match=r"relaxation=1000\.0.*86400 s"):
        ib.scaling_state(0.5, grid=grid, relaxation=1000)
    with pytest.raises(InvalidArgumentError, match="force='no'"):
        ib.scaling_state(0.5, grid=grid, relaxation=1000, force="no")
    # the estimate reads the rate: a larger exponent takes more steps on the same grid
    kernel = ib.kernel_of(0.5, 1.0)
    assert ib.relaxation_steps(kernel, grid, 10.0) < ib.relaxation_steps(
        ib.kernel_of(0.5, 2.0), grid, 10.0)


@pytest.mark.parametrize("path", [123, True, "", "   ", b"folder"])
def test_compile_cache_enable_refuses_what_is_not_a_folder(path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    before = compile_cache.current_choice()
    try:
        with pytest.raises(InvalidArgumentError, match="argument path="):
            compile_cache.enable(path)
    finally:
        compile_cache.restore_choice(before)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("half_width", [1e300, 1e31, float(np.finfo(float).max)])
def test_an_absurd_mapped_half_width_is_blamed_on_the_half_width(half_width):
    with pytest.raises(InvalidArgumentError, match="argument half_width="):
        vg.MappedGrid(161, half_width, 0.07)


def _built_uniform(tau):
    """A d = 1 Solution built from a known G, not solved: the uniform law's free part
    e^{−τ} φ(q e^{λτ}) plus (1 − e^{−τ}) f̂(q), whose density is known exactly."""
    grid = RESOLUTIONS["coarse"]
    weight, stretch = np.exp(-tau), np.exp(0.25 * (1 - 0.5**2) * tau)
    G = weight * get_law("uniform").phi(grid.q * stretch) + (1 - weight) * f_hat(grid.q)
    sol = Solution(0.5, "uniform", grid, np.array([tau]), G[None, :].astype(complex),
                   (G - f_hat(grid.q))[None, :].astype(complex))
    return sol, weight, stretch


@pytest.mark.parametrize("tau", [0.0, 0.5])
def test_density_counts_the_never_collided_particles_exactly(tau):
    sol, weight, stretch = _built_uniform(tau)
    edge = 3**0.5 * stretch
    x = np.array([-7.0, -2.5, -1.8, -1.0, 0.0, 0.3, 1.5, 1.6, 2.2, 30.0])
    x = x[np.abs(np.abs(x) - edge) > 0.05]
    exact = (weight * np.where(np.abs(x) < edge, 1 / (2 * edge), 0.0)
             + (1 - weight) * 2 / (np.pi * (1 + x**2) ** 2))
    # the transform of (1 − e^{−τ}) f̂ cut at q_max is left: about 1e-16 on "coarse"
    assert np.max(np.abs(sol.density(x)[1] - exact)) < 1e-9
    # the band-limited transform of G cut at q_max on the FFT grid (a trigonometric
    # polynomial, which spectral refinement relies on): its mass is G(0) = 1 exactly
    xs, P = band_limited_density(sol, 0)
    assert np.sum(P) * (xs[1] - xs[0]) == pytest.approx(1.0, abs=1e-12)


@pytest.fixture(scope="module")
def uniform_solves():
    from maxwell_kinetics import solve

    return {name: solve(0.5, "uniform", tau=[0.0, 0.5], resolution=name, progress=False)
            for name in ("coarse", "fine")}


_X = np.array([-3.0, -1.8, -1.5, -1.0, 0.0, 0.7, 1.5, 1.7, 1.8, 2.5])


@pytest.mark.slow
def test_density_at_tau_zero_is_the_initial_law_to_round_off(uniform_solves):
    sol = uniform_solves["coarse"]
    exact = np.where(np.abs(_X) < 3**0.5, 1.0 / (2.0 * 3**0.5), 0.0)
    assert np.max(np.abs(sol.density(_X, tau_index=0)[1] - exact)) < 1e-12
    x, P = band_limited_density(sol, 0)  # the FFT grid: the transform of G, of mass 1
    assert np.sum(P) * (x[1] - x[0]) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.slow
def test_density_after_collisions_agrees_with_a_fine_resolution(uniform_solves):
    coarse, fine = (uniform_solves[name].density(_X, tau=0.5)[1] for name in ("coarse", "fine"))
    # measured: 8.2e-3 with the exact free part, 2.2e-2 when it was transformed with the rest
    assert np.max(np.abs(coarse - fine)) < 0.012


@pytest.mark.parametrize("counts", [[1, -1], [0, 0], [2, -1]])
def test_weighted_kurtosis_refuses_negative_or_no_counts(counts):
    from particles.observables import weighted_kurtosis

    with pytest.raises(InvalidArgumentError, match="argument counts="):
        weighted_kurtosis([1.0, 2.0], counts)


def test_histogram_from_counts_refuses_more_samples_than_n():
    from particles.observables import histogram_from_counts

    with pytest.raises(InvalidArgumentError, match=r"argument count=\[5\.0, 1\.0\].*n = 3"):
        histogram_from_counts([0.0, 1.0, 2.0], [5, 1], 3, 1.0)
    with pytest.raises(InvalidArgumentError, match="at most n = 3 samples in each bin"):
        histogram_from_counts([0.0, 1.0, 2.0], [3.02, 0.0], 3, 1.0)  # 0.7 % above n
    assert histogram_from_counts([0.0, 1.0, 2.0], [3.0, 0.0], 3, 1.0).error[0] == 0.0  # n: p = 1
    # expected counts of a prediction may add up to more than n; each bin stays within n
    hist = histogram_from_counts([0.0, 1.0, 2.0], [2.0, 1.5], 3, 1.0)
    assert np.all(np.isfinite(hist.error))


def test_mean_sem_json_writes_no_nan():
    import json

    from particles.observables import mean_sem_json

    payload = mean_sem_json([float("nan"), 1.0])
    assert payload == [None, None]
    json.dumps(payload, allow_nan=False)


def test_a_negative_zero_time_is_the_time_zero():
    from particles.validation import check_times

    assert not np.any(np.signbit(check_times([-0.0, 1.0], "t")))
    assert not np.signbit(check_times(-0.0, "t")[0])


@pytest.mark.parametrize("q", [[True], [1j], "1", [[1.0, 2.0], [1j, 0.0]]])
def test_evaluate_refuses_what_is_not_a_real_q(q):
    sol, _, _ = _built_uniform(0.0)
    with pytest.raises(InvalidArgumentError, match="argument q="):
        sol.evaluate(q)


@pytest.mark.parametrize("s", [1e300, 300.0, -300.0])
def test_fourier_distance_refuses_an_exponent_whose_power_overflows(s):
    sol, _, _ = _built_uniform(0.0)
    with pytest.raises(InvalidArgumentError, match="argument s="):
        sol.fourier_distance(s)
    assert np.isfinite(sol.fourier_distance(2.5, 0))


def _built_boltzmann():
    """A BoltzmannSolution built by hand (a Gaussian on ±40, one time), not solved."""
    from maxwell_kinetics.boltzmann_solution import BoltzmannSolution

    grid = vg.VelocityGrid(321, 40.0)
    F = np.exp(-grid.c**2 / 2)[None, :] / np.sqrt(2 * np.pi)
    return BoltzmannSolution(0.5, 0.0, 1.0, "gaussian", grid, np.array([0.0]), F, np.zeros(1),
                             0.0, np.zeros(1), np.zeros(1), 0, 0.0)


@pytest.mark.parametrize("order", [190, 1000, 10**6])
def test_a_moment_order_whose_power_overflows_is_refused(order):
    sol = _built_boltzmann()
    with pytest.raises(InvalidArgumentError, match=f"argument orders=.*{order}"):
        sol.moments([2, order])
    state = ib.ScalingState(0.5, 1.0, sol.grid, sol.F[0])
    with pytest.raises(InvalidArgumentError, match=f"argument order={order}"):
        state.moment(order)
    assert sol.moments([4]).values[0, 0] == pytest.approx(3.0, rel=1e-9)


@pytest.mark.parametrize("G", [lambda q: "a", lambda q: np.ones(3)])
def test_invert_refuses_a_G_that_is_not_one_number_per_q(G):
    from maxwell_kinetics.velocity import invert

    with pytest.raises(InvalidArgumentError, match="argument G="):
        invert(G, x=[0.0])


def test_inverse_transform_refuses_a_period_with_no_node_below_q_max():
    from maxwell_kinetics.velocity import inverse_transform

    with pytest.raises(InvalidArgumentError, match=r"argument period=1e-300"):
        inverse_transform(lambda q: np.exp(-q * q / 2), period=1e-300)


@pytest.mark.parametrize("kwargs,name", [(dict(h=True), "h"), (dict(h=0.1, order="8"), "order"),
                                         (dict(h="0.1"), "h"), (dict(h=0.1, s_min="x"), "s_min")])
def test_a_resolution_refuses_booleans_and_text(kwargs, name):
    from maxwell_kinetics.grid import Resolution

    with pytest.raises(InvalidArgumentError, match=f"argument {name}="):
        Resolution("mine", **kwargs)


@pytest.mark.parametrize("args,kwargs,name", [
    ((float("nan"), 2), {}, "tau"), ((1.0, True), {}, "n_times"),
    ((1.0, 2), dict(dimension=7), "dimension"), ((1.0, 2), dict(window=0.0), "window")])
def test_estimate_solve_checks_its_arguments(args, kwargs, name):
    from maxwell_kinetics.grid import estimate_solve

    with pytest.raises(InvalidArgumentError, match=f"argument {name}="):
        estimate_solve(RESOLUTIONS["coarse"], *args, **kwargs)


@pytest.mark.parametrize("kwargs,name", [(dict(atol=1e300), "atol"),
                                         (dict(max_steps_per_window=0), "max_steps_per_window"),
                                         (dict(max_steps_per_window=True),
                                          "max_steps_per_window")])
def test_solver_options_refuse_what_controls_nothing(kwargs, name):
    from maxwell_kinetics.solution import SolverOptions

    with pytest.raises(InvalidArgumentError, match=f"argument {name}="):
        SolverOptions(**kwargs)


def test_solve_fourier_refuses_options_that_are_not_solver_options():
    from maxwell_kinetics.solver import solve_fourier

    with pytest.raises(InvalidArgumentError, match="argument options='fast'"):
        solve_fourier(0.5, "gaussian", tau=[1.0], resolution="coarse", progress=False,
                      options="fast")


def test_a_time_in_the_index_slot_is_refused_with_the_keyword_to_use():
    sol, _, _ = _built_uniform(0.5)
    with pytest.raises(InvalidArgumentError, match=r"tau_index=0\.5 .*tau=0\.5"):
        sol.histogram([-1.0, 0.0, 1.0], tau_index=0.5)


def test_a_name_moved_out_of_the_solver_names_its_new_home():
    with pytest.raises(ImportError, match=r"maxwell_kinetics\.deviation\.source"):
        from maxwell_kinetics.solver import source  # noqa: F401


@pytest.mark.parametrize("choice", ["garbage", (None,), (None, "yes"), (123, True), None])
def test_compile_cache_restore_choice_refuses_what_current_choice_never_returns(choice):
    before = compile_cache.current_choice()
    with pytest.raises(InvalidArgumentError, match="argument choice="):
        compile_cache.restore_choice(choice)
    assert compile_cache.current_choice() == before


def test_a_negative_zero_speed_is_returned_as_zero():
    sol, _, _ = _built_uniform(0.0)
    s, _ = sol.speed_density([-0.0, 1.0])
    assert not np.any(np.signbit(s))


def test_the_one_dimensional_speed_density_counts_the_free_part_exactly_too():
    sol, _, _ = _built_uniform(0.0)
    s, P = sol.speed_density([0.0, 0.5, 1.5, 1.8, 3.0])
    assert np.max(np.abs(P - [3**-0.5, 3**-0.5, 3**-0.5, 0.0, 0.0])) < 1e-12
    with pytest.raises(InvalidArgumentError, match="argument s="):
        sol.speed_density([1e300])
