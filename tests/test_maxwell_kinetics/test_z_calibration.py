"""The calibration of the verdicts' standard errors: counts of |z| beyond 1, 2, 3σ."""

import math

import pytest
from scipy.stats import binomtest

from maxwell_kinetics.app.comparisons.calibration import z_calibration
from particles.validation import InvalidArgumentError


def _record(z, status="agrees", relation="equal", short="", claim="a claim"):
    return {"claim": claim, "short": short, "deviation_in_sigma": z, "status": status,
            "relation": relation}


def _summary(**comparisons):
    return {"size": "small", "comparisons": {name: {"verdicts": records}
                                             for name, records in comparisons.items()}}


def test_exact_counts_and_expected_counts():
    zs = [0.1, -0.5, 1.5, -1.2, 2.5, -3.5, 0.0, 0.9, -2.1, 4.0]
    summary = _summary(a=[_record(z, short=f"a{i}") for i, z in enumerate(zs[:5])],
                       b=[_record(z, short=f"b{i}") for i, z in enumerate(zs[5:])])
    c = z_calibration(summary)
    assert c["n"] == 10
    assert c["observed"] == {1: 6, 2: 4, 3: 2}
    assert c["expected"] == pytest.approx({1: 3.173, 2: 0.455, 3: 0.027}, abs=1e-3)
    assert c["fractions"][2] == pytest.approx(math.erfc(2 / math.sqrt(2)))
    assert c["p_value"] == pytest.approx(binomtest(4, 10, c["fractions"][2]).pvalue)
    # the checks beyond 2σ, largest |z| first, with comparison and short claim
    assert [(b["comparison"], b["claim"], b["z"]) for b in c["beyond_2sigma"]] == [
        ("b", "b4", 4.0), ("b", "b0", -3.5), ("a", "a4", 2.5), ("b", "b3", -2.1)]


def test_boundaries_are_strict():
    c = z_calibration(_summary(a=[_record(1.0), _record(-2.0), _record(3.0)]))
    assert c["observed"] == {1: 2, 2: 1, 3: 0}


def test_records_without_a_finite_z_are_skipped():
    summary = _summary(a=[_record(None), _record(float("nan")), _record(float("inf")),
                          _record(2.5, claim="the long claim")])
    c = z_calibration(summary)
    assert c["n"] == 1
    assert c["observed"] == {1: 1, 2: 1, 3: 0}
    # without a short claim the claim is named
    assert c["beyond_2sigma"][0]["claim"] == "the long claim"


def test_no_statistical_checks_gives_zero_counts_and_no_p_value():
    for summary in (_summary(a=[_record(None), _record(None)]), _summary(), {}):
        c = z_calibration(summary)
        assert c["n"] == 0
        assert c["observed"] == {1: 0, 2: 0, 3: 0}
        assert c["expected"] == {1: 0.0, 2: 0.0, 3: 0.0}
        assert c["p_value"] is None
        assert c["beyond_2sigma"] == []


def test_mapping_of_comparison_summaries_and_subsets():
    comparisons = {"a": {"verdicts": [_record(5.0, status="explained"),
                                      _record(-9.0, relation="below"),
                                      _record(2.2), _record(0.3)]},
                   "b": {"other": 1}}
    assert z_calibration(comparisons)["observed"] == {1: 3, 2: 3, 3: 2}
    c = z_calibration(comparisons, statuses=["agrees"], relations=["equal"])
    assert c["n"] == 2 and c["observed"] == {1: 1, 2: 1, 3: 0}
    assert c["beyond_2sigma"][0]["z"] == 2.2


def test_bad_input_is_refused():
    with pytest.raises(InvalidArgumentError):
        z_calibration([1, 2])
    with pytest.raises(InvalidArgumentError):
        z_calibration(_summary(a="not a list"))


# ---- each z under its own law ------------------------------------------------------------

from maxwell_kinetics.app.comparisons.calibration import normal_z, p_value  # noqa: E402
from maxwell_kinetics.app.comparisons.verdicts import Check, judge, welch_dof  # noqa: E402


def test_p_value_of_a_t_with_one_degree_of_freedom_is_exact():
    # Student's t with 1 dof is Cauchy: P(|T| > z) = 1 − (2/π) arctan z, by hand
    assert p_value(1.0, 1) == pytest.approx(0.5, abs=1e-12)
    assert p_value(math.sqrt(3.0), 1) == pytest.approx(1.0 / 3.0, abs=1e-12)
    # a normal law (dof None): erfc(z/√2)
    assert p_value(2.0) == pytest.approx(math.erfc(2.0 / math.sqrt(2.0)), rel=1e-12)


def test_t_with_two_degrees_of_freedom_and_trials():
    # t₂: P(|T| > z) = 1 − z/√(2 + z²), exactly
    z = 4.93
    p1 = 1.0 - z / math.sqrt(2.0 + z * z)
    assert p_value(-z, 2) == pytest.approx(p1, rel=1e-10)
    # the largest of 11: 1 − (1 − p)^11
    assert p_value(-z, 2, trials=11) == pytest.approx(1.0 - (1.0 - p1) ** 11, rel=1e-10)


def test_normal_z_keeps_the_p_value_and_the_sign():
    assert normal_z(2.5) == 2.5
    # t₁ at z = 1 has p = 1/2: the normal z of p = 1/2 is the quartile 0.6745
    assert normal_z(-1.0, 1) == pytest.approx(-0.6744897501960817, abs=1e-9)
    assert abs(normal_z(6.82, 3)) < 6.82
    assert normal_z(1e6, 1000) == 38.0 or normal_z(1e6, 1000) > 30


@pytest.mark.parametrize(("args", "name"), [((float("nan"),), "z"), ((1.0, 0), "dof"),
                                            ((1.0, -2.0), "dof"), ((1.0, None, 0), "trials"),
                                            ((1.0, None, True), "trials")])
def test_bad_laws_are_refused(args, name):
    with pytest.raises(InvalidArgumentError, match=name):
        p_value(*args)


def test_the_counts_use_each_records_law():
    # z = √3 under t₁ has p = 1/3: its normal z is 0.967, inside 1σ; under a normal law it
    # is beyond 1σ
    rec = {**_record(math.sqrt(3.0)), "combined_dof": 1.0}
    assert z_calibration(_summary(a=[rec]))["observed"] == {1: 0, 2: 0, 3: 0}
    assert z_calibration(_summary(a=[rec]), student=False)["observed"] == {1: 1, 2: 0, 3: 0}
    # a record of before the degrees of freedom is normal
    assert z_calibration(_summary(a=[_record(math.sqrt(3.0))]))["observed"][1] == 1


def test_uniformity_and_tail_of_the_p_values():
    from scipy.stats import binomtest, kstest

    zs = [0.1, -0.5, 1.5, -1.2, 2.5]
    c = z_calibration(_summary(a=[_record(z) for z in zs]))
    ps = [math.erfc(abs(z) / math.sqrt(2.0)) for z in zs]
    assert c["ks"] == pytest.approx(kstest(ps, "uniform").statistic)
    assert c["ks_p"] == pytest.approx(kstest(ps, "uniform").pvalue)
    assert c["tail_p"] == pytest.approx(
        binomtest(1, 5, c["fractions"][2], alternative="greater").pvalue)
    assert c["rms_z"] == pytest.approx(math.sqrt(sum(z * z for z in zs) / 5))
    # the checks beyond 2σ carry their law
    b = c["beyond_2sigma"][0]
    assert (b["z"], b["z_normal"], b["dof"], b["trials"]) == (2.5, 2.5, None, 1)


def test_welch_degrees_of_freedom_by_hand():
    # two equal standard errors with 3 dof each: (2σ²)²/(2σ⁴/3) = 6
    assert welch_dof((0.1, 3), (0.1, 3)) == pytest.approx(6.0)
    # one part alone keeps its own; an exact σ adds nothing to the denominator
    assert welch_dof((0.2, 4), (0.0, 1)) == 4.0
    assert welch_dof((1.0, 2), (1.0, None)) == pytest.approx(8.0)  # (1 + 1)²/(1/2)
    assert welch_dof((1.0, None)) is None
    assert welch_dof() is None


def test_a_check_records_its_degrees_of_freedom_and_source():
    c = Check("q", 1.1, 0.1, 1.0, "exact: x", expected_sigma=0.1, dof=3, expected_dof=3,
              sigma_source="seeds: 4 runs each")
    v = judge("a claim", c).to_dict()
    assert v["dof"] == 3 and v["expected_dof"] == 3 and v["combined_dof"] == pytest.approx(6.0)
    assert v["sigma_source"] == "seeds: 4 runs each" and v["trials"] == 1
    assert judge("a claim", Check("q", 1.0, 0.1, 1.0, "x")).to_dict()["combined_dof"] is None
    for bad in ({"dof": 0}, {"dof": float("inf")}, {"expected_dof": -1}, {"trials": 0},
                {"trials": 1.5}):
        with pytest.raises(InvalidArgumentError, match=next(iter(bad))):
            Check("q", 1.0, 0.1, 1.0, "x", **bad)
