"""The particle runs behind the comparisons (maxwell_kinetics.app.comparisons.particle_runs): a
runner keeps its runs and hands out read-only data, runners share nothing, MD goes through the
run driver with the same results as advancing the engine directly, and the package's modules
import each other without cycles."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT

from maxwell_kinetics.app.comparisons import particle_runs as pr
from particles import md, observables
from particles.driver import simulate
from particles.lattice import Lattice

PACKAGE = ROOT / "maxwell_kinetics" / "app" / "comparisons"


def test_cached_lattice_runs_cannot_be_changed_by_a_caller():
    """A caller that writes into a returned array gets an error, and one that replaces entries
    of the returned dict changes nothing: the next caller gets the values of a fresh run."""
    args = (0.5, 64, (1.0, 2.0, 4.0), (0, 1))
    runner = pr.ParticleRuns()
    first = runner.lattice_runs(*args, structure=True)
    for key in ("times", "energy", "k", "structure"):
        assert not first[key].flags.writeable, key
        with pytest.raises(ValueError, match="read-only"):
            first[key][0] = 123.0
    first["energy"] = np.zeros(3)
    second = runner.lattice_runs(*args, structure=True)
    fresh = [simulate(Lattice(64, 0.5, "gaussian", True), [1.0, 2.0, 4.0], s, progress=False,
                      structure_factor=True) for s in (0, 1)]
    np.testing.assert_array_equal(second["energy"], [r.energy for r in fresh])
    np.testing.assert_array_equal(second["structure"], [r.structure[1] for r in fresh])


def test_lattice_runs_record_only_what_is_asked_and_the_dynamics_does_not_change():
    args = (0.5, 64, (1.0, 2.0, 4.0), (0, 1))
    energy_only = pr.lattice_runs(*args)
    assert set(energy_only) == {"times", "energy", "seconds"}
    full = pr.lattice_runs(*args, structure=True, snapshots=True)
    np.testing.assert_array_equal(energy_only["energy"], full["energy"])
    assert full["snapshots"].shape == (2, 3, 64)
    np.testing.assert_array_equal(full["energy"], np.mean(full["snapshots"] ** 2, axis=2))


def test_lattice_at_energy_is_read_only():
    out = pr.lattice_at_energy(0.5, 64, 0.2, (0, 1))
    # each trace stops at its first energy at or below the target
    assert all(t[-1, 1] <= 0.2 < t[-2, 1] for t in out["traces"])
    for key in ("tau", "energy", "snapshots"):
        assert not out[key].flags.writeable, key
    assert all(not t.flags.writeable for t in out["traces"])


def _md_direct(restitution, n, delta, times, seeds):
    """The loop md_runs ran before it used the driver: the engine advanced straight to each
    requested time."""
    params = md.MDParams(n=n, density=1.0, restitution=restitution, delta=delta, initial="gaussian")
    out = {k: np.empty((len(seeds), len(times), n)) for k in ("snapshots", "positions")}
    out["energy"] = np.empty((len(seeds), len(times)))
    out["tau"] = np.empty_like(out["energy"])
    for i, seed in enumerate(seeds):
        engine = md.MDEngine(params)
        state = engine.initial_state(np.random.default_rng(seed))
        for j, t in enumerate(times):
            state = engine.advance(state, t)
            out["energy"][i, j] = observables.energy(state.velocities)
            out["tau"][i, j] = md.collisions_per_particle(state)
            out["snapshots"][i, j] = state.velocities
            out["positions"][i, j] = md.rod_positions(state, params)
    return out


def test_md_runs_through_the_driver_equal_the_direct_engine_loop():
    """Bit for bit, with requested times between the driver's stops (every MD_STOP_STEP)."""
    times, seeds = (0.5, 13.25, 37.5), (0, 3)
    got = pr.md_runs(0.7, 60, 1e-4, times, seeds)
    want = _md_direct(0.7, 60, 1e-4, times, seeds)
    assert got["tau"][0, -1] > 1  # collisions happened
    for key, value in want.items():
        np.testing.assert_array_equal(got[key], value, err_msg=key)
        assert not got[key].flags.writeable, key


def test_a_runner_keeps_its_runs_and_runners_share_nothing(monkeypatch):
    calls = []
    real = pr.ParticleRuns._runs

    def counted(self, *args, **kwargs):
        calls.append(args[0])
        return real(self, *args, **kwargs)

    monkeypatch.setattr(pr.ParticleRuns, "_runs", counted)
    args = (0.5, 32, (1.0,), (0,))
    a, b = pr.ParticleRuns(), pr.ParticleRuns()
    a.lattice_runs(*args)
    a.lattice_runs(*args)
    assert calls == ["lattice"]  # kept by a
    b.lattice_runs(*args)
    assert calls == ["lattice", "lattice"]  # b has its own
    a.clear()
    a.lattice_runs(*args)
    assert len(calls) == 3


def test_md_runs_checkpoint_and_resume(tmp_path, monkeypatch):
    """With a checkpoint folder each run leaves its checkpoint; a later process (cache cleared)
    reads the finished runs back instead of running them (the engine's advance is made to fail),
    with the same records, the rods' positions of every time included (the driver keeps them
    with each snapshot, checkpoints too)."""
    times, seeds = (1.0, 2.5), (0, 1)
    first = pr.md_runs(0.7, 40, 1e-4, times, seeds, checkpoint_dir=tmp_path)
    files = sorted(tmp_path.glob("md_*.npz"))
    assert len(files) == 2

    def no_advance(*args, **kwargs):
        raise AssertionError("a finished run was run again")

    monkeypatch.setattr(md.MDEngine, "advance", no_advance)
    again = pr.md_runs(0.7, 40, 1e-4, times, seeds, checkpoint_dir=tmp_path)
    for key in ("energy", "tau", "snapshots", "positions"):
        np.testing.assert_array_equal(again[key], first[key], err_msg=key)
    assert np.isfinite(again["positions"]).all()


def _package_imports(path: Path) -> tuple[set[str], list[str]]:
    """Modules of the package that ``path`` imports (top level), and any import of one inside a
    function."""
    tree = ast.parse(path.read_text())
    found, nested = set(), []
    top = set(map(id, tree.body))
    for node in ast.walk(tree):
        names = []
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            names = [node.module] if node.module else [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
                "maxwell_kinetics.app.comparisons"):
            names = [node.module.split(".")[3] if node.module.count(".") > 2 else "__init__"]
        names = [n.split(".")[0] for n in names]
        if not names:
            continue
        if id(node) not in top:
            nested.append(f"{path.name}:{node.lineno}")
        found.update(names)
    return found, nested


def test_package_modules_import_without_cycles():
    """The import graph of maxwell_kinetics.app.comparisons (relative and absolute imports of its
    modules) has no cycle, no module imports the package itself, and no import of a package
    module hides inside a function."""
    modules = {p.stem: p for p in PACKAGE.glob("*.py")}
    graph = {}
    for name, path in modules.items():
        deps, nested = _package_imports(path)
        assert not nested, nested
        if name != "__init__":
            assert "__init__" not in deps, name
        graph[name] = {d for d in deps if d in modules} - {name}
    assert graph["base"] == set()
    assert graph["drawing"] == set()

    def visit(node, path):
        for dep in graph[node]:
            assert dep not in path, path + [dep]
            visit(dep, path + [dep])

    for name in graph:
        visit(name, [name])


def test_runs_through_the_ensemble_equal_the_serial_runs(tmp_path):
    """``reproduce --workers N`` / ``--full``: the comparisons' Ulam, lattice and MD runs go
    through the ensemble engine on dask (2 workers), one task file per run, and give the serial
    results bit for bit."""
    serial = {
        "ulam": pr.ulam_snapshots(0.5, "gaussian", 300, [0.5, 2.0], (0, 1, 2)),
        "lattice": pr.lattice_runs(0.5, 300, (1.0, 4.0), (0, 1), structure=True, snapshots=True),
        "md": pr.md_runs(0.7, 60, 1e-4, (0.5, 7.5), (0, 1)),
    }
    runner = pr.ParticleRuns(tmp_path / "runs", workers=2)
    parallel = {
        "ulam": runner.ulam_snapshots(0.5, "gaussian", 300, [0.5, 2.0], (0, 1, 2)),
        "lattice": runner.lattice_runs(0.5, 300, (1.0, 4.0), (0, 1), structure=True,
                                       snapshots=True),
        "md": runner.md_runs(0.7, 60, 1e-4, (0.5, 7.5), (0, 1)),
    }
    tasks = sorted((tmp_path / "runs").glob("task-*.npz"))
    assert len(tasks) == 3 + 2 + 2
    np.testing.assert_array_equal(parallel["ulam"], serial["ulam"])
    for model in ("lattice", "md"):
        for key, value in serial[model].items():
            if key != "seconds":
                np.testing.assert_array_equal(parallel[model][key], value, err_msg=key)
