"""Hostile input: every file read is untrusted, every run is bounded.

One test (at least) per class of failure found when the command line and the API were attacked:
files trusted too much (zip bomb, declared shapes, edited contents, a FIFO, a pickle, another
model's file, a newer version, a truncated file), unbounded work and memory, loose parsing,
dishonest failure, signals and concurrency, wrong types at the API.  The hostile files are built
here, by the tests themselves.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import zipfile

import numpy as np
import pytest
from helpers import edited_file, read_entries, run_error, run_json, write_entries

from particles import persistence
from particles.driver import CheckpointError, simulate
from particles.driver.checkpoint import CheckpointLock
from particles.initial import law_from_characteristic
from particles.lattice import Lattice
from particles.parsing import parse_float_list, parse_int, parse_seed
from particles.ulam import Ulam
from particles.validation import InvalidArgumentError

ULAM = ["simulate", "ulam", "--n", "200", "--restitution", "0.5", "--tau", "1,2", "--seed", "3"]


@pytest.fixture
def checkpoint(tmp_path, capsys):
    path = tmp_path / "good.ckpt"
    run_json(capsys, ULAM + ["--json", "--checkpoint", str(path)])
    return path


def resume_error(capsys, path, tmp_path) -> str:
    """Resume from ``path`` expecting exit 2 and nothing written; return stderr."""
    out = tmp_path / "out"
    out.mkdir(exist_ok=True)
    err = run_error(capsys, ULAM + ["--resume", str(path), "--save", str(out / "s.npz")])
    assert list(out.iterdir()) == []
    assert "resume=" in err and str(path.name) in err
    return err


# --------------------------------------------------------------------------- files


def test_round_trip_and_hash_over_meta_and_arrays(tmp_path):
    path = persistence.save(tmp_path / "x.npz", "thing", 1, {"a": np.arange(5.0)}, {"k": 1})
    loaded = persistence.load(path, "thing", (1,))
    assert loaded.meta["k"] == 1 and np.array_equal(loaded.arrays["a"], np.arange(5.0))
    assert not loaded.legacy and len(loaded.meta["sha256"]) == 64
    # the digest sees a change of one bit in the data, of one meta field, of a name
    base = persistence.digest(loaded.meta, loaded.arrays)
    changed = np.arange(5.0)
    changed.view(np.uint64)[2] ^= 1
    assert persistence.digest(loaded.meta, {"a": changed}) != base
    assert persistence.digest({**loaded.meta, "k": 2}, loaded.arrays) != base
    assert persistence.digest(loaded.meta, {"b": np.arange(5.0)}) != base


def test_an_edited_number_is_refused_by_the_hash(checkpoint, capsys, tmp_path):
    meta, arrays = read_entries(checkpoint)
    v = arrays["state.velocities"].copy()
    v[7] = 0.25  # one number changed, the hash left as it was
    edited = write_entries(tmp_path / "edited.ckpt", meta, {**arrays, "state.velocities": v},
                           resign=False)
    err = resume_error(capsys, edited, tmp_path)
    assert "do not match its hash" in err


def test_a_changed_seed_is_refused(checkpoint, capsys, tmp_path):
    meta, arrays = read_entries(checkpoint)
    meta["run"]["seed"] = 4
    unsigned = write_entries(tmp_path / "seed.ckpt", meta, arrays, resign=False)
    assert "do not match its hash" in resume_error(capsys, unsigned, tmp_path)
    # re-signed by someone who knows the format: still not this run's checkpoint
    signed = write_entries(tmp_path / "seed2.ckpt", meta, arrays)
    assert "seed" in resume_error(capsys, signed, tmp_path)


def test_consistently_edited_energies_are_refused(checkpoint, capsys, tmp_path):
    # every recorded energy halved (a consistent edit of the records): the hash refuses it
    meta, arrays = read_entries(checkpoint)
    edited = write_entries(tmp_path / "energy.ckpt", meta,
                           {**arrays, "rec.energy": arrays["rec.energy"] * 0.5}, resign=False)
    assert "do not match its hash" in resume_error(capsys, edited, tmp_path)


def _bomb(src, dst, name: str, gib: float):
    chunk = bytes(1 << 24)
    count = int(gib * 2**30) // 8
    with zipfile.ZipFile(src) as zin:
        entries = [(info, zin.read(info)) for info in zin.infolist()]
    with zipfile.ZipFile(dst, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=1) as zout:
        for info, data in entries:
            zout.writestr(info.filename, data)
        with zout.open(name + ".npy", "w", force_zip64=True) as fh:
            np.lib.format.write_array_header_1_0(
                fh, {"descr": "<f8", "fortran_order": False, "shape": (count,)})
            left = count * 8
            while left > 0:
                fh.write(chunk[: min(left, len(chunk))])
                left -= len(chunk)
    return dst


@pytest.mark.parametrize("name", ["junk", "state.velocities2", "rec.extra.x"])
def test_zip_bomb_is_refused_within_a_memory_bound(checkpoint, tmp_path, name):
    # An extra entry of 1 GiB of zeros, deflated to ~1 MB.  Loading it must be refused from the
    # entry's header, before decompressing: peak RSS of the loading process, measured in a
    # subprocess, stays within 150 MB of its baseline (numpy + the package: ~80 MB here), far
    # below the 1 GiB a whole decompression would take.
    bomb = _bomb(checkpoint, tmp_path / "bomb.ckpt", name, 1.0)
    assert bomb.stat().st_size < 20 * 2**20
    code = (
        "import resource, sys\n"
        "from particles.driver import simulate, CheckpointError\n"
        "from particles.ulam import Ulam\n"
        "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "try:\n"
        f"    simulate(Ulam(200, 0.5), [1.0, 2.0], 3, progress=False, resume={str(bomb)!r})\n"
        "    print('loaded')\n"
        "except CheckpointError as exc:\n"
        "    print('refused', exc)\n"
        "peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "print((peak - base) // 1024)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    lines = done.stdout.strip().splitlines()
    assert lines[0].startswith("refused") and "bomb.ckpt" in lines[0], done.stdout
    assert int(lines[-1]) < 150, f"peak RSS grew by {lines[-1]} MB"


def test_a_declared_huge_shape_is_refused_before_allocating(tmp_path):
    path = persistence.save(tmp_path / "x.npz", "thing", 1, {"a": np.zeros(3)})
    huge = tmp_path / "huge.npz"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(huge, "w") as zout:
        for info in zin.infolist():
            if info.filename == "a.npy":
                buf = __import__("io").BytesIO()
                np.lib.format.write_array_header_1_0(
                    buf, {"descr": "<f8", "fortran_order": False, "shape": (10**12,)})
                zout.writestr("a.npy", buf.getvalue() + bytes(24))
            else:
                zout.writestr(info, zin.read(info))
    with pytest.raises(persistence.FileFormatError, match="huge.npz.*shape"):
        persistence.load(huge, "thing", (1,))


def test_a_pickle_is_never_run(tmp_path):
    # an object array (which np.save writes as a pickle) in an otherwise valid file
    marker = tmp_path / "ran"
    payload = tmp_path / "p.npz"
    evil = np.empty(1, dtype=object)
    evil[0] = _Evil(str(marker))
    with open(payload, "wb") as fh:
        np.savez(fh, meta=np.array(json.dumps({"format": persistence.FORMAT_TAG,
                                               "kind": "thing", "version": 1})), a=evil)
    with pytest.raises(persistence.FileFormatError, match="object"):
        persistence.load(payload, "thing", (1,))
    assert not marker.exists()


class _Evil:
    def __init__(self, path):
        self.path = path

    def __reduce__(self):
        return (open, (self.path, "w"))


def test_a_fifo_is_refused_without_blocking(tmp_path, capsys):
    fifo = tmp_path / "pipe.ckpt"
    os.mkfifo(fifo)
    result = {}

    def attempt():
        try:
            simulate(Ulam(200, 0.5), [1.0], 3, progress=False, resume=fifo)
        except CheckpointError as exc:
            result["error"] = str(exc)

    worker = threading.Thread(target=attempt, daemon=True)
    worker.start()
    worker.join(timeout=10)
    if worker.is_alive():  # unblock the reader before failing
        with open(fifo, "wb"):
            pass
        pytest.fail("--resume on a FIFO blocked")
    assert "not a regular file" in result["error"] and "pipe.ckpt" in result["error"]


def test_truncated_file_is_refused(checkpoint, capsys, tmp_path):
    data = checkpoint.read_bytes()
    for cut in (10, len(data) // 2, len(data) - 30):
        bad = tmp_path / f"cut{cut}.ckpt"
        bad.write_bytes(data[:cut])
        resume_error(capsys, bad, tmp_path)


def test_another_models_file_is_refused(tmp_path, capsys):
    lattice = tmp_path / "lattice.ckpt"
    simulate(Lattice(200, 0.5), [1.0, 2.0], 3, progress=False, checkpoint=lattice)
    assert "model" in resume_error(capsys, lattice, tmp_path)
    result = tmp_path / "result.npz"
    simulate(Ulam(200, 0.5), [1.0, 2.0], 3, progress=False).save(result)
    assert "not a checkpoint" in resume_error(capsys, result, tmp_path)


def test_a_newer_version_is_named(checkpoint, tmp_path, capsys):
    newer = edited_file(checkpoint, tmp_path / "newer.ckpt", meta={"version": 99})
    assert "newer version" in resume_error(capsys, newer, tmp_path)


def test_files_of_version_0_1_0_still_load(tmp_path):
    # A result as 0.1.0 wrote it: a 'meta' entry {"kind": "result", "format": 1}, no hash.
    from particles.driver import RunResult

    run = simulate(Ulam(200, 0.5), [1.0, 2.0], 3, progress=False)
    run.save(tmp_path / "new.npz")
    meta, arrays = read_entries(tmp_path / "new.npz")
    old = {k: v for k, v in meta.items() if k not in ("format", "kind", "version", "sha256")}
    old.update({"kind": "result", "format": 1})
    write_entries(tmp_path / "old.npz", old, arrays)
    loaded = RunResult.load(tmp_path / "old.npz")
    assert np.array_equal(loaded.energy, run.energy)


def test_a_stale_temporary_file_is_cleaned_on_the_next_write(tmp_path):
    target = tmp_path / "run.ckpt"
    stale = tmp_path / "run.ckpt.abc123.tmp"  # what a writer killed mid-write leaves
    stale.write_bytes(b"partial")
    simulate(Ulam(200, 0.5), [1.0], 3, progress=False, checkpoint=target)
    assert target.exists() and not stale.exists()


def test_a_locked_checkpoint_path_is_refused(tmp_path):
    target = tmp_path / "run.ckpt"
    with CheckpointLock(target):  # another run holds it
        with pytest.raises(CheckpointError, match="run.ckpt.*another run"):
            simulate(Ulam(200, 0.5), [1.0], 3, progress=False, checkpoint=target)
    simulate(Ulam(200, 0.5), [1.0], 3, progress=False, checkpoint=target)  # free again
    assert not (tmp_path / "run.ckpt.lock").exists()


# --------------------------------------------------------------------------- bounds


@pytest.mark.parametrize(
    "argv, named",
    [
        (["simulate", "ulam", "--n", "1000", "--restitution", "0.5", "--tau", "1e300"],
         "tau=1e+300"),
        (["simulate", "lattice", "--n", "1e12", "--restitution", "0.5", "--tau", "1"],
         "n=1000000000000"),
        (["simulate", "md", "--n", "1000", "--density", "1e300", "--delta", "1e-4",
          "--restitution", "0.5", "--t", "1"], "t=1.0"),
    ],
)
def test_absurd_runs_are_refused_before_they_start(capsys, argv, named):
    err = run_error(capsys, argv)
    assert named in err and "estimate" in err


def test_force_lets_a_large_estimate_through():
    from particles import Lattice, Ulam, budget

    estimate = budget.estimate_run(Ulam(1000, 0.5), 1e12)  # 5e14 collisions
    with pytest.raises(InvalidArgumentError, match="tau=1000000000000.0.*force"):
        budget.check_budget(estimate)
    assert budget.check_budget(estimate, force=True) is estimate
    # memory is never forced: 1e12 sites do not fit
    with pytest.raises(InvalidArgumentError, match="n=1000000000000"):
        budget.check_budget(budget.estimate_run(Lattice(10**12, 0.5), 1.0), force=True)


# --------------------------------------------------------------------------- parsing


def test_seeds_are_exact_integers():
    assert parse_seed("9007199254740993") == 9007199254740993
    assert parse_seed(str(2**64 - 1)) == 2**64 - 1
    assert parse_int("2e5", "n", 2) == 200000
    for bad in ("1.5", "1e-3", "-1", str(2**64), "nan", "inf", "", "0x10"):
        with pytest.raises(InvalidArgumentError, match="seed"):
            parse_seed(bad)


def test_a_seed_above_2_53_is_stored_exactly(tmp_path, capsys):
    seed = "9007199254740993"
    out = run_json(capsys, ULAM[:-1] + [seed, "--json", "--save", str(tmp_path / "s.npz")])
    assert out["seed"] == int(seed)
    from particles.driver import RunResult

    assert RunResult.load(tmp_path / "s.npz").seed == int(seed)


@pytest.mark.parametrize("text", ["1,,2", ",", "", " , 2", "1,2,"])
def test_empty_list_elements_are_refused(text):
    with pytest.raises(InvalidArgumentError, match="tau"):
        parse_float_list(text, "tau")


@pytest.mark.parametrize(
    "argv, named",
    [
        (ULAM + ["--save", ""], "save"),
        (["reproduce", "--only", ","], "only"),
        (["convergence", "--resolutions", ","], "resolutions"),
        (["simulate", "ulam", "--n", "200", "--restitution", "0.5", "--tau", "1,,2"], "tau"),
    ],
)
def test_empty_values_are_refused(capsys, tmp_path, argv, named):
    err = run_error(capsys, argv)
    assert f"{named}=" in err


def test_one_path_for_two_outputs_is_refused(capsys, tmp_path):
    same = str(tmp_path / "same.npz")
    err = run_error(capsys, ULAM + ["--save", same, "--checkpoint", same])
    assert "different file" in err and not os.path.exists(same)


def test_plot_with_an_unknown_image_format_is_refused_before_work(capsys, tmp_path):
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--plot",
                             str(tmp_path / "g.notaformat")])
    assert "plot=" in err and "image" in err


# --------------------------------------------------------------------------- honesty


@pytest.mark.parametrize(
    "phi, variance, check",
    [
        # variance 1 and zero mean, but |φ(2)| = 1.9: not a characteristic function
        (lambda k: np.exp(-0.5 * k**2) + 0.3 * k**4 * np.exp(-0.25 * k**2), 1.0, "<= 1"),
        (lambda k: np.exp(-0.5 * k**2), 2.0, "variance"),
        (lambda k: np.exp(0.3j * k - 0.5 * k**2), 1.0, "zero mean"),
    ],
)
def test_law_from_characteristic_names_the_failed_check(phi, variance, check):
    with pytest.raises(InvalidArgumentError, match=check):
        law_from_characteristic(phi, variance)


# --------------------------------------------------------------------------- signals


def test_interrupt_during_start_up_exits_130_without_traceback(monkeypatch, capsys):
    from maxwell_kinetics.app import cli

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    assert cli.main(["simulate"]) == 130
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0 and "interrupted" in err and "Traceback" not in err


# --------------------------------------------------------------------------- the API


_WRONG = [None, "x", [1, 2], {"a": 1}, object(), float("nan"), -1, 1e300, True]


def _api_calls():
    from maxwell_kinetics.driven import steady_state
    from maxwell_kinetics.tails import tail_exponent
    from particles.driver import RunResult
    from particles.ensemble import EnsembleSpec, parse_seeds
    from particles.md import MDEngine, MDParams
    from particles.sticky import StickyParams

    one = {"n": 10, "restitution": 0.5}
    return {
        "Ulam.n": lambda v: Ulam(v, 0.5), "Ulam.r": lambda v: Ulam(10, v),
        "Ulam.initial": lambda v: Ulam(10, 0.5, v),
        "Ulam.dimension": lambda v: Ulam(10, 0.5, dimension=v),
        "Ulam.angular": lambda v: Ulam(10, 0.5, dimension=2, angular=v),
        "Ulam.driving": lambda v: Ulam(10, 0.5, driving=v),
        "Lattice.n": lambda v: Lattice(v, 0.5), "Lattice.rate": lambda v: Lattice(10, 0.5, rate=v),
        "MDParams.n": lambda v: MDParams(v, 1.0, 0.5),
        "MDParams.density": lambda v: MDParams(10, v, 0.5),
        "MDParams.delta": lambda v: MDParams(10, 1.0, 0.5, delta=v),
        "MDEngine.params": lambda v: MDEngine(v),
        "StickyParams.n": lambda v: StickyParams(v, 1.0),
        "StickyParams.density": lambda v: StickyParams(10, v),
        "simulate.engine": lambda v: simulate(v, [1.0], 0, progress=False),
        "simulate.times": lambda v: simulate(Ulam(10, 0.5), v, 0, progress=False),
        "simulate.seed": lambda v: simulate(Ulam(10, 0.5), [1.0], v, progress=False),
        "simulate.bins": lambda v: simulate(Ulam(10, 0.5), [1.0], 0, progress=False, bins=v),
        "simulate.checkpoint": lambda v: simulate(Ulam(10, 0.5), [1.0], 0, progress=False,
                                                  checkpoint=v) if v is not None else 1 / 0,
        "simulate.resume": lambda v: simulate(Ulam(10, 0.5), [1.0], 0, progress=False,
                                              resume=v) if v is not None else 1 / 0,
        "RunResult.load": lambda v: RunResult.load(v),
        "persistence.load": lambda v: persistence.load(v, "result", (1,)),
        "tail_exponent.d": lambda v: tail_exponent(v, 0.5),
        "tail_exponent.r": lambda v: tail_exponent(2, v),
        "tail_exponent.angular": lambda v: tail_exponent(2, 0.5, v),
        "steady_state.r": lambda v: steady_state(v, 1.0),
        "steady_state.D": lambda v: steady_state(0.5, v),
        "EnsembleSpec.model": lambda v: EnsembleSpec(v, one, [1], (1.0,)),
        "EnsembleSpec.params": lambda v: EnsembleSpec("ulam", v, [1], (1.0,)),
        "EnsembleSpec.seeds": lambda v: EnsembleSpec("ulam", one, v, (1.0,)),
        "EnsembleSpec.times": lambda v: EnsembleSpec("ulam", one, [1], v),
        "parse_seeds": lambda v: parse_seeds(v),
        "law_from_characteristic.variance":
            lambda v: law_from_characteristic(lambda k: np.exp(-k**2 / 2), v),
    }


@pytest.mark.parametrize("name", sorted(_api_calls()))
def test_wrong_types_at_the_api_raise_invalid_argument(name, tmp_path, monkeypatch):
    # every public entry point, every wrong value of _WRONG: either accepted (a valid value of
    # that type) or InvalidArgumentError; never AttributeError, TypeError, ValueError, ...
    monkeypatch.chdir(tmp_path)  # a path-like value that is accepted writes only here
    call = _api_calls()[name]
    for value in _WRONG:
        try:
            call(value)
        except (InvalidArgumentError, ZeroDivisionError):  # 1/0: None means "no file" there
            pass


@pytest.mark.parametrize(
    "call",
    [
        lambda: simulate("not an engine", [1.0], 0, progress=False),
        lambda: simulate(Ulam(10, 0.5), "abc", 0, progress=False),
        lambda: simulate(Ulam(10, 0.5), [1.0], "x", progress=False),
        lambda: Ulam("many", 0.5),
        lambda: Ulam(10, "half"),
        lambda: Lattice(10, None),
    ],
)
def test_wrong_types_at_the_api_examples(call):
    with pytest.raises(InvalidArgumentError):
        call()


@pytest.mark.parametrize("r, n", [(0.5, "8"), (0.99, "8")])
def test_a_fixed_point_that_did_not_converge_is_not_a_success(capsys, r, n):
    # n = 8 is too coarse: Newton runs out of iterations (r = 0.5, residual 0.27) or stops on a
    # small step at a non-solution (r = 0.99, residual 4.8e-3); both exit 3 with a warning and
    # "converged": false, never status 0
    from maxwell_kinetics.app.cli import main

    assert main(["fixed-point", "-r", str(r), "--n", n, "--json"]) == 3
    captured = capsys.readouterr()
    assert json.loads(captured.out)["converged"] is False
    assert "did not converge" in captured.err


@pytest.mark.parametrize(
    "argv, named",
    [
        (["solve", "-r", "0.5", "--tau", "1e300", "--resolution", "coarse"], "tau=1e+300"),
        (["convergence", "--tau-max", "1e300", "--out", "OUT"], "tau-max=1e+300"),
        (["fixed-point", "-r", "0.5", "--n", "100000000"], "n=100000000"),
    ],
)
def test_absurd_kinetic_runs_are_refused_before_they_start(capsys, tmp_path, argv, named):
    # τ = 1e300 is 5e299 windows; n = 1e8 dense Chebyshev operators need ~1e6 TB
    argv = [str(tmp_path / "cv") if a == "OUT" else a for a in argv]
    err = run_error(capsys, argv)
    assert named in err and "estimate" in err
    assert not (tmp_path / "cv").exists()


@pytest.mark.parametrize("case", ["a file", "under a file", "unwritable"])
def test_reproduce_out_is_checked_before_any_work(capsys, tmp_path, monkeypatch, case):
    # exit 2 naming --out and the value, before the first comparison runs (a comparison that
    # ran would raise here), and nothing written.  "unwritable": the folder refuses a file (as
    # root, permissions do not stop writes, so the refusal is simulated at the OS call).
    import tempfile

    from maxwell_kinetics.app import comparisons

    def must_not_run(*args, **kwargs):
        raise AssertionError("a comparison ran before --out was checked")

    monkeypatch.setitem(comparisons.COMPARISONS, "kinetic_theory", must_not_run)
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    out = {"a file": blocker, "under a file": blocker / "sub",
           "unwritable": tmp_path / "ro"}[case]
    if case == "unwritable":
        real = tempfile.TemporaryFile

        def refuse(*args, dir=None, **kwargs):
            if dir is not None and str(dir) == str(out):
                raise PermissionError(13, "Permission denied")
            return real(*args, dir=dir, **kwargs)

        monkeypatch.setattr(tempfile, "TemporaryFile", refuse)
    err = run_error(capsys, ["reproduce", "--only", "kinetic_theory", "--out", str(out)])
    assert "out=" in err and str(out.name) in err
    assert blocker.read_text() == "x" and not (tmp_path / "ro").exists()
