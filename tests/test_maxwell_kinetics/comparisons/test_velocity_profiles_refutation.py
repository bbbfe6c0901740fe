"""``velocity_profiles``: the claim "lattice v(i) = MD v(i)" (skewness of the increments at the
shock scale m = 64) is ``refuted`` only when the lattice with MD's collision rate (a rate ∝
|v_i − v_(i+1)|, ``lattice_rv_vi``) shows the cause: its v(i) equals MD's within its t allowance
AND differs from the constant-rate lattice's by a resolved amount.  Otherwise it stays
``disagrees`` (and fails ``reproduce``).  Synthetic summaries judged by the comparison's
``verdicts``: no runs.

The values of :func:`_measured` are the 32-seed run (seeds 0-31, N = 2·10⁴, r = 0.99, t = 3000,
m = 64): constant-rate lattice −0.0924 ± 0.0387, MD +0.2505 ± 0.0319 (z = −6.84), rate-matched
lattice +0.0665 ± 0.0302 (z = −4.19 against MD, +3.24 against the constant-rate lattice)."""

from __future__ import annotations

import pytest
import scipy.stats  # noqa: F401  (t_sigmas's import, paid at collection, not by one test)

from maxwell_kinetics.app.comparisons import VERDICTS
from maxwell_kinetics.app.comparisons.tolerances import t_sigmas
from maxwell_kinetics.app.comparisons.verdicts import disagreeing

_SCALES = [1, 4, 16, 64, 256]


def _field(value, scales=_SCALES):
    """A coarse-skewness entry whose m = 64 value is ``value`` (others harmless)."""
    skew = [[0.0, 0.01] for _ in scales]
    if 64 in scales:
        skew[scales.index(64)] = list(value)
    return {"scales": list(scales), "skewness": skew}


def _summary(lat, rv=None, md_vi=(0.2505, 0.0319), seeds=32, scales=_SCALES):
    coarse = {"md_vx": _field((-0.2023, 0.0494), scales), "md_vi": _field(md_vi, scales),
              "lattice_vi": _field(lat, scales)}
    if rv is not None:
        coarse["lattice_rv_vi"] = _field(rv, scales)
    return {"parameters": {"md_seeds": seeds, "lattice_seeds": seeds}, "coarse_skewness": coarse}


def _lattice(summary):
    records = [v.to_dict() for v in VERDICTS["velocity_profiles"](summary)]
    (found,) = [v for v in records if v["short"] == "4: lattice v(i) = MD v(i)"]
    return found


def _measured(rv=(0.0665, 0.0302)):
    return _summary((-0.0924, 0.0387), rv)


def test_the_measured_run_disagrees_the_rate_matched_lattice_misses_md():
    v = _lattice(_measured())
    assert v["status"] == "disagrees"
    assert "not shown" in v["why"]  # the record claims no cause the run does not show
    assert v["deviation_in_sigma"] == pytest.approx(-6.84, abs=0.01)
    ref = v["refutation"]
    # the rate moves v(i) by a resolved amount, but not onto MD's
    assert ref["holds"] is False and ref["expected"] == pytest.approx(0.2505)
    assert ref["deviation_in_sigma"] == pytest.approx(-4.19, abs=0.01)
    (moves,) = ref["requires"]
    assert moves["holds"] is True and moves["relation"] == "differs"
    assert moves["deviation_in_sigma"] == pytest.approx(3.24, abs=0.01)
    assert disagreeing({"velocity_profiles": {"verdicts": [v]}}) == [("velocity_profiles", v)]


def test_refuted_when_the_rate_matched_lattice_is_md_and_moves_away_from_the_constant_rate():
    v = _lattice(_measured(rv=(0.23, 0.03)))
    assert v["status"] == "refuted"
    assert "the lattice's v(i) is MD's" in v["why"]
    ref = v["refutation"]
    assert ref["holds"] is True and ref["requires"][0]["holds"] is True
    for c in (ref, ref["requires"][0]):  # each under its own t law (32 + 32 seeds)
        assert c["t_law"] is True
        assert c["sigmas"] == pytest.approx(t_sigmas(c["combined_dof"]))
        assert 31 < c["combined_dof"] <= 62
    assert disagreeing({"velocity_profiles": {"verdicts": [v]}}) == []  # refuted does not fail


def test_a_rate_matched_lattice_too_noisy_to_move_does_not_refute():
    # agrees with MD only because its error is wide: it agrees with the constant rate too
    v = _lattice(_measured(rv=(0.10, 0.30)))
    assert v["status"] == "disagrees"
    assert v["refutation"]["holds"] is True  # rv = MD within its (wide) allowance
    assert v["refutation"]["requires"][0]["holds"] is False  # not resolved from constant rate


def test_a_rate_matched_lattice_far_from_md_does_not_refute():
    v = _lattice(_measured(rv=(-0.09, 0.03)))  # the rate changed nothing
    assert v["status"] == "disagrees"
    v = _lattice(_measured(rv=(0.9, 0.03)))  # moved, past MD
    assert v["status"] == "disagrees"
    assert v["refutation"]["requires"][0]["holds"] is True


def test_a_summary_without_the_rate_matched_lattice_disagrees():
    v = _lattice(_summary((-0.0924, 0.0387)))
    assert v["status"] == "disagrees"
    assert v["refutation"]["measured"] is None and v["refutation"]["holds"] is False


def test_an_agreeing_lattice_and_a_run_too_small_are_unchanged():
    assert _lattice(_summary((0.24, 0.03), rv=(-0.5, 0.01)))["status"] == "agrees"
    small = _summary((-0.0924, 0.0387), rv=(0.23, 0.03), scales=[1, 4, 16])
    v = _lattice(small)
    assert v["status"] == "not measured" and v["measured_at"] == "default"
    assert "coarse-grain" in v["why"]
