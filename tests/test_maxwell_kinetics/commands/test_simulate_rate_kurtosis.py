"""``simulate ulam --rate relative_velocity --density n --t ...`` (the hard-rod Boltzmann DSMC in
time t) and its bad input; ``simulate --json`` gives ``kurtosis`` at every output time for every
model, equal to ⟨v⁴⟩/⟨v²⟩² of the run's velocities."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import run_error, run_json

from particles.driver import RunResult, simulate
from particles.ulam import Ulam


def test_simulate_ulam_relative_velocity_is_the_engine_in_time_t(capsys, tmp_path):
    path = tmp_path / "run.npz"
    out = run_json(capsys, ["simulate", "ulam", "--n", "500", "--restitution", "0.6",
                            "--rate", "relative_velocity", "--density", "2.5",
                            "--t", "0.5,2", "--seed", "3", "--save", str(path), "--json"])
    assert out["t"] == [0.5, 2.0] and "tau" not in out
    assert out["params"]["rate"] == "relative_velocity" and out["params"]["density"] == 2.5
    run = simulate(Ulam(500, 0.6, rate="relative_velocity", density=2.5), [0.5, 2.0], 3,
                   progress=False)
    assert out["energy"] == run.energy.tolist() and out["collisions"] == run.collisions[-1]
    saved = RunResult.load(path)
    v = saved.velocities
    assert out["kurtosis"][-1] == pytest.approx(np.mean(v**4) / np.mean(v**2) ** 2, rel=1e-12)
    assert np.array_equal(saved.kurtosis, run.kurtosis)


@pytest.mark.parametrize("argv, name, value", [
    (["--rate", "relative_velocity", "--tau", "1"], "tau", "'1'"),
    (["--rate", "maxwell", "--tau", "1"], "rate", "'maxwell'"),
    (["--rate", "relative_velocity", "--density", "0", "--t", "1"], "density", "'0'"),
    (["--rate", "relative_velocity", "--density", "-3", "--t", "1"], "density", "'-3'"),
    (["--rate", "relative_velocity", "--density", "inf", "--t", "1"], "density", "'inf'"),
    (["--rate", "relative_velocity", "--density", "nan", "--t", "1"], "density", "'nan'"),
    (["--density", "2", "--tau", "1"], "density", "2.0"),
])
def test_bad_rate_time_or_density_is_named_and_writes_nothing(capsys, tmp_path, argv, name,
                                                              value):
    path = tmp_path / "run.npz"
    err = run_error(capsys, ["simulate", "ulam", "--n", "50", "--restitution", "0.5", *argv,
                             "--save", str(path), "--json"])
    assert f"{name}={value}" in err
    assert not path.exists()


@pytest.mark.parametrize("argv", [
    ["ulam", "--n", "400", "--restitution", "0.5", "--tau", "0,1,3"],
    ["ulam", "--n", "400", "--restitution", "0.5", "--dimension", "2", "--tau", "0,1,3"],
    ["ulam", "--n", "400", "--restitution", "0.5", "--rate", "relative_velocity",
     "--t", "0,1,3"],
    ["lattice", "--n", "400", "--restitution", "0.5", "--tau", "0,1,3"],
    ["md", "--n", "100", "--density", "1", "--restitution", "0.9", "--t", "0,1,3"],
    ["sticky", "--n", "400", "--density", "1", "--t", "0,1,3"],
], ids=["ulam", "ulam-2d", "ulam-dsmc", "lattice", "md", "sticky"])
def test_json_has_the_kurtosis_at_every_time_for_every_model(capsys, tmp_path, argv):
    path = tmp_path / "run.npz"
    out = run_json(capsys, ["simulate", *argv, "--seed", "2", "--save", str(path), "--json"])
    kurtosis = out["kurtosis"]
    assert len(kurtosis) == 3 and all(k > 1.0 for k in kurtosis)  # ⟨v⁴⟩ ≥ ⟨v²⟩², > for N > 2
    v = RunResult.load(path).velocities
    x = v[:, 0] if v.ndim == 2 else v
    assert kurtosis[-1] == pytest.approx(np.mean(x**4) / np.mean(x**2) ** 2, rel=1e-12)
    assert len(set(kurtosis)) == 3  # one value per time, not the last one repeated


def test_the_ensemble_sweeps_the_density_of_the_dsmc_as_simulate_runs_it(capsys, tmp_path):
    base = ["ulam", "--n", "300", "--restitution", "0.5", "--rate", "relative_velocity",
            "--t", "0.5,1", "--json"]
    one = run_json(capsys, ["simulate", *base, "--density", "1", "--seed", "4"])
    two = run_json(capsys, ["simulate", *base, "--density", "2", "--seed", "4"])
    report = run_json(capsys, ["ensemble", *base, "--density", "1,2", "--seeds", "4",
                               "--serial", "--out", str(tmp_path / "e"), "--no-progress"])
    sets = report["aggregate"]["sets"]
    assert [s["params"]["density"] for s in sets] == [1.0, 2.0]
    for s, run in zip(sets, (one, two), strict=True):
        assert s["observables"]["energy"]["mean"] == run["energy"]
        assert s["observables"]["kurtosis"]["mean"] == run["kurtosis"]
    assert two["energy"][-1] < one["energy"][-1]  # twice the density cools faster in t
