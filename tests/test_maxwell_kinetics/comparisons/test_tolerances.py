"""Tolerances with a stated coverage: the quantile of each check's own law (Student's t of its
degrees of freedom, the largest of its trials) keeps the two-sided coverage of 3 normal σ, and
the seed-based checks of the comparisons allow it.  Exact arithmetic and synthetic summaries
(no runs)."""

from __future__ import annotations

import math

import pytest
from scipy import stats

from maxwell_kinetics.app.comparisons import VERDICTS
from maxwell_kinetics.app.comparisons.calibration import p_value
from maxwell_kinetics.app.comparisons.tolerances import NOMINAL_SIGMAS, t_sigmas
from maxwell_kinetics.app.comparisons.verdicts import Check, judge
from particles.validation import InvalidArgumentError

#: The two-sided tail of 3 normal σ.
TAIL = math.erfc(3 / math.sqrt(2))


def test_the_quantile_keeps_the_coverage_of_three_normal_sigma():
    """Known quantiles (4 seeds: 9.2189, 8: 4.5300), 3 for a normal law, and for every law the
    p-value of the allowed z under that law (the calibration's own p_value) is 0.27 %."""
    assert NOMINAL_SIGMAS == 3.0 and t_sigmas(None) == 3.0
    assert t_sigmas(3) == pytest.approx(9.2189, abs=1e-4)
    assert t_sigmas(7) == pytest.approx(4.5300, abs=1e-4)
    for dof, trials in ((2, 1), (3, 1), (5.5, 1), (60, 1), (None, 11), (2, 11), (3.6, 4)):
        assert p_value(t_sigmas(dof, 3.0, trials), dof, trials) == pytest.approx(TAIL, rel=1e-9)
    # the largest of 11 normal values: each at the Šidák coverage
    each = 1 - (1 - TAIL) ** (1 / 11)
    assert t_sigmas(None, 3.0, 11) == pytest.approx(stats.norm.isf(each / 2), rel=1e-12)
    assert t_sigmas(3, 2.0) == pytest.approx(stats.t.ppf(stats.norm.cdf(2.0), 3), rel=1e-12)


@pytest.mark.parametrize("bad", [{"dof": 0}, {"dof": -1.0}, {"dof": math.inf}, {"dof": True},
                                 {"n_sigma": 0.0}, {"n_sigma": math.nan},
                                 {"trials": 0}, {"trials": 1.5}])
def test_the_quantile_refuses_what_has_no_law(bad):
    args = {"dof": 3, "n_sigma": 3.0, "trials": 1, **bad}
    with pytest.raises(InvalidArgumentError, match=next(iter(bad))):
        t_sigmas(args["dof"], args["n_sigma"], args["trials"])


def test_a_check_under_its_own_law_allows_its_quantile():
    """σ = 1/8 from 4 seeds: 9.2189σ allowed (not 3σ); both sides measured with 3 dof each:
    the Welch–Satterthwaite 6 dof; no dof: 3σ; the record says how many σ."""
    k = t_sigmas(3)
    edge = 1.0 + k * 0.125
    check = Check("q", edge * (1 - 1e-12), 0.125, 1.0, "exact: test", dof=3, t_law=True)
    assert check.sigmas == pytest.approx(k) and check.allowed == pytest.approx(k * 0.125)
    assert judge("c", check).status == "agrees"
    beyond = Check("q", edge + 1e-9, 0.125, 1.0, "exact: test", dof=3, t_law=True)
    assert judge("c", beyond).status == "disagrees"
    assert judge("c", Check("q", 1.5, 0.125, 1.0, "exact: test", dof=3)).status == "disagrees"
    record = judge("c", check).to_dict()
    assert record["sigmas"] == pytest.approx(k) and record["t_law"] is True
    assert record["tolerance_text"] == "±9.22σ"
    both = Check("q", 1.0, 0.125, 1.0, "exact: test", expected_sigma=0.125, dof=3,
                 expected_dof=3, t_law=True)
    assert both.combined_dof == pytest.approx(6.0) and both.sigmas == pytest.approx(t_sigmas(6))
    law = Check("q", 1.0, 0.125, 1.0, "exact: test", t_law=True)
    assert law.sigmas == 3.0 and law.tolerance_text() == "±3σ"
    with pytest.raises(InvalidArgumentError, match="t_law"):
        Check("q", 1.0, 0.125, 1.0, "exact: test", t_law=1)


def _driven_summary(variance, error, seeds):
    row = {"restitution": 0.0, "variance": [variance, error], "variance_exact": 1.0,
           "variance_error_from": "seeds", "kurtosis": [3.0, 0.01], "kurtosis_exact": 3.0}
    return {"parameters": {"seeds": seeds}, "rows": [row]}


@pytest.mark.parametrize("seeds, status", [(4, "agrees"), (16, "disagrees")])
def test_a_seed_based_check_allows_the_quantile_of_its_seeds(seeds, status):
    """The driven steady variance 5σ above its exact value: inside t₃'s 9.22σ with 4 seeds,
    outside t₁₅'s 3.59σ with 16."""
    v = VERDICTS["driven_steady"](_driven_summary(1.0 + 5 * 0.0078125, 0.0078125, seeds))[0]
    assert v.check.t_law and v.check.dof == seeds - 1
    assert v.status == status


def test_the_hill_exponents_allow_the_quantile_of_their_runs():
    """A Hill exponent 5σ from the exact one over 4 runs agrees (9.22σ), over 16 it does not."""
    def summary(runs):
        particle = {"dimension": 2, "angular": "hard", "restitution": 0.0,
                    "alpha": [3.0 + 5 * 0.0625, 0.0625], "alpha_exact": 3.0,
                    "per_run": [3.0] * runs}
        return {"paper_2d_r0": {"hard": {"speed": 5.0}}, "particles": [particle]}

    four, sixteen = (VERDICTS["tail_exponents"](summary(n))[1] for n in (4, 16))
    assert four.status == "agrees" and four.check.sigmas == pytest.approx(t_sigmas(3))
    assert sixteen.status == "disagrees"
