"""Writes that fail and outputs that are checked too late: every writer of the command line on
a full disk, names at the file system's limit, unreadable inputs, files in ``--out`` that the
program did not write, and ``reproduce --only`` keeping the other comparisons of
``summary.json``.

The rule throughout: one line on stderr and exit status 2 (bad input, found before any work)
or 3 (a write the file system failed after the work); no temporary file left behind; and a
file the program did not write is never replaced (an existing file of the same name survives
byte for byte).

A full disk is a 64 KiB tmpfs filled to the last byte when this process may mount one (root
in a container); elsewhere it is an injected ``ENOSPC`` from ``os.fsync``, which every atomic
write calls before its rename.
"""

from __future__ import annotations

import errno
import fcntl
import json
import os
import subprocess
from pathlib import Path

import pytest
from helpers import run_error, run_json

from maxwell_kinetics.app import comparisons
from particles import persistence

#: A cheap run of each command that writes, and its output options.
SOLVE = ["solve", "--restitution", "0.5", "--tau", "1", "--resolution", "coarse", "--json"]
STEADY = ["steady", "--restitution", "0.5", "--driving", "1", "--json"]
ULAM = ["simulate", "ulam", "--n", "200", "--restitution", "0.5", "--tau", "1", "--json"]
REPRODUCE = ["reproduce", "--small", "--only", "tail_exponents", "--json", "--no-progress"]
CONVERGENCE = ["convergence", "--restitution", "0.5", "--tau-max", "10", "--resolutions",
               "coarse", "--json", "--no-progress"]


def _mount_tmpfs(where: Path) -> bool:
    """Mount a 64 KiB tmpfs on ``where``; False where this process may not."""
    try:
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(where)],
                              capture_output=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return False
    return done.returncode == 0


def _fill(folder: Path) -> None:
    """Fill the file system of ``folder`` to the last byte."""
    with open(folder / "filler", "wb") as fh:
        try:
            while True:
                fh.write(b"\0" * 4096)
                fh.flush()
        except OSError as exc:
            assert exc.errno == errno.ENOSPC
            try:
                fh.close()
            except OSError:
                pass


@pytest.fixture
def full_disk(tmp_path, monkeypatch):
    """``fill()``: a folder whose disk is full from then on (a real tmpfs, or injected)."""
    folder = tmp_path / "disk"
    folder.mkdir()
    mounted = _mount_tmpfs(folder)

    def fill():
        if mounted:
            _fill(folder)
        else:
            def no_space(fd):
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

            monkeypatch.setattr(persistence.os, "fsync", no_space)

    yield folder, fill
    if mounted:
        subprocess.run(["umount", str(folder)], check=False, timeout=10)


def _convergence_json() -> bytes:
    return json.dumps({"runs": [], "table": [], "order_fit": {}}).encode()


def _summary(size="small", names=("driven_steady",)) -> bytes:
    return json.dumps({"size": size, "comparisons": {n: {"x": 1.5} for n in names},
                       "seconds": 3.0}).encode()


def _png() -> bytes:
    return b"\x89PNG\r\n\x1a\n" + b"old image"


#: (id, argv with {} for the path, the path in the folder, the old content): every writer.
WRITERS = [
    ("solve-save", SOLVE + ["--save", "{}"], "sol.npz", b"old solution"),
    ("solve-plot", SOLVE + ["--plot", "{}"], "sol.png", b"old image"),
    ("steady-plot", STEADY + ["--plot", "{}"], "steady.png", b"old image"),
    ("simulate-save", ULAM + ["--save", "{}"], "run.npz", b"old result"),
    ("simulate-checkpoint", ULAM + ["--checkpoint", "{}"], "run.ckpt", b"old checkpoint"),
    ("reproduce-out", REPRODUCE + ["--out", "{}"], "summary.json", _summary()),
    ("convergence-out", CONVERGENCE + ["--out", "{}"], "convergence.json", _convergence_json()),
]


@pytest.mark.parametrize(("argv", "name", "old"), [w[1:] for w in WRITERS],
                         ids=[w[0] for w in WRITERS])
def test_a_full_disk_is_one_line_and_keeps_the_old_file(capsys, full_disk, argv, name, old):
    folder, fill = full_disk
    (folder / name).write_bytes(old)
    is_dir = argv[-2] == "--out"
    target = folder if is_dir else folder / name
    argv = [str(target) if a == "{}" else a for a in argv]
    fill()
    before = sorted(os.listdir(folder))
    err = run_error(capsys, argv, status=3)
    assert err.count("\n") == 1 and "Traceback" not in err, err
    option = argv[-2].lstrip("-")
    assert f"argument {option}=" in err and "No space left on device" in err, err
    assert (folder / name).read_bytes() == old  # the file there survives intact
    assert sorted(os.listdir(folder)) == before  # no temporary or partial file left


@pytest.mark.parametrize("option", ["save", "checkpoint"])
def test_a_legal_name_of_255_bytes_is_written(capsys, tmp_path, option):
    """The temporary ``<name>.<random>.tmp`` and the ``<name>.lock`` pass 255 bytes for such a
    name: both use a short hashed name instead, and neither is left behind."""
    name = "r" * 251 + ".npz"
    assert len(name.encode()) == 255
    other = "save" if option == "checkpoint" else "checkpoint"
    run_json(capsys, ULAM + [f"--{option}", str(tmp_path / name),
                             f"--{other}", str(tmp_path / "other.npz")])
    assert sorted(os.listdir(tmp_path)) == sorted([name, "other.npz"])
    if option == "checkpoint":  # and it resumes (the lock taken again)
        run_json(capsys, ULAM + ["--resume", str(tmp_path / name),
                                 "--checkpoint", str(tmp_path / name)])
        assert sorted(os.listdir(tmp_path)) == sorted([name, "other.npz"])


@pytest.mark.parametrize(("argv", "option"), [
    (SOLVE + ["--save"], "save"), (SOLVE + ["--plot"], "plot"), (STEADY + ["--plot"], "plot"),
    (ULAM + ["--checkpoint"], "checkpoint"), (ULAM + ["--save"], "save"),
    (REPRODUCE + ["--out"], "out"), (CONVERGENCE + ["--out"], "out"),
])
def test_a_name_too_long_is_refused_before_the_work(capsys, tmp_path, monkeypatch, argv, option):
    """A name of 256 bytes: exit 2 naming the option, before any computation."""
    _no_work(monkeypatch)
    name = "n" * 252 + (".png" if option == "plot" else ".npz")
    err = run_error(capsys, argv + [str(tmp_path / name)])
    assert f"argument {option}=" in err and "at most 255 bytes" in err, err
    assert os.listdir(tmp_path) == []


def _no_work(monkeypatch):
    """Make the long computations of convergence and reproduce fail the test if reached."""
    import maxwell_kinetics.app.convergence as convergence

    def reached(*args, **kwargs):
        raise AssertionError("the work started before the outputs were checked")

    monkeypatch.setattr(convergence, "convergence_study", reached)
    for name in comparisons.COMPARISONS:
        monkeypatch.setitem(comparisons.COMPARISONS, name, reached)


@pytest.mark.parametrize(("argv", "blocked"), [
    (CONVERGENCE, "convergence.png"), (CONVERGENCE, "convergence.json"),
    (REPRODUCE, "summary.json"), (REPRODUCE, "tail_exponents.npz"),
    (REPRODUCE, "tail_exponents.png"),
])
def test_every_file_in_out_is_checked_before_the_work(capsys, tmp_path, monkeypatch, argv,
                                                      blocked):
    """A directory where a file of ``--out`` goes: exit 2 naming ``out`` and that path, before
    the study or the first comparison runs, and nothing written."""
    _no_work(monkeypatch)
    (tmp_path / blocked).mkdir()
    err = run_error(capsys, argv + ["--out", str(tmp_path)])
    assert f"argument out='{tmp_path / blocked}'" in err and "path=" not in err, err
    assert os.listdir(tmp_path) == [blocked]


# --------------------------------------------------------------------------- reproduce --only


def test_reproduce_only_merges_into_the_summary(capsys, tmp_path):
    """``--only Y`` after ``--only X`` keeps X's numbers in summary.json, unchanged."""
    run_json(capsys, ["reproduce", "--small", "--only", "tail_exponents", "--json",
                      "--no-progress", "--out", str(tmp_path)])
    first = json.loads((tmp_path / "summary.json").read_text())
    payload = run_json(capsys, ["reproduce", "--small", "--only", "driven_steady", "--json",
                                "--no-progress", "--out", str(tmp_path)])
    assert payload["comparisons"] == ["driven_steady"]
    assert payload["in_summary"] == ["driven_steady", "tail_exponents"]
    merged = json.loads((tmp_path / "summary.json").read_text())
    assert merged["size"] == "small"
    assert merged["comparisons"]["tail_exponents"] == first["comparisons"]["tail_exponents"]
    assert "driven_steady" in merged["comparisons"]
    # the order of the comparisons, whatever order they were run in
    order = [n for n in comparisons.COMPARISONS if n in merged["comparisons"]]
    assert list(merged["comparisons"]) == order


def test_reproduce_only_keeps_the_other_fields_of_the_summary(capsys, tmp_path):
    """A summary with fields of its own (the stored full-size one has ``provenance``) keeps
    them; the entry run is replaced, the other one kept."""
    old = {"size": "small", "provenance": {"a": "by hand"},
           "comparisons": {"tail_exponents": {"x": 1}, "kinetic_theory": {"y": 2}}}
    (tmp_path / "summary.json").write_text(json.dumps(old))
    run_json(capsys, REPRODUCE + ["--out", str(tmp_path)])
    new = json.loads((tmp_path / "summary.json").read_text())
    assert new["provenance"] == old["provenance"]
    assert new["comparisons"]["kinetic_theory"] == {"y": 2}
    assert new["comparisons"]["tail_exponents"] != {"x": 1}


def test_reproduce_refuses_a_summary_of_another_size(capsys, tmp_path, monkeypatch):
    _no_work(monkeypatch)
    old = _summary(size="full", names=("kinetic_theory",))
    (tmp_path / "summary.json").write_bytes(old)
    err = run_error(capsys, REPRODUCE + ["--out", str(tmp_path)])
    assert str(tmp_path / "summary.json") in err and "'full'" in err and "'small'" in err, err
    assert (tmp_path / "summary.json").read_bytes() == old
    assert os.listdir(tmp_path) == ["summary.json"]


@pytest.mark.parametrize("content", [
    b"{not json", b"[1, 2]", b"\xff\xfe binary", b'{"size": "huge", "comparisons": {}}',
    b'{"size": "small", "comparisons": [1]}', b'{"size": "small", "comparisons": {"a": 1}}',
], ids=["not-json", "a-list", "not-utf8", "unknown-size", "list-of-comparisons", "bad-entry"])
def test_reproduce_never_replaces_a_summary_that_is_not_ours(capsys, tmp_path, monkeypatch,
                                                             content):
    _no_work(monkeypatch)
    (tmp_path / "summary.json").write_bytes(content)
    err = run_error(capsys, REPRODUCE + ["--out", str(tmp_path)])
    assert f"argument out='{tmp_path / 'summary.json'}'" in err, err
    assert (tmp_path / "summary.json").read_bytes() == content
    assert os.listdir(tmp_path) == ["summary.json"]


@pytest.mark.parametrize(("argv", "name"), [
    (REPRODUCE, "tail_exponents.png"), (REPRODUCE, "tail_exponents.npz"),
    (CONVERGENCE, "convergence.png"), (CONVERGENCE, "convergence.json"),
])
def test_a_file_in_out_that_is_not_ours_is_never_replaced(capsys, tmp_path, monkeypatch, argv,
                                                          name):
    _no_work(monkeypatch)
    (tmp_path / name).write_bytes(b"the user's notes")
    err = run_error(capsys, argv + ["--out", str(tmp_path)])
    assert f"argument out='{tmp_path / name}'" in err, err
    assert (tmp_path / name).read_bytes() == b"the user's notes"
    assert os.listdir(tmp_path) == [name]


# --------------------------------------------------------------------------- inputs


def test_an_unreadable_resume_file_is_one_line(capsys, tmp_path, monkeypatch):
    """Root reads a chmod-000 file, so the refusal of ``open`` is injected."""
    ckpt = tmp_path / "run.ckpt"
    run_json(capsys, ULAM + ["--checkpoint", str(ckpt)])

    def refused(path, *args, **kwargs):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))

    monkeypatch.setattr(persistence, "open", refused, raising=False)
    err = run_error(capsys, ULAM + ["--resume", str(ckpt), "--save", str(tmp_path / "s.npz")])
    assert "argument resume=" in err and "Permission denied" in err, err
    assert sorted(os.listdir(tmp_path)) == ["run.ckpt"]


# --------------------------------------------------------------------------- temporary files


def test_a_live_writers_temporary_file_is_left_alone(tmp_path):
    """The clean-up of stale temporaries skips one that a writer holds (its flock) and the
    temporaries of another name (``x.b`` beside ``x``)."""
    live = tmp_path / "x.npz.abcd1234.tmp"
    other = tmp_path / "x.npz.b.abcd1234.tmp"  # a temporary of "x.npz.b"
    stale = tmp_path / "x.npz.dead0000.tmp"
    for path in (live, other, stale):
        path.write_bytes(b"partial")
    with open(live, "rb") as held:
        fcntl.flock(held.fileno(), fcntl.LOCK_EX)
        persistence.write_text(tmp_path / "x.npz", "new")
        assert live.exists() and other.exists() and not stale.exists()
    assert (tmp_path / "x.npz").read_text() == "new"


def test_write_error_of_the_library_names_the_file_and_keeps_the_old_one(tmp_path):
    target = tmp_path / "x.txt"
    target.write_text("old")

    def fails(fh):
        fh.write(b"half")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(persistence.WriteError, match="x.txt.*No space left") as info:
        persistence.write_atomic(target, fails, "save")
    assert info.value.exit_status == 3 and info.value.name == "save"
    assert target.read_text() == "old" and os.listdir(tmp_path) == ["x.txt"]


# --------------------------------------------------------------------------- hostile paths


@pytest.mark.parametrize(("argv", "option"), [
    (SOLVE + ["--save"], "save"), (ULAM + ["--checkpoint"], "checkpoint"),
    (ULAM + ["--save"], "save"),
])
def test_a_file_path_ending_in_a_slash_is_refused(capsys, tmp_path, argv, option):
    """``--save new/`` names a folder: it used to write a file called ``new``."""
    err = run_error(capsys, argv + [str(tmp_path / "new") + "/"])
    assert f"argument {option}=" in err and "ends in '/'" in err, err
    assert os.listdir(tmp_path) == []


def test_a_path_longer_than_path_max_is_one_line(capsys, tmp_path):
    """Short names, 4 KiB in all: exit 2 naming the option, not an OSError from os.stat."""
    deep = tmp_path.joinpath(*["d" * 200] * 21) / "x.npz"
    err = run_error(capsys, ULAM + ["--save", str(deep)])
    assert "argument save=" in err and "bytes" in err, err


def test_a_binary_cluster_config_is_one_line(tmp_path):
    from particles.ensemble.cluster import load_cluster_config
    from particles.validation import InvalidArgumentError

    config = tmp_path / "c.toml"
    config.write_bytes(b"\xff\xfe\x00binary")
    with pytest.raises(InvalidArgumentError, match="config.*valid TOML") as err:
        load_cluster_config(config, "slurm")
    assert err.value.name == "config"


def test_two_links_to_one_checkpoint_share_one_lock(tmp_path):
    """A run given a symlink to the checkpoint another run writes is refused (the lock lies
    beside the file written, not beside the link)."""
    from particles.driver import CheckpointError, simulate
    from particles.driver.checkpoint import CheckpointLock
    from particles.ulam import Ulam

    real = tmp_path / "real.ckpt"
    link = tmp_path / "link.ckpt"
    link.symlink_to(real)
    with CheckpointLock(link):
        with pytest.raises(CheckpointError, match="another run"):
            simulate(Ulam(200, 0.5), [1.0], 3, progress=False, checkpoint=real)
    assert sorted(os.listdir(tmp_path)) == ["link.ckpt"]


def test_a_huge_summary_is_refused_without_being_read_whole(capsys, tmp_path, monkeypatch):
    """A summary.json past the cap (made small here) is refused, not loaded into memory."""
    from maxwell_kinetics.app import output

    _no_work(monkeypatch)
    monkeypatch.setattr(output, "MAX_JSON_BYTES", 40)
    content = _summary()
    assert len(content) > 40
    (tmp_path / "summary.json").write_bytes(content)
    err = run_error(capsys, REPRODUCE + ["--out", str(tmp_path)])
    assert "summary.json" in err and "larger than 40 bytes" in err, err
    assert (tmp_path / "summary.json").read_bytes() == content


ENSEMBLE = ["ensemble", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1", "--seeds",
            "1", "--serial", "--json", "--no-progress"]


def test_ensemble_on_a_full_disk_names_out(capsys, full_disk):
    folder, fill = full_disk
    fill()
    err = run_error(capsys, ENSEMBLE + ["--out", str(folder / "ens")], status=3)
    assert err.count("\n") == 1 and "argument out=" in err and "No space left" in err, err
    assert not [p for p in folder.rglob("*") if p.name.endswith(".tmp")]


def test_ensemble_folder_name_too_long_is_one_line(capsys, tmp_path):
    err = run_error(capsys, ENSEMBLE + ["--out", str(tmp_path / ("e" * 256))])
    assert "argument out=" in err and "at most 255 bytes" in err, err
    assert os.listdir(tmp_path) == []


def test_a_summary_of_another_size_is_replaced_when_every_entry_is_run_again(capsys, tmp_path):
    """No mixing of sizes can happen when the run replaces every entry the summary holds; it
    still takes --force (results of another size are never replaced by accident)."""
    old = _summary(size="full", names=("tail_exponents",))
    (tmp_path / "summary.json").write_bytes(old)
    assert "--force" in run_error(capsys, REPRODUCE + ["--out", str(tmp_path)])
    assert (tmp_path / "summary.json").read_bytes() == old
    run_json(capsys, REPRODUCE + ["--force", "--out", str(tmp_path)])
    new = json.loads((tmp_path / "summary.json").read_text())
    assert new["size"] == "small" and list(new["comparisons"]) == ["tail_exponents"]
    assert new["comparisons"]["tail_exponents"] != {"x": 1.5}


def test_an_interrupted_reproduce_keeps_the_finished_comparisons(capsys, tmp_path, monkeypatch):
    """summary.json is rewritten after each comparison: a Ctrl-C in the second keeps the
    numbers of the first."""
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setitem(comparisons.COMPARISONS, "driven_steady", interrupted)
    run_error(capsys, ["reproduce", "--small", "--only", "tail_exponents,driven_steady",
                       "--no-progress", "--out", str(tmp_path)], status=130)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert list(summary["comparisons"]) == ["tail_exponents"]
    assert sorted(os.listdir(tmp_path)) == ["summary.json", "tail_exponents.npz",
                                            "tail_exponents.png"]


def test_a_library_write_reports_the_users_option(tmp_path):
    """A save deep in the library (argument ``path``) names the option the path came from."""
    target = tmp_path / "x.npz"
    persistence.name_outputs({target: "save"})
    try:
        def fails(fh):
            raise OSError(errno.EIO, os.strerror(errno.EIO))

        with pytest.raises(persistence.WriteError, match="argument save=") as info:
            persistence.write_atomic(target, fails)
        assert info.value.exit_status == 3
    finally:
        persistence.name_outputs({})


def test_two_runs_into_one_folder_at_once_keep_both_entries(capsys, tmp_path, monkeypatch):
    """Another run (``--only driven_steady``) writes summary.json while this one computes:
    the entry it wrote survives this run's write (the summary is read again under a lock)."""
    real = comparisons.COMPARISONS["tail_exponents"]

    def meanwhile(*args, **kwargs):
        result = real(*args, **kwargs)
        (tmp_path / "summary.json").write_bytes(_summary(size="small"))  # the other run
        return result

    monkeypatch.setitem(comparisons.COMPARISONS, "tail_exponents", meanwhile)
    run_json(capsys, REPRODUCE + ["--out", str(tmp_path)])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["comparisons"]["driven_steady"] == {"x": 1.5}
    assert "tail_exponents" in summary["comparisons"]


def test_a_lock_file_that_is_a_symlink_creates_nothing_elsewhere(capsys, tmp_path):
    """``<checkpoint>.lock`` planted as a symlink: refused before the run, naming checkpoint and
    the lock; the file it points to is not created (it used to be, and stayed behind)."""
    victim = tmp_path / "victim"
    (tmp_path / "run.ckpt.lock").symlink_to(victim)
    err = run_error(capsys, ULAM + ["--checkpoint", str(tmp_path / "run.ckpt")])
    assert "argument checkpoint=" in err and "run.ckpt.lock" in err and "symlink" in err, err
    assert not victim.exists() and not (tmp_path / "run.ckpt").exists()
