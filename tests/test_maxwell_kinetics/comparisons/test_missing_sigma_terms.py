"""The σ terms that three comparisons' checks were missing, each on a synthetic case where the
term matters: the kinetic prediction's numerical error in the χ² of ``kinetic_vs_ulam``, the
seed dependence of the overdispersion φ of ``ulam_collapse`` (runs rescaled by their own
heavy-tailed v0), and the k-dependence of the Hill exponents of ``tail_exponents``."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import statistics as st
from maxwell_kinetics.app.comparisons import _kinetic_vs_ulam, _tail_exponents, _ulam_collapse

EDGES = np.linspace(-3.0, 3.0, 25)


def _gaussian_bins(edges):
    from scipy.stats import norm

    return np.diff(norm.cdf(edges))


def test_prediction_error_enters_the_chi2():
    """Gaussian samples (8 runs of 20 000) against the Gaussian bins with a planted error of 6
    binomial standard errors in four bins: the plain χ²/(dof·φ) is far above 1; with that error
    as the prediction's δ it is back within 4√(2/dof) of 1, and with δ = 0 it is the
    comparison's own χ²/dof / φ."""
    rng = np.random.default_rng(7)
    x = rng.standard_normal((8, 20_000))
    exact = _gaussian_bins(EDGES)
    total = x.size
    planted = np.zeros_like(exact)
    planted[[10, 11, 14, 15]] = 6.0 * np.sqrt(exact[[10, 11, 14, 15]] / total)
    wrong = exact + planted
    cmp = st.compare_histograms(x, EDGES, wrong)
    plain, _ = _kinetic_vs_ulam.chi2_with_prediction_error(cmp, EDGES, wrong, np.zeros_like(wrong))
    assert plain == pytest.approx(cmp.chi2_dof / cmp.overdispersion, rel=1e-12)
    tolerance = 4.0 * np.sqrt(2.0 / cmp.dof)
    assert plain > 1.0 + 2 * tolerance  # the planted error shows without its σ term
    with_error, worst = _kinetic_vs_ulam.chi2_with_prediction_error(cmp, EDGES, wrong, planted)
    assert abs(with_error - 1.0) < tolerance
    assert worst == pytest.approx(6.0, rel=0.05)


def test_verdict_pools_the_chi2_with_the_prediction_error():
    """The verdict reads each row's ``prediction_error``: rows whose plain χ²/(dof·φ) is 3
    (dof 30, φ 1) but 1 with the prediction's error agree; its σ source names the term."""
    row = {"tau": 0.5, "chi2_dof": 3.0, "dof": 30, "overdispersion": [1.0, 0.1],
           "chi2_over_overdispersion": 3.0,
           "prediction_error": {"measured": True, "chi2_over_overdispersion": 1.0,
                                "max_in_sigma": 5.0},
           "smoothed": {"chi2_dof": 1.0, "dof": 30, "overdispersion": [1.0, 0.1]}}
    summary = {"cases": [{"restitution": 0.5, "initial": "asymmetric", "rows": [row] * 4}],
               "n_scan": {"slope": [-0.5, 0.02], "slope_expected": -0.5, "n": [1, 2, 3]},
               "parameters": {"scan_seeds": 8}}
    verdict = _kinetic_vs_ulam.verdicts(summary)[0]
    assert verdict.check.measured == pytest.approx(1.0)
    assert verdict.status == "agrees"
    assert "P(2h)" in verdict.check.sigma_source


def _phi_spread(scale_noise: float, replicas: int = 40, runs: int = 8, m: int = 4000):
    """φ of ``replicas`` independent sets of ``runs`` Gaussian runs, each run multiplied by
    1 + ``scale_noise``·t₃ (a heavy-tailed common scale, like a run's own v0 under an x⁻⁴
    tail): the spread of φ between replicas, the mean independent-bin error and the mean
    jackknife error."""
    rng = np.random.default_rng(11)
    exact = _gaussian_bins(EDGES)
    phis, bins, jack = [], [], []
    for _ in range(replicas):
        scale = 1.0 + scale_noise * np.clip(rng.standard_t(3, size=(runs, 1)), -5, 5)
        x = rng.standard_normal((runs, m)) * scale
        cmp = st.compare_histograms(x, EDGES, exact)
        phis.append(cmp.overdispersion)
        bins.append(cmp.overdispersion_error)
        jack.append(_ulam_collapse.overdispersion_jackknife(x, EDGES, exact))
    return float(np.std(phis, ddof=1)), float(np.mean(bins)), float(np.mean(jack))


def test_phi_jackknife_holds_the_common_scale():
    """Runs rescaled by a heavy-tailed common factor: φ's spread between replicas is several
    times its independent-bin error, and the jackknife over runs measures it (within a factor
    2); without the common factor both errors describe the spread."""
    spread, bins, jack = _phi_spread(0.05)
    assert spread > 3.0 * bins
    assert 0.5 < jack / spread < 2.0
    spread, bins, jack = _phi_spread(0.0)
    assert 0.5 < bins / spread < 2.0 and 0.5 < jack / spread < 2.0


class _BrokenTailRuns:
    """A stand-in particle runner: 2D velocities whose speeds have an exact c⁻⁴ tail above
    c₀ = 3 carrying 2.5 % of the mass (the 2D hard model's exponent at r = 0) and a uniform
    bulk below it, so that Hill's estimator over a top reaching below c₀ is biased."""

    def ulam_final(self, params, tau, seeds, progress=None):
        out = []
        for seed in seeds:
            rng = np.random.default_rng(100 + seed)
            n = params["n"]
            tail = rng.uniform(size=n) < 0.025
            speed = np.where(tail, 3.0 * rng.uniform(size=n) ** (-1.0 / 4.0),
                             3.0 * rng.uniform(size=n))
            angle = rng.uniform(0.0, 2 * np.pi, size=n)
            out.append(np.column_stack([speed * np.cos(angle), speed * np.sin(angle)]))
        return np.array(out)


def test_hill_bias_is_a_stated_systematic():
    """16 runs of 20 000 speeds with the power law above c₀ only (about 500 per run), top 600:
    the mean Hill exponent is biased (high here) by many of its seed σ, so the seed σ alone
    disagrees; the k-dependence |α(top) − α(top/3)| as a systematic σ covers the bias and the
    verdict agrees, its σ source saying so."""
    c = _tail_exponents.run("small", progress=False, runner=_BrokenTailRuns(),
                            particle_cases=((2, "hard", 0.0),), n=20_000, seeds=16, top=600)
    p = c.summary["particles"][0]
    mean, err = p["alpha"]
    assert abs(mean - p["alpha_exact"]) / err > 4.0  # the bias, in seed σ
    assert p["top_systematic"] > 2.0 * err
    assert abs(p["in_sigma"]) < 3.0
    verdict = _tail_exponents.verdicts(c.summary)[1]
    assert verdict.status == "agrees"
    assert "k-dependence" in verdict.check.sigma_source
