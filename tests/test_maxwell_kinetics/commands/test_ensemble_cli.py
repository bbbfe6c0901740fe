"""``maxwell-kinetics ensemble``: the command line of the ensemble engine (serial executor here;
the dask paths are tested in ``test_ensemble.py``)."""

import numpy as np
import pytest
from helpers import run_error, run_json

from maxwell_kinetics.app.cli import main
from particles.driver import simulate
from particles.ulam import Ulam


def test_sweep_and_seeds_match_serial_runs(capsys, tmp_path):
    out = run_json(capsys, ["ensemble", "ulam", "--n", "300", "--restitution", "0.3,0.9",
                            "--tau", "1,2", "--seeds", "1-3", "--serial", "--out",
                            str(tmp_path / "e"), "--json"])
    assert out["tasks"] == 6 and out["ran"] == 6 and out["ok"] and out["failed"] == []
    sets = out["aggregate"]["sets"]
    assert [s["params"]["restitution"] for s in sets] == [0.3, 0.9]
    energies = np.array([simulate(Ulam(300, 0.9), [1.0, 2.0], seed, progress=False).energy
                         for seed in (1, 2, 3)])
    got = sets[1]["observables"]["energy"]
    assert got["mean"] == energies.mean(axis=0).tolist()
    assert np.allclose(got["sem"], energies.std(axis=0, ddof=1) / np.sqrt(3), rtol=1e-12)
    # a rerun skips every finished task
    again = run_json(capsys, ["ensemble", "ulam", "--n", "300", "--restitution", "0.3,0.9",
                              "--tau", "1,2", "--seeds", "1-3", "--serial", "--out",
                              str(tmp_path / "e"), "--json"])
    assert again["ran"] == 0 and again["skipped"] == 6


def test_a_failed_task_exits_3_and_is_listed(capsys, tmp_path):
    argv = ["ensemble", "md", "--n", "100", "--density", "1", "--restitution", "0",
            "--delta", "0,0.01", "--t", "1,40", "--seeds", "1", "--serial",
            "--out", str(tmp_path / "e"), "--json"]
    assert main(argv) == 3
    import json

    out = json.loads(capsys.readouterr().out)
    assert len(out["failed"]) == 1 and out["failed"][0]["params"]["delta"] == 0.0
    assert "InelasticCollapseError" in out["failed"][0]["error"]


@pytest.mark.parametrize(
    "extra, named",
    [
        (["--seeds", "1,1"], "seeds="),
        (["--seeds", "3-1"], "seeds="),
        (["--seeds", ""], "seeds="),
        (["--seeds", "1", "--restitution", ","], "restitution="),
        (["--seeds", "1", "--restitution", "0.5,0.5"], "restitution="),
        (["--seeds", "1", "--n", "1"], "n="),
    ],
)
def test_bad_input_exits_2_and_writes_nothing(capsys, tmp_path, extra, named):
    out = tmp_path / "e"
    argv = ["ensemble", "ulam", "--n", "300", "--restitution", "0.5", "--tau", "1",
            "--serial", "--out", str(out)] + extra
    err = run_error(capsys, argv)
    assert named in err and not out.exists()


def test_unknown_model_or_parameter_exits_2(capsys, tmp_path):
    run_error(capsys, ["ensemble", "nonsense", "--out", str(tmp_path)])
    run_error(capsys, ["ensemble", "ulam", "--n", "10", "--restitution", "0.5", "--tau", "1",
                       "--seeds", "1", "--out", str(tmp_path / "e"), "--density", "1"])


def test_an_unreachable_scheduler_fails_within_the_timeout(capsys, tmp_path, monkeypatch):
    import time

    import particles.ensemble.cluster

    monkeypatch.setattr(particles.ensemble.cluster, "SCHEDULER_TIMEOUT", 1.0)
    start = time.monotonic()
    err = run_error(capsys, ["ensemble", "ulam", "--n", "300", "--restitution", "0.5",
                             "--tau", "1", "--seeds", "1", "--scheduler", "tcp://127.0.0.1:9",
                             "--out", str(tmp_path / "e")])
    assert "scheduler=" in err and time.monotonic() - start < 20
    assert not (tmp_path / "e").exists()


def test_out_folder_of_user_files_or_another_ensemble_exits_2_and_is_kept(capsys, tmp_path):
    base = ["ensemble", "ulam", "--n", "300", "--restitution", "0.5", "--seeds", "1",
            "--serial", "--no-progress", "--out"]
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "ensemble.npz").write_bytes(b"my own aggregate")
    err = run_error(capsys, [*base, str(mine), "--tau", "1"])
    assert f"out='{mine}'" in err and "no manifest.npz" in err and len(err.splitlines()) == 1
    assert [p.name for p in mine.iterdir()] == ["ensemble.npz"]
    assert (mine / "ensemble.npz").read_bytes() == b"my own aggregate"
    ens = tmp_path / "ens"
    assert main([*base, str(ens), "--tau", "1"]) == 0
    capsys.readouterr()
    before = {p.name: p.read_bytes() for p in ens.iterdir()}
    err = run_error(capsys, [*base, str(ens), "--tau", "1,2"])  # other times
    assert f"out='{ens}'" in err and "another" in err
    assert {p.name: p.read_bytes() for p in ens.iterdir()} == before


def test_force_without_workers_exits_2(capsys, tmp_path):
    # --force only lifts the bound on --workers: alone (or with --serial) it would mean nothing
    for where in ([], ["--serial"]):
        out = tmp_path / f"e{len(where)}"
        err = run_error(capsys, ["ensemble", "ulam", "--n", "300", "--restitution", "0.5",
                                 "--tau", "1", "--seeds", "1", "--force", *where,
                                 "--out", str(out)])
        assert "force=" in err and "workers" in err and not out.exists()


def test_ensemble_without_json_prints_the_means_and_their_errors(capsys, tmp_path):
    # the text output said where the aggregate was and nothing of it
    out = tmp_path / "e"
    assert main(["ensemble", "ulam", "--n", "300", "--restitution", "0.5", "--tau", "1,2",
                 "--seeds", "1-2", "--serial", "--out", str(out), "--no-progress"]) == 0
    text = capsys.readouterr().out
    with np.load(out / "ensemble.npz", allow_pickle=False) as saved:
        energy = saved["set0.energy.mean"].tolist()
    assert "set 0: n=300, restitution=0.5 (2 seeds)" in text
    assert "energy" in text and "kurtosis" in text
    rows = [line.split() for line in text.splitlines() if line.strip()[:1].isdigit()]
    assert [float(r[0]) for r in rows] == [1.0, 2.0]
    assert [float(r[1]) for r in rows] == pytest.approx(energy, rel=1e-5)  # 6 digits shown


def test_cluster_without_config_names_the_options_not_a_none(capsys, tmp_path):
    # the library's own refusal reads "config=None"; a command-line user never typed a None
    out = tmp_path / "e"
    err = run_error(capsys, ["ensemble", "ulam", "--n", "300", "--restitution", "0.5",
                             "--tau", "1", "--seeds", "1", "--cluster", "slurm",
                             "--out", str(out)])
    assert "cluster='slurm'" in err and "--config FILE" in err and "None" not in err
    assert not out.exists()


# ------------------------------------------------------------- a batch cluster, end to end

_FAKE_SUBMIT = """#!/bin/sh
# A stand-in batch system: keep a copy of the job script, run it here in its own session
# (process group), answer like the real command with the group's id as the job id.
cp "$1" "{jobs}/job-$$.sh"
setsid sh "{jobs}/job-$$.sh" > "{jobs}/job-$$.log" 2>&1 < /dev/null &
echo "$!" > "{jobs}/job-$$.group"
echo "{answer} $!"
"""
_FAKE_CANCEL = """#!/bin/sh
# A stand-in cancel command: note the ids it was given, then end each job's process group as
# the real commands do: SIGTERM at once, SIGKILL to what is left after a grace period (Slurm's
# KillWait, 30 s by default; {grace} s here).  A dask worker still starting when its scheduler
# closed can ignore the SIGTERM until its own --death-timeout (60 s): the SIGKILL ends it.
# (No "--" before the negative id: dash's kill refuses it, "Illegal number".)
for id in "$@"; do
  echo "$id" >> "{jobs}/cancelled"
  kill -TERM "-$id" 2>/dev/null
  ( sleep {grace}; kill -KILL "-$id" 2>/dev/null ) > /dev/null 2>&1 < /dev/null &
done
exit 0
"""
#: The stand-in cancel command's grace between SIGTERM and SIGKILL, in seconds.
_CANCEL_GRACE = 5


def _live_members(group):
    """Processes of ``group`` that have not ended (a zombie, ended but not yet reaped by its
    parent, does not count), read from /proc."""
    import os

    live = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:  # ended while we looked
            continue
        if int(fields[2]) == group and fields[0] != "Z":
            live.append(int(entry))
    return live


@pytest.mark.parametrize("kind, submit, cancel, answer, directive", [
    ("slurm", "sbatch", "scancel", "Submitted batch job", "#SBATCH -p normal"),
    ("pbs", "qsub", "qdel", "", "#PBS -q normal"),
])
def test_ensemble_on_a_batch_cluster_from_the_command_line(capsys, tmp_path, monkeypatch, kind,
                                                           submit, cancel, answer, directive):
    """``ensemble --cluster slurm|pbs --config FILE``: the command builds the dask-jobqueue
    cluster from the TOML file and submits ``jobs`` job scripts through the batch system's
    command (here a stand-in on PATH that runs the script on this machine); the ensemble run
    by those jobs' workers equals the serial one, and each script carries the config."""
    pytest.importorskip("dask_jobqueue")
    import os
    import stat

    jobs, bin_dir = tmp_path / "jobs", tmp_path / "bin"
    jobs.mkdir()
    bin_dir.mkdir()
    for name, text in ((submit, _FAKE_SUBMIT.format(jobs=jobs, answer=answer)),
                       (cancel, _FAKE_CANCEL.format(jobs=jobs, grace=_CANCEL_GRACE))):
        (bin_dir / name).write_text(text)
        (bin_dir / name).chmod(stat.S_IRWXU)
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.environ['PATH']}")
    config = tmp_path / "cluster.toml"
    config.write_text(f'[{kind}]\nqueue = "normal"\nwalltime = "00:10:00"\ncores = 2\n'
                      'memory = "2GB"\njobs = 1\ninterface = "lo"\n')
    common = ["ensemble", "ulam", "--n", "300", "--restitution", "0.3,0.9", "--tau", "1,2",
              "--seeds", "1-2", "--json"]
    import signal
    import time

    def give_up(*_):  # a job that never reaches the scheduler would leave the run waiting
        raise TimeoutError("no worker of the submitted job within 120 s")

    previous = signal.signal(signal.SIGALRM, give_up)
    signal.alarm(120)
    try:
        out = run_json(capsys, common + ["--cluster", kind, "--config", str(config),
                                         "--out", str(tmp_path / "batch")])
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    serial = run_json(capsys, common + ["--serial", "--out", str(tmp_path / "serial")])
    assert out["ok"] and out["ran"] == 4 and out["failed"] == []
    assert out["aggregate"]["sets"] == serial["aggregate"]["sets"]
    scripts = sorted(jobs.glob("job-*.sh"))
    assert len(scripts) == 1, [p.name for p in jobs.iterdir()]
    text = scripts[0].read_text()
    assert directive in text and "--nworkers 2" in text and "--nthreads 1" in text, text
    # the job was cancelled when the run closed its cluster: the batch system's cancel command
    # was called with the job's id, and the job's processes end (within the stand-in's grace
    # and its SIGKILL; 60 s are allowed for a loaded machine)
    group = int(scripts[0].with_suffix(".group").read_text())
    assert (jobs / "cancelled").read_text().split() == [str(group)]
    if os.path.isdir("/proc"):
        for _ in range(600):
            if not _live_members(group):
                break
            time.sleep(0.1)
        else:
            os.killpg(group, signal.SIGKILL)
            raise AssertionError("the batch job outlived the ensemble by 60 s")


@pytest.mark.parametrize(("option", "text", "shown"), [
    ("--restitution", "0.3,0.3", "0.3"), ("--restitution", "0.3,0.30", "0.3"),
    ("--n", "100,100", "100"),
])
def test_a_swept_value_given_twice_is_a_repeated_value(capsys, tmp_path, option, text, shown):
    # Before: "0.3,0.3" was "expected a list of names without repeats" (a number is no name),
    # while "0.3,0.30" was "distinct values": one rule, one message, whatever the spelling.
    argv = ["ensemble", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1",
            "--seeds", "1", "--serial", "--out", str(tmp_path / "o"), "--no-progress"]
    argv[argv.index(option) + 1] = text
    err = run_error(capsys, argv)
    assert f"argument {option[2:]}='{text}'" in err
    assert f"distinct values ({shown} is given twice)" in err
    assert not (tmp_path / "o").exists()
