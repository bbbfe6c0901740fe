"""The comparisons of ``maxwell-kinetics reproduce`` at the small size, with their quantitative
checks.  Every statistical tolerance is derived from the sample sizes and seeds of the run; the
small-size parameters are in ``maxwell_kinetics.app.comparisons`` (presets ``small``).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from maxwell_kinetics import statistics as st
from maxwell_kinetics.app import comparisons
from maxwell_kinetics.app.comparisons import _kinetic_vs_ulam, analysis
from maxwell_kinetics.exact import f_hat
from particles.validation import InvalidArgumentError

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def kinetic(comparison):
    return comparison("kinetic_theory")


@pytest.fixture(scope="module")
def vs_ulam(comparison):
    return comparison("kinetic_vs_ulam")


@pytest.fixture(scope="module")
def collapse(comparison):
    return comparison("ulam_collapse")


@pytest.fixture(scope="module")
def energy(comparison):
    return comparison("energy_decay")


@pytest.fixture(scope="module")
def structure(comparison):
    return comparison("structure_factors")


def _chi2_tolerance(row) -> float:
    """χ²/(dof φ) is 1 under the null; its relative standard deviation combines √(2/dof) (χ²)
    and φ's own standard error (between-seed variance, see statistics.compare_histograms).
    Tolerance: 4 standard deviations (one-sided false-failure probability ~3e-5 per check)."""
    phi, phi_err = row["overdispersion"]
    return 1.0 + 4.0 * math.sqrt(2.0 / row["dof"] + (phi_err / phi) ** 2)


def test_statistics_exact_bins_of_f():
    """interval_probabilities of f̂ against the exact CDF of f (quadrature, no statistics)."""
    edges = np.linspace(-6, 6, 49)
    got = st.interval_probabilities(f_hat, edges, 200.0)
    assert np.max(np.abs(got - st.f_interval_probabilities(edges))) < 1e-8


def test_contraction_bound_holds(kinetic):
    """d_s(G(τ), f̂) ≤ e^{−γ(s)τ} d_s(G(0), f̂) (rigorous); 1e-9 relative slack for round-off.
    Checked where the bound is above the solver's floor, which must include τ ≥ 100.  τ = 0,
    where the ratio is 1 by construction, is not in the maximum: measured 0.950, 0.975, 0.993
    for s = 2.2, 2.5, 2.8 (all at τ = 1), so a maximum of 1 would mean τ = 0 crept back."""
    for s, ratio in kinetic.summary["max_distance_over_bound"].items():
        assert ratio <= 1.0 + 1e-9, s
        assert ratio < 0.999, s
        assert kinetic.summary["bound_checked_up_to_tau"][s] >= 100.0, s


def test_contraction_check_with_nothing_to_check_reports_none():
    """With only τ = 0 saved (an override) no bound can be checked: None, not a crash."""
    c = comparisons.kinetic_theory("small", tau=(0.0,))
    assert set(c.summary["max_distance_over_bound"].values()) == {None}
    assert set(c.summary["bound_checked_up_to_tau"].values()) == {None}


def test_moment_multiscaling(kinetic):
    """ln(M_n/M_2^{n/2}) grows at n a_2/2 − a_n: the slope fitted on the second half of the
    τ range carries the subleading exponentials, measured 0.35 % for n = 4 at τ ≤ 100."""
    for n, g in kinetic.summary["moment_growth_rates"].items():
        assert g["fitted"] == pytest.approx(g["predicted"], rel=0.01), n


def test_tail_develops(kinetic):
    """At the last τ the fitted tail slope on [5, 15] approaches the one of f on the same window
    (−3.94); at τ = 0 (Gaussian) there is no power-law tail to fit at all."""
    s = kinetic.summary
    assert abs(s["tail_slope"][-1] - s["tail_slope_of_f"]) < 0.05
    assert s["tail_slope"][0] is None or s["tail_slope"][0] < -8


def test_kinetic_matches_ulam_within_statistics(vs_ulam):
    """Raw and smoothed (σ = 0.15, see comparisons.kinetic_vs_ulam) histograms of the Ulam
    particles against the solver's prediction at the same τ, each row within the tolerance."""
    for case in vs_ulam.summary["cases"]:
        for row in case["rows"]:
            assert row["chi2_over_overdispersion"] < _chi2_tolerance(row), (case["initial"], row)
            smoothed = row["smoothed"]
            assert smoothed["chi2_over_overdispersion"] < _chi2_tolerance(smoothed), (
                case["initial"], row["tau"], smoothed)


def test_smoothed_comparison_detects_a_wrong_law(vs_ulam):
    """The smoothed comparison has teeth: the particles at τ = 0.5 against the solver's law at
    a later τ (r = 0.5, bimodal: the humps have moved) are far outside the tolerance."""
    sol = comparisons.kinetic_solution(0.5, "bimodal", vs_ulam.summary["parameters"]["tau"],
                               "fine")
    edges = analysis.bin_edges(vs_ulam.summary["parameters"]["edges"])
    snapshots = comparisons.ulam_snapshots(0.5, "bimodal", 20_000, [0.5], list(range(6)))
    x = analysis.rescaled(snapshots[0])
    wrong = _kinetic_vs_ulam._smoothed_comparison(sol, 1, x, edges, 0.15, seed=0).summary()
    assert wrong["chi2_over_overdispersion"] > 10 * _chi2_tolerance(wrong)


def test_kinetic_vs_ulam_distance_falls_like_inverse_sqrt_n(vs_ulam):
    """Slope of ln D_KS against ln N; its standard error comes from the seed scatter of each
    point (8 seeds per N at the small size).  3 standard errors."""
    slope, err = vs_ulam.summary["n_scan"]["slope"]
    assert abs(slope + 0.5) < 3 * err
    assert err < 0.1  # the check has teeth: a slope of 0 (no convergence) would fail


def test_ulam_collapse_within_statistical_error(collapse):
    """Shape of P(v, τ) (median-rescaled) against f within the statistical error, each r."""
    for row in collapse.summary["rows"]:
        shape = row["median_scaled"]
        assert shape["chi2_over_overdispersion"] < _chi2_tolerance(shape), row["restitution"]


def test_ulam_collapse_phi_error_holds_the_jackknife(collapse):
    """φ's error in the summary is the larger of the independent-bin one and the jackknife over
    seeds (both recorded: the run's own rescaling moves all bins together); the verdicts' σ is
    the larger of the scatter of the same statistic over the null's replicas of exact samples
    and its jackknife over the run's seeds, and their σ source says so."""
    for row in collapse.summary["rows"]:
        for key in ("v0_scaled", "median_scaled", "v0_scaled_vs_kinetic"):
            entry = row[key]
            larger = max(entry["overdispersion_error_jackknife"],
                         entry["overdispersion_error_bins"])
            assert entry["overdispersion"][1] == pytest.approx(larger), (row["restitution"], key)
    null = collapse.summary["iid_null"]
    verdicts = comparisons.VERDICTS["ulam_collapse"](collapse.summary)
    assert len(verdicts) == 2 * len(collapse.summary["rows"])
    for verdict in verdicts:
        assert f"{null['replicas']} replicas" in verdict.check.sigma_source
        kind = "median_scaled" if "median" in verdict.check.quantity else "v0_scaled"
        row = collapse.summary["rows"][verdicts.index(verdict) // 2]
        entry = row["median_scaled" if kind == "median_scaled" else "v0_scaled"]
        assert verdict.check.sigma == max(null[kind][1],
                                          entry["chi2_over_overdispersion_jackknife"])


def test_lattice_energy_exponents(energy):
    """Lattice, N = 2·10⁴, 4 seeds, τ ≤ 400 (small preset), r = 0.5.

    Initial rate on τ ∈ [0, 0.25]: measured −0.3758 ± 0.0027 against the exact −0.375 (0.3σ).

    Late exponent on τ ∈ [40, 400]: measured −0.4774 ± 0.0086 (seeds 0.0079, window drift
    0.0034), 2.64σ from −1/2 under a 3σ limit.  The gap is systematic, not noise: the local
    exponent of these runs is −0.501 on τ ∈ [10, 40], −0.474 on [40, 126], −0.481 on
    [126, 400] (and −0.489 on [400, 2000] with the same seeds run longer): the window sits in
    a pre-asymptotic dip, which the half-window drift term does not capture.  With 8 seeds
    instead of 4 the fit on [40, 400] gave −0.481 ± 0.006, 3.2σ: more seeds would make this
    check fail, not pass better, and a later window needs longer runs than the small preset's
    (whose run parameters are fixed).  So what it can tell at this size: −1/2 from −2/3 (22σ
    apart), and from the initial exponential; it cannot resolve a deviation of ≈ 5 % from −1/2.
    """
    s = energy.summary
    early = s["lattice_initial_rate"]
    assert abs(early["deviation_in_sigma"]) < 3
    late = s["lattice_late_exponent"]
    assert abs(late["deviation_in_sigma"]) < 3
    # What the check resolves: the MD exponent −2/3 is far outside the lattice's uncertainty.
    assert abs(late["slope"][0] + 2.0 / 3.0) > 10 * late["uncertainty"]


def test_md_late_exponent(energy):
    """MD, N = 1000, 3 seeds, t ≤ 40 (small preset), fit on t ∈ [12, 40]: measured
    −0.647 ± 0.099 (seeds 0.074, window drift 0.066).  The per-run slopes scatter by ≈ 0.12, so
    three runs give σ ≈ 0.1, and −2/3 and −1/2 (0.17 apart) are 1.7σ apart: this sample does not
    resolve the exponent, and the runs that do (≈ 20 seeds, ~2–5 min) are beyond this suite's
    budget.  The exponent is therefore checked by ``benchmarks/md_late_exponent.py``, the same
    runs and fit with 24 seeds: −0.685 ± 0.025, 0.7σ from −2/3 and 7.4σ from −1/2
    (benchmarks/README.md).  What this sample does tell, asserted here: the slope agrees with
    −2/3 within 3σ, its uncertainty is below 0.2, the decay has left Haff's t⁻² (−2 is 13.6σ
    away) and has not stopped (0 is 6.5σ away), the last two at 5σ."""
    late = energy.summary["md_late_exponent"]
    assert abs(late["deviation_in_sigma"]) < 3
    assert late["uncertainty"] < 0.2
    slope, err = late["slope"][0], late["uncertainty"]
    assert abs(slope + 2.0) > 5 * err
    assert abs(slope) > 5 * err


def test_md_fits_use_the_preset_windows(energy):
    """The MD Haff fit and late fit are made on the windows of the preset, on every recorded
    time inside them and no other: the summary's windows are the preset's, and the per-run
    slopes recomputed here from the recorded energies on those windows are the reported ones."""
    s, d = energy.summary, energy.data
    params = comparisons.PRESETS["energy_decay"]["small"]
    t, e, t0 = d["md_t"], d["md_energy"], d["t0"]
    for key, window, abscissa in (("md_haff_exponent", "md_haff_window",
                                   lambda c: np.log1p(c / t0)),
                                  ("md_late_exponent", "md_late_window", np.log)):
        lo, hi = params[window]
        fit = s[key]
        assert fit["window"] == [lo, hi], key
        inside = (t >= lo) & (t <= hi)
        assert fit["fit_points"] == inside.sum() >= 3, key
        assert fit["fit_range"] == [t[inside][0], t[inside][-1]], key
        slopes = [np.polyfit(abscissa(t[inside]), np.log(run[inside]), 1)[0] for run in e]
        assert np.allclose(fit["per_run"], slopes, rtol=1e-12, atol=0), key
        assert fit["slope"][0] == pytest.approx(np.mean(slopes), rel=1e-12), key


def test_structure_factor_collapse(structure):
    """The theory's rescaling k τ^{1/2} (lattice) and k t^{2/3} (MD) brings the curves of different
    times together: the spread of ln S at the theory's z is below the unscaled spread."""
    for lab in ("lattice", "md"):
        s = structure.summary[lab]
        assert s["collapse_spread_at_z_theory"][0] < 0.5 * s["collapse_spread_unscaled"][0], lab


def test_structure_numbers_carry_uncertainties(structure):
    """Every number of the seed-mean S(k) comes with a jackknife error over the seeds, and
    z_best is not a grid point with a zero error.  Measured at this size (4 lattice seeds):
    lattice z_best 0.5016 ± 0.0008 (the 0.01 grid alone gave 0.50 ± 0.0: all replicas on one
    grid point); without the constraint the spread still falls at z = 1, the end of the scan,
    so z_best is reported as at the edge with no error.  |z_best − 1/2| < 0.01 for the lattice:
    a wrong rescaling (z = 2/3, or none) would fail it."""
    lat = structure.summary["lattice"]
    z, err = lat["z_best"]
    assert not lat["z_best_at_scan_edge"]
    assert err is not None and 0.0 < err < 0.01
    assert abs(z - 0.5) < 0.01
    free = structure.summary["lattice_no_constraint"]
    assert free["z_best_at_scan_edge"] and free["z_best"][1] is None
    for lab in ("lattice", "lattice_no_constraint", "md"):
        s = structure.summary[lab]
        for key in ("collapse_spread_at_z_theory", "collapse_spread_unscaled"):
            value, err = s[key]
            assert err is not None and 0.0 < err < 0.2 * value, (lab, key)
        value, err = s["porod_slope_per_time"][-1]
        assert err is not None and err > 0.0, lab


def test_jackknife_needs_three_replicas():
    assert analysis.jackknife([1.0, 2.0]) is None
    assert analysis.jackknife([1.0, None, 2.0]) is None
    # Leave-one-out means of (1, 2, 3, 4): the jackknife error equals the standard error.
    loo = [np.mean(np.delete([1.0, 2.0, 3.0, 4.0], i)) for i in range(4)]
    assert analysis.jackknife(loo) == pytest.approx(np.std([1, 2, 3, 4], ddof=1) / 2)


def test_no_porod_tail_without_constraint(structure):
    """Without the kinematic constraint the slope on the Porod window is far from −2 (more than
    5 seed standard errors)."""
    slope, err = structure.summary["lattice_no_constraint"]["porod_slope_last_time"]
    assert abs(slope + 2.0) > 5 * err


def test_porod_slope_with_constraint(structure):
    """Porod k⁻² with the constraint: per-seed slopes at τ = 2000 on k τ^{1/2} ∈ [8, 30],
    k ≤ 0.5 (the window's reasons are in :func:`comparisons.structure_factors`), within 3 seed
    standard errors (4 seeds; the error measured on 8 other seeds was 0.023)."""
    slope, err = structure.summary["lattice"]["porod_slope_last_time"]
    assert abs(slope + 2.0) < 3 * err


def test_reproduce_cli_small(tmp_path, capsys):
    from maxwell_kinetics.app.cli import main

    out = tmp_path / "res"
    assert main(["reproduce", "--small", "--only", "kinetic_theory", "--out", str(out),
                 "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["comparisons"] == ["kinetic_theory"]
    summary = json.loads((out / "summary.json").read_text())
    assert "max_distance_over_bound" in summary["comparisons"]["kinetic_theory"]
    assert (out / "kinetic_theory.png").stat().st_size > 0
    again = comparisons.Comparison.load(out / "kinetic_theory.npz")
    assert again.name == "kinetic_theory"
    assert again.summary["sup_error"] == summary["comparisons"]["kinetic_theory"]["sup_error"]


def _assert_same(a, b, where="data"):
    """Deep equality of what Comparison.save wrote and load returned (types included)."""
    from maxwell_kinetics.solver import Solution

    assert type(a) is type(b), where
    if isinstance(a, dict):
        assert list(a) == list(b), where
        for k in a:
            _assert_same(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _assert_same(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=True), where
    elif isinstance(a, st.HistogramComparison):
        _assert_same(vars(a), vars(b), where)
    elif isinstance(a, Solution):
        assert np.array_equal(a.G, b.G) and np.array_equal(a.tau, b.tau), where
        assert a.resolution == b.resolution and a.restitution == b.restitution, where
    elif isinstance(a, float) and math.isnan(a):
        assert math.isnan(b), where
    else:
        assert a == b, where


@pytest.mark.parametrize("name", ["kinetic", "vs_ulam", "collapse", "energy", "structure",
                                  "distributions"])
def test_comparison_save_load_round_trip(name, request, tmp_path):
    """Every comparison's summary and figure data come back from its .npz unchanged (arrays bit
    for bit, tuples as tuples, float keys as floats, solutions and histogram records rebuilt),
    and the figure can be drawn again from the loaded data."""
    import matplotlib.pyplot as plt

    result = request.getfixturevalue(name)
    result.save(tmp_path / "c.npz")
    again = comparisons.Comparison.load(tmp_path / "c.npz")
    assert again.name == result.name
    _assert_same(result.summary, again.summary, "summary")
    _assert_same(result.data, again.data)
    plt.close(again.figure())


def test_comparison_load_rejects_other_files(tmp_path):
    bad = tmp_path / "bad.npz"
    np.savez(bad, x=np.arange(3))
    with pytest.raises(InvalidArgumentError, match="path"):
        comparisons.Comparison.load(bad)
    other = tmp_path / "other.npz"
    np.savez(other, __skeleton__=np.array('{"format": "something else/9"}'))
    with pytest.raises(InvalidArgumentError, match="something else"):
        comparisons.Comparison.load(other)
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(InvalidArgumentError, match="junk.npz"):
        comparisons.Comparison.load(tmp_path / "junk.npz")


def test_reproduce_cli_bad_only(tmp_path, capsys):
    from maxwell_kinetics.app.cli import main

    assert main(["reproduce", "--only", "nope", "--out", str(tmp_path / "x")]) == 2
    assert "only" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


@pytest.fixture(scope="module")
def distributions(comparison):
    return comparison("velocity_distributions")


def _sigma(m, a, b, q):
    """Difference of the shape number ``q`` of models a and b over their combined standard
    error (each from the scatter between seeds, 4 seeds at the small size)."""
    (va, ea), (vb, eb) = m[a][q], m[b][q]
    return (va - vb) / math.hypot(ea, eb)


def test_md_two_hump_precursor_in_homogeneous_cooling(distributions):
    """Early stage (t = 400, r = 0.99, E within 20 % of Haff's law: homogeneous): the MD
    distribution is platykurtic (two humps): ⟨x⁴⟩ below the Gaussian 3 by more than 4 standard
    errors (seed scatter)."""
    early = distributions.summary["stages"]["early"]
    assert abs(early["info"]["energy_over_haff"] - 1.0) < 0.2
    k, err = early["models"]["md"]["kurtosis"]
    assert 3.0 - k > 4 * err


def test_ulam_prediction_fails_at_equal_energy(distributions):
    """⟨|x|⟩ (bounded, finite for f) of MD and of the lattice differ from the Ulam model's at the
    same energy by more than 4 combined standard errors: early for both, late for MD.  The late
    lattice is not asserted at this size: at N = 2000 and τ ≈ 600–5·10⁴ a run holds only a few
    correlated domains, and its seed scatter (measured ±0.02 in ⟨|x|⟩, against ±0.004 at
    N = 2·10⁴) does not resolve the difference (2.5σ measured)."""
    early = distributions.summary["stages"]["early"]["models"]
    for name in ("md", "lattice_r0.99"):
        assert abs(_sigma(early, name, "ulam", "abs_mean")) > 4, name
    late = distributions.summary["stages"]["late"]["models"]
    assert abs(_sigma(late, "md", "ulam", "abs_mean")) > 4


def test_md_and_the_rate_proportional_lattice_agree_early(distributions):
    # Paper Fig. 1a: "the lattice reproduces MD's two humps" holds for the lattice whose bonds
    # collide at a rate ∝ |Δ| (as MD pairs do): ⟨x⁴⟩ within 4 combined standard errors of MD
    # (4 seeds each; measured at this size 1.7σ, at N = 2·10⁴ and 6 seeds 1.957 ± 0.004 against
    # 1.973 ± 0.007, benchmarks/fig1a.py), and both have two humps (⟨x⁴⟩ < 2.2, Gaussian 3).
    m = distributions.summary["stages"]["early"]["models"]
    assert abs(_sigma(m, "md", "lattice_rv_r0.99", "kurtosis")) < 4
    assert m["md"]["kurtosis"][0] < 2.2 and m["lattice_rv_r0.99"]["kurtosis"][0] < 2.2


def test_the_constant_rate_lattice_misses_the_two_humps(distributions):
    # ... while the paper's lattice (constant rate per bond) is nearly Gaussian at that energy:
    # more than 10 standard errors from MD (measured 32.6σ here; 2.95 against 1.96 at the full
    # size).  This replaces the strict xfail that recorded the disagreement.
    m = distributions.summary["stages"]["early"]["models"]
    assert _sigma(m, "md", "lattice_r0.99", "kurtosis") < -10
    assert m["lattice_r0.99"]["kurtosis"][0] > 2.6


def test_velocity_profiles_report_increment_skewness(tmp_path, comparison):
    """Comparison 7 runs and reports the increment skewness of the three profiles with seed
    errors, raw and coarse-grained on the scales of ``profile_scales`` (the paper's sign test is
    ``test_md_shock_asymmetry_in_the_coarse_grained_profiles``, at N = 2·10⁴: at this size there
    are too few clusters).  Its result survives save/load."""
    res = comparison("velocity_profiles")  # the session's run (the legend test draws it too)
    for key in ("md_vx", "md_vi", "lattice_vi", "lattice_rv_vi"):
        value, err = res.summary["increment_skewness"][key]["skewness"]
        assert math.isfinite(value) and err > 0
        coarse = res.summary["coarse_skewness"][key]
        assert coarse["scales"] == [1, 4, 16]
        assert coarse["skewness"][0] == [value, err]
        assert all(math.isfinite(v) and e > 0 for v, e in coarse["skewness"])
    res.figure()
    res.save(tmp_path / "p.npz")
    again = comparisons.Comparison.load(tmp_path / "p.npz")
    _assert_same(res.summary, again.summary, "summary")
    _assert_same(res.data, again.data)


def test_coarse_increment_skewness_of_a_sawtooth():
    """A sawtooth that rises over 95 samples and drops over 5 has two increment values, the
    drop with probability p = 0.05: skewness −(1 − 2p)/√(p(1 − p)) = −4.1295 exactly.  Mirrored
    (−v) the sign flips.  White noise of the sawtooth's amplitude hides it in the raw increments
    and block means over 20 samples bring it back.  Over 200 other noise seeds (1000-1199): raw
    γ₁ = −0.0002 (sd 0.0072, largest |γ₁| 0.022; bound 0.05, 7 sd), m = 20 −0.638 (sd 0.026,
    largest −0.550; bound −0.4, 9 sd)."""
    saw = np.concatenate([np.linspace(0, 1, 95, endpoint=False),
                          np.linspace(1, 0, 5, endpoint=False)])
    v = np.tile(saw, 1000)
    p = 0.05
    exact = -(1 - 2 * p) / math.sqrt(p * (1 - p))
    assert comparisons.coarse_increment_skewness(v, 1) == pytest.approx(exact, rel=1e-9)
    assert comparisons.coarse_increment_skewness(-v, 1) == pytest.approx(-exact, rel=1e-9)
    for m in (5, 20):  # the mirror identity holds at every scale, and so does the sign
        assert comparisons.coarse_increment_skewness(-v, m) == pytest.approx(
            -comparisons.coarse_increment_skewness(v, m), rel=1e-12)
        assert comparisons.coarse_increment_skewness(v, m) < 0
    noisy = v + np.random.default_rng(0).normal(0.0, 1.0, v.size)
    assert abs(comparisons.coarse_increment_skewness(noisy, 1)) < 0.05
    assert comparisons.coarse_increment_skewness(noisy, 20) < -0.4


def test_coarse_increment_skewness_matches_a_plain_loop_and_rejects_bad_input():
    rng = np.random.default_rng(3)
    v = rng.exponential(size=1003)
    for m in (1, 3, 7, 100):
        means = [sum(v[b * m:(b + 1) * m]) / m for b in range(len(v) // m)]
        inc = [means[(b + 1) % len(means)] - means[b] for b in range(len(means))]
        mu = sum(inc) / len(inc)
        m2 = sum((d - mu) ** 2 for d in inc) / len(inc)
        m3 = sum((d - mu) ** 3 for d in inc) / len(inc)
        assert comparisons.coarse_increment_skewness(v, m) == pytest.approx(m3 / m2**1.5, rel=1e-10)
    for bad in (0, -2, 1.5, True, 400):
        with pytest.raises(ValueError, match="scale"):
            comparisons.coarse_increment_skewness(v, bad)
    with pytest.raises(ValueError, match="profile"):
        comparisons.coarse_increment_skewness(v.reshape(17, 59), 2)
    assert comparisons.profile_scales(2000) == (1, 4, 16)
    assert comparisons.profile_scales(20_000) == (1, 4, 16, 64, 256)


def test_md_shock_asymmetry_in_the_coarse_grained_profiles():
    """Paper Fig. 4: v(x, t) of the MD has large negative gradients (shocks), v(i, t) large
    positive ones.  At the default preset (r = 0.99, δ = 1e-4, N = 2·10⁴, t = 3000, seeds 0-3)
    the sign asymmetry is asserted on the coarse-grained profiles (m = 256 labels or L/N), and
    the raw increments are asserted to hide it.  Tolerances from 24 other seeds (100-123) at
    the same parameters: m = 256, v(i) +0.488 (sd 0.229, all 24 > 0), v(x) −0.770 (sd 0.347,
    all 24 < 0): the 4-seed means sit 4.2 and 4.4 standard errors from zero; raw −0.011 (sd
    0.007) and −0.019 (sd 0.017), far inside the bound 0.1.  The test can fail: at t = 400, in
    the homogeneous stage, the same seeds give m = 256 means of +0.15 (v(i)) and +0.12 (v(x))."""
    params = comparisons.PRESETS["velocity_profiles"]["default"]
    md = comparisons.md_runs(params["restitution"], params["md_n"], params["delta"],
                     (params["md_t_early"], params["md_t_late"]), tuple(range(params["md_seeds"])))
    vi, vx = [], []
    for x, v in zip(md["positions"][:, 1], md["snapshots"][:, 1], strict=True):
        g = comparisons.velocity_on_grid(x, v, float(params["md_n"]))  # density 1: L = N
        vi.append([comparisons.coarse_increment_skewness(v, m) for m in (1, 256)])
        vx.append([comparisons.coarse_increment_skewness(g, m) for m in (1, 256)])
    vi, vx = np.mean(vi, axis=0), np.mean(vx, axis=0)
    assert abs(vi[0]) < 0.1 and abs(vx[0]) < 0.1
    assert vi[1] > 0 > vx[1], (vi, vx)


def test_velocity_profiles_preset():
    """Fig. 4 at the paper's size at ``--full`` (the paper's: r = 0.99, N = 2·10⁴ for MD and the
    lattice), with more seeds than the default; at small and default size the run parameters
    equal comparison 4's, so that one process shares the MD and lattice runs of the two."""
    full = comparisons.PRESETS["velocity_profiles"]["full"]
    assert full["restitution"] == 0.99
    assert full["md_n"] == full["lattice_n"] == 20_000
    default = comparisons.PRESETS["velocity_profiles"]["default"]
    assert full["md_seeds"] > default["md_seeds"]
    assert full["lattice_seeds"] > default["lattice_seeds"]
    for size in ("small", "default"):
        for key, value in comparisons.PRESETS["velocity_profiles"][size].items():
            assert comparisons.PRESETS["velocity_distributions"][size][key] == value, (size, key)


def test_fft_density_agrees_with_quadrature_bins(vs_ulam):
    """The figure's kinetic curve (the solver's inverse-FFT density) integrated over each bin
    against the quadrature bin probabilities used for χ².  They differ by the cut at q_max of
    the never-collided part's jump (asymmetric law; computed by comparisons.never_collided_cut),
    by the quadrature's taking that part out of G on the solver's nodes (the FFT interpolates
    it: within the quadrature's own numerical-error estimate, bin by bin) and by integration
    error.  Measured at this size on the comparison's grid (q ≤ 1000), after removing the cut:
    8.4e-5, 1.8e-5, 5.8e-8 (asymmetric, τ = 0.5, 2, 8; the largest error estimates 2.2e-4,
    7.4e-5, 1.1e-7) and ≤ 6.7e-14 (bimodal); the raw difference where the jump's weight is
    small (bimodal law, or e^{−τ} ≤ 1e-3).  Tolerance 5e-6 beyond the estimate: 6x below the
    smallest standard error of a bin with probability > 1e-3 at this size (3.0e-5), so a
    difference within it would not show in the χ²."""
    for case in vs_ulam.summary["cases"]:
        for row in case["rows"]:
            fft = row["fft_vs_quadrature"]
            assert fft["max_cut_removed_beyond_numerical_error"] < 5e-6, (
                case["initial"], row["tau"], fft)
            if case["initial"] != "asymmetric":  # smooth: nothing for the estimate to cover
                assert fft["max_abs_cut_removed"] < 5e-6, (case["initial"], row["tau"], fft)
            if case["initial"] != "asymmetric" or math.exp(-row["tau"]) <= 1e-3:
                assert fft["max_abs"] < 5e-6, (case["initial"], row["tau"], fft)
    # The check is not empty: at τ = 0.5 the jump's cut shows in the raw FFT density (8.4e-6
    # with the grid ending at q ≈ 1000; 4.5e-4 when it ended at q ≈ 35).
    asym = next(c for c in vs_ulam.summary["cases"] if c["initial"] == "asymmetric")
    assert asym["rows"][0]["fft_vs_quadrature"]["never_collided_cut_max_abs"] > 2e-6
