"""``maxwell-kinetics simulate sticky``: the JSON contract (the keys of ``simulate md`` plus
``clusters`` and ``mean_cluster_mass``), agreement with the Python engine, and bad input."""

import numpy as np
import pytest
from helpers import run_error, run_json

from particles.driver import simulate
from particles.sticky import StickyGas, StickyParams

BASE = ["simulate", "sticky", "--n", "500", "--density", "1.5", "--seed", "4"]


def test_json_has_the_md_keys_and_the_clusters(capsys, tmp_path):
    out = run_json(capsys, BASE + ["--t", "0,1,30", "--json", "--structure-factor", "--profile",
                                   "--save", str(tmp_path / "s.npz")])
    assert {"t", "energy", "momentum", "seconds", "histogram", "clusters",
            "mean_cluster_mass", "k", "S", "C", "profile"} <= set(out)
    run = simulate(StickyGas(StickyParams(500, 1.5)), [0.0, 1.0, 30.0], 4, progress=False)
    assert out["energy"] == run.energy.tolist()
    assert out["clusters"] == [int(c) for c in run.extras["clusters"]]
    assert out["clusters"][0] == 500 and out["clusters"][1] > out["clusters"][2]
    assert np.allclose(np.array(out["mean_cluster_mass"]) * out["clusters"], 500)
    assert max(abs(m) for m in out["momentum"]) < 1e-10
    assert len(out["profile"]["x"]) == 500


def test_profile_of_a_finished_checkpoint_is_the_profile_of_the_run(capsys, tmp_path):
    ckpt = tmp_path / "s.ckpt"
    argv = BASE + ["--t", "1,30", "--json", "--profile"]
    plain = run_json(capsys, argv + ["--checkpoint", str(ckpt)])
    resumed = run_json(capsys, argv + ["--resume", str(ckpt)])  # already finished
    assert resumed["profile"] == plain["profile"] and resumed["energy"] == plain["energy"]


@pytest.mark.parametrize(
    "extra, named",
    [
        (["--n", "1", "--t", "1"], "n="),
        (["--density", "0", "--t", "1"], "density="),
        (["--density", "-2", "--t", "1"], "density="),
        (["--t", "-1"], "t="),
        (["--t", "2,1"], "t="),
        (["--t", "1", "--initial", "nonsense"], "initial="),
    ],
)
def test_bad_input_exits_2_naming_the_argument(capsys, tmp_path, extra, named):
    save = tmp_path / "s.npz"
    err = run_error(capsys, BASE + extra + ["--save", str(save)])
    assert named in err and not save.exists()


def test_a_corrupt_checkpoint_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.ckpt"
    bad.write_bytes(b"PK\x03\x04 not really a zip")
    err = run_error(capsys, BASE + ["--t", "1", "--resume", str(bad)])
    assert "resume=" in err and "bad.ckpt" in err


def test_chunks_print_the_library_numbers(capsys):
    from particles.sticky_chunks import simulate_chunks

    out = run_json(capsys, BASE + ["--t", "1,30", "--chunks", "3", "--json"])
    res = simulate_chunks(StickyParams(500, 1.5), [1.0, 30.0], 4, 3)
    assert out["energy"] == res.energy.tolist() and out["clusters"] == res.clusters.tolist()
    assert out["chunks"] == 3 and sum(out["mass_distribution"]["count"]) == out["clusters"][-1]
    # one chunk is the single-process engine: the numbers of plain simulate sticky
    one = run_json(capsys, BASE + ["--t", "1,30", "--chunks", "1", "--json"])
    plain = run_json(capsys, BASE + ["--t", "1,30", "--json"])
    assert one["energy"] == plain["energy"] and one["clusters"] == plain["clusters"]
    assert one["histogram"] == plain["histogram"]


def test_chunks_give_the_structure_factor_of_the_engine(capsys):
    # --chunks 1 --structure-factor: the keys and numbers of plain simulate sticky; K = 3: those
    # of the library (the chunks' own initial state differs from the single engine's)
    from particles.sticky_chunks import simulate_chunks

    argv = BASE + ["--t", "1,30", "--json", "--structure-factor"]
    one = run_json(capsys, argv + ["--chunks", "1"])
    plain = run_json(capsys, argv)
    assert all(one[key] == plain[key] for key in ("k", "S", "C"))
    three = run_json(capsys, argv + ["--chunks", "3"])
    res = simulate_chunks(StickyParams(500, 1.5), [1.0, 30.0], 4, 3, structure_factor=True)
    assert three["S"] == res.S.tolist() and three["C"] == res.C.tolist()
    assert len(three["k"]) == 251


@pytest.mark.parametrize("extra, name", [
    (["--chunks", "0"], "chunks"),
    (["--chunks", "251"], "chunks"),  # N/2 = 250
    (["--chunks", "x"], "chunks"),
    (["--chunks", "2", "--save", "OUT"], "save"),
    (["--chunks", "2", "--checkpoint", "OUT"], "checkpoint"),
    (["--chunks", "2", "--profile"], "profile"),
    (["--chunks", "2", "--workers", "0"], "workers"),
    (["--chunks", "2", "--workers", "2", "--scheduler", "tcp://127.0.0.1:9"], "--scheduler"),
])
def test_bad_chunk_options_exit_2_and_write_nothing(capsys, tmp_path, extra, name):
    argv = BASE + ["--t", "1"] + [str(tmp_path / "out") if a == "OUT" else a for a in extra]
    err = run_error(capsys, argv)
    assert name in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "extra, named",
    [
        (["--workers", "2"], "workers="),  # without --chunks the workers would run nothing
        (["--scheduler", "tcp://127.0.0.1:9"], "scheduler="),
        (["--chunks", "1", "--workers", "2"], "workers="),  # K = 1 runs here, not on workers
        (["--chunks", "1", "--scheduler", "tcp://127.0.0.1:9"], "scheduler="),
        (["--chunks", "2", "--scheduler", ""], "scheduler="),
        (["--chunks", "2", "--scheduler", "tcp://a b"], "scheduler="),
    ],
)
def test_dask_options_that_would_do_nothing_exit_2(capsys, extra, named):
    err = run_error(capsys, BASE + ["--t", "1"] + extra)
    assert named in err and ("--chunks" in err or "address" in err)
    assert len(err.strip().splitlines()) == 1


def test_chunks_report_progress_when_asked(capsys):
    from maxwell_kinetics.app.cli import main

    assert main(BASE + ["--t", "1,2,3", "--chunks", "2", "--progress"]) == 0
    assert "sticky chunks" in capsys.readouterr().err
    assert main(BASE + ["--t", "1,2,3", "--chunks", "2", "--no-progress"]) == 0
    assert capsys.readouterr().err == ""


def _without_timing(out):
    return {k: v for k, v in out.items() if k != "seconds"}


def test_chunks_on_dask_workers_equal_the_chunks_run_here(capsys):
    # --chunks K with --workers W (a local cluster of W processes) or --scheduler (a running
    # cluster): the chunks are the same computations, so every number equals the in-process
    # K-chunk run (each chunk draws from its own child seed, wherever it runs).
    argv = ["simulate", "sticky", "--n", "600", "--density", "1.5", "--seed", "4", "--t",
            "1,30,200", "--chunks", "3", "--json", "--structure-factor"]
    here = run_json(capsys, argv)
    on_workers = run_json(capsys, argv + ["--workers", "2"])
    assert _without_timing(on_workers) == _without_timing(here)
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster:
        on_scheduler = run_json(capsys, argv + ["--scheduler", cluster.scheduler_address])
    assert _without_timing(on_scheduler) == _without_timing(here)
    assert here["chunks"] == 3 and sum(here["mass_distribution"]["count"]) == here["clusters"][-1]
