"""Comparisons 8 (sticky_vs_md) and 9 (late_stage) at the small size, and direct checks of the
exact sticky gas at N = 10⁶."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.stats import chi2 as chi2_dist

from maxwell_kinetics.app.comparisons import Comparison
from maxwell_kinetics.app.comparisons.analysis import mass_density, paired_numbers
from particles.sticky import StickyGas, StickyParams
from particles.sticky_observables import cluster_mass_distribution

# Student t with 2 degrees of freedom (3 seeds): |t| > 5 has two-sided probability 0.038, so
# "within 5 standard errors over 3 seeds" is a ~96 % statement, not a 3σ Gaussian one.
T_3_SEEDS = 5.0


@pytest.fixture(scope="module")
def paired(comparison):
    # ~25 s: MD N = 1000 to t = 40, 3 seeds; the session's run (the legend test draws it too)
    return comparison("sticky_vs_md")


@pytest.fixture(scope="module")
def late(comparison):
    # ~7 s: sticky gas N = 10⁵, 3 seeds, 9 times, and N = 2·10⁶, 4 seeds, 5 times; shared with
    # the notebook test through the session's ``comparison`` fixture
    return comparison("late_stage")


def _assert_same(a, b):
    if isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b)
    elif isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            _assert_same(a[k], b[k])
    elif isinstance(a, (list, tuple)):
        assert type(a) is type(b) and len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _assert_same(x, y)
    else:
        assert a == b or (isinstance(a, float) and math.isnan(a) and math.isnan(b))


# --------------------------------------------------------------------- comparison 8


def test_paired_numbers_against_a_hand_computed_case():
    e_md = np.array([[1.0, 2.0], [3.0, 4.0]])
    e_st = np.array([[2.0, 2.0], [3.0, 8.0]])
    p, u = paired_numbers(e_md, e_st)
    np.testing.assert_allclose(p, [[-0.5, 0.0], [0.0, -0.5]])
    np.testing.assert_allclose(u, [[1 / 3 - 1, 2 / 8 - 1], [3 / 2 - 1, 4 / 2 - 1]])


def test_paired_md_and_sticky_agree_better_than_independent_seeds(paired):
    p = paired.summary["paired"]
    # Independent initial states of N = 1000 differ by the seed-to-seed scatter of E t^{2/3}
    # (measured here: 16-27 % relative std over 3 seeds; with an independent code: 3.8 % at
    # N = 2·10⁴, i.e. ~17 % at N = 1000 by 1/√N), while paired runs share it (0.4-2 % at
    # N = 2·10⁴ with that code).
    # The unpaired rms comes from 6 seed pairs × 8 times; its relative uncertainty is ~40 %
    # (3 independent seeds), so a factor 3 below it is a margin the estimate cannot erase.
    assert p["paired_rms"] < p["unpaired_rms_window"] / 3.0
    assert p["paired_rms"] < float(np.mean(p["seed_relative_std"]))
    # The mean paired difference over the window is zero within its error: no bias between
    # MD (δ = 10⁻⁴) and the sticky gas in the late stage (5 s.e. of 3 seeds, see T_3_SEEDS).
    rel = np.array(paired.data["paired"])  # (seeds, times)
    per_seed = rel.mean(axis=1)
    se = per_seed.std(ddof=1) / math.sqrt(per_seed.size)
    assert abs(per_seed.mean()) < T_3_SEEDS * se + 1e-12
    assert all(t >= 10.0 for t in p["times"]) and p["times"][-1] == 40.0


def test_departure_runs_are_reported_per_t_delta(paired):
    for dep in paired.summary["departure"]:
        assert len(dep["ratio"]) == len(dep["t_delta"]) == len(dep["times"])
        np.testing.assert_allclose(dep["t_delta"], np.asarray(dep["times"]) * dep["delta"])
        # both sides come from the same initial state: equal at t = 10 (t δ = 1) within the
        # paired scatter of the late stage (3.6 % rms at N = 1000 above; 5 of it)
        assert abs(dep["ratio"][0] - 1.0) < 0.18


# --------------------------------------------------------------------- comparison 9


def _chi2_bound(dof: int) -> float:
    """χ² of a histogram against a law with nothing fitted has mean dof and standard deviation
    √(2 dof); dof + 5√(2 dof) is exceeded with probability ~1e-4 at 15-40 dof (the χ² tail is
    heavier than a Gaussian's), so the 8 checks below fail falsely with probability ~1e-3."""
    return dof + 5.0 * math.sqrt(2.0 * dof)


def test_energy_decays_as_t_to_minus_two_thirds_over_two_decades(late):
    e = late.summary["energy"]
    assert e["fit_range"][1] / e["fit_range"][0] >= 100.0
    z, se = e["exponent"]
    # 5 s.e. over 3 seeds (T_3_SEEDS).  The drift of E t^{2/3} itself (0.445-0.450 over
    # t ∈ [10, 1000], measured at N = 10⁷ with 12 seeds) shifts the fitted exponent by at most
    # ln(0.450/0.445)/ln 100 = 0.0024, below the tolerance (measured se 0.0044).
    assert abs(z + 2.0 / 3.0) < T_3_SEEDS * se


def test_velocity_and_mass_laws_are_the_exact_ones_at_late_times(late):
    # Small preset: N = 2·10⁶, 4 seeds pooled, nothing fitted.  At t ≥ 1000 the finite-t
    # corrections are below what 10⁵ clusters resolve (measured here: velocity χ²/dof 22.4/22,
    # 16.2/20, 6.4/18, 23.8/16 and mass 41.1/27, 31.5/35, 26.5/38, 30.7/37 at t = 10³ … 10⁵).
    rows = [r for r in late.summary["exact"]["per_time"] if r["t"] >= 1000.0]
    assert len(rows) >= 3 and rows[-1]["t"] >= 1e5
    for r in rows:
        for key in ("velocity", "mass"):
            assert r[key]["dof"] >= 10, (r["t"], key)
            assert r[key]["chi2"] < _chi2_bound(r[key]["dof"]), (r["t"], key, r[key])


def test_corrections_to_scaling_shrink_with_t(late):
    rows = late.summary["exact"]["per_time"]
    first, last = rows[0], rows[-1]
    assert first["t"] == 10.0 and last["t"] / first["t"] >= 1e4
    for key in ("velocity", "mass"):
        # at t = 10 the same test rejects the exact law (measured χ²/dof 51 and 1446), so the
        # late agreement above is not a test without power
        assert first[key]["chi2"] > _chi2_bound(first[key]["dof"]), key
        assert first[key]["chi2"] / first[key]["dof"] > last[key]["chi2"] / last[key]["dof"]
    # The number of clusters × t^{2/3}/N, a scale-free correction: 22 % below its exact limit
    # at t = 10 (measured −0.217), within its noise at t = 10⁵ (~1/√5000 = 1.4 % relative,
    # measured −0.004).  A factor 5 between them leaves room for 3 times that noise.
    c0 = abs(first["cluster_number"]["relative"])
    c1 = abs(last["cluster_number"]["relative"])
    assert c0 > 0.1 and c1 < c0 / 5.0


def test_tail_exponent_agrees_with_the_exact_one_where_resolved(late):
    tail = late.summary["tail"]
    eng = tail["engine"]
    w = np.asarray(eng["beta_w"])
    z = np.asarray(eng["z"])
    moderate = (w >= 1.0) & (w <= 2.5) & np.isfinite(z)
    # Chords of ln(−ln S) between neighbouring grid points at t = 1000 (4 seeds of 2·10⁶),
    # errors by the delta method with the clusters as independent (the variance of a
    # mass-weighted count is Σ m²; the same model as the velocity histogram, whose χ² above is
    # consistent with it).  Each |z| < 3 has probability 0.997, so with ≤ 4 chords a false
    # failure has probability ≤ 1 %.  Measured z: −0.02, −1.48, 0.42, −1.72.
    assert moderate.sum() >= 3
    assert np.all(np.abs(z[moderate]) < 3.0), z
    # At t = 10 the same chords are far below the exact ones (measured β ≈ 1.42-1.50 against
    # 1.46-1.70, z down to −15): the old "β ≈ 1.5 against 3" was a finite-t correction.
    early = late.summary["exact"]["per_time"][0]["tail"]
    ze = np.asarray(early["z"])
    we = np.asarray(early["beta_w"])
    assert np.nanmin(ze[(we >= 1.0) & (we <= 2.5)]) < -5.0


def test_the_deep_tail_ensemble_does_not_depend_on_the_processes():
    # the deep-tail part at a tiny size: 6 gases of 10⁵ in blocks of 2, on 1 and on 2 processes
    # (joined in seed order): the same summary, bit for bit; and it pools all the particles
    import json

    from maxwell_kinetics.app.comparisons import PRESETS
    from maxwell_kinetics.app.comparisons.sticky_tail import deep_tail_runs

    params = {**PRESETS["late_stage"]["small"], "deep_seeds": 6, "deep_n": 100_000, "deep_block": 2,
              "deep_times": (31.6, 316.0)}
    one = deep_tail_runs({**params, "deep_workers": 1}, False)["summary"]["deep_tail"]
    two = deep_tail_runs({**params, "deep_workers": 2}, False)["summary"]["deep_tail"]
    assert json.dumps(one) == json.dumps(two)
    assert one["particles"] == 600_000 and [r["t"] for r in one["per_time"]] == [31.6, 316.0]
    assert all(r["deepest"]["clusters"] == 25 for r in one["per_time"])
    assert deep_tail_runs({**params, "deep_seeds": 0}, False) == {"summary": {}, "data": {}}


def test_the_exact_tail_exponent_reaches_two_only_beyond_any_sample(late):
    ex = late.summary["tail"]["exact"]
    beta = np.asarray(ex["beta"])
    assert np.all(np.diff(beta) > 0) and beta[-1] < ex["limit"]
    # β = 2 (Gaussian) is crossed where P(|w| > w) is ~2e-8, far below the deepest survival
    # that the sample resolves (25 clusters beyond: measured 8.5e-5 here, ~1e-6 at the default
    # size): the sample's β stays below 2 whatever the law's asymptote.
    two = ex["crossings"]["2"]
    assert 3.0 < two["w"] < 5.0
    deep = late.summary["tail"]["engine"]["deepest"]
    assert two["survival"] < deep["survival"] / 100.0
    # the engine's deepest point is the exact law's within the Poisson error of 25 clusters
    # (20 %, 3 of it; measured 8.5e-5 against 7.3e-5): at t = 1000 the depth is not a finite-t
    # artefact (at t = 10 the engine's is 20 times the exact one)
    assert abs(deep["survival"] / deep["exact_survival"] - 1.0) < 3 * deep["survival_error"] / \
        deep["survival"]


def test_cluster_mass_exponent_is_minus_one_half_with_corrections(late):
    # The secondary number: the small-μ fit A μ^a + B + C μ^{1/2} of the pooled runs at
    # t = 10⁴, 3·10⁴, 10⁵ (N = 2·10⁶, 4 seeds, m ≥ 10, μ ≤ 0.3), errors of Poisson cluster
    # counts (test_mass_density_errors_are_poisson).  Measured here: a = −0.649 ± 0.348.
    fits = late.summary["mass"]["secondary_fit"]["fits"]
    a, se = fits["corrected"]["a"]
    assert abs(a + 0.5) < 3.0 * se
    # Goodness of fit with a held at −1/2 (A, B, C free): χ² below the 99.9 % quantile of χ²
    # with its degrees of freedom, so a false failure has probability 10⁻³.
    prof = fits["profile"]
    assert prof["chi2"]["-1/2"] < chi2_dist.ppf(0.999, prof["dof"])
    assert fits["corrected"]["chi2_dof"] < chi2_dist.ppf(0.999, prof["dof"] - 1) / (prof["dof"] - 1)


def test_displacements_follow_chernoffs_law(late):
    disp = late.summary["displacement"]
    var, se = disp["variance"]
    # ⟨z²⟩ → Var Z = 0.26356 (Chernoff) at large t; at t = 1000 the finite-t excess is about
    # +0.2 % (measured at N = 10⁷: ⟨D²⟩ t^{−4/3} = 0.6656 against 0.6641).  3 seeds
    # (T_3_SEEDS) plus 0.5 % for that drift; measured here 0.2682 ± 0.0024.
    assert abs(var - disp["chernoff_variance"]) < T_3_SEEDS * se + 5e-3 * disp["chernoff_variance"]
    # the histogram is a density and sits on Chernoff's near the centre (|z| < 1, bins of 0.1;
    # measured: at most 4.4 % off; 20 % leaves room for the seed scatter of 3 runs at N = 10⁵,
    # whose clusters of ~100 particles move as one)
    from particles.sticky_exact import chernoff_density

    edges, hist = late.data["z_edges"], late.data["z_hist"]
    centres = 0.5 * (edges[:-1] + edges[1:])
    assert np.sum(hist * np.diff(edges)) == pytest.approx(1.0, abs=1e-12)
    core = np.abs(centres) < 1.0
    np.testing.assert_allclose(hist[core], chernoff_density(centres[core]), rtol=0.2)


def test_mass_density_errors_are_poisson():
    # One table at t = 1000 (M = 100), L = 10⁴: bin [0.1, 0.2) holds the integers 10…19
    # (k = 10), and 30 + 20 clusters of masses 12 and 15: Φ = M² 50 / (L k), σ = M² √50 / (L k).
    tables = [(np.array([5, 12, 15]), np.array([7.0, 30.0, 20.0]))]
    phi, err, counted = mass_density(tables, [1000.0], 1e4, np.array([0.1, 0.2]), 10,
                                     errors=True)
    big_m = 1000.0 ** (2.0 / 3.0)
    k = np.ceil(0.2 * big_m) - np.ceil(0.1 * big_m)
    assert counted[0] == 50.0
    assert phi[0] == pytest.approx(big_m**2 * 50 / (1e4 * k), rel=1e-12)
    assert err[0] == pytest.approx(big_m**2 * math.sqrt(50) / (1e4 * k), rel=1e-12)
    # Against the scatter of independent runs: 12 seeds, N = 10⁶, t = 10⁴, bins μ ∈ [0.02, 0.32)
    # in 4 octaves.  The mean over bins of (seed variance)/(Poisson variance) has a standard
    # error of about √(2/11)/2 ≈ 0.21 (4 bins, 11 dof each), and the tolerance is 3 of them
    # (measured: 0.95).  Errors too small by √2 (ratio 2) or a wrong power of M in σ fail;
    # errors too large by √2 (ratio 0.5) would sit at 2.4 of them and are not excluded here.
    engine = StickyGas(StickyParams(1_000_000, 1.0, "gaussian"))
    edges = 0.02 * 2.0 ** np.arange(5)
    rows = []
    for seed in range(12):
        state = engine.advance(engine.initial_state(np.random.default_rng(seed)), 1e4)
        rows.append(mass_density([cluster_mass_distribution(state)], [1e4], engine.params.length,
                                 edges, 1, errors=True))
    phis = np.array([r[0] for r in rows])
    errs = np.array([r[1] for r in rows])
    ratio = phis.var(axis=0, ddof=1) / np.mean(errs**2, axis=0)
    assert abs(ratio.mean() - 1.0) < 3 * 0.21


def test_structure_factor_collapses_with_a_porod_tail(late):
    s = late.summary["structure"]
    slope, se = s["porod_slope_last_fitted_time"]
    # Per-seed Porod fits at the last time with a fit, 3 seeds (T_3_SEEDS); the discrete
    # step spectrum 1/(4 sin²(k/2)) differs from k⁻² by ≤ 3 % at k = 0.6, a slope bias ≤ 0.03.
    assert abs(slope + 2.0) < T_3_SEEDS * se + 0.03
    # rescaling by t^{2/3} collapses 2 decades of time (spread of ln S: measured 0.11 against
    # 2.1 unscaled)
    assert s["collapse_spread_at_z"] < 0.25 * s["collapse_spread_unscaled"]


def test_shocks_have_the_signs_of_the_paper(late):
    sk = late.summary["skewness"]
    q = sk["scales"].index(4)
    vi, vi_se = sk["vi"][q]
    vx, vx_se = sk["vx"][q]
    # Fig. 4: v(i) large positive gradients, v(x) large negative ones (3 seeds, T_3_SEEDS)
    assert vi > T_3_SEEDS * vi_se and vx < -T_3_SEEDS * vx_se


def test_late_velocity_law_is_gaussian_like(late):
    # Fig. 1b: Gaussian-like.  The exact late-time law has kurtosis ⟨w⁴⟩/⟨w²⟩² = 3.0410
    # (quadrature of particles.sticky_exact.exact_velocity_density, here); its finite-t bias at
    # t ≥ 316 (ℓ = t^{2/3} ≥ 46 particles per unit μ) is 0.008 ± 0.011, 0.000 ± 0.012 (N = 10⁶,
    # 12 seeds), below the noise.  One run of N = 10⁵ scatters by 0.12 (t = 316) and 0.18
    # (t = 1000), measured over 60 seeds: the mean of the fixture's 3 seeds must lie within 5
    # of those over √3 (the engine at N = 10⁶ is held closer in test_sticky_exact.py).
    exact = _exact_kurtosis()
    times = late.summary["kurtosis"]["times"]
    for t, sigma_run in ((316.228, 0.12), (1000.0, 0.18)):
        k, _ = late.summary["kurtosis"]["kurtosis"][times.index(t)]
        assert abs(k - exact) < 5 * sigma_run / math.sqrt(3), (t, k, exact)
    assert abs(exact - 3.0) < 0.05  # near-Gaussian, not Gaussian


@functools.lru_cache(maxsize=1)
def _exact_kurtosis():
    from particles.sticky_exact import exact_velocity_density

    x, weight = np.polynomial.legendre.leggauss(120)  # P(w) < 1e-160 beyond w = 15
    w = 7.5 * (x + 1.0)
    p = exact_velocity_density(w) * weight
    return float(np.sum(w**4 * p) * np.sum(p) / np.sum(w**2 * p) ** 2)  # ⟨w⁴⟩⟨1⟩/⟨w²⟩²


def test_both_comparisons_save_load_and_draw(paired, late, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for c in (paired, late):
        path = tmp_path / f"{c.name}.npz"
        c.save(path)
        back = Comparison.load(path)
        assert back.name == c.name
        _assert_same(c.summary, back.summary)
        _assert_same(c.data, back.data)
        fig = back.figure()
        assert len(fig.axes) >= 3
        plt.close(fig)


def test_late_stage_figure_has_two_rows_and_no_overlapping_titles(late):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = late.figure()
    try:
        axes = fig.axes
        rows = sorted({round(ax.get_position().y0, 3) for ax in axes})
        assert len(axes) == 8 and len(rows) == 2
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        boxes = []
        for ax in axes:
            title = ax.title.get_window_extent(renderer)
            boxes.append((round(ax.get_position().y0, 3), title))
            # each title sits within its own column (it may not reach into a neighbour's)
            pos = ax.get_window_extent(renderer)
            width = pos.x1 - pos.x0
            assert title.x0 > pos.x0 - 0.2 * width and title.x1 < pos.x1 + 0.2 * width, \
                ax.get_title()
        for i, (row_a, a) in enumerate(boxes):
            for row_b, b in boxes[i + 1:]:
                if row_a == row_b:
                    assert not a.overlaps(b)
        # the zoomed window: a few clusters, not thousands of labels
        assert 3 <= late.data["window"]["masses"].size <= 12
    finally:
        plt.close(fig)


# --------------------------------------------------------------------- engine at N = 10⁶


def test_sticky_gas_at_a_million_particles():
    from particles.sticky_exact import exact_moments

    engine = StickyGas(StickyParams(1_000_000, 1.0))
    st = engine.advance(engine.initial_state(np.random.default_rng(0)), 10.0)
    m, c = cluster_mass_distribution(st)
    assert int((m * c).sum()) == 1_000_000
    assert abs(st.velocities.sum()) < 1e-6
    # E t^{2/3} and the kurtosis at t = 1000 (ℓ = t^{2/3} = 100), 8 seeds, against the exact
    # late-time law (particles.sticky_exact, pinned by test_sticky_exact.py).  Finite-t: the
    # corrections are of order 1/ℓ (integer masses; E t^{2/3} = 0.4494 at t = 10, ℓ = 4.6), and
    # at t = 1000 measured at 0.4436 ± 0.0009 against 0.44275 (N = 10⁷, 4 seeds,
    # benchmarks/README.md), below the noise here.
    # One run scatters by 0.008 in E t^{2/3} and 0.043 in the kurtosis (10 and 12 seeds
    # measured): tolerances 5 standard errors of the mean of 8, i.e. 0.014 and 0.076.
    t, seeds = 1000.0, 8
    et, kurt = [], []
    for seed in range(seeds):
        v = engine.advance(engine.initial_state(np.random.default_rng(seed)), t).velocities
        e = float(np.mean(v**2))
        et.append(e * t ** (2.0 / 3.0))
        kurt.append(float(np.mean(v**4)) / e**2)
    exact = exact_moments()["velocity_variance"]
    assert abs(np.mean(et) - exact) < 5 * 0.008 / math.sqrt(seeds), (np.mean(et), exact)
    assert abs(np.mean(kurt) - _exact_kurtosis()) < 5 * 0.043 / math.sqrt(seeds), np.mean(kurt)


def test_seed_based_verdicts_allow_the_t_quantile_and_law_based_ones_three_sigma(late):
    """E's exponent, the Porod slope and Chernoff's variance have σ from the 3 seeds: each
    allows t's quantile at 2 dof (19.2σ, the energy plus its drift as a stated tolerance);
    the mass exponent (a fit with the counts' errors) and the χ² keep 3σ."""
    import copy

    from maxwell_kinetics.app.comparisons import VERDICTS
    from maxwell_kinetics.app.comparisons.tolerances import t_sigmas

    s = copy.deepcopy(late.summary)
    records = [v.to_dict() for v in VERDICTS["late_stage"](s)]
    seed_based = [v for v in records if v["sigma_source"].startswith("seeds")]
    assert len(seed_based) == 3
    for v in seed_based:
        assert v["t_law"] is True and v["combined_dof"] == 2
        assert v["sigmas"] == pytest.approx(t_sigmas(2))
    law = [v for v in records if not v["sigma_source"].startswith("seeds")]
    assert law and all(v["sigmas"] == 3.0 and not v["t_law"] for v in law)
    # Chernoff's variance 6σ off: 3 normal σ called it "disagrees", t (2 dof) does not
    var, se = s["displacement"]["variance"]
    s["displacement"]["variance"] = [s["displacement"]["chernoff_variance"] + 6 * se, se]
    (chernoff,) = [v for v in VERDICTS["late_stage"](s) if "Chernoff" in v.claim]
    assert chernoff.status == "agrees"
    s["displacement"]["variance"] = [s["displacement"]["chernoff_variance"] + 25 * se, se]
    (chernoff,) = [v for v in VERDICTS["late_stage"](s) if "Chernoff" in v.claim]
    assert chernoff.status == "disagrees"
