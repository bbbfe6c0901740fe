"""Output paths that are not regular files: every output option of every subcommand, generated
from the parser, against a device node, a FIFO, a socket, a symlink to a file in another folder
and a symlink to a folder.  After each run the object at the path must be the same kind of
object as before (a device stays a device, a link stays a link), and a refused run exits 2,
names the option and writes nothing.

Writing replaces a file by a rename; before these checks, ``--save /dev/null`` run as root
turned the system's null device into a regular file.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import stat
import tempfile
from pathlib import Path

import numpy as np
import pytest
from helpers import run_error

from maxwell_kinetics.app.cli import build_parser, main
from particles import persistence
from particles.paths import file_kind
from particles.validation import InvalidArgumentError

#: Options that name a file the command writes, and those that name a folder it writes into.
FILE_OPTIONS = {"save", "checkpoint", "plot"}
DIR_OPTIONS = {"out"}

#: A cheap run of each subcommand (path of subcommands, then its other arguments); the output
#: option is appended.  Every subcommand that has an output option must be listed here.
CHEAP = {
    ("solve",): ["--restitution", "0.5", "--tau", "1", "--resolution", "coarse", "--json"],
    ("steady",): ["--restitution", "0.5", "--driving", "1", "--json"],
    ("convergence",): ["--restitution", "0.5", "--tau-max", "10", "--json"],
    ("reproduce",): ["--small", "--only", "energy_decay", "--json", "--no-progress"],
    ("simulate", "ulam"): ["--n", "100", "--restitution", "0.5", "--tau", "1", "--json"],
    ("simulate", "lattice"): ["--n", "100", "--restitution", "0.5", "--tau", "1", "--json"],
    ("simulate", "md"): ["--n", "100", "--density", "1", "--restitution", "0.5", "--t", "1",
                         "--json"],
    ("simulate", "sticky"): ["--n", "100", "--density", "1", "--t", "1", "--json"],
    ("ensemble", "ulam"): ["--n", "100", "--restitution", "0.5", "--tau", "1", "--seeds", "1",
                           "--serial", "--json", "--no-progress"],
    ("ensemble", "lattice"): ["--n", "100", "--restitution", "0.5", "--tau", "1", "--seeds",
                              "1", "--serial", "--json", "--no-progress"],
    ("ensemble", "md"): ["--n", "100", "--density", "1", "--restitution", "0.5", "--t", "1",
                         "--seeds", "1", "--serial", "--json", "--no-progress"],
    ("ensemble", "sticky"): ["--n", "100", "--density", "1", "--t", "1", "--seeds", "1",
                             "--serial", "--json", "--no-progress"],
}
#: Runs too long to carry out in full here: they are checked up to the refusal, and a folder
#: option through a symlink to a folder by the check that runs before any work.
COSTLY = {("convergence",), ("reproduce",)}


def _output_options(parser: argparse.ArgumentParser, path=()) -> list[tuple[tuple, str]]:
    """(subcommand path, option dest) of every output option, by walking the real parser."""
    found = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found += _output_options(sub, (*path, name))
        elif action.dest in FILE_OPTIONS | DIR_OPTIONS and action.option_strings:
            found.append((path, action.dest))
    return found


OPTIONS = _output_options(build_parser())


def test_every_output_option_is_covered():
    assert OPTIONS, "the parser walk found no output option"
    commands = {path for path, _ in OPTIONS}
    assert commands <= set(CHEAP), f"add a cheap run for {sorted(commands - set(CHEAP))}"
    # the options known to exist today are all found (the walk is not vacuous)
    for expected in [(("solve",), "save"), (("solve",), "plot"), (("steady",), "plot"),
                     (("simulate", "md"), "checkpoint"), (("ensemble", "sticky"), "out"),
                     (("reproduce",), "out"), (("convergence",), "out")]:
        assert expected in OPTIONS


@pytest.fixture
def short_dir():
    """A folder with a short path (a socket's path is limited to about 100 bytes)."""
    d = tempfile.mkdtemp(prefix="mk-", dir="/tmp")
    yield Path(d)
    shutil.rmtree(d, ignore_errors=True)


def _make(kind: str, where: Path) -> Path:
    path = where / f"special-{kind}"
    if kind == "device":
        if os.geteuid() != 0:
            pytest.skip("mknod of a character device needs root (CI and containers run as root)")
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))  # the null device's numbers
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "socket":
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.bind(str(path))
        s.close()
    return path


SPECIAL = {"device": "character device", "fifo": "FIFO", "socket": "socket"}


def _argv(path: tuple, option: str, target: Path) -> list[str]:
    return [*path, *CHEAP[path], f"--{option}", str(target)]


@pytest.mark.parametrize("kind", sorted(SPECIAL))
@pytest.mark.parametrize(("path", "option"), OPTIONS, ids=lambda x: "-".join(x)
                         if isinstance(x, tuple) else x)
def test_special_file_is_refused_and_kept(capsys, short_dir, path, option, kind):
    target = _make(kind, short_dir)
    if option == "plot":  # an image path needs an image suffix: the special file has one
        os.rename(target, target.with_suffix(".png"))
        target = target.with_suffix(".png")
    before = sorted(os.listdir(short_dir))
    err = run_error(capsys, _argv(path, option, target))
    assert f"argument {option}=" in err, err
    assert SPECIAL[kind] in err and str(target) in err
    assert file_kind(target) == SPECIAL[kind]  # still the same kind of object
    assert sorted(os.listdir(short_dir)) == before  # nothing written beside it


@pytest.mark.parametrize(("path", "option"), OPTIONS, ids=lambda x: "-".join(x)
                         if isinstance(x, tuple) else x)
def test_symlink_to_directory(capsys, tmp_path, path, option):
    folder = tmp_path / "elsewhere"
    folder.mkdir()
    link = tmp_path / ("link.png" if option == "plot" else "link")
    link.symlink_to(folder, target_is_directory=True)
    if option in FILE_OPTIONS:  # a file option onto a folder is refused
        err = run_error(capsys, _argv(path, option, link))
        assert "directory" in err and str(link) in err
        assert os.listdir(folder) == []
    elif path not in COSTLY:  # a folder option follows the link and writes into the folder
        assert main(_argv(path, option, link)) == 0
        capsys.readouterr()
        assert os.listdir(folder)
    else:  # too costly to run here: the check that runs before any work accepts it
        from particles.paths import check_output_dir

        assert check_output_dir(link, option) == link
    assert link.is_symlink() and link.resolve() == folder.resolve()


@pytest.mark.parametrize(("path", "option"), OPTIONS, ids=lambda x: "-".join(x)
                         if isinstance(x, tuple) else x)
def test_symlink_to_file_in_another_folder(capsys, tmp_path, path, option):
    other = tmp_path / "other"
    other.mkdir()
    suffix = ".png" if option == "plot" else ".npz"
    real = other / f"target{suffix}"
    real.write_bytes(b"old")
    link = tmp_path / f"link{suffix}"
    link.symlink_to(real)
    if option in DIR_OPTIONS:  # a folder option onto a link to a file is refused
        err = run_error(capsys, _argv(path, option, link))
        assert "regular file" in err and str(link) in err
        assert real.read_bytes() == b"old"
    else:  # every command with a file option is cheap enough to run
        assert path not in COSTLY
        assert main(_argv(path, option, link)) == 0
        capsys.readouterr()
        data = real.read_bytes()
        # the target got the new file, written beside it (no temporary left there)
        assert data != b"old" and (data[:8] == b"\x89PNG\r\n\x1a\n" or data[:2] == b"PK")
        assert sorted(os.listdir(other)) == [real.name]
    assert link.is_symlink() and link.resolve() == real.resolve()


# --------------------------------------------------------------------------- Python API


@pytest.mark.parametrize("kind", sorted(SPECIAL))
def test_persistence_never_renames_onto_a_special_file(short_dir, kind):
    target = _make(kind, short_dir)
    with pytest.raises(InvalidArgumentError, match=SPECIAL[kind]):
        persistence.save(target, "result", 1, {"x": np.arange(3)})
    with pytest.raises(InvalidArgumentError, match=SPECIAL[kind]):
        persistence.write_text(target, "text")
    assert file_kind(target) == SPECIAL[kind]
    assert os.listdir(short_dir) == [target.name]


def test_persistence_refuses_a_special_file_that_appears_while_writing(short_dir):
    target = short_dir / "out.npz"

    def write(fh):  # a FIFO takes the path between the check and the rename
        fh.write(b"data")
        os.mkfifo(target)

    with pytest.raises(InvalidArgumentError, match="FIFO"):
        persistence.write_atomic(target, write)
    assert file_kind(target) == "FIFO"
    assert os.listdir(short_dir) == [target.name]  # the temporary file is removed


def test_persistence_writes_through_a_symlink_chain(tmp_path):
    (tmp_path / "a").mkdir()
    real = tmp_path / "a" / "real.npz"
    hop = tmp_path / "hop.npz"
    link = tmp_path / "link.npz"
    hop.symlink_to(real)  # dangling: the file is created at the end of the chain
    link.symlink_to(hop)
    persistence.save(link, "result", 1, {"x": np.arange(3)})
    assert link.is_symlink() and hop.is_symlink() and real.is_file()
    assert np.array_equal(persistence.load(link, "result", (1,)).arrays["x"], np.arange(3))


def test_solution_and_run_result_save_refuse_a_fifo(short_dir):
    from particles.driver import simulate
    from particles.ulam import Ulam

    fifo = _make("fifo", short_dir)
    result = simulate(Ulam(50, 0.5), [1.0], 1, progress=False)
    with pytest.raises(InvalidArgumentError, match="FIFO"):
        result.save(fifo)
    with pytest.raises(InvalidArgumentError, match="checkpoint.*FIFO"):
        simulate(Ulam(50, 0.5), [1.0], 1, progress=False, checkpoint=fifo)
    assert file_kind(fifo) == "FIFO"


def test_ensemble_folder_that_is_a_fifo(short_dir):
    from particles.ensemble import EnsembleSpec, run_ensemble

    fifo = _make("fifo", short_dir)
    spec = EnsembleSpec("ulam", {"n": 50, "restitution": 0.5}, (1,), (1.0,))
    with pytest.raises(InvalidArgumentError, match="out.*FIFO"):
        run_ensemble(spec, fifo, executor="serial", progress=False)
    assert file_kind(fifo) == "FIFO"
