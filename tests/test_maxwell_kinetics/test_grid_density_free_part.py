"""Solution.density() on the FFT grid counts the never-collided particles of a built-in law
exactly (no Gibbs ringing, never negative), as density(x) does; the band-limited transform of
all of G, which the comparisons' spectral refinement needs, is band_limited_density."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import statistics as st
from maxwell_kinetics.app.comparisons.kinetic_predictions import fft_bin_probabilities
from maxwell_kinetics.exact import f_hat
from maxwell_kinetics.grid import RESOLUTIONS
from maxwell_kinetics.kinetic_histogram import band_limited_density, law_density
from maxwell_kinetics.solution import Solution
from maxwell_kinetics.velocity import cut_at
from particles.initial import get_law

SQRT3 = 3**0.5
#: λ of r = 1/2 in d = 1: (1 − r²)/4
LAM = 0.25 * (1 - 0.5**2)


def _built(law_name, tau):
    """A d = 1 Solution of r = 1/2 built from a known G, not solved: the law's free part
    e^{−τ} φ(q e^{λτ}) plus (1 − e^{−τ}) f̂(q), whose density is known exactly."""
    grid = RESOLUTIONS["coarse"]
    weight, stretch = np.exp(-tau), np.exp(LAM * tau)
    G = weight * get_law(law_name).phi(grid.q * stretch) + (1 - weight) * f_hat(grid.q)
    sol = Solution(0.5, law_name, grid, np.array([tau]), G[None, :].astype(complex),
                   (G - f_hat(grid.q))[None, :].astype(complex))
    return sol, weight, stretch


def _exact_uniform(x, weight, stretch):
    edge = SQRT3 * stretch
    return (weight * np.where(np.abs(x) < edge, 1 / (2 * edge), 0.0)
            + (1 - weight) * 2 / (np.pi * (1 + x**2) ** 2))


def test_the_grid_density_of_the_uniform_law_at_tau_zero_is_the_law_itself():
    sol, weight, stretch = _built("uniform", 0.0)
    x, P = sol.density()
    away = np.abs(np.abs(x) - SQRT3) > 0.05
    # uniform on [−√3, √3] (unit variance): 1/(2√3) inside, 0 outside
    assert np.max(np.abs(P[away] - _exact_uniform(x[away], weight, stretch))) < 1e-12
    assert np.min(P) >= 0.0
    # the grid is the FFT's: spacing 2π/(2·q_max)-ish, period 1000, mass ≈ 1 (a Riemann sum
    # of a step: off by at most a grid spacing times the height)
    assert np.sum(P) * (x[1] - x[0]) == pytest.approx(1.0, abs=(x[1] - x[0]) / SQRT3)


def test_the_grid_density_of_the_uniform_law_after_collisions_does_not_ring():
    sol, weight, stretch = _built("uniform", 0.5)
    x, P = sol.density(tau_index=0)
    away = np.abs(np.abs(x) - SQRT3 * stretch) > 0.05
    # what is left is the transform of (1 − e^{−τ}) f̂ cut at q_max (a few 1e-12 on "coarse")
    assert np.max(np.abs(P[away] - _exact_uniform(x[away], weight, stretch))) < 1e-9
    assert np.min(P) >= 0.0


def test_the_grid_density_of_the_asymmetric_law_at_tau_zero_is_the_law_itself():
    # v = X − 1, X ~ Exp(1): P(x) = e^{−(x+1)} for x > −1, 0 below; a jump at −1
    sol, _, _ = _built("asymmetric", 0.0)
    x, P = sol.density()
    away = np.abs(x + 1.0) > 0.05
    exact = np.where(x > -1.0, np.exp(-(np.maximum(x, -1.0) + 1.0)), 0.0)
    assert np.max(np.abs(P[away] - exact[away])) < 1e-12
    assert np.min(P) >= 0.0


def test_the_band_limited_density_has_no_frequency_above_q_max():
    sol, _, _ = _built("uniform", 0.0)
    q_max = sol.resolution.q_max
    x, P = band_limited_density(sol, 0)
    dx = x[1] - x[0]
    assert np.sum(P) * dx == pytest.approx(1.0, abs=1e-12)  # G(0) = 1
    q = 2 * np.pi * np.fft.rfftfreq(P.size, d=dx)
    spectrum = np.abs(np.fft.rfft(np.fft.ifftshift(P))) * dx
    assert np.max(spectrum[q > 1.01 * q_max]) < 1e-12
    # the exact density on the same grid has a jump, hence frequencies above q_max, and
    # agrees with the band-limited one away from the jump only to the Gibbs tail (~1e-2)
    x2, exact = sol.density(tau_index=0)
    assert np.array_equal(x, x2)
    assert np.max((np.abs(np.fft.rfft(np.fft.ifftshift(exact))) * dx)[q > 1.01 * q_max]) > 1e-3


def test_law_density_is_never_negative_nor_wrong_beside_a_jump():
    v = SQRT3 + np.linspace(-0.05, 0.05, 10001)
    d = law_density(get_law("uniform"), v)
    assert np.min(d) >= 0.0
    exact = np.where(v < SQRT3, 1 / (2 * SQRT3), 0.0)
    beside = np.abs(v - SQRT3) > 1e-4
    assert np.max(np.abs(d[beside] - exact[beside])) < 1e-9


@pytest.mark.parametrize("law_name", ["uniform", "asymmetric"])
def test_the_fft_bin_probabilities_are_those_of_g_cut_at_q_max(law_name):
    # fft_bin_probabilities integrates the band-limited transform of all of G: its bins are
    # the bin probabilities of G cut at q_max (interval_probabilities, Gauss–Legendre in q;
    # 2e-3 to 2e-2 apart when it integrated the density with the exact free part)
    sol, _, _ = _built(law_name, 0.5)
    edges = np.linspace(-3.0, 3.0, 25)
    prob, x, P = fft_bin_probabilities(sol, 0, edges)
    cut = st.interval_probabilities(cut_at(lambda q: sol.evaluate(q, 0), sol.resolution.q_max),
                                    edges, sol.resolution.q_max)
    assert np.max(np.abs(prob - cut)) < 1e-6
    grid, band = band_limited_density(sol, 0)
    shown = (grid >= edges[0]) & (grid <= edges[-1])
    assert np.array_equal(x, grid[shown]) and np.array_equal(P, band[shown])
