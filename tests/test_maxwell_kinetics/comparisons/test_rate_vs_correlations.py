"""Comparison 12 (rate_vs_correlations) at the small size, its exact pieces, and the hard-rod
Boltzmann equation solved deterministically against its DSMC (the Ulam engine with the rate
|v − w|)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from maxwell_kinetics.app.comparisons import (
    Comparison,
    collisions_per_particle,
    kurtosis_split,
    maxwell_kurtosis,
)
from maxwell_kinetics.app.comparisons.verdicts import STATUSES
from maxwell_kinetics.inelastic_boltzmann import solve_boltzmann
from maxwell_kinetics.velocity_grid import VelocityGrid
from particles.driver import simulate
from particles.observables import rescaled_histogram
from particles.ulam import Ulam

#: The grid of the small comparison (one compiled solver serves both).
GRID = VelocityGrid(101, 6.0)
VERDICT_KEYS = {"claim", "quantity", "measured", "sigma", "expected", "source", "tolerance",
                "status", "why", "explanation"}


@pytest.fixture(scope="module")
def split(comparison):
    return comparison("rate_vs_correlations")


def test_maxwell_kurtosis_is_the_closed_form_at_r_one_half():
    # r = 1/2 from the unit Gaussian: K(τ) = −3 + 6 e^{9τ/128} (exact)
    tau = np.array([0.0, 10.0, 50.0])
    np.testing.assert_allclose(maxwell_kurtosis(0.5, tau), -3 + 6 * np.exp(9 * tau / 128),
                               rtol=1e-9)


def test_kurtosis_split_share_error_is_the_derivative():
    """The share C/(R + C) moves with MD's kurtosis (C = K_MD − K_B) at the rate R/(R + C)²:
    the stated error is that rate times σ (a central difference of the share)."""
    k_b, k_m, k_md, err = 1.86, 3.05, 1.95, 0.01
    out = kurtosis_split([k_md], [err], [k_b], [k_m])
    h = 1e-6
    plus = kurtosis_split([k_md + h], [err], [k_b], [k_m])["correlation_share"][0]
    minus = kurtosis_split([k_md - h], [err], [k_b], [k_m])["correlation_share"][0]
    assert out["correlation_share_error"][0] == pytest.approx(err * abs(plus - minus) / (2 * h),
                                                              rel=1e-6)
    assert out["rate"][0] + out["correlation"][0] == pytest.approx(k_md - k_m)


def test_collisions_per_particle_need_the_solution_from_t_zero():
    late = SimpleNamespace(t=np.array([1.0, 2.0]))
    with pytest.raises(ValueError, match="t = 0"):
        collisions_per_particle(late)


def test_collisions_per_particle_start_at_the_gaussian_rate(split):
    """τ(t) of the hard-rod solution: dτ/dt = n⟨|v − w|⟩ = 2n/√π for the unit Gaussian at
    t = 0.  Over the first saved step Δt the rate falls by less than (1 − r²)Δt relative
    (d ln⟨|v − w|⟩/dt = ½ d ln T/dt ≥ −(1 − r²)/√π·√T for a near-Gaussian law, T ≤ 1)."""
    for case in split.data["cases"]:
        t, tau, r = case["dense_t"], case["tau"], case["restitution"]
        mean_rate = tau[1] / t[1]
        assert mean_rate <= 2 / math.sqrt(math.pi) * (1 + 1e-9)
        assert mean_rate >= 2 / math.sqrt(math.pi) * (1 - (1 - r * r) * t[1])
        assert np.all(np.diff(tau) > 0)


def test_collision_numbers_agree_with_the_dsmc_and_md(split):
    """The DSMC collides as the equation says: its collisions per particle (mean of 4 runs of
    N = 5000) within 4 standard errors of τ(t), plus the trapezoid error of τ(t) (≤ 1e-3
    relative on the small preset's 101 times); MD, which obeys the equation only while
    correlations are weak, within 2 % at r = 0.99 up to t = 400 (measured ≤ 0.3 %)."""
    for case in split.data["cases"]:
        rec, at = case["models"]["dsmc"], case["at"]
        tau = case["tau"][at]
        runs = rec["per_run_collisions_per_particle"]
        mean, sem = runs.mean(axis=0), runs.std(axis=0, ddof=1) / math.sqrt(runs.shape[0])
        assert np.all(np.abs(mean - tau) <= 4 * sem + 1e-3 * tau), (mean, tau, sem)
    quasi = split.data["cases"][0]
    md_tau = quasi["models"]["md"]["collisions_per_particle"]
    np.testing.assert_allclose(md_tau, quasi["tau"][quasi["at"]], rtol=0.02)


def test_summary_carries_verdicts_judged_from_its_numbers(split):
    verdicts = split.summary["verdicts"]
    assert verdicts and all(VERDICT_KEYS <= set(v) for v in verdicts)
    assert all(v["status"] in STATUSES for v in verdicts)
    # the kinetic checks: DSMC against the deterministic solution and the Ulam particles against
    # the exact Maxwell kurtosis, at every time of both r, within 3 sampling errors (delta
    # method over 4 runs of N = 5000 independent particles)
    checks = [v for v in verdicts if "agrees with" in v["claim"]]
    assert len(checks) == 4 and all(v["status"] == "agrees" for v in checks), checks
    # the paper's attribution: judged from the split's shares, whatever its status
    (paper,) = [v for v in verdicts if "due to correlations" in v["claim"]]
    share = split.summary["cases"][0]["rows"][-1]["split"]["correlation_share"][0]
    assert paper["measured"] == share and paper["explanation"] is None
    # its refutation is the DSMC's own estimate of the share, against the split's
    assert paper["refutation"]["expected"] == share
    # a claim this size resolves: every verdict of this comparison agrees or refutes the paper
    assert all(v["status"] in ("agrees", "refuted") for v in verdicts), verdicts
    for case in split.summary["cases"]:
        assert case["rows"][0]["t"] > 0
        for row in case["rows"]:
            s = row["split"]
            assert s["total"][0] == pytest.approx(row["kurtosis"]["md"][0]
                                                  - row["kurtosis"]["maxwell_exact"])


def test_save_load_and_figure(split, tmp_path):
    path = tmp_path / "rate_vs_correlations.npz"
    split.save(path)
    back = Comparison.load(path)
    assert back.summary["verdicts"] == split.summary["verdicts"]
    fig = back.figure()
    assert len(fig.axes) == 4


def test_deterministic_hard_rods_agree_with_their_dsmc():
    """r = 0.9, t = 10, N = 10⁵, 4 seeds: the DSMC kurtosis (mean over seeds) within 3 of its
    standard errors (from the seed scatter) of the deterministic one, and the pooled histogram of
    x = (v − ⟨v⟩)/√var (4·10⁵ samples, binomial errors) against the solution's bin probabilities:
    χ²/dof within 1 ± 5√(2/dof), the spread of χ²/dof for independent samples of one law."""
    det = solve_boltzmann(0.9, [0.0, 10.0], grid=GRID)
    engine = Ulam(100_000, 0.9, rate="relative_velocity", density=1.0)
    runs = [simulate(engine, [10.0], seed, progress=False, snapshots=True).snapshots[0]
            for seed in range(4)]
    x = np.array([v - v.mean() for v in runs])
    k = np.mean(x**4, axis=1) / np.mean(x**2, axis=1) ** 2
    sem = k.std(ddof=1) / 2.0
    assert abs(k.mean() - det.kurtosis[-1]) <= 3 * sem, (k, det.kurtosis[-1])
    edges = np.round(np.arange(-4.0, 4.0 + 1e-9, 0.2), 12)
    d = rescaled_histogram(x, edges).distance(det.histogram(edges, t=10.0))
    assert abs(d.chi2_dof - 1) <= 5 * math.sqrt(2 / d.dof), d
