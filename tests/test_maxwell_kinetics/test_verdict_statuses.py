"""The five statuses of a verdict and the comparisons' verdicts on synthetic summaries (no runs):
a headline that can disagree (``rate_vs_correlations``), an explanation that first requires
molecular chaos at the window's start (``energy_decay``), claims this size does not resolve
(``not measured``: ``velocity_profiles``, MD's collapse exponent), a refuted claim of the paper
(Fig. 1a), the DSMC's energy, tolerances from the seeds' σ (Student's t) and the exit status
of ``reproduce``."""

from __future__ import annotations

import math

import pytest

from maxwell_kinetics.app.commands.reproduce import exit_status
from maxwell_kinetics.app.comparisons import VERDICTS
from maxwell_kinetics.app.comparisons.tolerances import t_sigmas
from maxwell_kinetics.app.comparisons.verdicts import (
    STATUSES,
    Check,
    judge,
    status_counts,
    student_sigmas,
    verdict_table,
)
from particles.validation import InvalidArgumentError


def _check(measured, sigma=0.125, expected=1.0, quantity="q", **kw):
    return Check(quantity, measured, sigma, expected, "exact: test", **kw)


def _by_short(records, text):
    (found,) = [v for v in records if text in v["short"]]
    return found


def _records(name, summary):
    return [v.to_dict() for v in VERDICTS[name](summary)]


# --------------------------------------------------------------------------- the judge


def test_the_statuses():
    assert STATUSES == ("agrees", "disagrees", "explained", "refuted", "not measured")


def test_not_measured_comes_first_and_names_the_size_that_measures():
    small = _check(64.0, None, 16.0, "scale", relation="at_most")  # fails: 64 > 16
    v = judge("c", _check(5.0), _check(1.0, quantity="e"), resolution=small,
              measured_at="default")
    assert v.status == "not measured" and v.to_dict()["measured_at"] == "default"
    assert v.to_dict()["resolution"]["holds"] is False
    resolved = _check(8.0, None, 16.0, "scale", relation="at_most")
    assert judge("c", _check(5.0), resolution=resolved, measured_at="default").status \
        == "disagrees"
    with pytest.raises(InvalidArgumentError, match="measured_at"):
        judge("c", _check(1.0), resolution=small)


def test_refuted_needs_its_own_check_and_comes_after_an_explanation():
    fails, holds = _check(5.0), _check(1.0, quantity="cause")
    assert judge("c", fails, refutation=holds).status == "refuted"
    assert judge("c", fails, refutation=_check(5.0, quantity="cause")).status == "disagrees"
    assert judge("c", _check(1.0), refutation=holds).status == "agrees"
    assert judge("c", fails, _check(1.0, quantity="e"), refutation=holds).status == "explained"


def test_an_explanation_of_several_checks_needs_every_one():
    first, last = _check(1.0, quantity="first"), _check(5.0, quantity="last", relation="differs")
    assert judge("c", _check(5.0), (first, last)).status == "explained"
    v = judge("c", _check(5.0), (_check(5.0, quantity="first"), last))
    assert v.status == "disagrees"
    record = v.to_dict()["explanation"]
    assert record["quantity"] == "last" and record["holds"] is True
    assert [r["holds"] for r in record["requires"]] == [False]


def test_student_sigmas_keep_the_coverage_of_three_sigma():
    assert student_sigmas(3) == pytest.approx(19.2067, abs=1e-3)
    assert student_sigmas(4) == pytest.approx(9.2189, abs=1e-3)
    assert student_sigmas(10**6) == pytest.approx(3.0, abs=1e-4)
    with pytest.raises(InvalidArgumentError, match="seeds"):
        student_sigmas(1)


def test_exit_status_fails_only_on_a_claim_this_size_resolves():
    ok = judge("ok", _check(1.0)).to_dict()
    unmeasured = judge("z", _check(5.0), resolution=_check(0.0, None, 1.0, "t", relation="above"),
                       measured_at="default").to_dict()
    refuted = judge("paper", _check(5.0), refutation=_check(1.0, quantity="cause")).to_dict()
    bad = judge("bad", _check(5.0)).to_dict()
    assert unmeasured["status"] == "not measured" and refuted["status"] == "refuted"
    assert exit_status({"a": {"verdicts": [ok, unmeasured]}}) == 0
    assert exit_status({"a": {"verdicts": [ok, refuted]}}) == 0
    assert exit_status({"a": {"verdicts": [ok, unmeasured, refuted]}, "b": {"verdicts": [bad]}}) \
        == 3
    counts = status_counts({"a": {"verdicts": [ok, unmeasured, refuted, bad]}})
    assert counts == {"agrees": 1, "disagrees": 1, "explained": 0, "refuted": 1,
                      "not measured": 1}


def test_the_table_fits_100_columns_and_names_where_a_claim_is_measured():
    long = judge("a very long claim " * 10, _check(123456.789, 0.000123456),
                 resolution=_check(0.0, None, 1.0, "t", relation="above"),
                 measured_at="full", why="the run is short " * 10).to_dict()
    table = verdict_table({"comparison_with_a_name": {"verdicts": [long]}})
    assert max(len(line) for line in table.splitlines()) <= 100
    assert "not measured [1]" in table and "[1] not measured: measured at --full" in table


# --------------------------------------------------------------------------- rate_vs_correlations


def _rate_summary(share, k_md=1.9, k_dsmc=1.845, dsmc_energy=(0.0366, 0.0001),
                  md_energy=(0.899, 0.0006), ulam_energy=1.0):
    """A rate_vs_correlations summary with what its verdicts read: at the last time MD's
    kurtosis departs from the Maxwell model's 3.05 by −1.15, the DSMC's by −1.205."""
    def row(t, share_value, kurtosis_md, kurtosis_dsmc, e_md, e_dsmc, e_b):
        return {"t": t,
                "kurtosis": {"md": [kurtosis_md, 0.01], "dsmc": [kurtosis_dsmc, 0.006],
                             "boltzmann": 1.86, "maxwell_exact": 3.05},
                "energy": {"md": list(e_md), "dsmc": list(e_dsmc), "boltzmann": e_b,
                           "maxwell": [e_b * ulam_energy, 0.0004], "maxwell_exact": e_b},
                "collisions_per_particle": 2.0 * t,
                "split": {"correlation_share": [share_value, 0.009],
                          "correlation": [0.0, 0.07]},
                "dsmc_minus_boltzmann_in_sigma": 1.0,
                "maxwell_particles_minus_exact_in_sigma": 1.0}

    first = row(5.0, 0.5, 2.86, 2.86, md_energy, (0.897, 0.001), 0.8968)
    last = row(400.0, share, k_md, k_dsmc, (0.0373, 0.0003), dsmc_energy, 0.03658)
    return {"cases": [{"restitution": 0.99, "rows": [first, last]}]}


@pytest.mark.parametrize("share", [-5.0, 0.2])
def test_a_correlation_share_the_particles_do_not_show_disagrees(share):
    """The old explanation, the rate share 1 − share ≥ 1/2, was the check's complement: any
    share below 1/2 was ``explained``.  The DSMC's own estimate of the share, (MD − DSMC)/(MD −
    Maxwell) = −0.048, refutes the paper only where it equals the split's share."""
    v = _records("rate_vs_correlations", _rate_summary(share))[0]
    assert v["status"] == "disagrees"


def test_a_small_correlation_share_the_dsmc_measures_too_refutes_the_paper():
    v = _records("rate_vs_correlations", _rate_summary(-0.03))[0]
    assert v["status"] == "refuted" and v["refutation"]["holds"]
    assert v["refutation"]["measured"] == pytest.approx((1.9 - 1.845) / (1.9 - 3.05))
    assert _records("rate_vs_correlations", _rate_summary(0.6))[0]["status"] == "agrees"


def test_the_dsmc_energy_is_read_against_its_deterministic_solution():
    """3.6σ off at the last time (the summary's own numbers): disagrees."""
    off = _rate_summary(-0.03, dsmc_energy=(0.03658 * (1 + 3.6 * 0.003), 0.03658 * 0.003))
    v = _by_short(_records("rate_vs_correlations", off), "DSMC E")
    assert v["status"] == "disagrees" and v["deviation_in_sigma"] == pytest.approx(3.6)
    ok = _by_short(_records("rate_vs_correlations", _rate_summary(-0.03)), "DSMC E")
    assert ok["status"] == "agrees"


def test_the_ulam_particles_energy_is_read_against_the_exact_one():
    """The Ulam rate × 1.01 moved E at the last τ by 11σ and no verdict read it."""
    off = _by_short(_records("rate_vs_correlations", _rate_summary(-0.03, ulam_energy=1.5)),
                    "Ulam E")
    assert off["status"] == "disagrees"
    ok = _by_short(_records("rate_vs_correlations", _rate_summary(-0.03)), "Ulam E")
    assert ok["status"] == "agrees"


def test_md_energy_at_the_first_time_is_a_verdict():
    off = _rate_summary(-0.03, md_energy=(0.8968 * (1 + 8 * 0.001), 0.8968 * 0.001))
    v = _by_short(_records("rate_vs_correlations", off), "MD E = Boltzmann E")
    assert v["status"] == "disagrees" and v["deviation_in_sigma"] == pytest.approx(8.0)


# --------------------------------------------------------------------------- energy_decay


def _energy_summary(md_slope, start, end):
    def fit(slope, sigma, expected, window):
        return {"slope": [slope, sigma], "uncertainty": sigma, "expected": expected,
                "window": list(window)}

    return {"parameters": {"restitution": 0.5},
            "md_haff_exponent": fit(md_slope, 0.0625, -2.0, (0.3, 2.0)),
            "md_late_exponent": fit(-2 / 3, 0.1, -2 / 3, (25.0, 100.0)),
            "lattice_initial_rate": fit(-0.375, 0.01, -0.375, (0.0, 0.25)),
            "lattice_late_exponent": fit(-0.5, 0.005, -0.5, (100.0, 2000.0)),
            "boltzmann_haff_exponent": {"slope": -2.02, "expected": -2.0, "window": [0.3, 2.0]},
            "md_energy_over_boltzmann": {"times": [0.34, 1.88],
                                         "ratio": [list(start), list(end)]}}


def test_a_broken_md_engine_is_not_explained_by_leaving_molecular_chaos():
    """MD's p × 1.10: the Haff slope misses by 6σ and E_MD/E_Boltzmann at the window's end is
    off, but it is 8σ off at the window's START too, where molecular chaos must hold."""
    s = _energy_summary(-2.375, start=(1.08, 0.01), end=(1.2, 0.02))
    records = _records("energy_decay", s)
    haff = records[0]
    assert haff["status"] == "disagrees"
    assert haff["explanation"]["requires"][0]["holds"] is False
    early = _by_short(records, "window start")
    assert early["status"] == "disagrees" and early["deviation_in_sigma"] == pytest.approx(8.0)


def test_haff_is_explained_when_md_starts_under_molecular_chaos_and_leaves_it():
    records = _records("energy_decay", _energy_summary(-2.375, start=(1.0, 0.01),
                                                       end=(1.2, 0.02)))
    assert records[0]["status"] == "explained"
    assert _by_short(records, "window start")["status"] == "agrees"


# --------------------------------------------------------------------------- not measured


def _structure_summary(md_times, z_md=0.7267, z_err=0.0066):
    part = lambda z, theory: {"z_best": [z, z_err], "z_theory": theory,  # noqa: E731
                              "porod_slope_last_time": [-2.0, 0.1]}
    return {"parameters": {"restitution": 0.5, "md_times": list(md_times)},
            "lattice": part(0.5, 0.5), "md": part(z_md, 2 / 3),
            "lattice_no_constraint": {"porod_slope_last_time": [0.0, 0.1]}}


def test_md_collapse_exponent_is_not_measured_at_the_small_size():
    v = _by_short(_records("structure_factors", _structure_summary((10.0, 20.0, 40.0))),
                  "MD collapse")
    assert v["status"] == "not measured" and v["measured_at"] == "default"
    measured = _by_short(_records("structure_factors", _structure_summary((25.0, 50.0, 100.0))),
                         "MD collapse")
    assert measured["status"] == "disagrees"  # 0.7267 ± 0.0066 is 9σ from 2/3
    good = _structure_summary((25.0, 50.0, 100.0), z_md=0.6913, z_err=0.0247)
    assert _by_short(_records("structure_factors", good), "MD collapse")["status"] == "agrees"


def _profiles_summary(scales, skew):
    field = {"scales": list(scales), "skewness": [[skew, 0.05]] * len(scales)}
    return {"coarse_skewness": {"md_vx": field, "md_vi": field, "lattice_vi": field}}


def test_velocity_profiles_too_small_to_coarse_grain_are_not_measured():
    records = _records("velocity_profiles", _profiles_summary((1, 4, 16), 0.5))
    assert [v["status"] for v in records] == ["not measured"] * 3
    assert all(v["measured_at"] == "default" for v in records)
    judged = _records("velocity_profiles", _profiles_summary((1, 4, 16, 64), 0.5))
    assert [v["status"] for v in judged] == ["disagrees", "agrees", "agrees"]


# --------------------------------------------------------------------------- Fig. 1a, tolerances


def _distributions_summary(lattice_rv, md_abs=0.818, md_abs_err=0.00364):
    def models(**kw):
        return {name: {"kurtosis": list(k), "abs_mean": list(a)} for name, (k, a) in kw.items()}

    early = models(md=((1.896, 0.0098), (0.8, 0.01)), lattice=((2.938, 0.03), (0.8, 0.01)),
                   lattice_rv=(lattice_rv, (0.8, 0.01)), ulam=((3.14, 0.053), (0.8, 0.01)))
    early = {"md": early["md"], "lattice_r0.99": early["lattice"],
             "lattice_rv_r0.99": early["lattice_rv"], "ulam": early["ulam"]}
    late = models(md=((2.4, 0.06), (md_abs, md_abs_err)), lattice=((2.4, 0.06), (md_abs, 0.01)))
    late = {"md": late["md"], "lattice_r0.5": late["lattice"]}
    return {"parameters": {"restitution": 0.99, "lattice_late_restitution": 0.5, "md_seeds": 4},
            "stages": {"early": {"models": early}, "late": {"models": late}}}


def test_fig_1a_is_refuted_with_its_cause_not_explained():
    v = _records("velocity_distributions", _distributions_summary((1.94, 0.024)))[0]
    assert v["status"] == "refuted" and v["refutation"]["holds"]
    broken = _records("velocity_distributions", _distributions_summary((2.5, 0.024)))[0]
    assert broken["status"] == "disagrees"


def test_the_gaussian_bulk_has_no_stated_tolerance_only_the_seeds_sigma():
    v = _by_short(_records("velocity_distributions", _distributions_summary((1.94, 0.024))),
                  "Gaussian")
    assert v["tolerance"] == 0.0 and v["n_sigma"] == pytest.approx(student_sigmas(4))
    assert v["deviation_in_sigma"] == pytest.approx((0.818 - math.sqrt(2 / math.pi)) / 0.00364)
    far = _distributions_summary((1.94, 0.024), md_abs=0.8179 + 0.00364 * 8.0,
                                 md_abs_err=0.00364)
    assert _by_short(_records("velocity_distributions", far), "Gaussian")["status"] == "disagrees"


def _sticky_summary(differences, seeds=3):
    return {"parameters": {"seeds": seeds},
            "paired": {"times": [10.0 * (i + 1) for i in range(len(differences))],
                       "relative_difference": [list(d) for d in differences],
                       "paired_over_unpaired": 0.1}}


def test_sticky_vs_md_is_judged_from_the_paired_sigma_with_students_t():
    ok = _records("sticky_vs_md", _sticky_summary([(-0.03, 0.008), (0.002, 0.004)]))[0]
    assert ok["status"] == "agrees" and ok["tolerance"] == 0.0
    # the t law of the largest of 2 values at 2 dof (Šidák), not one value's 19.2σ
    assert ok["t_law"] and ok["sigmas"] == pytest.approx(t_sigmas(2, 3.0, 2))
    assert ok["n_sigma"] == 3.0 and ok["measured"] == -0.03
    off = _records("sticky_vs_md", _sticky_summary([(0.0, 0.01), (0.3, 0.01)]))[0]
    assert off["status"] == "disagrees" and off["measured"] == 0.3


# ------------------------------------------------ G → f̂ within the solver's error floor

def _kinetic_theory(taus, sups):
    return {"parameters": {"restitution": 0.5, "tail_window": [5.0, 15.0]}, "tau": taus,
            "sup_error": sups,
            "max_distance_over_bound": {"2.5": 0.9},
            "moment_growth_rates": {"4": {"fitted": 0.07, "predicted": 0.07}},
            "tail_slope": [-4.0], "tail_slope_of_f": -4.0}


def test_g_tends_to_f_hat_within_twice_the_coarse_floor():
    # r = 0.5, coarse grid: floor 7.35e-8 (the solver started at f̂), allowed twice that
    taus = [0.0, 200.0, 500.0, 1000.0]
    at_floor = _records("kinetic_theory", _kinetic_theory(taus, [0.27, 4e-4, 2.4e-6, 7.3e-8]))[0]
    assert at_floor["status"] == "agrees"
    assert at_floor["tolerance"] == pytest.approx(2 * 7.35e-8)
    assert "floor" in at_floor["sigma_source"]
    # 3e-7 is 30 000 times under the old 1e-2, and twice the allowed floor: it disagrees
    above = _records("kinetic_theory", _kinetic_theory(taus, [0.27, 4e-4, 2.4e-6, 3e-7]))[0]
    assert above["status"] == "disagrees"
    # the transient left at the last τ: 2.4e-6 · (2.4e-6/4e-4)^(500/300), by hand
    expected = 2.4e-6 * math.exp(-math.log(4e-4 / 2.4e-6) / 300.0 * 500.0)
    assert at_floor["resolution"]["measured"] == pytest.approx(expected, rel=1e-12)


def test_g_tends_to_f_hat_is_not_measured_before_the_floor():
    # the small size's last τ = 100: the approach to f̂ is still at 1e-3
    taus = [0.0, 20.0, 50.0, 100.0]
    v = _records("kinetic_theory", _kinetic_theory(taus, [0.27, 0.0465, 0.0137, 3.37e-3]))[0]
    assert v["status"] == "not measured" and v["measured_at"] == "default"


# ------------------------------------- the degrees of freedom and source of each σ

def test_the_records_carry_the_law_of_their_z():
    # sticky_vs_md: 3 seeds (2 dof), the largest |z| of the window's 2 times
    v = _records("sticky_vs_md", _sticky_summary([(-0.03, 0.008), (0.002, 0.004)]))[0]
    assert (v["dof"], v["combined_dof"], v["trials"]) == (2, 2.0, 2)
    assert v["sigma_source"].startswith("seeds: standard error over 3 paired runs")
    # the Gaussian bulk: 4 MD seeds, 3 dof, one value
    g = _by_short(_records("velocity_distributions", _distributions_summary((1.94, 0.024))),
                  "Gaussian")
    assert (g["dof"], g["trials"]) == (3, 1) and "4 MD runs" in g["sigma_source"]


def test_the_driven_variance_is_normal_when_its_sigma_is_the_pooled_particles():
    row = {"restitution": 0.0, "variance": [1.0, 0.01], "variance_exact": 1.0,
           "kurtosis": [3.6, 0.05], "kurtosis_exact": 3.6}
    seeds = _records("driven_steady", {"parameters": {"seeds": 8},
                                       "rows": [{**row, "variance_error_from": "seeds"}]})
    pooled = _records("driven_steady", {"parameters": {"seeds": 8},
                                        "rows": [{**row,
                                                  "variance_error_from": "pooled particles"}]})
    assert [v["dof"] for v in seeds] == [7, 7]
    assert [v["dof"] for v in pooled] == [None, 7]  # the kurtosis's σ is the seeds' still
    assert pooled[0]["sigma_source"].startswith("pooled particles")
