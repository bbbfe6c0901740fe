"""The worker count: never more workers than tasks, and a bound (4 × the CPUs) above which a
count is refused unless forced, in the Python API and in ``ensemble`` and ``reproduce``."""

from __future__ import annotations

import os

import pytest
from helpers import run_error

from particles import ensemble
from particles.ensemble import EnsembleSpec, run_ensemble
from particles.validation import InvalidArgumentError
from particles.workers import check_workers, max_workers

BOUND = 4 * (os.cpu_count() or 1)


def test_bound_is_four_times_the_cpus():
    assert max_workers() == BOUND


@pytest.mark.parametrize("bad", [0, -1, 2.0, True, "2", None])
def test_bad_counts(bad):
    if bad is None:
        assert check_workers(None) is None
        return
    with pytest.raises(InvalidArgumentError, match="workers"):
        check_workers(bad)


def test_above_the_bound_is_refused_unless_forced():
    assert check_workers(BOUND) == BOUND
    with pytest.raises(InvalidArgumentError, match=rf"workers={BOUND + 1}.*at most {BOUND}"):
        check_workers(BOUND + 1)
    assert check_workers(BOUND + 1, force=True) == BOUND + 1
    assert check_workers(100_000, force=True, tasks=2) == 2


def _spy_connect(monkeypatch):
    """Record the worker count the local cluster would get; run the tasks in this process."""
    seen = []

    def connect(executor, workers, scheduler, cluster, config):
        seen.append(workers)
        return None, []

    monkeypatch.setattr(ensemble.run, "connect", connect)
    return seen


def test_no_more_workers_than_tasks(monkeypatch, tmp_path):
    seen = _spy_connect(monkeypatch)
    spec = EnsembleSpec("ulam", {"n": 50, "restitution": 0.5}, (1, 2), (1.0,))
    report = run_ensemble(spec, tmp_path / "a", workers=BOUND, progress=False)
    assert seen == [2] and len(report.ran) == 2
    # default (one per CPU) is capped too; a rerun with nothing left starts no cluster at all
    run_ensemble(spec, tmp_path / "b", progress=False)
    assert seen[-1] == min(os.cpu_count() or 1, 2)
    run_ensemble(spec, tmp_path / "b", workers=2, progress=False)
    assert len(seen) == 2


def test_api_refuses_above_the_bound_before_any_work(monkeypatch, tmp_path):
    seen = _spy_connect(monkeypatch)
    spec = EnsembleSpec("ulam", {"n": 50, "restitution": 0.5}, (1, 2), (1.0,))
    with pytest.raises(InvalidArgumentError, match="force"):
        run_ensemble(spec, tmp_path / "out", workers=100_000, progress=False)
    assert seen == [] and not (tmp_path / "out").exists()
    run_ensemble(spec, tmp_path / "out", workers=100_000, force=True, progress=False)
    assert seen == [2]


def test_cli_refuses_above_the_bound(capsys, tmp_path):
    base = ["--n", "100", "--restitution", "0.5", "--tau", "1", "--seeds", "1-2"]
    err = run_error(capsys, ["ensemble", "ulam", *base, "--workers", "100000",
                             "--out", str(tmp_path / "e")])
    assert "workers=100000" in err and f"at most {BOUND}" in err and "--force" in err
    err = run_error(capsys, ["reproduce", "--small", "--workers", "100000",
                             "--out", str(tmp_path / "r")])
    assert "workers=100000" in err and f"at most {BOUND}" in err
    assert not (tmp_path / "e").exists() and not (tmp_path / "r").exists()


def test_cli_force_starts_only_as_many_workers_as_tasks(capsys, monkeypatch, tmp_path):
    from helpers import run_json

    seen = _spy_connect(monkeypatch)
    payload = run_json(capsys, ["ensemble", "ulam", "--n", "100", "--restitution", "0.5",
                                "--tau", "1", "--seeds", "1-2", "--workers", "100000", "--force",
                                "--out", str(tmp_path / "e"), "--json", "--no-progress"])
    assert seen == [2] and payload["tasks"] == 2
