"""Small drift of the kinetic side: the Solution records the angular_nodes of its solve (and
keeps it through save and load), the comparisons' solution cache is bounded, and the one-off
particle-run functions show their real signatures."""

from __future__ import annotations

import inspect
from collections import OrderedDict
from types import SimpleNamespace

import numpy as np
import pytest

from maxwell_kinetics.solver import Solution, solve


def test_solution_records_angular_nodes_and_keeps_them_on_disk(tmp_path):
    # the "accurate" η rule: the scheme test_scaling_tails.py's planar fixture compiles (the
    # same worker runs both files: tests/conftest.py, SHARED_COMPILATIONS)
    sol = solve(0.5, tau=[0.5], resolution="coarse", dimension=2, angular_nodes=8,
                angular_rule="accurate")
    assert sol.angular_nodes == 8
    sol.save(tmp_path / "s.npz")
    assert Solution.load(tmp_path / "s.npz").angular_nodes == 8
    meta, arrays = sol.to_record()
    del meta["angular_nodes"]  # a record written before the field: the solve's default
    assert Solution.from_record(meta, arrays).angular_nodes == 16


def test_the_comparisons_solution_cache_is_bounded(monkeypatch):
    from maxwell_kinetics import solver
    from maxwell_kinetics.app.comparisons import kinetic_predictions as kp

    calls = []

    def fake_solve(restitution, law, taus, resolution, progress=False):
        calls.append(restitution)
        return SimpleNamespace(tau=np.array(taus), G=np.zeros(2), deviation=np.zeros(2))

    monkeypatch.setattr(solver, "solve", fake_solve)
    monkeypatch.setattr(kp, "_SOLUTIONS", OrderedDict())
    monkeypatch.setattr(kp, "MAX_CACHED_SOLUTIONS", 3, raising=False)
    for r in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):
        kp.kinetic_solution(r, "gaussian", [1.0])
        assert len(kp._SOLUTIONS) <= 3
    assert len(kp._SOLUTIONS) == 3
    kp.kinetic_solution(0.6, "gaussian", [1.0])  # still cached: no new solve
    kp.kinetic_solution(0.1, "gaussian", [1.0])  # dropped: solved again
    assert calls == [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.1]


@pytest.mark.parametrize("name", ["ulam_snapshots", "ulam_final", "lattice_runs",
                                  "lattice_at_energy", "md_runs", "sticky_runs"])
def test_one_off_particle_runs_show_the_method_signature(name):
    from maxwell_kinetics.app.comparisons import particle_runs

    method = inspect.signature(getattr(particle_runs.ParticleRuns, name))
    function = inspect.signature(getattr(particle_runs, name))
    expected = list(method.parameters.values())[1:]  # without self
    assert list(function.parameters.values()) == expected
    assert function.return_annotation == method.return_annotation
