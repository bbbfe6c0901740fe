"""The one result contract (maxwell_kinetics.kinetic_result.KineticResult), checked on both
kinds of kinetic result: the Fourier solver's Solution (time tau) and the velocity grid's
BoltzmannSolution (time t), each member against a direct computation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from maxwell_kinetics.boltzmann_solution import BoltzmannSolution
from maxwell_kinetics.inelastic_boltzmann import solve_boltzmann
from maxwell_kinetics.kinetic_result import KineticResult
from maxwell_kinetics.moments import Moments
from maxwell_kinetics.solution import Solution
from maxwell_kinetics.solver import solve
from maxwell_kinetics.velocity_grid import MappedGrid, VelocityGrid
from particles.validation import InvalidArgumentError


@pytest.fixture(scope="module", params=["fourier", "grid"])
def result(request):
    if request.param == "fourier":
        return solve(0.5, "gaussian", tau=[0, 1], resolution="coarse", progress=False)
    return solve_boltzmann(0.5, [0.0, 0.5], grid=VelocityGrid(61, 7.0), rtol=1e-9)


def test_both_meet_the_protocol_with_their_time_name(result):
    assert isinstance(result, KineticResult)
    own = {Solution: "tau", BoltzmannSolution: "t"}[type(result)]
    assert result.time_name == own
    assert isinstance(result.times, np.ndarray) and result.times.dtype == float
    np.testing.assert_array_equal(result.times, getattr(result, own))  # the old name still works


def test_moments_are_one_type_rescaled_with_raw_moments_and_energy(result):
    m = result.moments((2, 4))
    assert isinstance(m, Moments) and m.time_name == result.time_name
    np.testing.assert_array_equal(m.times, result.times)
    np.testing.assert_allclose(m.values[:, 0], 1.0, rtol=1e-12)  # rescaled by v0: <x^2> = 1
    np.testing.assert_allclose(m.kurtosis(), result.kurtosis, rtol=1e-12)
    raw = m.raw()
    energy = raw[:, 0] + (result.mean**2 if isinstance(result, BoltzmannSolution) else 0.0)
    np.testing.assert_allclose(result.energy, energy, rtol=1e-12)
    assert result.energy[0] == pytest.approx(1.0, rel=1e-12)  # unit initial variance
    assert result.energy[1] < 1.0  # cooling
    assert np.all(m.errors >= 0)
    # tau only where the time is tau; a Moments is not an array
    if result.time_name == "tau":
        np.testing.assert_array_equal(m.tau, result.times)
    else:
        with pytest.raises(AttributeError, match="times"):
            m.tau  # noqa: B018
    for use in (lambda: m[:, 0], lambda: np.asarray(m), lambda: len(m), lambda: list(m)):
        with pytest.raises(TypeError, match=r"not an array.*raw\(\)"):
            use()


def test_the_grids_raw_moments_are_the_old_central_moments():
    sol = solve_boltzmann(0.5, [0.0, 0.5], grid=VelocityGrid(61, 7.0), rtol=1e-9)
    orders = (0, 1, 2, 3, 4, 6)
    c = sol.grid.c
    old = np.array([[sol.grid.h * np.sum(row * c**k) for k in orders] for row in sol.F])
    old = old * sol.scale[:, None] ** np.asarray(orders)
    np.testing.assert_allclose(sol.moments(orders).raw(), old, rtol=1e-12, atol=1e-15)


def test_the_fourier_moments_scale_is_v0():
    sol = solve(0.5, "gaussian", tau=[0, 1], resolution="coarse", progress=False)
    lam = (1 - 0.5**2) / 4
    np.testing.assert_allclose(sol.moments().scale, np.exp(-lam * sol.times), rtol=1e-14)
    np.testing.assert_allclose(sol.energy, np.exp(-2 * lam * sol.times), rtol=1e-14)


def test_density_and_histogram_take_the_time_by_value_under_one_keyword(result):
    last, first = float(result.times[-1]), float(result.times[0])
    own = result.time_name
    x = np.linspace(-2.0, 2.0, 9)
    xs, P = result.density(x, time=first)
    np.testing.assert_array_equal(xs, x)
    np.testing.assert_array_equal(P, result.density(x, **{own: first})[1])
    np.testing.assert_array_equal(result.density(x)[1], result.density(x, time=last)[1])
    gauss = np.exp(-0.5 * x**2) / math.sqrt(2 * math.pi)
    np.testing.assert_allclose(P, gauss, atol=1e-4)  # the initial law: a unit Gaussian
    with pytest.raises(InvalidArgumentError, match="argument time="):
        result.density(x, time=last, **{own: last})
    edges = np.linspace(-3.0, 3.0, 13)
    hist = result.histogram(edges, time=last)
    same = result.histogram(edges, **{own: last})
    np.testing.assert_array_equal(hist.density, same.density)
    # the probabilities sum to the mass inside the edges (a Gaussian-like law: about 0.997)
    xf = np.linspace(-3.0, 3.0, 601)
    mass = np.trapezoid(result.density(xf, time=last)[1], xf)
    assert float(np.sum(hist.density * np.diff(edges))) == pytest.approx(mass, abs=1e-4)
    # a prediction's error is its numerical error: 0 on the velocity grid, the Fourier
    # solution's own estimate (below 1e-6 per bin here) for Solution
    assert np.all(hist.error >= 0) and np.max(hist.error * np.diff(edges)) < 1e-6
    scale = result.moments((2,)).scale[-1]
    assert hist.v0 == pytest.approx(scale, rel=1e-9)


def test_save_and_load_round_trip_bit_for_bit(result, tmp_path):
    path = tmp_path / "result.npz"
    result.save(path)
    back = type(result).load(path)
    meta, arrays = result.to_record()
    meta_back, arrays_back = back.to_record()
    assert meta == meta_back
    assert sorted(arrays) == sorted(arrays_back)
    for key, value in arrays.items():
        assert arrays_back[key].dtype == value.dtype
        np.testing.assert_array_equal(arrays_back[key], value, strict=True)
    assert type(back.times) is np.ndarray
    if isinstance(result, BoltzmannSolution):
        assert back.grid == result.grid
        np.testing.assert_array_equal(back.grid.c, result.grid.c)
        assert back.steps == result.steps and back.seconds == result.seconds


def test_a_mapped_grid_round_trips(tmp_path):
    grid = MappedGrid(81, 200.0, 0.25)
    f = np.exp(-0.5 * grid.c**2) / math.sqrt(2 * math.pi)
    sol = BoltzmannSolution(0.5, 0.0, 1.0, "gaussian", grid, np.array([0.0, 1.0]),
                            np.array([f, f]), np.array([0.0, -0.1]), 0.25,
                            np.array([-0.1, -0.2]), np.array([1e-30, 2e-30]), 7, 0.5)
    sol.save(tmp_path / "mapped.npz")
    back = BoltzmannSolution.load(tmp_path / "mapped.npz")
    assert isinstance(back.grid, MappedGrid) and back.grid == grid
    for name in ("t", "F", "log_scale", "energy_rate", "edge_mass"):
        np.testing.assert_array_equal(getattr(back, name), getattr(sol, name), strict=True)
    assert (back.mean, back.steps, back.seconds, back.exponent) == (0.25, 7, 0.5, 0.0)


def test_load_refuses_the_other_kind(tmp_path):
    from particles.persistence import FileFormatError

    sol = solve(0.5, "gaussian", tau=[0, 1], resolution="coarse", progress=False)
    sol.save(tmp_path / "fourier.npz")
    with pytest.raises(FileFormatError):
        BoltzmannSolution.load(tmp_path / "fourier.npz")


def test_to_xarray_names_its_time_coordinate(result):
    pytest.importorskip("xarray")
    data = result.to_xarray()
    assert result.time_name in data.coords
    np.testing.assert_array_equal(data.coords[result.time_name].values, result.times)


def test_plot_draws_one_line_per_saved_time(result):
    pytest.importorskip("matplotlib")
    ax = result.plot()
    assert hasattr(ax, "lines") and len(ax.lines) == len(result.times)
    assert ax.figure is not None
    ax2 = result.plot(ax=ax)
    assert ax2 is ax and len(ax.lines) == 2 * len(result.times)
