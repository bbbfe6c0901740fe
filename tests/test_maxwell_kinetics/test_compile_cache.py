"""The persistent compilation cache (maxwell_kinetics.compile_cache).

Fresh processes are the point of the cache, so the main checks run the solver in subprocesses
(1D, coarse grid, τ ≤ 3: a few seconds cold, about one and a half warm).  Whether a process
traced the scheme is read from ``_kinetic_scheme.TRACES``: a process that loads the executable
from the cache traces nothing.  A solve compiles one function (``step``); the warm cache also
holds the executable of a second configuration (the asymmetric law: a complex G, so arrays of
another shape), which the damage tests swap with the first one's.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from maxwell_kinetics import compile_cache

_SOLVE = """
import hashlib, json, sys
import jax
import numpy as np
from maxwell_kinetics import _kinetic_scheme, compile_cache
from maxwell_kinetics.solver import solve
for option in sys.argv[2:]:
    if option == "edit":  # as after an edit of the sources or an upgrade of a library
        compile_cache._code_fingerprint = lambda: "sources after an edit"
    elif option.startswith("jax-cache="):  # JAX's own persistent cache, on by the user
        jax.config.update("jax_compilation_cache_dir", option.split("=", 1)[1])
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
folder = compile_cache.enable(sys.argv[1])
sol = solve(0.5, "gaussian", (1.0, 3.0), "coarse")
own = sorted(p.name for p in folder.glob("*.entry")) if folder else []
if "also-complex" in sys.argv[2:]:
    solve(0.5, "asymmetric", (1.0,), "coarse")
print(json.dumps({"folder": str(folder), "traces": dict(_kinetic_scheme.TRACES), "own": own,
                  "G": hashlib.sha256(np.ascontiguousarray(sol.G).tobytes()).hexdigest()}))
"""


def _start(cache: Path, *options: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", _SOLVE, str(cache), *options],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _finish(proc: subprocess.Popen, timeout: float = 300) -> dict:
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise
    assert proc.returncode == 0, err
    assert err == "", err  # no warning either (a damaged entry is rebuilt silently)
    return json.loads(out)


def _solve_in_fresh_process(cache: Path, *options: str) -> dict:
    return _finish(_start(cache, *options))


def _entries(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.glob("*.entry"))}


def _valid(name: str, data: bytes) -> bool:
    return compile_cache._open(name.removesuffix(".entry"), data) is not None


def _reference_digest() -> str:
    """G of the same solve in this process, without the cache (plain ``jax.jit``)."""
    from maxwell_kinetics.solver import solve

    assert compile_cache.active_path() is None
    sol = solve(0.5, "gaussian", (1.0, 3.0), "coarse")
    return hashlib.sha256(np.ascontiguousarray(sol.G).tobytes()).hexdigest()


@pytest.fixture(scope="module")
def reference() -> str:
    """The digest of G from a solve with the cache off (this process, plain ``jax.jit``)."""
    return _reference_digest()


def _copy_of(warm, tmp_path) -> tuple[Path, Path]:
    """A copy of the warm cache: (root, folder of entries)."""
    root = tmp_path / "cache"
    shutil.copytree(warm[0], root)
    return root, root / warm[1].name


def _entries_of(warm, folder: Path) -> tuple[Path, Path]:
    """(the entry of the solve of ``_SOLVE``, the entry of the second configuration) in
    ``folder``, a copy of the warm cache's folder."""
    (own,) = warm[2]["own"]
    (other,) = {p.name for p in folder.glob("*.entry")} - {own}
    return folder / own, folder / other


@pytest.fixture(scope="module")
def warm(tmp_path_factory):
    """A cache filled by one fresh process: (root, folder of entries, that process's report)."""
    root = tmp_path_factory.mktemp("warm") / "cache"
    cold = _solve_in_fresh_process(root, "also-complex")
    return root, Path(cold["folder"]), cold


def test_a_fresh_process_fills_the_cache_and_the_next_one_loads_it(warm):
    root, folder, cold = warm
    assert folder.parent == root
    assert cold["traces"] == {"step": 2}  # one function, compiled for each configuration
    before = _entries(folder)
    assert len(cold["own"]) == 1 and len(before) == 2
    assert {name.split("-")[0] for name in before} == {"aot_step"}  # compiled ahead of time
    assert all(_valid(name, data) for name, data in before.items())

    again = _solve_in_fresh_process(root)
    assert again["traces"] == {}  # loaded: nothing traced, nothing compiled
    assert again["G"] == cold["G"]
    assert _entries(folder) == before  # nothing added or rewritten
    # and the numbers are those of the solver without any cache
    assert cold["G"] == _reference_digest()


def test_damaged_entries_are_never_trusted_and_are_rebuilt(warm, tmp_path):
    root = tmp_path / "cache"
    shutil.copytree(warm[0], root)
    folder = root / warm[1].name
    damaged = {}
    for i, path in enumerate(sorted(folder.glob("*.entry"))):
        data = path.read_bytes()
        if i % 3 == 0:
            data = data[: len(data) // 2]  # truncated (a writer killed mid-way)
        elif i % 3 == 1:
            data = data[:-1] + bytes([data[-1] ^ 0xFF])  # one flipped byte in the content
        else:
            data = os.urandom(len(data))  # garbage
        path.write_bytes(data)
        damaged[path.name] = data
    assert damaged and not any(_valid(n, d) for n, d in damaged.items())

    report = _solve_in_fresh_process(root, "also-complex")  # both configurations
    assert report["G"] == warm[2]["G"]
    assert report["traces"] == {"step": 2}  # compiled again, not loaded
    rebuilt = _entries(folder)
    assert set(damaged) <= set(rebuilt)
    assert all(_valid(name, data) for name, data in rebuilt.items())
    again = _solve_in_fresh_process(root)  # the next run loads what this one stored
    assert again["traces"] == {} and again["G"] == warm[2]["G"]


def test_two_processes_starting_at_once_on_an_empty_cache(tmp_path):
    root = tmp_path / "cache"
    procs = [_start(root), _start(root)]
    first, second = (_finish(p) for p in procs)
    assert first["G"] == second["G"]
    folder = Path(first["folder"])
    entries = _entries(folder)
    assert entries and all(_valid(name, data) for name, data in entries.items())
    assert not list(folder.glob(".tmp-*"))  # every write was renamed into place


#: ``delete`` and ``truncate`` run in ``make test-full`` only: in ``make test`` the FIFO test
#: below checks a missing (unreadable) entry of the solve and the damaged-entries test above
#: truncated ones, each compiled again, stored whole and loaded by the next run.
@pytest.mark.parametrize("damage", [pytest.param("delete", marks=pytest.mark.full),
                                    pytest.param("truncate", marks=pytest.mark.full),
                                    "swap", "edit"])
def test_an_executable_compiled_again_is_whole_and_every_later_run_is_right(
        warm, tmp_path, reference, damage):
    # The solve's entry is gone (deleted, truncated, swapped with another entry's file),
    # or the key changed (an edit of the sources, an upgrade of a library): the run compiles
    # again and stores the new executable, and the NEXT run loads it.  Both runs must give the
    # numbers of the cache-off solve (once, a stored executable lacked its code: every later
    # run failed with "Function ... not found" until the folder was deleted).
    root, folder = _copy_of(warm, tmp_path)
    own, other = _entries_of(warm, folder)
    options = ()
    if damage == "delete":
        own.unlink()
    elif damage == "truncate":
        own.write_bytes(own.read_bytes()[:1000])
    elif damage == "swap":
        data = own.read_bytes()
        own.write_bytes(other.read_bytes())
        other.write_bytes(data)
    else:
        options = ("edit",)
    first = _solve_in_fresh_process(root, *options)
    second = _solve_in_fresh_process(root, *options)
    assert first["G"] == second["G"] == reference
    assert second["traces"] == {}  # the second run loaded what the first one stored


def test_an_entry_that_fails_when_it_runs_is_dropped_and_the_solve_is_right(
        warm, tmp_path, reference):
    # Each executable sealed under the other's key (the two configurations' arrays differ in
    # shape): both pass the checksum and load, and fail when called.  The solves compile
    # afresh, replace both entries, and are right.
    root, folder = _copy_of(warm, tmp_path)
    own, other = _entries_of(warm, folder)
    contents = {path: compile_cache._open(path.name.removesuffix(".entry"), path.read_bytes())
                for path in (own, other)}
    for path, source in ((own, other), (other, own)):
        path.write_bytes(compile_cache._seal(path.name.removesuffix(".entry"), contents[source]))
    swapped = _entries(folder)
    assert all(_valid(name, data) for name, data in swapped.items())
    report = _solve_in_fresh_process(root, "also-complex")
    assert report["G"] == reference
    assert report["traces"] == {"step": 2}  # compiled again, both
    rebuilt = _entries(folder)  # both replaced by fresh executables...
    assert set(rebuilt) == set(swapped)
    assert all(rebuilt[name] != swapped[name] for name in (own.name, other.name))
    again = _solve_in_fresh_process(root)
    assert again["G"] == reference and again["traces"] == {}  # ...and loaded by the next


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_in_the_folder_is_skipped_not_opened(warm, tmp_path, reference):
    root, folder = _copy_of(warm, tmp_path)
    own, _ = _entries_of(warm, folder)
    own.unlink()
    os.mkfifo(own)  # opened for reading, it would block until a writer comes: never
    os.mkfifo(folder / "a-fifo-of-no-entry")
    report = _finish(_start(root), timeout=120)
    assert report["G"] == reference
    assert own.is_file() and _valid(own.name, own.read_bytes())  # replaced
    again = _finish(_start(root), timeout=120)  # the next run loads what this one stored
    assert again["traces"] == {} and again["G"] == reference


def test_with_jax_own_cache_on_only_whole_executables_are_stored(tmp_path, reference):
    # A user who switched on JAX's own persistent cache: the second process gets its compiles
    # from there, and XLA serializes such an executable without the code of its functions.
    # Nothing that does not run is stored: the third process (JAX's cache off) loads what the
    # second one stored, or compiles, and removes nothing.
    jax_cache = f"jax-cache={tmp_path / 'jax-own'}"
    first = _solve_in_fresh_process(tmp_path / "one", jax_cache)
    second = _solve_in_fresh_process(tmp_path / "two", jax_cache)
    stored = _entries(Path(second["folder"]))
    third = _solve_in_fresh_process(tmp_path / "two")
    assert first["G"] == second["G"] == third["G"] == reference
    after = _entries(Path(third["folder"]))
    assert all(after[name] == data for name, data in stored.items())  # none failed, none dropped
    assert {name.split("-")[0] for name in after} == {"aot_step"}


# -- the store itself ------------------------------------------------------------------------
def test_an_entry_read_under_another_key_is_foreign_and_removed(tmp_path):
    store = compile_cache._Store(tmp_path)
    store.put("jit_a-01", b"payload of a")
    assert store.get("jit_a-01") == b"payload of a"
    shutil.copy(tmp_path / "jit_a-01.entry", tmp_path / "jit_b-02.entry")
    assert store.get("jit_b-02") is None
    assert not (tmp_path / "jit_b-02.entry").exists()
    (tmp_path / "jit_c-03.entry").write_bytes(b"not an entry at all")
    assert store.get("jit_c-03") is None
    assert store.get("jit_a-01") == b"payload of a"  # the good one is left alone


def test_the_store_reads_regular_files_only_and_none_too_large(tmp_path, monkeypatch):
    store = compile_cache._Store(tmp_path)
    store.put("jit_a-01", b"payload of a")
    good = (tmp_path / "jit_a-01.entry").read_bytes()
    # a symbolic link to a valid entry is not followed (it could point to /dev/zero) ...
    (tmp_path / "elsewhere").write_bytes(good)
    link = tmp_path / "jit_a-01.entry"
    link.unlink()
    link.symlink_to(tmp_path / "elsewhere")
    assert store.get("jit_a-01") is None
    assert (tmp_path / "elsewhere").read_bytes() == good  # ... and what it points to stays
    store.put("jit_a-01", b"payload of a")  # the next write replaces the link
    assert not link.is_symlink() and store.get("jit_a-01") == b"payload of a"
    if hasattr(os, "mkfifo"):  # a FIFO is not opened (no writer: the reader would block)
        link.unlink()
        os.mkfifo(link)
        assert store.get("jit_a-01") is None
    # an entry above the limit is damaged: not read, removed
    monkeypatch.setattr(compile_cache, "MAX_ENTRY_BYTES", len(good) - 1)
    store.put("jit_b-02", b"payload of a")
    assert store.get("jit_b-02") is None
    assert not (tmp_path / "jit_b-02.entry").exists()


def test_entries_unused_for_a_month_are_removed_and_a_load_keeps_one(tmp_path, monkeypatch):
    # Each edit or upgrade changes the keys: the old entries would pile up for ever.
    import time

    folder = compile_cache.enable(tmp_path / "c")
    compile_cache.disable()
    store = compile_cache._Store(folder)
    for key in ("aot_old-01", "aot_used-02", "aot_recent-03"):
        store.put(key, b"an executable")
    month = compile_cache.UNUSED_DAYS * 86400.0
    now = time.time()
    for key, age in (("aot_old-01", month + 60), ("aot_used-02", month + 60),
                     ("aot_recent-03", month - 3600)):
        os.utime(folder / f"{key}.entry", (now - age, now - age))
    (folder / ".tmp-killed").write_bytes(b"half")
    os.utime(folder / ".tmp-killed", (now - 7200, now - 7200))
    assert store.get("aot_used-02") == b"an executable"  # loaded now: its month starts again
    assert compile_cache.enable(tmp_path / "c") == folder
    compile_cache.disable()
    assert sorted(p.name for p in folder.iterdir()) == ["aot_recent-03.entry",
                                                         "aot_used-02.entry"]


# -- where the cache lives, and turning it off ------------------------------------------------
def test_default_folder_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv(compile_cache.ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert compile_cache.configured_path() == tmp_path / "maxwell-kinetics" / "jax"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/ignored")
    assert compile_cache.default_path() == Path.home() / ".cache" / "maxwell-kinetics" / "jax"
    monkeypatch.setenv(compile_cache.ENV, str(tmp_path / "mine"))
    assert compile_cache.configured_path() == tmp_path / "mine"


@pytest.mark.parametrize("word", ["1", "on", "ON", "yes", "true", "", "  "])
def test_the_variable_saying_on_means_the_default_folder(monkeypatch, tmp_path, word):
    # not a folder named "1" or "on" in the working folder
    monkeypatch.setenv(compile_cache.ENV, word)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert compile_cache.configured_path() == tmp_path / "maxwell-kinetics" / "jax"


@pytest.mark.parametrize("word", ["0", "off", "OFF", "none", "false", "no"])
def test_the_variable_turns_the_cache_off(monkeypatch, tmp_path, word):
    monkeypatch.setenv(compile_cache.ENV, word)
    monkeypatch.chdir(tmp_path)
    assert compile_cache.enable() is None
    assert compile_cache.active_path() is None
    assert list(tmp_path.iterdir()) == []


_JAX_OPTIONS = ("jax_compilation_cache_dir", "jax_enable_compilation_cache",
                "jax_persistent_cache_min_compile_time_secs",
                "jax_persistent_cache_enable_xla_caches")


def test_enable_and_disable_change_no_jax_setting(tmp_path):
    # A Python user's JAX stays as it was: JAX's own persistent cache is not switched on (it
    # would write every function of the user's program into the folder).
    import jax

    before = {name: getattr(jax.config, name) for name in _JAX_OPTIONS}
    folder = compile_cache.enable(tmp_path / "c")
    try:
        assert folder is not None and folder.is_dir()
        assert {name: getattr(jax.config, name) for name in _JAX_OPTIONS} == before
        assert compile_cache.enable(tmp_path / "c") == folder  # again: the same, no change
        jax.jit(lambda x: x * 3.0)(np.arange(3.0)).block_until_ready()
        assert list(folder.iterdir()) == []  # a function of the user's: not in the folder
    finally:
        compile_cache.disable()
    assert {name: getattr(jax.config, name) for name in _JAX_OPTIONS} == before
    assert compile_cache.active_path() is None


_CLI = ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse", "--json", "--no-progress"]


def _main(capsys, argv):
    from maxwell_kinetics.app.cli import main

    status = main(argv)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.parametrize("where", ["file", "file/sub", "loop", "new\nline"])
def test_an_unusable_folder_gives_one_warning_line_and_the_solve_runs(
        monkeypatch, tmp_path, capsys, where):
    (tmp_path / "file").write_text("a regular file is in the way")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")  # a symbolic link to itself
    (tmp_path / "new\nline").write_text("a file whose name has a line break")
    monkeypatch.setenv(compile_cache.ENV, str(tmp_path / where))
    status, out, err = _main(capsys, _CLI)
    assert status == 0
    assert json.loads(out)["G_real"]
    lines = err.splitlines()
    shown = str(tmp_path / where) if "\n" not in where else repr(str(tmp_path / where))
    assert len(lines) == 1 and "warning" in lines[0] and shown in lines[0]
    assert compile_cache.active_path() is None
    assert (tmp_path / "file").read_text() == "a regular file is in the way"


def test_no_cache_writes_nothing_and_cli_runs_leave_jax_as_found(monkeypatch, tmp_path, capsys):
    import jax

    # first a run with another folder: its executables are in this process's memory, and the
    # next folder must still get its own entries
    monkeypatch.setenv(compile_cache.ENV, str(tmp_path / "other"))
    assert _main(capsys, _CLI)[0] == 0
    assert list((tmp_path / "other").rglob("*.entry"))
    root = tmp_path / "cache"
    monkeypatch.setenv(compile_cache.ENV, str(root))
    status, out, err = _main(capsys, [*_CLI, "--no-cache"])
    assert status == 0 and err == ""
    assert not root.exists()
    status, _, err = _main(capsys, _CLI)  # the default: on, in the folder of the variable
    assert status == 0 and err == ""
    assert list(root.rglob("*.entry"))
    assert compile_cache.active_path() is None  # switched off again when the command ended
    assert jax.config.jax_compilation_cache_dir is None


@pytest.mark.parametrize("command", ["solve", "fixed-point", "steady", "tail-exponent",
                                     "convergence", "reproduce"])
def test_every_kinetic_subcommand_takes_no_cache(command):
    from maxwell_kinetics.app.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices[command]
    assert "--no-cache" in sub._option_string_actions


def test_a_failed_window_is_reported_not_hidden():
    # diffrax runs with throw=False (a host callback would keep the executable out of the
    # cache): a window that fails (here: two steps allowed) must still stop the solve.
    from maxwell_kinetics.solver import SolverOptions, solve

    options = dataclasses.replace(SolverOptions(), max_steps_per_window=2)
    with pytest.raises(FloatingPointError, match="non-finite G at tau=1"):
        solve(0.5, "gaussian", (1.0,), "coarse", options=options)


@pytest.mark.parametrize("platforms, command", [
    ("cuda", ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse", "--save", "G.npz"]),
    ("nonsense", ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse", "--plot",
                  "G.png"]),
    ("nonsense", ["reproduce", "--small", "--only", "kinetic_theory", "--out", "figures"]),
])
def test_an_unusable_jax_platforms_is_one_line_and_exit_2(tmp_path, platforms, command):
    # No GPU here (cuda), or no such platform: the user's setting is refused like a bad option,
    # before anything is written (the output, the figures folder, the cache folder).
    env = {**os.environ, "JAX_PLATFORMS": platforms, compile_cache.ENV: str(tmp_path / "cache")}
    proc = subprocess.run([sys.executable, "-m", "maxwell_kinetics.app.cli", *command, "--json"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"maxwell-kinetics {command[0]}: error: ")
    assert f"JAX_PLATFORMS={platforms!r}" in lines[0]
    assert list(tmp_path.iterdir()) == []
