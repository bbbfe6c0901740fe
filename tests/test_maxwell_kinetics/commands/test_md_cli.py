"""``maxwell-kinetics simulate md``: JSON contract, profiles, checkpoint/resume, collapse, bad
input (exit status 2, the argument and the value named, nothing written)."""

import re

import numpy as np
import pytest
from helpers import run_json

from maxwell_kinetics.app.cli import main

BASE = ["simulate", "md", "--n", "1000", "--density", "1", "--restitution", "0.7"]



def test_json_output_contract(capsys):
    argv = BASE + ["--delta", "1e-3", "--initial", "uniform", "--t", "0,1,2.5", "--seed", "4"]
    argv += ["--json", "--structure-factor", "--profile"]
    out = run_json(capsys, argv)
    keys = {"t", "energy", "collisions_per_particle", "momentum", "collisions", "seconds"}
    assert keys | {"histogram", "k", "S", "C", "profile", "params", "seed"} <= set(out)
    assert "total_momentum" not in out  # one momentum key, under its documented name
    assert out["t"] == [0.0, 1.0, 2.5]
    for key in ("energy", "collisions_per_particle", "momentum", "collisions"):
        assert len(out[key]) == 3, key
    assert out["energy"][0] == pytest.approx(1.0, abs=1e-14)
    assert 0 < out["energy"][2] < out["energy"][1] < 1
    assert out["collisions"][0] == 0 and out["collisions"][2] > 1000
    assert out["collisions_per_particle"] == [2 * c / 1000 for c in out["collisions"]]
    assert max(abs(m) for m in out["momentum"]) < 1e-11  # total momentum, conserved
    assert out["params"]["delta"] == 1e-3 and out["params"]["initial"] == "uniform"
    assert set(out["histogram"]) == {"centres", "density", "error"}
    assert len(out["k"]) == len(out["S"]) == len(out["C"]) == 501
    assert out["C"][0] == pytest.approx(out["energy"][-1], rel=1e-12)
    prof = out["profile"]
    assert len(prof["x"]) == len(prof["v_x"]) == len(prof["v_i"]) == 1000
    assert np.all(np.diff(prof["x"]) >= 0) and 0 <= prof["x"][0] and prof["x"][-1] < 1000
    assert sorted(prof["v_x"]) == sorted(prof["v_i"])
    again = run_json(capsys, argv)  # same seed, same numbers
    assert again["energy"] == out["energy"] and again["profile"] == out["profile"]


def test_rods_and_text_output(capsys):
    # sigma = 0.25 at n = 2 is the point gas at density 4: same collisions
    rods = run_json(
        capsys,
        BASE[:4]
        + ["--density", "2", "--rod-length", "0.25", "--restitution", "0.7", "--t", "1", "--json"],
    )
    points = run_json(
        capsys, BASE[:4] + ["--density", "4", "--restitution", "0.7", "--t", "1", "--json"]
    )
    assert rods["collisions"] == points["collisions"] and rods["energy"] == points["energy"]
    assert main(BASE + ["--t", "0.5,1"]) == 0
    text = capsys.readouterr().out
    assert "md:" in text and "energy" in text


def test_checkpoint_resume_and_reference_give_the_same_numbers(capsys, tmp_path):
    ckpt = tmp_path / "md.ckpt"
    argv = BASE + ["--delta", "1e-3", "--t", "1,3", "--seed", "2", "--json", "--profile"]
    plain = run_json(capsys, argv)
    first = run_json(capsys, argv + ["--checkpoint", str(ckpt)])
    resumed = run_json(capsys, argv + ["--resume", str(ckpt)])  # already finished
    for key in ("energy", "collisions", "momentum", "histogram", "profile"):
        assert plain[key] == first[key] == resumed[key], key
    ref = run_json(capsys, argv + ["--method", "reference"])
    assert ref["energy"] == plain["energy"] and ref["collisions"] == plain["collisions"]


def test_inelastic_collapse_exits_3_with_a_clear_message(capsys, tmp_path):
    # delta = 0, N(1 - r) = 500: collapses near t = 4 (tests/test_particles/test_md.py)
    saved = tmp_path / "never.npz"
    argv = ["simulate", "md", "--n", "1000", "--density", "1", "--restitution", "0.5"]
    code = main(argv + ["--t", "50", "--seed", "3", "--json", "--save", str(saved)])
    assert code == 3
    captured = capsys.readouterr()
    assert captured.out == ""
    assert re.search(r"inelastic collapse at t=.*particles \[.*set delta > 0", captured.err)
    assert not saved.exists()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--n", "1", "--density", "1", "--restitution", "0.5", "--t", "1"], "n='1'"),
        (["--n", "1e9x", "--density", "1", "--restitution", "0.5", "--t", "1"], "n='1e9x'"),
        (["--n", "10", "--density", "0", "--restitution", "0.5", "--t", "1"], "density='0'"),
        (["--n", "10", "--density", "-2", "--restitution", "0.5", "--t", "1"], "density='-2'"),
        (
            [
                "--n",
                "10",
                "--density",
                "1",
                "--rod-length",
                "1.0",
                "--restitution",
                "0.5",
                "--t",
                "1",
            ],
            r"rod-length=1.0.*fit",  # the option as typed
        ),
        (["--n", "10", "--density", "1", "--restitution", "1.5", "--t", "1"], "restitution='1.5'"),
        (
            ["--n", "10", "--density", "1", "--restitution", "-0.1", "--t", "1"],
            "restitution='-0.1'",
        ),
        (
            ["--n", "10", "--density", "1", "--restitution", "0.5", "--delta=-1e-3", "--t", "1"],
            "delta='-1e-3'",
        ),
        (["--n", "10", "--density", "1", "--restitution", "0.5", "--t=-1,2"], r"t=\[-1.0, 2.0\]"),
        (["--n", "10", "--density", "1", "--restitution", "0.5", "--t", "2,1"], r"t=\[2.0, 1.0\]"),
        (
            ["--n", "10", "--density", "1", "--restitution", "0.5", "--t", "1", "--initial", "x"],
            "initial='x'",
        ),
    ],
)
def test_bad_input_exits_2_naming_argument_and_value(capsys, tmp_path, args, message):
    ckpt = tmp_path / "never.ckpt"
    saved = tmp_path / "never.npz"
    code = main(["simulate", "md", *args, "--checkpoint", str(ckpt), "--save", str(saved)])
    assert code == 2
    err = capsys.readouterr().err
    assert "error" in err and re.search(message, err), err
    assert list(tmp_path.iterdir()) == []


def test_corrupt_or_foreign_checkpoint_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.ckpt"
    bad.write_text("not a checkpoint")
    argv = BASE + ["--delta", "1e-3", "--t", "1"]
    assert main(argv + ["--resume", str(bad)]) == 2
    assert "bad.ckpt" in capsys.readouterr().err
    good = tmp_path / "good.ckpt"
    assert main(argv + ["--checkpoint", str(good)]) == 0
    capsys.readouterr()
    assert main(BASE + ["--delta", "2e-3", "--t", "1", "--resume", str(good)]) == 2
    err = capsys.readouterr().err
    assert "good.ckpt" in err and "delta" in err
    lattice = ["simulate", "lattice", "--n", "1000", "--restitution", "0.7", "--tau", "1"]
    assert main(lattice + ["--resume", str(good)]) == 2
    assert "model" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.ckpt", "good.ckpt"]
