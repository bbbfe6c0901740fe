"""The d-dim. and driven comparisons at the small size: tail exponents (equation against particles)
and the driven steady state (kinetic theory against driven Ulam particles)."""

import math

import pytest

from maxwell_kinetics.app import comparisons
from maxwell_kinetics.tails import tail_exponent


@pytest.fixture(scope="module")
def tails(comparison):
    return comparison("tail_exponents")


@pytest.fixture(scope="module")
def driven(comparison):
    return comparison("driven_steady")


def test_tail_exponents_from_the_equation(tails):
    s = tails.summary
    assert s["paper_2d_r0"]["hard"]["speed"] == pytest.approx(5.0, abs=1e-9)
    assert s["paper_2d_r0"]["uniform"]["speed"] == pytest.approx(1 + 2 * 2.143764538, rel=1e-8)
    # s* grows as r → 1 (the tails thin out), for every model
    for curve in tails.data["curves"].values():
        assert all(b > a for a, b in zip(curve, curve[1:], strict=False))


def test_particle_tails_agree_with_the_equation(tails):
    # Hill's estimator from the top 100 of 5e4 speeds per run, 4 runs: the tolerance is 4
    # standard errors from the run-to-run scatter (measured: hard -0.5σ, uniform -3.0σ, the
    # latter the estimator's threshold bias at top/N = 0.2 %, which shrinks at the default size)
    for p in tails.summary["particles"]:
        mean, err = p["alpha"]
        assert abs(mean - p["alpha_exact"]) < 4 * err, p
        assert p["alpha_exact"] == pytest.approx(
            2 * tail_exponent(p["dimension"], p["restitution"], p["angular"]).s)


def test_driven_particles_reach_the_exact_steady_state(driven):
    for row in driven.summary["rows"]:
        # variance and kurtosis: mean over 4 runs of N = 2e4 within 4 standard errors (from the
        # run scatter) of D/(pq)(1 - 1/N)² and 3 + 6pq/(2 - pq) (measured |z| <= 0.5)
        assert abs(row["variance_in_sigma"]) < 4 and abs(row["kurtosis_in_sigma"]) < 4
        # density: χ²/dof of the pooled histogram (8e4 samples, binomial errors) on ~33 bins;
        # its spread is √(2/dof) ≈ 0.25, so below 2 (measured 1.12 and 1.01)
        assert row["density_chi2_per_dof"] < 2.0
        # tail slope on |v|/√D in [3, 6]: particles against the exact density on the same
        # window, within 10 % (the fit's statistical error at these counts is ~5 %)
        assert row["tail_slope"] == pytest.approx(row["tail_slope_theory_same_window"], rel=0.1)
        assert row["tail_slope_asymptotic"] == -1 / math.sqrt(driven.summary["parameters"]
                                                             ["driving"])


@pytest.mark.parametrize("name", ["tails", "driven"])
def test_save_load_and_figure(request, tmp_path, name):
    result = request.getfixturevalue(name)
    result.figure()
    result.save(tmp_path / "c.npz")
    again = comparisons.Comparison.load(tmp_path / "c.npz")
    assert again.summary == result.summary
    again.figure()
