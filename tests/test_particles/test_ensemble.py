"""Ensembles (particles/ensemble.py): the spec, task files, reruns, failures, dask execution.

Reference for every result: :func:`particles.driver.simulate` run directly in this process with
the same engine, times and seed; ensembles must reproduce it bit for bit (same RNG stream, and
a resumed run equals an uninterrupted one).  Sizes are small (N = 10³, τ ≤ 12) so each run takes
milliseconds; the dask tests use 2 worker processes.
"""

from __future__ import annotations

import dataclasses
import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from particles import ensemble, persistence
from particles.driver import simulate
from particles.ensemble import (
    EnsembleSpec,
    load_task,
    parse_seeds,
    register_model,
    run_ensemble,
)
from particles.lattice import Lattice
from particles.ulam import Ulam
from particles.validation import InvalidArgumentError

N = 1000
TAU = (4.0, 8.0, 12.0)


# --------------------------------------------------------------------------- test models
# (module level: the workers unpickle the factories by reference, importing this module)


@dataclasses.dataclass(frozen=True)
class _KillerUlam(Ulam):
    """Ulam whose first advance to τ = 8 anywhere kills its own process (marker file)."""

    marker: str = ""

    def advance(self, state, until, rng):
        if until >= 8.0 and not os.path.exists(self.marker):
            Path(self.marker).touch()
            os._exit(1)
        return super().advance(state, until, rng)


def killer(n, restitution, marker):
    return _KillerUlam(n, restitution, "gaussian", marker=marker)


register_model("ulam-killer", killer)


def _spec(**kw):
    base = dict(model="ulam", params={"n": N, "restitution": [0.5, 0.9]}, seeds="1-3",
                times=TAU)
    base.update(kw)
    return EnsembleSpec(**base)


def _arrays(path):
    return persistence.load(path, "ensemble", (ensemble.FORMAT_VERSION,)).arrays


def _assert_same_arrays(a, b):
    assert sorted(a) == sorted(b)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key, strict=True)


# --------------------------------------------------------------------------- seeds and spec


def test_parse_seeds():
    assert parse_seeds("1-16,20,25-27") == (*range(1, 17), 20, 25, 26, 27)
    assert parse_seeds(" 7 , 3-3 ") == (7, 3)
    assert parse_seeds(f"0,{2**64 - 1}") == (0, 2**64 - 1)
    for bad in ("", "1,,2", "1,", "5-3", "1,1", "1-3,2", "-1", "a", "1-2-3", "1.5",
                str(2**64), "1 2"):
        with pytest.raises(InvalidArgumentError) as err:
            parse_seeds(bad)
        assert err.value.name == "seeds"


def test_expand_is_the_product_of_swept_parameters_and_seeds():
    spec = _spec(params={"n": [N, 2 * N], "restitution": [0.5, 0.7, 0.9]}, seeds=[5, 2])
    tasks = spec.expand()
    assert [(t.params["n"], t.params["restitution"], t.seed) for t in tasks] == [
        (n, r, s) for n in (N, 2 * N) for r in (0.5, 0.7, 0.9) for s in (5, 2)
    ]
    assert [t.set_index for t in tasks] == [i for i in range(6) for _ in range(2)]
    assert len({t.key for t in tasks}) == 12
    # the key is the run's identity: 1e3 and 1000 (engine parameters) are the same task
    again = _spec(params={"n": [1e3], "restitution": 0.5}, seeds=[5]).expand()[0]
    assert again.key == tasks[0].key
    # ... and it changes with what the result depends on
    for other in (_spec(seeds=[6]), _spec(times=(4.0, 8.0)),
                  _spec(options={"structure_factor": "last"}), _spec(model="lattice")):
        assert tasks[0].key not in {t.key for t in other.expand()}
    # but not with the checkpoint interval (no effect on the result)
    assert _spec(seeds=[5], options={"checkpoint_interval": 0}).expand()[0].key == tasks[0].key


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"model": "nope"}, "model"),
        ({"params": {"n": N, "restitution": 0.5, "speed": 1}}, "params"),
        ({"params": {"n": N}}, "params"),  # restitution missing
        ({"params": {"n": [], "restitution": 0.5}}, "n"),  # empty grid
        ({"params": {"n": [N, N], "restitution": 0.5}}, "n"),
        ({"params": {"n": N, "restitution": [0.5, 2.0]}}, "restitution"),
        ({"seeds": [1, 2, 1]}, "seeds"),
        ({"seeds": []}, "seeds"),
        ({"seeds": [-1]}, "seeds"),
        ({"seeds": [2**64]}, "seeds"),
        ({"times": (4.0, 2.0)}, "tau"),
        ({"options": {"frobnicate": True}}, "options"),  # snapshots is an option now
        # booleans taken for numbers, values that build one engine twice, bytes as seeds,
        # non-finite histogram edges
        ({"options": {"structure_factor": 1}}, "structure_factor"),
        ({"options": {"structure_factor": 0}}, "structure_factor"),
        ({"options": {"structure_factor": np.True_}}, "structure_factor"),
        ({"options": {"checkpoint_interval": True}}, "checkpoint_interval"),
        ({"options": {"bins": [0.0, 1.0, np.nan]}}, "bins"),
        ({"params": {"n": N, "restitution": True}}, "restitution"),
        ({"params": {"n": N, "restitution": [0.5, True]}}, "restitution"),
        ({"params": {"n": N, "restitution": [1, 1.0]}}, "params"),
        ({"params": {"n": [N, 1e3], "restitution": 0.5}}, "params"),
        ({"seeds": b"1"}, "seeds"),
        ({"times": [True, 2.0]}, "tau"),
    ],
)
def test_bad_spec_fails_before_any_work(tmp_path, kwargs, name):
    with pytest.raises(InvalidArgumentError) as err:
        _spec(**kwargs)
    assert err.value.name == name
    assert not any(tmp_path.iterdir())


def test_md_times_are_named_t():
    with pytest.raises(InvalidArgumentError) as err:
        EnsembleSpec("md", {"n": 100, "density": 1.0, "restitution": 0.5}, [1], [-1.0])
    assert err.value.name == "t"


# --------------------------------------------------------------------------- serial runs


@pytest.mark.parametrize("model, engine", [("ulam", Ulam), ("lattice", Lattice)])
def test_serial_ensemble_equals_simulate(tmp_path, model, engine):
    spec = _spec(model=model, options={"structure_factor": "last"})
    report = run_ensemble(spec, tmp_path / "out", executor="serial", progress=False)
    assert report.ok and report.tasks == 6 and len(report.ran) == 6
    energies = {}
    for task in spec.expand():
        ref = simulate(engine(**task.params), spec.times, task.seed, progress=False,
                       structure_factor="last")
        got = load_task(tmp_path / "out" / task.filename, task.identity)
        for name in ("times", "energy", "momentum", "collisions", "velocities"):
            np.testing.assert_array_equal(getattr(got, name), getattr(ref, name), strict=True)
        np.testing.assert_array_equal(got.histogram.density, ref.histogram.density)
        np.testing.assert_array_equal(got.structure[1], ref.structure[1])
        for key in ref.extras:
            np.testing.assert_array_equal(got.extras[key], ref.extras[key])
        energies.setdefault(task.set_index, []).append(ref.energy)
    # aggregate: mean and standard error (ddof = 1) over the 3 seeds, against NumPy's own
    a = _arrays(report.aggregate_path)
    for index, rows in energies.items():
        rows = np.array(rows)
        np.testing.assert_allclose(a[f"set{index}.energy.mean"], rows.mean(axis=0), rtol=1e-15)
        np.testing.assert_allclose(a[f"set{index}.energy.sem"],
                                   rows.std(axis=0, ddof=1) / np.sqrt(3), rtol=1e-12)
        s = report.aggregate["sets"][index]
        assert s["n_seeds"] == 3 and s["seeds"] == [1, 2, 3]
        assert s["observables"]["energy"]["mean"] == a[f"set{index}.energy.mean"].tolist()
        assert a[f"set{index}.structure.S.mean"].shape == (1, N // 2 + 1)
    assert report.aggregate["sets"][1]["params"] == {"n": N, "restitution": 0.9}
    json.dumps(report.to_json(), allow_nan=False)  # strict JSON


def test_one_seed_has_no_standard_error(tmp_path):
    report = run_ensemble(_spec(seeds=[4]), tmp_path, executor="serial", progress=False)
    obs = report.aggregate["sets"][0]["observables"]["energy"]
    assert obs["sem"] == [None, None, None] and None not in obs["mean"]


def test_same_seed_twice_gives_byte_identical_files(tmp_path):
    """Task files hold no wall-clock time, so two runs of one task write the same bytes."""
    spec = _spec(seeds=[3])
    for sub in ("a", "b"):
        run_ensemble(spec, tmp_path / sub, executor="serial", progress=False)
    for task in spec.expand():
        assert (tmp_path / "a" / task.filename).read_bytes() == (
            tmp_path / "b" / task.filename).read_bytes()


def test_interrupted_ensemble_runs_only_the_missing_tasks(tmp_path, monkeypatch):
    spec = _spec()  # 6 tasks
    calls = []
    real = ensemble.run_task

    def interrupted(task, factory, out):
        if len(calls) == 4:
            raise KeyboardInterrupt
        calls.append(task.key)
        return real(task, factory, out)

    monkeypatch.setattr(ensemble.run, "run_task", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(spec, tmp_path, executor="serial", progress=False)
    monkeypatch.setattr(ensemble.run, "run_task", real)
    report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert len(report.skipped) == 4 and set(report.skipped) == set(calls)
    assert len(report.ran) == 2 and not set(report.ran) & set(calls)
    again = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert len(again.ran) == 0 and len(again.skipped) == 6
    fresh = run_ensemble(spec, tmp_path / "fresh", executor="serial", progress=False)
    _assert_same_arrays(_arrays(report.aggregate_path), _arrays(fresh.aggregate_path))


def test_interrupted_task_resumes_from_its_checkpoint(tmp_path, monkeypatch):
    spec = _spec(seeds=[2], params={"n": N, "restitution": 0.5})
    task = spec.expand()[0]
    real = Ulam.advance

    def stop_at_8(self, state, until, rng):
        if until == 8.0:
            raise KeyboardInterrupt
        return real(self, state, until, rng)

    monkeypatch.setattr(Ulam, "advance", stop_at_8)
    with pytest.raises(KeyboardInterrupt):
        run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert (tmp_path / task.checkpoint_name).exists()  # saved by the driver on Ctrl-C
    assert not (tmp_path / task.filename).exists()
    monkeypatch.setattr(Ulam, "advance", real)
    report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert report.resumed == (task.key,)
    assert not (tmp_path / task.checkpoint_name).exists()
    ref = simulate(Ulam(N, 0.5), spec.times, 2, progress=False)
    got = load_task(tmp_path / task.filename)
    np.testing.assert_array_equal(got.velocities, ref.velocities)
    np.testing.assert_array_equal(got.energy, ref.energy)


def test_damaged_task_files_are_detected_recomputed_reported(tmp_path):
    spec = _spec()
    first = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    tasks = spec.expand()
    before = {t.key: (tmp_path / t.filename).read_bytes() for t in tasks}
    truncated, flipped, swapped = tasks[0], tasks[3], tasks[4]
    p = tmp_path / truncated.filename
    p.write_bytes(before[truncated.key][: len(before[truncated.key]) // 2])
    p = tmp_path / flipped.filename
    data = bytearray(before[flipped.key])
    data[len(data) // 2] ^= 0xFF  # one byte inside the velocities
    p.write_bytes(bytes(data))
    (tmp_path / swapped.filename).write_bytes(before[tasks[5].key])  # another task's file
    report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert sorted(report.ran) == sorted([truncated.key, flipped.key, swapped.key])
    found = {d["key"]: d for d in report.recomputed}
    assert set(found) == {truncated.key, flipped.key, swapped.key}
    assert found[swapped.key]["reason"] == "written for another task"
    assert found[flipped.key]["seed"] == flipped.seed
    assert found[flipped.key]["params"] == flipped.params
    assert all(d["reason"] for d in report.recomputed)
    after = {t.key: (tmp_path / t.filename).read_bytes() for t in tasks}
    assert after == before
    _assert_same_arrays(_arrays(first.aggregate_path), _arrays(report.aggregate_path))


def test_failing_task_others_finish(tmp_path):
    """MD with r = 0 and δ = 0 collapses (measured: N = 200, t < 0.5); δ = 0.01 runs."""
    spec = EnsembleSpec("md", {"n": 200, "density": 1.0, "restitution": 0.0,
                               "delta": [0.0, 0.01]}, [1, 2], [0.5, 1.0])
    report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    assert not report.ok and len(report.failed) == 2 and len(report.ran) == 4
    for f in report.failed:
        assert f["params"]["delta"] == 0.0 and f["seed"] in (1, 2)
        assert f["error"].startswith("InelasticCollapseError")
    sets = report.aggregate["sets"]
    assert sets[0]["n_seeds"] == 0 and sets[1]["n_seeds"] == 2
    # MD's own τ(t) is aggregated, not 2·collisions/N over again
    ok = [t for t in spec.expand() if t.set_index == 1]
    cpp = [load_task(tmp_path / t.filename).extras["collisions_per_particle"] for t in ok]
    assert sets[1]["observables"]["collisions_per_particle"]["mean"] == (
        (cpp[0] + cpp[1]) / 2).tolist()
    js = report.to_json()
    assert js["ok"] is False and js["failed"][0]["params"]["delta"] == 0.0
    json.dumps(js, allow_nan=False)


# --------------------------------------------------------------------------- the folder


def test_folder_of_another_format_version_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    persistence.save(out / ensemble.MANIFEST, "ensemble-manifest", ensemble.FORMAT_VERSION + 1,
                     {}, {})
    listing = sorted(out.iterdir())
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(), out, executor="serial", progress=False)
    assert err.value.name == "out" and "version" in str(err.value)
    assert sorted(out.iterdir()) == listing


def _listing(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_a_folder_of_other_files_is_refused_and_kept(tmp_path):
    # the user's own ensemble.npz (and nothing else) in a folder without a manifest
    out = tmp_path / "mine"
    out.mkdir()
    (out / ensemble.AGGREGATE).write_bytes(b"my own results")
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(), out, executor="serial", progress=False)
    assert err.value.name == "out" and str(out) in str(err.value)
    assert "no manifest.npz" in str(err.value) and "'ensemble.npz'" in str(err.value)
    assert _listing(out) == {ensemble.AGGREGATE: b"my own results"}


def test_another_ensemble_in_the_folder_is_refused_and_the_same_one_resumes(tmp_path):
    spec = _spec(seeds="1-2")
    first = run_ensemble(spec, tmp_path, executor="serial", progress=False)
    before = _listing(tmp_path)
    assert len(first.ran) == 4
    others = {"times": _spec(seeds="1-2", times=(4.0, 8.0)),
              "model": _spec(seeds="1-2", model="lattice"),
              "grid": _spec(seeds="1-2", params={"n": N, "restitution": [0.5, 0.7]}),
              "options": _spec(seeds="1-2", options={"structure_factor": "last"}),
              "fewer seeds": _spec(seeds="1")}
    for what, other in others.items():
        with pytest.raises(InvalidArgumentError) as err:
            run_ensemble(other, tmp_path, executor="serial", progress=False)
        assert err.value.name == "out" and str(tmp_path) in str(err.value), what
        assert _listing(tmp_path) == before, what  # nothing written, nothing replaced
    assert "seeds" in str(err.value)  # the last: why the fewer seeds are refused
    # the same spec resumes (a checkpoint interval changes no result: the same ensemble) ...
    again = run_ensemble(_spec(seeds="1-2", options={"checkpoint_interval": 5}), tmp_path,
                         executor="serial", progress=False)
    assert len(again.ran) == 0 and len(again.skipped) == 4
    after = _listing(tmp_path)  # the aggregate is written again (its spec has the interval)
    assert {k: v for k, v in after.items() if k != ensemble.AGGREGATE} == {
        k: v for k, v in before.items() if k != ensemble.AGGREGATE}
    # ... also with the swept values in another order (the same grid) ...
    again = run_ensemble(_spec(seeds="2,1", params={"n": N, "restitution": [0.9, 0.5]}),
                         tmp_path, executor="serial", progress=False)
    assert len(again.ran) == 0 and len(again.skipped) == 4
    # ... and more seeds run only the new ones
    more = run_ensemble(_spec(seeds="1-3"), tmp_path, executor="serial", progress=False)
    assert len(more.ran) == 2 and len(more.skipped) == 4


def test_a_manifest_of_an_earlier_release_is_judged_by_its_task_files(tmp_path):
    # a manifest without the ensemble it belongs to: adopted when every task file is this
    # spec's, refused otherwise
    spec = _spec(seeds="1")
    run_ensemble(spec, tmp_path, executor="serial", progress=False)
    persistence.save(tmp_path / ensemble.MANIFEST, "ensemble-manifest",
                     ensemble.FORMAT_VERSION, {}, {"writer": "particles.ensemble"})
    before = _listing(tmp_path)
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(seeds="2"), tmp_path, executor="serial", progress=False)
    assert err.value.name == "out" and "task files of another ensemble" in str(err.value)
    assert _listing(tmp_path) == before
    again = run_ensemble(_spec(seeds="1-2"), tmp_path, executor="serial", progress=False)
    assert len(again.ran) == 2 and len(again.skipped) == 2
    with pytest.raises(InvalidArgumentError):  # the manifest now names its ensemble
        run_ensemble(_spec(seeds="1-2", times=(4.0,)), tmp_path, executor="serial",
                     progress=False)


def test_bad_executor_arguments_write_nothing(tmp_path):
    out = tmp_path / "out"
    for kwargs, name in (({"workers": 0}, "workers"),
                         ({"workers": 2, "scheduler": "tcp://x:1"}, "scheduler"),
                         ({"cluster": "sge", "config": "x.toml"}, "cluster"),
                         ({"config": "x.toml"}, "config"),
                         ({"executor": "threads"}, "executor")):
        with pytest.raises(InvalidArgumentError) as err:
            run_ensemble(_spec(), out, progress=False, **kwargs)
        assert err.value.name == name
    for kwargs, name in (({"force": "no", "workers": 2}, "force"),
                         ({"shared": 1}, "shared"),
                         ({"progress": "no"}, "progress"),
                         ({"scheduler": ""}, "scheduler"), ({"scheduler": 5}, "scheduler"),
                         ({"cluster": "slurm", "config": 5}, "config")):
        with pytest.raises(InvalidArgumentError) as err:
            run_ensemble(_spec(), out, **{"progress": False, **kwargs})
        assert err.value.name == name
    assert not out.exists()


def test_unreachable_scheduler_is_a_clear_error(tmp_path, monkeypatch):
    monkeypatch.setattr(ensemble.cluster, "SCHEDULER_TIMEOUT", 1.0)
    out = tmp_path / "out"
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(), out, scheduler="tcp://127.0.0.1:9", progress=False)
    assert err.value.name == "scheduler"
    assert not out.exists()


# --------------------------------------------------------------------------- dask


def _local_cluster():
    from distributed import LocalCluster

    return LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                        scheduler_kwargs={"dashboard": False})


def test_dask_ensemble_on_a_scheduler_equals_serial(tmp_path):
    """``scheduler=ADDRESS``: an existing cluster (2 worker processes)."""
    spec = _spec(model="lattice")
    serial = run_ensemble(spec, tmp_path / "serial", executor="serial", progress=False)
    with _local_cluster() as cluster:
        report = run_ensemble(spec, tmp_path / "dask", scheduler=cluster.scheduler_address,
                              progress=False)
    assert report.executor == "dask" and report.ok and len(report.ran) == 6
    _assert_same_arrays(_arrays(serial.aggregate_path), _arrays(report.aggregate_path))
    for task in spec.expand():
        assert (tmp_path / "serial" / task.filename).read_bytes() == (
            tmp_path / "dask" / task.filename).read_bytes()


def test_batch_cluster_path_failure_is_reported_others_finish(tmp_path, monkeypatch):
    """``cluster="slurm"`` with a config, on a local stand-in for the batch cluster (no batch
    system here): the config is read, the cluster scaled to ``jobs`` and used, then closed."""
    from distributed import LocalCluster
    from distributed.core import Status

    made = []

    class StandIn(LocalCluster):
        scaled = None

        def scale(self, n=0, jobs=None, **kwargs):  # scale(jobs=...) keeps its 2 workers
            if jobs is None:
                return super().scale(n, **kwargs)
            self.scaled = jobs

    def make(kind, settings):
        assert kind == "slurm" and settings["cores"] == 2
        made.append(StandIn(n_workers=2, threads_per_worker=1, processes=True,
                            dashboard_address=":0", scheduler_kwargs={"dashboard": False}))
        return made[-1]

    monkeypatch.setattr(ensemble.cluster, "make_cluster", make)
    config = tmp_path / "c.toml"
    config.write_text('cores = 2\nmemory = "2GB"\njobs = 1\n')
    spec = EnsembleSpec("md", {"n": 200, "density": 1.0, "restitution": 0.0,
                               "delta": [0.0, 0.01]}, [1, 2], [0.5, 1.0])
    report = run_ensemble(spec, tmp_path / "out", cluster="slurm", config=config,
                          progress=False)
    assert len(made) == 1 and made[0].scaled == 1 and made[0].status == Status.closed
    assert len(report.failed) == 2 and len(report.ran) == 4
    assert {f["params"]["delta"] for f in report.failed} == {0.0}
    assert "InelasticCollapseError" in report.failed[0]["traceback"]


def test_killed_worker_task_is_rerun_and_aggregate_equals_serial(tmp_path):
    """A local cluster of 2 workers (the default executor path); the first advance to τ = 8 of
    any task kills its worker process (os._exit) after the τ = 4 checkpoint was written."""
    marker = tmp_path / "killed"
    spec = _spec(model="ulam-killer",
                 params={"n": N, "restitution": [0.5, 0.9], "marker": str(marker)},
                 seeds="1-2", options={"checkpoint_interval": 0})
    report = run_ensemble(spec, tmp_path / "dask", workers=2, progress=False)
    assert marker.exists()  # a worker did die
    assert report.ok and sorted(report.ran) == sorted(t.key for t in spec.expand())
    # the killed worker's task(s) continued from their checkpoints: at least one (more when the
    # dying worker held more), each a task of the spec, in the aggregate once
    assert len(report.resumed) >= 1 and set(report.resumed) <= set(report.ran)
    assert [s["n_seeds"] for s in report.aggregate["sets"]] == [2, 2]
    assert [s["seeds"] for s in report.aggregate["sets"]] == [[1, 2], [1, 2]]
    reference = _spec(params={"n": N, "restitution": [0.5, 0.9]}, seeds="1-2")
    serial = run_ensemble(reference, tmp_path / "serial", executor="serial", progress=False)
    _assert_same_arrays(_arrays(serial.aggregate_path), _arrays(report.aggregate_path))


# --------------------------------------------------------------------------- batch clusters


def test_slurm_and_pbs_job_scripts(tmp_path):
    config = tmp_path / "cluster.toml"
    config.write_text(
        'queue = "normal"\nwalltime = "02:00:00"\ncores = 8\nmemory = "16GB"\n'
        'account = "proj42"\njobs = 3\njob_script_prologue = ["module load python"]\n'
    )
    slurm = ensemble.cluster_job_script("slurm", config)
    for line in ("#SBATCH -p normal", "#SBATCH -A proj42", "#SBATCH -t 02:00:00",
                 "#SBATCH --cpus-per-task=8", "module load python"):
        assert line in slurm, slurm
    assert "--nworkers 8" in slurm and "--nthreads 1" in slurm  # one thread per worker
    pbs = ensemble.cluster_job_script("pbs", config)
    for line in ("#PBS -q normal", "#PBS -A proj42", "#PBS -l walltime=02:00:00",
                 "ncpus=8"):
        assert line in pbs, pbs
    assert ensemble.load_cluster_config(config, "slurm")["jobs"] == 3


def test_cluster_config_errors(tmp_path):
    cases = {
        'cores = 8\n': "config",  # no memory
        'cores = 8\nmemory = "1GB"\nqueues = "x"\n': "config",  # unknown key
        'cores = "8"\nmemory = "1GB"\n': "config",
        'cores = 8\nmemory = \n': "config",  # not TOML
    }
    for text, name in cases.items():
        config = tmp_path / "c.toml"
        config.write_text(text)
        with pytest.raises(InvalidArgumentError) as err:
            ensemble.load_cluster_config(config, "slurm")
        assert err.value.name == name
    with pytest.raises(InvalidArgumentError) as err:
        ensemble.load_cluster_config(tmp_path / "missing.toml", "pbs")
    assert err.value.name == "config"
    # a [slurm] table is read for slurm
    config = tmp_path / "t.toml"
    config.write_text('[slurm]\ncores = 4\nmemory = "8GB"\n[pbs]\ncores = 2\nmemory = "4GB"\n')
    assert ensemble.load_cluster_config(config, "slurm")["cores"] == 4
    assert ensemble.load_cluster_config(config, "pbs")["processes"] == 2


def test_import_particles_does_not_import_distributed(fresh_interpreter_code):
    """dask.distributed and dask_jobqueue are imported only when an ensemble runs on dask.
    (dask itself is imported by pyfftw.interfaces whenever dask is installed: not checked.)"""
    out = fresh_interpreter_code(
        "import sys, particles, particles.ensemble; "
        "print(sorted({m.split('.')[0] for m in sys.modules} & "
        "{'distributed', 'dask_jobqueue', 'maxwell_kinetics'}))"
    )
    assert out.strip() == "[]"


def test_a_batch_cluster_without_dask_jobqueue_is_one_clear_line(capsys, tmp_path, monkeypatch):
    # dask-jobqueue is an optional extra: without it, --cluster is refused before any work,
    # naming what to install (the import made to fail in this process)
    from maxwell_kinetics.app.cli import main

    monkeypatch.setitem(sys.modules, "dask_jobqueue", None)
    config = tmp_path / "c.toml"
    config.write_text('cores = 2\nmemory = "2GB"\n')
    for kind in ("slurm", "pbs"):
        out = tmp_path / f"out-{kind}"
        code = main(["ensemble", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1",
                     "--seeds", "1", "--cluster", kind, "--config", str(config),
                     "--out", str(out), "--no-progress"])
        captured = capsys.readouterr()
        assert code == 2 and captured.out == "" and not out.exists()
        lines = captured.err.strip().splitlines()
        assert len(lines) == 1 and "Traceback" not in captured.err
        assert "pip install 'maxwell-kinetics[cluster]'" in lines[0]
        assert f"cluster='{kind}'" in lines[0]
    with pytest.raises(InvalidArgumentError) as err:
        ensemble.cluster_job_script("slurm", config)
    assert err.value.name == "cluster"


def test_a_batch_cluster_without_config_is_named(tmp_path):
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(), tmp_path / "out", cluster="slurm", progress=False)
    assert err.value.name == "config" and "TOML" in str(err.value)
    assert not (tmp_path / "out").exists()


def test_a_dangling_manifest_is_named_as_such(tmp_path):
    (tmp_path / ensemble.MANIFEST).symlink_to(tmp_path / "nowhere")
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(_spec(), tmp_path, executor="serial", progress=False)
    assert err.value.name == "out" and "manifest.npz: no such file" in str(err.value)
    assert [p.name for p in tmp_path.iterdir()] == [ensemble.MANIFEST]


def test_a_shared_folder_holds_many_ensembles_and_is_no_ensembles_own(tmp_path):
    # the comparisons' runs (reproduce --workers) put the tasks of many ensembles in one folder
    one, other = _spec(seeds="1"), _spec(seeds="1", model="lattice", times=(4.0,))
    for spec in (one, other, one):
        run_ensemble(spec, tmp_path / "runs", executor="serial", progress=False, shared=True)
    names = {p.name for p in (tmp_path / "runs").glob("task-*.npz")}
    assert names == {t.filename for t in one.expand() + other.expand()}
    # ... but neither may adopt it as its own, nor a shared run an ensemble's own folder
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(one, tmp_path / "runs", executor="serial", progress=False)
    assert err.value.name == "out" and "share" in str(err.value)
    run_ensemble(one, tmp_path / "own", executor="serial", progress=False)
    with pytest.raises(InvalidArgumentError) as err:
        run_ensemble(one, tmp_path / "own", executor="serial", progress=False, shared=True)
    assert err.value.name == "out"


def test_the_aggregate_of_a_folder_that_does_not_exist_is_refused(tmp_path):
    # a mistyped folder gave an aggregate with no seeds, as if no task had finished
    from particles.ensemble import EnsembleSpec, aggregate

    spec = EnsembleSpec("ulam", {"n": 100, "restitution": 0.5}, [1.0, 2.0], [1, 2])
    with pytest.raises(InvalidArgumentError, match=r"out=.*no_such_folder.*existing folder"):
        aggregate(spec, tmp_path / "no_such_folder")
    arrays, summary = aggregate(spec, tmp_path)  # an existing folder with no task yet: empty
    assert summary["sets"][0]["n_seeds"] == 0
