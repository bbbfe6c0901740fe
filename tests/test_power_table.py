"""The resolving-power tables: ``docs/figures/power_small.json`` (written by
``benchmarks/power.py``) covers every registered comparison, its schema, that of
``power_default.json``, and the rendering of the tables on "Reproducing the paper"
(``docs/_ext/results.py``)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
ROW_KEYS = {"claim", "status", "relation", "z", "allowance", "ratio"}
STATUSES = {"agrees", "disagrees", "explained", "refuted", "not measured"}


@pytest.fixture(scope="module")
def results():
    """``docs/_ext/results.py``, imported as the docs test does (its folder on the path)."""
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import results
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    return results


def _json(name: str) -> dict:
    return json.loads((DOCS / "figures" / name).read_text())


def _check_row(row: dict, full: bool) -> None:
    assert isinstance(row["claim"], str) and row["claim"]
    assert row["z"] is None or isinstance(row["z"], (int, float))
    if full:
        assert set(row) == ROW_KEYS, row
        assert row["status"] in STATUSES
        assert row["ratio"] is None or row["ratio"] >= 0


def test_every_comparison_has_a_power_entry():
    from maxwell_kinetics.app.comparisons import COMPARISONS

    data = _json("power_small.json")
    assert data["size"] == "small"
    for name in COMPARISONS:
        entry = data["comparisons"].get(name)
        assert entry, f"{name}: no entry in power_small.json"
        if entry.get("no_plant"):
            assert isinstance(entry["no_plant"], str) and len(entry["no_plant"]) > 20
            continue
        planted = [p for p, runs in entry["plants"].items() if any(float(e) > 0 for e in runs)]
        assert planted, f"{name}: no planted error measured"
        assert all(p in data["plants"] for p in planted), name


def test_power_small_schema():
    data = _json("power_small.json")
    assert set(data["plants"]) >= {p for e in data["comparisons"].values()
                                   for p in e.get("plants", {})}
    for name, entry in data["comparisons"].items():
        assert set(entry) <= {"plants", "baseline", "no_plant"}, name
        for row in entry.get("baseline", {}).get("verdicts", []):
            _check_row(row, True)
        for runs in entry.get("plants", {}).values():
            for eps, out in runs.items():
                assert 0.0 <= float(eps) < 1.0
                for row in out["verdicts"] + out["disagrees"]:
                    _check_row(row, True)
                assert all(r["status"] == "disagrees" for r in out["disagrees"])
                if out["largest"] is not None:
                    _check_row(out["largest"], True)
                    assert out["largest"]["status"] != "not measured"
                if float(eps) > 0:
                    assert out["seconds"] >= 0 and out["load"]


def test_power_default_schema():
    """Each default-size result is either copied from benchmarks/README.md (naming its
    section) or measured by benchmarks/power.py (with every verdict, seconds and load)."""
    data = _json("power_default.json")
    assert data["size"] == "default"
    for entry in data["comparisons"].values():
        for runs in entry["plants"].values():
            for eps, out in runs.items():
                assert 0.0 <= float(eps) < 1.0
                if float(eps) == 0:
                    continue
                measured = "verdicts" in out
                if measured:
                    assert out["seconds"] >= 0 and out["load"] and "source" not in out
                    for row in out["verdicts"]:
                        _check_row(row, True)
                else:
                    assert out["source"].startswith("benchmarks/README.md, section")
                for row in out["disagrees"] + [out["largest"] or {"claim": "-", "z": None}]:
                    _check_row(row, measured)


SMALL = {"size": "small",
         "plants": {"ulam_rate": "the rate × (1 + ε)", "md_p": "MD's p"},
         "comparisons": {
             "demo": {"plants": {
                 "ulam_rate": {
                     "0": {"disagrees": [], "largest": None,
                           "verdicts": [{"claim": "E at the end", "status": "agrees",
                                         "z": 0.1, "allowance": 3.0, "ratio": 0.03}]},
                     "0.01": {"disagrees": [{"claim": "E at the end", "status": "disagrees",
                                             "z": -11.2, "allowance": 3.0, "ratio": 3.73}],
                              "largest": None, "verdicts": []}},
                 "md_p": {
                     "0": {"disagrees": [], "largest": None,
                           "verdicts": [{"claim": "Haff slope", "status": "agrees",
                                         "z": 0.75, "allowance": 19.2, "ratio": 0.04}]},
                     "0.01": {"disagrees": [], "largest": None, "verdicts": []},
                     "0.05": {"disagrees": [],
                              "largest": {"claim": "Haff slope", "status": "agrees",
                                          "z": -0.09, "allowance": 19.2, "ratio": 0.005},
                              "verdicts": [{"claim": "Haff slope", "status": "agrees",
                                            "z": -0.09, "allowance": 19.2, "ratio": 0.005}]}},
                 "lattice_p": {"0": {"disagrees": [], "largest": None, "verdicts": []},
                               "0.05": {"disagrees": [], "largest": None, "verdicts": [
                                   {"claim": "signs", "status": "not measured", "z": None,
                                    "allowance": 3.0, "ratio": None}]}},
                 "dsmc_rate": {"0": {"disagrees": [], "largest": None, "verdicts": []}}}},
             "bare": {"no_plant": "No engine parameter: the comparison is exact arithmetic."}}}
DEFAULT = {"size": "default", "comparisons": {"demo": {"plants": {"ulam_rate": {
    "0.01": {"disagrees": [{"claim": "E at the end", "z": -114.0}], "largest": None,
             "source": "benchmarks/README.md, section x"}}}}}}


def test_the_table_has_a_row_per_planted_error(results):
    lines = results.power_table("demo", SMALL, DEFAULT)
    rows = [line for line in lines if line.startswith("- ")]
    assert rows == [
        "- **the rate × (1 + ε).** `--small`: 1 %: “E at the end” z = -11.2 (allowed 3σ); "
        "default size: 1 %: “E at the end” z = -114",
        "- **MD's p.** `--small`: not at 5 %: it moves “Haff slope” most, from z = +0.75 to "
        "-0.09, against 19.2σ allowed; default size: —",
        "- **lattice_p.** `--small`: not at 5 %: every verdict is *not measured* at this size; "
        "default size: —",
    ]
    assert results.power_table("bare", SMALL) [-2] == (
        "No engine parameter: the comparison is exact arithmetic.")
    assert results.power_table("absent", SMALL) == []


def test_the_reproducing_page_shows_the_table(results, tmp_path):
    summary = {"size": "small", "comparisons": {"demo": {"parameters": {}, "verdicts": []}}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    page = results.render(tmp_path, tmp_path / "out", (SMALL, DEFAULT))
    assert "**Resolving power.**" in page
    assert "- **MD's p.** `--small`: not at 5 %" in page
    assert "default size: 1 %: “E at the end” z = -114" in page
    assert "Resolving power" not in results.render(tmp_path, tmp_path / "out")
