"""The kinetic prediction in the bins of a particle run (Solution.histogram), times chosen by
value (tau=) as well as by index, and a solution as labelled arrays (Solution.to_xarray)."""

import math
import sys

import numpy as np
import pytest

from maxwell_kinetics import solve
from maxwell_kinetics import statistics as st
from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.grid import RESOLUTIONS
from maxwell_kinetics.solution import Solution
from particles import Ulam, simulate
from particles.validation import InvalidArgumentError


@pytest.fixture(scope="module")
def sol():
    return solve(0.5, "gaussian", tau=[1.0, 2.0], resolution="coarse", progress=False)


def _direct_bins(sol, edges, k):
    """∫ P(x, τ) dx over each bin by 40-point Gauss–Legendre in x, P from Solution.density."""
    t, w = np.polynomial.legendre.leggauss(40)
    a, b = edges[:-1], edges[1:]
    x = 0.5 * (b - a)[:, None] * (t[None, :] + 1) + a[:, None]
    _, P = sol.density(x.ravel(), tau_index=k)
    return (P.reshape(x.shape) * w[None, :]).sum(axis=1) * 0.5 * (b - a)


def test_histogram_is_the_bin_integral_of_the_density(sol):
    edges = np.array([-6.0, -3.0, -1.5, -0.4, 0.0, 0.3, 1.0, 2.2, 4.0, 7.5])
    for k, tau in enumerate(sol.tau):
        h = sol.histogram(edges, tau=float(tau))
        # The histogram takes the never-collided part out of G on the nodes and the density
        # interpolates it: the two agree within the histogram's own numerical error (measured
        # 1.4e-8 apart at most, errors 2e-7 and more on these wide bins).
        width = np.diff(edges)
        assert np.all(np.abs(h.density * width - _direct_bins(sol, edges, k))
                      <= h.error * width + 1e-10)
        assert np.all(h.error >= 0) and np.max(h.error * width) < 1e-6
        assert h.samples == 0 and np.array_equal(h.edges, edges)
        assert h.v0 == pytest.approx(np.exp(-0.25 * (1 - 0.5**2) * tau), rel=1e-14)


def _isotropic_solution(d, angular):
    """A d-dimensional Solution built from known G, not solved (a d ≥ 2 solve costs a minute of
    compilation): τ = 0 the Gaussian e^{−q²/2}, τ = 1 f̂(q) = (1 + q) e^{−q}, both radial
    characteristic functions in every d (Gaussian; Matérn 3/2), whose one-component marginals are
    N(0, 1) and f(x) = 2/(π(1 + x²)²)."""
    grid = RESOLUTIONS["coarse"]
    G = np.array([np.exp(-grid.q**2 / 2), f_hat(grid.q)], dtype=complex)
    return Solution(0.5, "gaussian", grid, np.array([0.0, 1.0]), G, G - f_hat(grid.q),
                    dimension=d, angular=angular)


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
def test_histogram_in_d_2_and_3_is_the_marginal_of_one_component(d, angular):
    sol = _isotropic_solution(d, angular)
    edges = np.array([-6.0, -3.0, -1.5, -0.4, 0.0, 0.3, 1.0, 2.2, 4.0, 7.5])
    width = np.diff(edges)
    for k in range(2):
        h = sol.histogram(edges, tau_index=k)
        assert np.max(np.abs(h.density * width - _direct_bins(sol, edges, k))) < 1e-10
    # Against the exact marginals: f's CDF to round-off (G = f̂ is stored exactly, its deviation
    # is 0); N(0, 1) to the interpolation of G − f̂ on the coarse grid (measured 3.1e-8).
    exact_f = np.diff(st.f_cdf(edges))
    assert np.max(np.abs(sol.histogram(edges, tau=1.0).density * width - exact_f)) < 1e-13
    exact_gauss = np.diff([0.5 * math.erfc(-e / math.sqrt(2)) for e in edges])
    assert np.max(np.abs(sol.histogram(edges, tau=0.0).density * width - exact_gauss)) < 1e-7
    # v0² = e^{−Λτ}, Λ = 2 p (1 − p) ⟨η⟩, ⟨η⟩ = 1/d (uniform) or 2/(d + 1) (hard), p = 3/4
    mean_eta = 1 / d if angular == "uniform" else 2 / (d + 1)
    rate = 2 * 0.75 * 0.25 * mean_eta
    assert sol.histogram(edges, tau=1.0).v0 == pytest.approx(math.exp(-rate / 2), rel=1e-14)
    assert sol.histogram(edges, tau=0.0).v0 == 1.0


def test_histogram_against_an_ulam_run_of_a_million(sol):
    # One run of N = 10⁶ (its own x = v/√E, the histogram's convention) against the prediction
    # on the run's own bins; χ²/dof within 1 ± 5√(2/dof) (the tolerance: 5 standard
    # deviations of χ²/dof for independent samples; measured 1.25 and 0.90 with seed 1).
    run = simulate(Ulam(1_000_000, 0.5), list(sol.tau), seed=1, progress=False)
    for h, tau in zip(run.histograms, sol.tau, strict=True):
        d = h.distance(sol.histogram(h.edges, tau=float(tau)))
        assert abs(d.chi2_dof - 1) < 5 * np.sqrt(2 / d.dof), d
        assert d.ks < 5 * 0.87 / np.sqrt(1_000_000)


def test_tau_and_tau_index_give_identical_results(sol):
    q = np.linspace(0.0, 5.0, 7)
    x = np.linspace(-3, 3, 5)
    edges = np.linspace(-3, 3, 7)
    for k, tau in enumerate(sol.tau):
        tau = float(tau)
        assert np.array_equal(sol.evaluate(q, k), sol.evaluate(q, tau=tau))
        assert np.array_equal(sol.density(x, k)[1], sol.density(x, tau=tau)[1])
        assert np.array_equal(sol.speed_density(x[x >= 0], k)[1],
                              sol.speed_density(x[x >= 0], tau=tau)[1])
        assert sol.sup_error(k) == sol.sup_error(tau=tau)
        assert sol.fourier_distance(2.5, k) == sol.fourier_distance(2.5, tau=tau)
        assert np.array_equal(sol.moments(tau_index=k).values, sol.moments(tau=tau).values,
                              equal_nan=True)
        assert np.array_equal(sol.histogram(edges, tau_index=k).density,
                              sol.histogram(edges, tau=tau).density)
    assert np.array_equal(sol.density(x)[1], sol.density(x, tau=float(sol.tau[-1]))[1])


@pytest.mark.parametrize("tau", [1.5, 3.0, -1.0, float("nan"), "1", True])
def test_a_tau_not_among_the_saved_times_is_refused_naming_it(sol, tau):
    with pytest.raises(InvalidArgumentError, match=r"tau=.*saved times: 1, 2"):
        sol.histogram([0.0, 1.0], tau=tau)
    with pytest.raises(InvalidArgumentError, match=r"tau=.*saved times"):
        sol.density([0.0], tau=tau)


def test_tau_and_tau_index_together_are_refused(sol):
    with pytest.raises(InvalidArgumentError, match="tau or tau_index, not both"):
        sol.evaluate([0.5], 0, tau=1.0)


@pytest.mark.parametrize("edges", [[0.0, 0.0, 1.0], [1.0, 0.0], [0.0, np.inf], [0.0],
                                   [[0.0, 1.0]], "0,1", [0.0, np.nan, 1.0]])
def test_bad_edges_are_refused_naming_edges(sol, edges):
    with pytest.raises(InvalidArgumentError, match="argument edges="):
        sol.histogram(edges)


def test_solution_to_xarray(sol):
    xr = pytest.importorskip("xarray")
    ds = sol.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert np.array_equal(ds["G"].sel(tau=2.0).values, sol.G[1])
    assert np.array_equal(ds["q"].values, sol.q)
    # the density on [−20, 20] by default (the FFT grid is 16 384 points over ±500), or on x
    x = np.linspace(-20.0, 20.0, 801)
    assert np.array_equal(ds["x"].values, x)
    assert np.array_equal(ds["density"][0].values, sol.density(x, tau_index=0)[1])
    mine = sol.to_xarray(x=[-1.0, 0.0, 2.5])
    assert mine["density"].shape == (len(sol.tau), 3)
    np.testing.assert_array_equal(mine["density"][1].values,
                                  sol.density([-1.0, 0.0, 2.5], tau_index=1)[1])
    with pytest.raises(InvalidArgumentError, match="argument x="):
        sol.to_xarray(x=[0.0, np.nan])


def test_solution_to_xarray_without_xarray_names_the_extra(sol, monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match=r"maxwell-kinetics\[xarray\]"):
        sol.to_xarray()


def test_never_collided_particles_are_a_fraction_e_minus_tau_stretched_by_e_lambda_tau():
    # The loss term −G of ∂τG removes each particle at rate 1, so a fraction e^{−τ} has never
    # collided; those keep their initial velocity while v0 = e^{−λτ} shrinks, so in x = v/v0 they
    # are the initial law stretched by e^{λτ}.  r = 1/2: λ = 3/16; at τ = 2, e^{−2} and e^{3/8}.
    # The histogram subtracts them from G and adds them back from the law's CDF with the same
    # weight and stretch, so an error in either cancels in the bins except through the cut of G
    # at q_max: checked here directly.  A Solution built from known G (no solve); round-off
    # only, 1e-15.
    from maxwell_kinetics.kinetic_histogram import free_part

    grid = RESOLUTIONS["coarse"]
    G = np.array([np.exp(-grid.q**2 / 2)] * 2, dtype=complex)
    one = Solution(0.5, "uniform", grid, np.array([0.0, 2.0]), G, G - f_hat(grid.q))
    weight, stretch, law = free_part(one, 1)
    assert weight == pytest.approx(math.exp(-2.0), rel=1e-15)
    assert stretch == pytest.approx(math.exp(3 / 8), rel=1e-15)
    assert law.name == "uniform"
    assert free_part(one, 0)[:2] == (1.0, 1.0)
    # d ≥ 2: no exact free part (the histogram is the transform of G alone)
    assert free_part(_isotropic_solution(2, "uniform"), 1) is None
