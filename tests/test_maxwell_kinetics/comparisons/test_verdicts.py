"""Verdicts: the judge on known inputs, the records every comparison's summary carries, the
table ``reproduce`` prints, and exit status 3 when a measured value is moved outside its
tolerance.  The judge's tests are exact arithmetic (no statistics); the reproduce test runs
``tail_exponents`` at the small size once (about 2 s alone, 10 s on a loaded machine)."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from maxwell_kinetics.app import comparisons
from maxwell_kinetics.app.comparisons import _tail_exponents
from maxwell_kinetics.app.comparisons.verdicts import (
    STATUSES,
    Check,
    disagreeing,
    judge,
    pair,
    pooled_ratio,
    verdict_table,
    with_verdicts,
)
from particles.validation import InvalidArgumentError

#: The fields every verdict record of a summary holds.
FIELDS = {"claim", "quantity", "measured", "sigma", "expected", "source", "n_sigma", "tolerance",
          "relation", "tolerance_text", "status", "why", "explanation"}


def _check(measured, sigma=0.125, expected=1.0, **kw):
    """A check with binary-exact numbers (σ = 1/8: 3σ = 0.375), so that edges are exact."""
    return Check("q", measured, sigma, expected, "exact: test", **kw)


# --------------------------------------------------------------------------- the judge


def test_agrees_inside_the_tolerance_and_disagrees_just_outside():
    """3σ with σ = 1/8 allows 0.375: the edge agrees, 1e-9 beyond it disagrees, both sides."""
    assert judge("c", _check(1.375)).status == "agrees"
    assert judge("c", _check(0.625)).status == "agrees"
    assert judge("c", _check(1.375 + 1e-9)).status == "disagrees"
    assert judge("c", _check(0.625 - 1e-9)).status == "disagrees"
    # n_sigma, a stated tolerance and the expected value's own error widen it
    assert judge("c", _check(1.625, n_sigma=5)).status == "agrees"
    assert judge("c", _check(1.625 + 1e-9, n_sigma=5)).status == "disagrees"
    assert judge("c", _check(1.4375, tolerance=0.0625)).status == "agrees"
    assert judge("c", _check(1.4375 + 1e-9, tolerance=0.0625)).status == "disagrees"
    both = _check(1.0 + 3 * np.hypot(0.125, 0.25) * (1 - 1e-12), expected_sigma=0.25)
    assert judge("c", both).status == "agrees"
    assert both.allowed == pytest.approx(3 * np.hypot(0.125, 0.25))


def test_exact_numbers_need_a_stated_tolerance():
    assert judge("c", _check(1.0, sigma=None)).status == "agrees"
    assert judge("c", _check(1.0 + 1e-12, sigma=None)).status == "disagrees"
    assert judge("c", _check(1.0 + 1e-12, sigma=None, tolerance=1e-9)).status == "agrees"


def test_bounds_and_resolved_differences():
    assert judge("c", _check(1.375, relation="at_most")).status == "agrees"
    assert judge("c", _check(-5.0, relation="at_most")).status == "agrees"
    assert judge("c", _check(1.376, relation="at_most")).status == "disagrees"
    assert judge("c", _check(0.625, relation="at_least")).status == "agrees"
    assert judge("c", _check(9.0, relation="at_least")).status == "agrees"
    assert judge("c", _check(0.624, relation="at_least")).status == "disagrees"
    # a difference resolved by 3σ: 0.625 is exactly 3σ below 1, 0.626 is not
    assert judge("c", _check(0.625, relation="below")).status == "agrees"
    assert judge("c", _check(0.626, relation="below")).status == "disagrees"
    assert judge("c", _check(1.5, relation="below")).status == "disagrees"
    assert judge("c", _check(1.375, relation="above")).status == "agrees"
    assert judge("c", _check(1.374, relation="above")).status == "disagrees"
    assert judge("c", _check(0.5, relation="differs")).status == "agrees"
    assert judge("c", _check(1.5, relation="differs")).status == "agrees"
    assert judge("c", _check(1.25, relation="differs")).status == "disagrees"


def test_a_zero_difference_is_not_resolved():
    """With no standard error and no tolerance the allowed deviation is 0, and
    equal values do not differ, lie below or above: a resolved difference needs d != 0."""
    for relation in ("below", "above", "differs"):
        for sigma in (None, 0.0):
            check = _check(1.0, sigma=sigma, relation=relation)
            assert not check.holds(), relation
            assert judge("c", check).status == "disagrees", relation
    # any non-zero difference on the right side is resolved when nothing is allowed
    assert judge("c", _check(1.0 - 2**-20, sigma=None, relation="below")).status == "agrees"
    assert judge("c", _check(1.0 + 2**-20, sigma=None, relation="above")).status == "agrees"
    assert judge("c", _check(1.0 - 2**-20, sigma=None, relation="differs")).status == "agrees"
    # the bounds and equality still hold at zero difference
    for relation in ("equal", "at_most", "at_least"):
        assert judge("c", _check(1.0, sigma=None, relation=relation)).status == "agrees"


def test_an_expected_value_not_measured_does_not_hold():
    """Another model's number that is missing (None) is not replaced by a
    value: the check does not hold, whatever is measured, and its record shows no expected
    value."""
    check = Check("q", 0.0, 0.1, None, "model: another", expected_sigma=None)
    assert check.deviation is None and not check.holds()
    v = judge("c", check)
    assert v.status == "disagrees"
    record = v.to_dict()
    assert record["expected"] is None and record["deviation_in_sigma"] is None
    json.dumps(record, allow_nan=False)
    assert "vs — (model: another)" in verdict_table({"x": {"verdicts": [record]}})


def test_a_missing_md_value_is_not_zero_in_the_velocity_profiles():
    """The lattice's v(i) skewness is judged against MD's; an MD value that
    could not be measured at the shock scale was replaced by 0.0, so a lattice skewness near 0
    agreed with nothing.  It must not agree (nor be explained by a run too small: the lattice
    reached the scale)."""
    scales = [1, 4, 16, 64]

    def field(value, error):
        return {"scales": scales, "skewness": [[0.0, 0.1]] * 3 + [[value, error]]}

    s = {"coarse_skewness": {"md_vx": field(-1.0, 0.1), "md_vi": field(None, None),
                             "lattice_vi": field(0.0, 0.1)}}
    lattice = comparisons.VERDICTS["velocity_profiles"](s)[2].to_dict()
    assert "lattice" in lattice["claim"]
    assert lattice["expected"] is None
    assert lattice["status"] == "disagrees"


def test_explained_only_when_the_claim_fails_and_its_explanation_holds():
    fails, holds, also_fails = _check(2.0), _check(1.125), _check(3.0)
    v = judge("c", fails, holds, why="the cause")
    assert (v.status, v.why) == ("explained", "the cause")
    assert judge("c", fails, also_fails).status == "disagrees"
    assert judge("c", fails).status == "disagrees"
    # a claim that holds agrees whatever its explanation says
    assert judge("c", holds, also_fails).status == "agrees"


def test_a_quantity_not_measured_does_not_hold():
    for missing in (None, float("nan"), float("inf")):
        assert judge("c", _check(missing)).status == "disagrees"
        assert judge("c", _check(missing), _check(1.0)).status == "explained"
    assert pair([None, 0.1]) == (None, 0.1)
    assert pair(2.0) == (2.0, None)
    assert pair(None) == (None, None)


@pytest.mark.parametrize("kwargs, name", [
    ({"relation": "near"}, "relation"), ({"n_sigma": -1}, "n_sigma"),
    ({"tolerance": float("nan")}, "tolerance"), ({"sigma": -0.1}, "sigma"),
    ({"expected": float("inf")}, "expected"), ({"expected_sigma": -1.0}, "expected_sigma"),
])
def test_bad_checks_are_refused_naming_the_argument(kwargs, name):
    args = {"quantity": "q", "measured": 1.0, "sigma": 0.1, "expected": 1.0, "source": "s"}
    args.update(kwargs)
    with pytest.raises(InvalidArgumentError, match=name):
        Check(**args)


def test_judge_refuses_an_empty_claim_and_what_is_not_a_check():
    with pytest.raises(InvalidArgumentError, match="claim"):
        judge(" ", _check(1.0))
    with pytest.raises(InvalidArgumentError, match="check"):
        judge("c", 1.0)
    with pytest.raises(InvalidArgumentError, match="explanation"):
        judge("c", _check(1.0), explanation="because")


def test_records_hold_every_field_and_the_explanation():
    v = judge("claim", _check(2.0), _check(1.0), why="w")
    record = v.to_dict()
    assert FIELDS <= set(record)
    assert record["status"] == "explained"
    assert record["deviation_in_sigma"] == pytest.approx(8.0)
    assert record["explanation"]["holds"] is True
    json.dumps(record, allow_nan=False)
    summary = with_verdicts({"x": 1}, lambda s: [v])
    assert summary["verdicts"] == [record]
    with pytest.raises(InvalidArgumentError, match="verdicts"):
        with_verdicts({}, lambda s: [])
    assert disagreeing({"a": summary, "b": {}}) == []


def test_pooled_ratio_of_histogram_comparisons():
    """Σ χ²/φ over Σ dof, with error √(2/Σdof + mean (δφ/φ)²)."""
    rows = [{"chi2_dof": 2.0, "dof": 10, "overdispersion": [2.0, 0.2]},
            {"chi2_dof": 1.0, "dof": 30, "overdispersion": [1.0, 0.1]},
            {"chi2_dof": 5.0, "dof": 10, "overdispersion": [None, None]}]  # left out
    ratio, err = pooled_ratio(rows)
    assert ratio == pytest.approx((2.0 * 10 / 2.0 + 1.0 * 30) / 40)
    assert err == pytest.approx(np.sqrt(2 / 40 + 0.01))
    assert pooled_ratio(rows[2:]) == (None, None)


def test_the_table_has_one_line_per_claim_and_the_counts():
    ok = judge("claim one", _check(1.0), short="one").to_dict()
    bad = judge("claim two", _check(5.0)).to_dict()
    why = judge("claim three", _check(5.0), _check(1.0), why="the reason").to_dict()
    table = verdict_table({"first": {"verdicts": [ok, bad]}, "second": {"verdicts": [why]},
                           "none": {}})
    lines = table.splitlines()
    # header, rule, two groups of claims, rule, two notes, the counts, dof's legend, the exit
    # status
    assert len(lines) == 13 and lines[0].split() == ["claim", "measured", "±", "σ", "expected",
                                                     "z", "dof", "status"]
    assert max(len(line) for line in lines) <= 100
    assert lines[2] == "first:" and lines[5] == "second:"
    assert lines[3].split()[0] == "one" and lines[3].endswith("+0.0     ∞  agrees")
    assert "claim two" in lines[4] and "5 ± 0.125" in lines[4] and "+32.0" in lines[4] \
        and lines[4].endswith("disagrees [1]")
    assert "claim three" in lines[6] and lines[6].endswith("explained [2]")
    assert lines[8].startswith("[1] disagrees: 5 ± 0.125 vs 1 (exact: test)")
    assert lines[9] == "[2] explained: the reason"
    assert lines[10] == "1 agrees, 1 disagrees, 1 explained, 0 refuted, 0 not measured"
    assert lines[11].startswith("dof: ")
    assert disagreeing({"first": {"verdicts": [ok, bad]}}) == [("first", bad)]


def test_the_table_shows_the_degrees_of_freedom_of_each_z():
    """The dof column: the Welch–Satterthwaite dof of a measured expected value (one decimal),
    a seed count's (integer), ∞ for a normal law, ×k for the largest of k values, — without
    a z; the median line stays well inside the 100 columns."""
    records = [judge("seeds", _check(1.0, dof=3), short="seeds").to_dict(),
               judge("welch", _check(1.0, dof=3, expected_sigma=0.125, expected_dof=3),
                     short="welch").to_dict(),
               judge("welch, unequal", _check(1.0, dof=3, expected_sigma=0.25, expected_dof=7),
                     short="unequal").to_dict(),
               judge("scan", _check(1.0, dof=2, trials=11), short="scan").to_dict(),
               judge("law", _check(1.0), short="law").to_dict(),
               judge("exact", _check(1.0, sigma=None, tolerance=0.5), short="exact").to_dict()]
    lines = verdict_table({"x": {"verdicts": records}}).splitlines()
    rows = {line.split()[0]: line.split() for line in lines[3:9]}
    dof_column = {name: row[-2] for name, row in rows.items()}
    assert dof_column == {"seeds": "3", "welch": "6", "unequal": "9.5", "scan": "2×11",
                          "law": "∞", "exact": "—"}
    assert records[2]["combined_dof"] == pytest.approx(0.078125**2 / (2**-12 / 3 + 2**-8 / 7))
    widths = sorted(len(line) for line in lines)
    assert widths[-1] <= 100 and widths[len(widths) // 2] <= 90
    # a record of before the degrees of freedom (no combined_dof): no column value
    old = {k: v for k, v in records[0].items() if k not in ("dof", "combined_dof")}
    assert verdict_table({"x": {"verdicts": [old]}}).splitlines()[3].split()[-2] == "—"


# --------------------------------------------------------------------------- the comparisons


def test_every_comparison_makes_its_verdicts_with_the_judge():
    """One pattern per comparison module: ``verdicts(summary)`` and ``run`` ending with
    ``with_verdicts`` (so a new comparison cannot forget them)."""
    for name in comparisons.COMPARISONS:
        module = importlib.import_module(f"maxwell_kinetics.app.comparisons._{name}")
        assert callable(getattr(module, "verdicts", None)), name
        source = Path(module.__file__).read_text()
        assert "with_verdicts(summary, verdicts)" in source, name
        assert not any(f'"{s}"' in source for s in STATUSES), f"{name} writes a status by hand"


@pytest.mark.slow
@pytest.mark.parametrize("name", list(comparisons.COMPARISONS))
def test_every_summary_has_verdicts_with_the_required_fields(comparison, name):
    """At the small size (the session's comparisons, shared with the other comparison tests)."""
    verdicts = comparison(name).summary["verdicts"]
    assert len(verdicts) >= 1
    for v in verdicts:
        assert FIELDS <= set(v), name
        assert v["status"] in STATUSES
        assert v["claim"].strip() and "\n" not in v["claim"]
        assert v["source"].split(":")[0] in ("exact", "paper", "model"), v["source"]


# --------------------------------------------------------------------------- reproduce


def test_a_measured_value_moved_outside_its_tolerance_disagrees_and_exits_3(
        monkeypatch, tmp_path, capsys):
    """The Hill exponents' mean is moved by +10 (their 3σ at the small size is < 1): the
    particle verdicts turn into ``disagrees``, the files are still written, the table says so,
    and the exit status is 3; the untouched verdict (the paper's α = 5) still agrees."""
    from maxwell_kinetics.app.cli import main

    real = _tail_exponents.mean_sem
    monkeypatch.setattr(_tail_exponents, "mean_sem", lambda a: (real(a)[0] + 10.0, real(a)[1]))
    out = tmp_path / "r"
    argv = ["reproduce", "--small", "--only", "tail_exponents", "--no-progress", "--out", str(out)]
    assert main(argv) == 3
    printed = capsys.readouterr().out
    lines = printed.splitlines()
    start = lines.index("tail_exponents:") + 1
    rows = lines[start:start + len(lines[start:]) - len(
        [x for x in lines[start:] if not x.startswith("  ")])]
    written = json.loads((out / "summary.json").read_text())
    verdicts = written["comparisons"]["tail_exponents"]["verdicts"]
    assert len(rows) == len(verdicts) >= 2
    assert [v["status"] for v in verdicts] == ["agrees"] + ["disagrees"] * (len(verdicts) - 1)
    assert all("disagrees [" in row for row in rows[1:])
    assert (out / "tail_exponents.png").is_file() and (out / "tail_exponents.npz").is_file()
    # --json: the same summary (run_all is not run again: its result is what was written)
    from maxwell_kinetics.app import reproduce

    monkeypatch.setattr(reproduce, "run_all", lambda *a, **k: written)
    assert main(argv + ["--json"]) == 3
    payload = json.loads(capsys.readouterr().out)
    assert payload["disagrees"] == len(verdicts) - 1
    assert [v["status"] for v in payload["verdicts"]["tail_exponents"]] == \
        [v["status"] for v in verdicts]


# --------------------------------------------------------------------------- the docs page


def test_the_results_page_leads_with_the_verdicts_and_folds_the_numbers(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[3] / "docs" / "_ext"))
    sys.modules.pop("results", None)
    results = importlib.import_module("results")
    ok = judge("the claim", _check(1.0)).to_dict()
    why = judge("the other claim", _check(5.0), _check(1.0), why="the reason").to_dict()
    summary = {"size": "small", "comparisons": {
        "kinetic_theory": {"verdicts": [ok, why], "fit": {"slope": [1.0, 0.1]}}}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    (tmp_path / "kinetic_theory.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    page = results.render(tmp_path, tmp_path / "gen")
    section = page[page.index("## 1."):]
    # one expandable row per claim (short claim, measured ± σ, expected, z, status), before
    # the figure and the folded numbers
    assert section.index('<span class="v-claim">the claim</span>') \
        < section.index("```{figure}") < section.index("<details>\n") \
        < section.index("| `fit` | 1 ± 0.1 |") < section.index("\n</details>\n")
    row = section[section.index('<details class="verdict status-explained">'):]
    row = row[:row.index("</details>")]
    assert '<span class="v-claim">the other claim</span>' in row
    assert '<span class="v-num">5 ± 0.125</span><span class="v-num">1</span>' in row
    assert '<span class="v-num">+32.0</span><span class="v-status">explained</span>' in row
    assert "<dt>why</dt><dd>the reason</dd>" in row
    # opened: where σ comes from, its degrees of freedom, what this size resolves (3 · 0.125)
    assert "<dt>σ from</dt><dd>not recorded</dd>" in row
    assert "<dt>degrees of freedom</dt><dd>∞ (normal)</dd>" in row
    assert "<dd>deviations beyond 0.375 (38 % of the expected value)</dd>" in row
    assert ":width: 100%" in section  # scaled: Sphinx links it to the full-size image
    assert "1 agrees, 1 explained, 0 refuted, 0 not measured, 0 disagrees" in page


def test_the_results_page_calibrates_each_z_under_its_own_law(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[3] / "docs" / "_ext"))
    sys.modules.pop("results", None)
    results = importlib.import_module("results")
    # z = 4.93 from 3 seeds (t, 2 dof), the largest of 11 times: p = 1 − (1 − p₁)^11 with
    # p₁ = 1 − z/√(2 + z²) (t₂ exactly), 0.35, so its normal z is 0.93: beyond 2σ only under
    # the normal law
    sticky = judge("paired", _check(1.0 - 4.93 * 0.125, dof=2, trials=11, n_sigma=19.2,
                                    sigma_source="seeds: 3 runs")).to_dict()
    far = judge("far", _check(1.0 + 2.5 * 0.125)).to_dict()
    summary = {"size": "small", "comparisons": {"sticky_vs_md": {"verdicts": [sticky, far]}}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    page = results.render(tmp_path, tmp_path / "gen")
    calibration = page[page.index("## Calibration"):page.index("## 1.")]
    assert "| normal law (σ exact) | 2 | 2 (0.63) | 2 (0.09) | 1 (0.01) |" in calibration
    assert "| each z under its own law | 2 | 1 (0.63) | 1 (0.09) | 0 (0.01) |" in calibration
    assert "- sticky vs md: far (z = +2.50; normal law)" in calibration
    assert "paired (z" not in calibration
    assert "<dd>2 (Student's t), the largest |z| of 11</dd>" in page
    assert "<dt>σ from</dt><dd>seeds: 3 runs</dd>" in page
