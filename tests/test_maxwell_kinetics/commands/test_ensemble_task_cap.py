"""An ensemble holds at most ``MAX_TASKS`` tasks (seeds x parameter sets) in all, counted from
the ranges' bounds before any seed is listed: ``--seeds 1-10000000`` grew to 4.5 GB in 90 s with
no task written, because the only cap was on each range (10**7 seeds), so a comma list of ranges
each under it, or one range times a parameter sweep, expanded without bound."""

from __future__ import annotations

import itertools
import time

import pytest
from helpers import run_error

from particles.ensemble import EnsembleSpec, parse_seeds
from particles.ensemble.spec import MAX_TASKS
from particles.validation import InvalidArgumentError

ONE = {"n": 10, "restitution": 0.5}


def test_seeds_over_the_total_are_refused_before_anything_is_listed(capsys, tmp_path):
    out = tmp_path / "ens"
    seeds = "1-5000000,5000001-10000000"  # each range under the old per-range cap of 10**7
    start = time.perf_counter()
    err = run_error(capsys, ["ensemble", "ulam", "--n", "1000", "--restitution", "0.5",
                             "--tau", "1", "--seeds", seeds, "--out", str(out)])
    assert time.perf_counter() - start < 5.0  # no list of 10**7 seeds, let alone tasks
    assert f"argument seeds='{seeds}' is invalid" in err
    assert f"at most {MAX_TASKS} tasks" in err and "got 10000000 seeds" in err
    assert not out.exists()


def test_the_count_is_seeds_times_parameter_sets(capsys, tmp_path):
    # 20000 seeds in two ranges, under the cap alone; times 6 parameter sets, over it
    out = tmp_path / "ens"
    start = time.perf_counter()
    err = run_error(capsys, ["ensemble", "ulam", "--n", "10,20", "--restitution",
                             "0.3,0.5,0.9", "--tau", "1", "--seeds", "1-10000,10001-20000",
                             "--out", str(out)])
    assert time.perf_counter() - start < 5.0
    assert "argument seeds='1-10000,10001-20000' is invalid" in err
    assert "got 20000 seeds x 6 parameter sets = 120000); " in err
    assert f"at most {MAX_TASKS} tasks" in err
    assert not out.exists()


def test_the_library_counts_the_tasks_before_the_grid_and_the_seeds():
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError) as err:  # ranges each well under the old cap
        EnsembleSpec("ulam", {"n": [10, 20], "restitution": [0.3, 0.5, 0.9]},
                     "1-10000,10001-20000", (1.0,))
    assert err.value.name == "seeds" and "120000" in str(err.value)
    for seeds in (range(10**12), range(10**30), itertools.count(), [1] * (MAX_TASKS + 1)):
        with pytest.raises(InvalidArgumentError) as err:
            EnsembleSpec("ulam", ONE, seeds, (1.0,))
        assert err.value.name == "seeds" and f"at most {MAX_TASKS} tasks" in str(err.value)
    # a sweep over the cap on its own is the parameters' fault
    sweep = {"n": list(range(10, 410)), "restitution": [i / 1000 for i in range(400)]}
    with pytest.raises(InvalidArgumentError) as err:
        EnsembleSpec("ulam", sweep, [1], (1.0,))
    assert err.value.name == "params" and "160000 parameter sets" in str(err.value)
    assert time.perf_counter() - start < 5.0


def test_parse_seeds_takes_up_to_the_cap_in_all():
    assert len(parse_seeds(f"1-{MAX_TASKS}")) == MAX_TASKS
    assert len(parse_seeds(f"1-{MAX_TASKS // 2}", sets=2)) == MAX_TASKS // 2
    half = MAX_TASKS // 2
    for text, sets in ((f"0-{MAX_TASKS}", 1), (f"1-{half},{half + 1}-{MAX_TASKS + 1}", 1),
                       (f"1-{half}", 3), (f"1-{2**64 - 1}", 1)):
        with pytest.raises(InvalidArgumentError) as err:
            parse_seeds(text, sets=sets)
        assert err.value.name == "seeds" and err.value.value == text
        assert f"at most {MAX_TASKS} tasks" in str(err.value)
    # a repeated seed in a long list is found without a quadratic search
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError, match=r"repeated: \[5\]"):
        parse_seeds(f"1-{MAX_TASKS - 1},5")
    assert time.perf_counter() - start < 5.0
