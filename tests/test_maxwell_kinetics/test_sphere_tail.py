"""The cooling state's tail (maxwell_kinetics.sphere_tail): the predicted rate A = 2K/ζ*, the
fit of ln F = a + μ ln c − A c recovering a synthetic tail exactly, a power law (the Maxwell
model's tail) fitted as A = 0, and the refusals."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from maxwell_kinetics.sphere_grid import SphereGrid
from maxwell_kinetics.sphere_tail import (
    MIN_SHELLS,
    fit_tail,
    measure_tail,
    radial_profile,
    tail_rate,
)
from maxwell_kinetics.tails import tail_exponent
from particles.sphere_kernels import HardSpheres, VariableHardSpheres
from particles.validation import InvalidArgumentError

GRIDS = {2: SphereGrid(64, 14.0, 10.0, 64, 16), 3: SphereGrid(32, 11.0, 8.0, 11, 12)}


def _radius(grid: SphereGrid, d: int) -> np.ndarray:
    axis = grid.nodes()
    return np.sqrt(sum(x**2 for x in np.meshgrid(*([axis] * d), indexing="ij")))


def test_the_predicted_rate_is_twice_the_whole_sphere_factor_over_the_cooling_rate():
    assert tail_rate(HardSpheres(0.5), 3, 2.0) == pytest.approx(2 * math.pi, rel=1e-15)
    assert tail_rate(HardSpheres(0.5), 2, 2.0) == pytest.approx(4.0, rel=1e-15)
    # in d = 3 hard spheres are variable hard spheres of rate |g| with t scaled by β₃ = 2π:
    # their ζ* (per unit τ = ∫n√T dt) is 2π times larger, and their tail the same
    zeta = 0.61
    assert tail_rate(HardSpheres(0.5), 3, 2 * math.pi * zeta) == pytest.approx(
        tail_rate(VariableHardSpheres(0.5, exponent=1.0), 3, zeta), rel=1e-14)
    for gamma in (0.0, 0.5):  # no exponential tail for γ < 1
        with pytest.raises(InvalidArgumentError, match="kernel"):
            tail_rate(VariableHardSpheres(0.5, exponent=gamma), 2, 1.0)
    with pytest.raises(InvalidArgumentError, match="dimension"):
        tail_rate(HardSpheres(0.5), 4, 1.0)
    with pytest.raises(InvalidArgumentError, match="cooling_rate"):
        tail_rate(HardSpheres(0.5), 3, 0.0)


@pytest.mark.parametrize("d", [2, 3])
def test_the_fit_recovers_a_synthetic_exponential_tail_exactly(d):
    grid, A, mu, a = GRIDS[d], 2.97, 0.7, -1.3
    r = _radius(grid, d)
    F = np.exp(a + mu * np.log(np.where(r > 0, r, 1.0)) - A * r)
    profile = radial_profile(F, grid)
    fit = fit_tail(profile, (3.0, 6.0), predicted=A)
    assert fit.rate == pytest.approx(A, abs=1e-10)
    assert fit.power == pytest.approx(mu, abs=1e-10)
    assert fit.amplitude == pytest.approx(a, abs=1e-9)
    assert fit.window_systematic < 1e-10 and fit.rate_error < 1e-10
    assert fit.shells >= MIN_SHELLS and fit.predicted == A
    # the local slope −d ln F/dc between shells is A − μ/c to the shells' averaging
    speed, slope = profile.local_slope()
    far = speed > 3
    assert np.allclose(slope[far], A - mu / speed[far], atol=5e-3)


@pytest.mark.parametrize("d", [2, 3])
def test_a_power_law_tail_like_the_maxwell_models_is_fitted_as_not_exponential(d):
    # the Maxwell model's cooling state has F ∝ c^(−d−2s*) (maxwell_kinetics.tails): the fit
    # gives A = 0 and μ = −d − 2s* exactly, where a hard-sphere tail has A = 2K/ζ* > 0
    law = tail_exponent(d, 0.5, "uniform" if d == 2 else "hard")
    grid = GRIDS[d]
    r = _radius(grid, d)
    F = np.where(r > 0, r, 1.0) ** -law.exponents["density"]
    fit = fit_tail(radial_profile(F, grid), (3.0, 6.0))
    assert abs(fit.rate) < 1e-10 and fit.window_systematic < 1e-10
    assert fit.power == pytest.approx(-law.exponents["density"], abs=1e-9)


def test_the_profile_stops_at_the_floor_the_round_off_and_the_cutoff():
    grid = GRIDS[2]
    r = _radius(grid, 2)
    F = np.exp(-0.5 * r**2)
    profile = radial_profile(F, grid, floor=1e-12)
    assert profile.threshold == 1e-12
    assert np.exp(profile.node_log_density).min() > 1e-12
    edge = math.sqrt(2 * math.log(1e12))  # F = 1e-12 there
    assert edge - 2 * grid.spacing < profile.resolved <= edge + grid.spacing
    assert profile.log_density == pytest.approx(-0.5 * profile.speed**2, abs=0.05)
    # a negative excursion of 1e-9 (round-off, Gibbs) raises the floor to 100 times it
    noisy = F.copy()
    noisy[0, 0] = -1e-3  # a corner, beyond R: the absorbing layer's, not counted
    assert radial_profile(noisy, grid).threshold == 1e-12
    noisy[grid.points // 2, 20] = -1e-9  # |c| = 5.25 < R
    assert radial_profile(noisy, grid).threshold == pytest.approx(1e-7)
    assert radial_profile(noisy, grid).resolved < profile.resolved
    flat = radial_profile(np.exp(-0.1 * r), grid)  # resolved everywhere: up to R, not L
    assert flat.resolved == pytest.approx(grid.cutoff - grid.cutoff % grid.spacing)


@pytest.mark.parametrize("d", [2, 3])
def test_the_nodes_near_the_axes_can_be_left_out(d):
    # ringing of the Fourier cutoff along the axes (negative values there) stops the profile;
    # without the nodes within 20° of an axis the exact tail is resolved again, and fitted
    grid = GRIDS[d]
    r = _radius(grid, d)
    F = np.exp(1.0 - 2.0 * r)
    axes = np.meshgrid(*([grid.nodes()] * d), indexing="ij")
    on_axis = np.max(np.abs(np.stack(axes)), axis=0) > math.cos(math.radians(5)) * r
    ringing = np.where(on_axis & (r > 4), -1e-4, 0.0)
    assert radial_profile(F + ringing, grid).resolved < 4.5
    clean = radial_profile(F + ringing, grid, axis_gap=20.0)
    assert clean.resolved > 7.0 and clean.threshold == pytest.approx(1e-12 * math.e)
    assert fit_tail(clean, (3.0, 6.0)).rate == pytest.approx(2.0, abs=1e-10)
    with pytest.raises(InvalidArgumentError, match="axis_gap"):
        radial_profile(F, grid, axis_gap=45.0)


def test_windows_out_of_reach_are_refused():
    grid = GRIDS[2]
    r = _radius(grid, 2)
    F = np.exp(-2.0 * r)
    profile = radial_profile(F, grid)
    with pytest.raises(InvalidArgumentError, match="window"):
        fit_tail(profile, (3.0, 3.5))  # fewer than MIN_SHELLS shells
    with pytest.raises(InvalidArgumentError, match="window"):
        fit_tail(profile, (6.0, profile.resolved))  # the moved window leaves the profile
    with pytest.raises(InvalidArgumentError, match="window"):
        fit_tail(profile, (5.0, 4.0))
    with pytest.raises(InvalidArgumentError, match="F"):
        radial_profile(F[:-1], grid)
    state = SimpleNamespace(F=F, grid=grid, dimension=2, cooling_rate=2.7)
    fit = measure_tail(state, (3.0, 6.0), kernel=HardSpheres(0.5))
    assert fit.rate == pytest.approx(2.0, abs=1e-10)
    assert fit.predicted == pytest.approx(8.0 / 2.7, rel=1e-14)
    assert measure_tail(state, (3.0, 6.0), kernel=VariableHardSpheres(0.5, exponent=0.0)
                        ).predicted is None
    with pytest.raises(InvalidArgumentError, match="window"):
        measure_tail(state, (3.0, 6.0), margin=4.0)  # 6 + 0.75 > R − 4 = 6


def test_a_spacing_that_is_no_binary_fraction_gives_one_radius_shells_without_a_warning():
    # h = 22/48 (the default d = 2 grid): a shell's nodes at ±x lie at one radius only to
    # round-off, where a straight line in |c| is ill-posed (NumPy's RankWarning, an error in
    # this suite); such a shell's spread is the rms of ln F about its mean.  An F that is not
    # even in x makes that spread nonzero: it must equal the nodes' standard deviation.  (Off
    # the axes, the four nodes (±h, ±h) make such a shell.)
    grid = SphereGrid(48, 11.0, 7.5, 48, 16)
    axis = grid.nodes()
    x, y = np.meshgrid(axis, axis, indexing="ij")
    r = np.hypot(x, y)
    F = np.exp(-0.5 * r**2) * (1.0 + 0.01 * x)
    profile = radial_profile(F, grid, axis_gap=20.0)
    off = np.max(np.abs(np.stack([x, y])), axis=0) <= math.cos(math.radians(20.0)) * r
    width = profile.width
    for k, speed in enumerate(profile.speed):
        pick = off & (np.floor(r / width).astype(int) == int(speed // width))
        radii = r[pick]
        if radii.size >= 3 and np.ptp(radii) <= 1e-9 * width:
            assert profile.spread[k] == pytest.approx(np.std(np.log(F[pick])), rel=1e-12)
            assert profile.spread[k] > 1e-4
            break
    else:
        pytest.fail("no one-radius shell on this grid")
