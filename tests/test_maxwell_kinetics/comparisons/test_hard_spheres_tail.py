"""The tail part of comparison 13, hard_spheres (``_hard_spheres_tail``): the window rule, the
Maxwell model's scaled density from its Fourier fixed point, and the claims' logic on
synthetic cooling states (the Maxwell model's own state agrees, an exact exponential with a
collision rate ∝ |c| is refuted, the same without that cause disagrees) and on planted
records (a drifting rate is not measured, a stable one is judged)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

from maxwell_kinetics.app.comparisons import _hard_spheres_tail as hs_tail
from maxwell_kinetics.sphere_grid import GRIDS
from maxwell_kinetics.tails import tail_exponent
from particles.sphere_kernels import HardSpheres

matplotlib.use("Agg")

#: The default size's d = 2 second grid.
SECOND = GRIDS[2]["coarse"]
#: ζ* that makes the predicted A = 2K/ζ* = 3 for hard disks (K = 4).
ZETA = 8.0 / 3.0


def _states(law, d=2):
    """Two synthetic 'cooling states' F = law(|c|) on the default size's grids of d."""
    out = []
    for grid in (GRIDS[d]["default"], GRIDS[d]["coarse"]):
        axes = np.meshgrid(*([grid.nodes()] * d), indexing="ij")
        r = np.sqrt(sum(x**2 for x in axes))
        out.append(SimpleNamespace(F=law(r), grid=grid, dimension=d, cooling_rate=ZETA))
    return out


def _row(tail, d=2):
    return {"dimension": d, "grid": "default", "second_grid": "coarse", "tail": tail}


def _statuses(row):
    return {v.short: v.status for v in hs_tail.verdicts(row)}


def _hard_loss(state):
    """A hard-disk-like collision loss ν F with ν = K|c| (K = 4): the rate grows with |c|."""
    axes = np.meshgrid(*([state.grid.nodes()] * state.dimension), indexing="ij")
    return 4.0 * np.sqrt(sum(x**2 for x in axes)) * state.F


def _maxwell_loss(state):
    """The Maxwell model's loss: ν = 1 at every c."""
    return np.asarray(state.F)


@pytest.fixture(scope="module")
def exponential():
    # F ∝ exp(−3|c|): the fitted form with μ = 0 and A = 3, the predicted rate itself
    return hs_tail.measure(_states(lambda r: np.exp(-3.0 * r)), HardSpheres(0.5), 2,
                           loss=_hard_loss)


def test_the_window_is_the_outermost_one_of_five_and_a_half_shells():
    lo, hi, shift = hs_tail.tail_window(7.0, 0.5)
    assert (hi - lo) == pytest.approx(hs_tail.WINDOW_SHELLS * 0.5)
    assert shift == pytest.approx((hi - lo) / 4) and hi + shift == pytest.approx(7.0)


def test_the_maxwell_density_is_of_unit_variance_with_the_tails_power_law():
    # d = 2, α = 0.5 ("uniform", the γ = 0 variable hard spheres): ∫F dc = 1 and ⟨|c|²⟩ = d
    # (unit variance per component, as the spectral grid's c), and the local log-log slope
    # −d ln F/d ln c at large c tends to the DENSITY exponent d + 2s* of maxwell_kinetics.tails
    law = tail_exponent(2, 0.5, "uniform")
    c = np.linspace(0.0, 60.0, 2401)[1:]
    F = hs_tail.maxwell_density(0.5, 2, c)
    dc = c[1] - c[0]
    assert np.sum(2 * math.pi * c * F) * dc == pytest.approx(1.0, abs=2e-3)
    assert np.sum(2 * math.pi * c**3 * F) * dc == pytest.approx(2.0, abs=2e-2)
    far = np.array([20.0, 25.0])
    slope = -np.diff(np.log(hs_tail.maxwell_density(0.5, 2, far))) / np.diff(np.log(far))
    assert slope[0] == pytest.approx(law.exponents["density"], rel=0.05)


def test_the_maxwell_models_own_state_agrees_with_the_claim():
    # the claim's logic: a cooling state whose tail IS the Maxwell model's (its exact scaled
    # state on the grids) is fitted with the Maxwell model's own A, and the claim "the
    # Maxwell model's power-law tail is this tail" agrees, never refuted
    states = _states(lambda r: hs_tail.maxwell_density(0.5, 2, r))
    record, figure = hs_tail.measure(states, HardSpheres(0.5), 2, loss=_maxwell_loss)
    assert record["measured"] and figure is not None
    assert record["window"][0] >= hs_tail.TAIL_START
    assert record["rate"] == pytest.approx(record["maxwell"]["rate"], abs=1e-9)
    # 1 but for the grid's normalisation of F (its sum over the box) and the shell's mean of
    # ln F taken at the shell's mean |c|
    assert record["maxwell"]["density_ratio"] == pytest.approx(1.0, rel=5e-3)
    assert _statuses(_row(record))["d=2: Maxwell tail = HS tail"] == "agrees"


def test_an_exact_exponential_is_refuted_and_its_rate_found(exponential):
    record, _ = exponential
    assert record["measured"] and record["rate"] == pytest.approx(3.0, abs=1e-9)
    assert record["predicted_rate"] == pytest.approx(3.0, rel=1e-12)
    # the window: the outermost inside both grids' resolved profiles (the cutoffs R = 7.5, 7)
    assert min(record["resolved"]) <= 7.0
    assert record["window"][1] + record["shift"] == pytest.approx(min(record["resolved"]))
    assert record["grid_difference"] < 1e-9
    # A = 3 is far from the Maxwell model's own A on the same window (its exact state: not yet
    # its power law there, A > 0 but well below 1), and the collision frequency rises across
    # the window as K|c|: refuted, the cause shown
    maxwell = record["maxwell"]
    assert 0.0 < maxwell["rate"] < 1.0 and maxwell["numerical_error"] < 1e-6
    rates = record["collision_rate"]
    assert rates["ratio"] == pytest.approx(rates["speeds"][1] / rates["speeds"][0], rel=1e-3)
    statuses = _statuses(_row(record))
    assert statuses["d=2: Maxwell tail = HS tail"] == "refuted", maxwell
    assert statuses["d=2: HS tail A = 2K/ζ*"] in ("agrees", "not measured")
    # how far: the Maxwell model overpopulates the tail at the last resolved |c|
    assert record["maxwell"]["density_ratio"] > 1.0


def _planted(exponential, **changes):
    record = {**exponential[0], **changes}
    return _row(record)


def test_a_drifting_rate_is_not_measured_and_a_wrong_one_disagrees(exponential):
    # A's theory is judged only when the window starts beyond the crossover 2A (= 6 here) and
    # the window systematic is at most the fit error
    far = [6.2, 8.8]
    drifting = _planted(exponential, rate=3.3, rate_error=0.04, window_systematic=0.2,
                        grid_difference=0.01, window=far)
    assert _statuses(drifting)["d=2: HS tail A = 2K/ζ*"] == "not measured"
    stable = _planted(exponential, rate=3.01, rate_error=0.02, rate_dof=3,
                      window_systematic=0.01, grid_difference=0.0, window=far)
    assert _statuses(stable)["d=2: HS tail A = 2K/ζ*"] == "agrees"
    wrong = _planted(exponential, rate=3.6, rate_error=0.02, rate_dof=3,
                     window_systematic=0.01, grid_difference=0.0, window=far)
    assert _statuses(wrong)["d=2: HS tail A = 2K/ζ*"] == "disagrees"
    # the same stable fit on a window before the crossover measures the crossover
    early = _planted(exponential, rate=3.6, rate_error=0.02, rate_dof=3,
                     window_systematic=0.01, grid_difference=0.0, window=[3.7, 6.2])
    verdict = next(v for v in hs_tail.verdicts(early) if v.short == "d=2: HS tail A = 2K/ζ*")
    assert verdict.status == "not measured" and "before the crossover 2A = 6.00" in verdict.why


def test_a_check_too_loose_to_tell_the_tails_apart_is_not_measured(exponential):
    # the full size's d = 2 grids (fine, default): the second grid's cutoff bends F inside the
    # window, a grid difference of 0.74 in A and 3 dof each let the check allow 2.8, more
    # than the gap 2K/ζ* − A_Maxwell: the claim must not agree, it is not measured
    record = exponential[0]
    loose = _planted(exponential, rate=2.55, rate_error=0.135, rate_dof=3,
                     grid_difference=0.74,
                     maxwell={**record["maxwell"], "rate": 0.26, "rate_error": 0.017,
                              "rate_dof": 3, "difference_systematic": 0.87})
    verdict = next(v for v in hs_tail.verdicts(loose)
                   if v.short == "d=2: Maxwell tail = HS tail")
    assert verdict.check.allowed > 3.0 - 0.26 and verdict.check.holds()
    assert verdict.status == "not measured" and "cannot tell the two tails apart" in verdict.why
    # the same record with the default size's grid difference is resolved again (refuted)
    tight = _planted(exponential, rate=2.55, rate_error=0.135, rate_dof=3,
                     grid_difference=0.0,
                     maxwell={**record["maxwell"], "rate": 0.26, "rate_error": 0.017,
                              "rate_dof": 3, "difference_systematic": 0.2})
    assert _statuses(tight)["d=2: Maxwell tail = HS tail"] == "refuted"


def test_a_failure_without_the_rising_collision_rate_is_not_refuted():
    # the same exponential with the Maxwell model's constant collision rate: the check fails
    # as before, but the cause is not shown, so the verdict is a plain disagreement
    record, _ = hs_tail.measure(_states(lambda r: np.exp(-3.0 * r)), HardSpheres(0.5), 2,
                                loss=_maxwell_loss)
    assert record["collision_rate"]["ratio"] == pytest.approx(1.0, abs=1e-12)
    assert _statuses(_row(record))["d=2: Maxwell tail = HS tail"] == "disagrees"


def test_no_window_and_no_cooling_state_are_not_measured(exponential):
    # a profile resolved only to |c| = 5 on the coarser grid (the d = 3 grids: 4–5) leaves no
    # window starting at |c| ≥ 3: both claims not measured, with the reason
    law = lambda r: np.exp(-3.0 * r)  # noqa: E731
    states = _states(law)
    states[1].F = np.where(np.hypot(*np.meshgrid(SECOND.nodes(), SECOND.nodes())) < 5.0,
                           states[1].F, 0.0)
    record, figure = hs_tail.measure(states, HardSpheres(0.5), 2, loss=_hard_loss)
    assert not record["measured"] and figure is None and "below |c| = 3" in record["reason"]
    assert set(_statuses(_row(record)).values()) == {"not measured"}
    assert hs_tail.verdicts(_row(hs_tail.not_computed(2))) == []
    # d = 3: even an exact exponential leaves no window on the default size's grids (shells
    # of h = 0.75 up to the cutoffs R = 7, 6): not measured, the reason recorded
    record, figure = hs_tail.measure(_states(law, 3), HardSpheres(0.5), 3, loss=_hard_loss)
    assert not record["measured"] and figure is None and record["window"][0] < 3.0
    statuses = _statuses(_row(record, 3))
    assert statuses == {"d=3: Maxwell tail = HS tail": "not measured",
                        "d=3: HS tail A = 2K/ζ*": "not measured"}
    # the records name no window that starts below the rule's first |c| (here a negative one)
    for v in hs_tail.verdicts(_row(record, 3)):
        assert "none from |c| ≥ 3" in v.check.quantity and "[-" not in v.check.quantity


def test_the_panel_draws_the_fit_the_prediction_and_the_maxwell_model(exponential):
    import matplotlib.pyplot as plt

    record, figure = exponential
    fig, ax = plt.subplots()
    try:
        assert hs_tail.draw(ax, [_row(record)], [{"tail": figure}])
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any(x.startswith("fit A = 3.00") for x in labels)
        assert any("2K/ζ* = 3.00" in x for x in labels)
        assert any("Maxwell model" in x for x in labels)
        assert not hs_tail.draw(ax, [_row(hs_tail.not_computed(2))], [{"tail": None}])
    finally:
        plt.close(fig)


def test_the_table_names_a_grid_no_size_uses_not_a_flag(exponential):
    # a claim that no size of reproduce measures says where it would be measured in words; a
    # claim measured at another size names that size's flag
    from maxwell_kinetics.app.comparisons.verdicts import verdict_table, with_verdicts

    record, _ = exponential
    drifting = dict(record, window_systematic=5 * record["rate_error"] + 0.1)
    summary = with_verdicts({"rows": [_row(drifting)]},
                            lambda s: hs_tail.verdicts(s["rows"][0]))
    table = verdict_table({"hard_spheres": summary})
    assert "measured on a wider grid than any size's (none yet), not at this size" in table
    assert "--a wider" not in table
