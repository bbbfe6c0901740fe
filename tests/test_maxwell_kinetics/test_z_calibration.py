"""The calibration of the verdicts' standard errors: counts of |z| beyond 1, 2, 3σ."""

import math

import pytest
from scipy.stats import binomtest

from maxwell_kinetics.app.comparisons.verdicts import z_calibration
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
