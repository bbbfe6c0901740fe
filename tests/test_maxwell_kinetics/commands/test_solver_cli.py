"""``maxwell-kinetics solve`` and ``convergence``: JSON contract, numbers, bad input.

The CLI is called in-process through ``main(argv)`` (argparse errors raise ``SystemExit(2)``,
validation errors make ``main`` return 2).  Each successful solve costs a JIT compilation of a
few seconds, so the successful runs are shared through module-level fixtures.
"""

import argparse
import json

import numpy as np
import pytest
from helpers import run_error, run_json

from maxwell_kinetics.app.cli import build_parser, join_negative_values

SOLVE_KEYS = {"restitution", "initial", "resolution", "tau", "sup_error", "q", "G_real", "G_imag",
              "seconds", "kurtosis", "moments"}




def test_solve_json_contract_and_spec_values(capsys, tmp_path):
    # r = 0.5, unit Gaussian, default resolution: the reference case (one solve, one compile).
    plot, save = tmp_path / "g.png", tmp_path / "g.npz"
    out = run_json(capsys, ["solve", "--restitution", "0.5", "--initial", "gaussian", "--tau",
                            "10,50,100", "--q", "0.5,1,2,5", "--json", "--plot", str(plot),
                            "--save", str(save)])
    assert SOLVE_KEYS <= set(out)
    assert out["restitution"] == 0.5
    assert out["initial"] == "gaussian"
    assert out["resolution"] == "default"
    assert out["tau"] == [10.0, 50.0, 100.0]
    assert out["q"] == [0.5, 1.0, 2.0, 5.0]
    assert out["seconds"] > 0
    # Reference value measured by two independent methods; the target is agreement to 1 %.
    for measured, value in zip([8.7e-2, 1.37e-2, 3.37e-3], out["sup_error"], strict=True):
        assert value == pytest.approx(measured, rel=0.01)
    for key in ("G_real", "G_imag"):
        assert np.asarray(out[key]).shape == (3, 4), key
    # the kurtosis ⟨x⁴⟩ = −3 + 6 e^{9τ/128} of the exact moment equation (r = 0.5), to 1e-7
    closed = -3 + 6 * np.exp(9 / 128 * np.array(out["tau"]))
    np.testing.assert_allclose(out["kurtosis"], closed, rtol=1e-7)
    moments = out["moments"]
    assert moments["orders"] == [2, 4, 6] and moments["values"][2][1] == out["kurtosis"][2]
    # ⟨x⁶⟩ at τ = 100 has grown past what the grid resolves: null, with the reason
    assert moments["values"][2][2] is None and "not analytic" in moments["reasons"][2][2]
    assert np.all(np.asarray(out["G_imag"]) == 0.0)  # symmetric data: G is real
    # G is positive and decreasing over these q at every saved τ
    assert np.all(np.diff(np.asarray(out["G_real"]), axis=1) < 0)
    assert np.all(np.asarray(out["G_real"]) > 0)
    # --plot and --save wrote their files; the saved Solution reloads with the same errors
    from maxwell_kinetics.solver import Solution

    assert plot.stat().st_size > 0
    back = Solution.load(save)
    assert np.allclose(back.sup_error(), out["sup_error"], rtol=1e-12, atol=0)


def test_solve_asymmetric_law_gives_imaginary_part(capsys):
    # "--q -0.5,0.5,1,2": a value starting with '-' after a space reaches the solver.
    out = run_json(capsys, ["solve", "--restitution", "0", "--initial", "asymmetric",
                            "--resolution", "coarse", "--tau", "0.5,1", "--q", "-0.5,0.5,1,2",
                            "--json"])
    assert out["q"] == [-0.5, 0.5, 1.0, 2.0]
    real, imag = np.asarray(out["G_real"]), np.asarray(out["G_imag"])
    assert imag.shape == (2, 4) and real.shape == (2, 4)
    # Im G ≈ −m₃ q³/6 = −q³/3 at small q for the shifted exponential (m₃ = 2): clearly nonzero
    assert np.all(imag[:, 1:] < -0.01)
    # G(−q) = conj G(q)
    assert np.array_equal(real[:, 0], real[:, 1]) and np.array_equal(imag[:, 0], -imag[:, 1])


BAD_SOLVE = [
    (["--restitution", "1.5"], "restitution='1.5'"),
    (["--restitution=-0.5"], "restitution='-0.5'"),
    (["--restitution", "nan"], "restitution='nan'"),
    (["--restitution", "inf"], "restitution='inf'"),
    (["--tau=-1,2"], "tau='-1,2'"),
    (["--tau", "1,nan"], "tau='1,nan'"),
    (["--tau", "1,inf"], "tau='1,inf'"),
    (["--tau", "5,2"], "tau='5,2'"),
    (["--tau", "1,1"], "tau='1,1'"),
    (["--initial", "maxwellian"], "initial='maxwellian'"),
    (["--q", "0.5,100"], "q='0.5,100'"),
    (["--q", "1,nan"], "q='1,nan'"),
]


@pytest.mark.parametrize("extra, shown", BAD_SOLVE, ids=[" ".join(e) for e, _ in BAD_SOLVE])
def test_solve_bad_input(extra, shown, capsys, tmp_path):
    plot, save = tmp_path / "p.png", tmp_path / "s.npz"
    defaults = {"--restitution": "0.5", "--tau": "1,2"}
    for option in extra:  # the bad value replaces the default (an option given twice is refused)
        defaults.pop(option.split("=")[0], None)
    argv = ["solve", *[x for pair in defaults.items() for x in pair], "--resolution", "coarse",
            "--json", "--plot", str(plot), "--save", str(save)]
    err = run_error(capsys, argv + extra)
    assert shown in err
    assert not plot.exists() and not save.exists()


def test_unknown_initial_lists_the_laws(capsys):
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--initial", "cauchy"])
    assert "initial='cauchy'" in err
    for name in ("asymmetric", "bimodal", "gaussian", "laplace", "uniform"):
        assert name in err


def test_convergence_writes_json_and_figure(capsys, tmp_path):
    out_dir = tmp_path / "conv"
    out = run_json(capsys, ["convergence", "--restitution", "0.5", "--resolutions", "coarse",
                            "--tau-max", "10", "--out", str(out_dir), "--json"])
    assert out["out"] == str(out_dir)
    assert len(out["table"]) == 1
    row = out["table"][0]
    assert row["restitution"] == 0.5 and row["resolution"] == "coarse"
    written = json.loads((out_dir / "convergence.json").read_text())
    assert written["table"] == out["table"]
    run = written["runs"][0]
    assert run["tau"][0] == 1.0 and run["tau"][-1] == 10.0
    # at τ = 10 the error is still the physical distance to f̂: independently measured 8.7e-2 (coarse
    # resolution: its floor 7e-8 is far below); the floor is the median of the last 5 outputs
    assert run["sup_error"][-1] == pytest.approx(8.7e-2, rel=0.01)
    assert row["floor"] == pytest.approx(np.median(run["sup_error"][-5:]), rel=1e-12)
    assert (out_dir / "convergence.png").stat().st_size > 0


@pytest.mark.parametrize("bad", ["1.5", "nan"])
def test_convergence_bad_restitution_writes_nothing(bad, capsys, tmp_path):
    out_dir = tmp_path / "conv"
    err = run_error(capsys, ["convergence", "--restitution", bad, "--resolutions", "coarse",
                             "--tau-max", "10", "--out", str(out_dir)])
    assert "restitution=" in err and bad in err
    assert not out_dir.exists()


# -- values that start with '-' -------------------------------------------------------------
NEGATIVE = [
    (["solve", "--restitution", "0.5", "--tau", "-1,2"], "tau='-1,2'"),
    (["solve", "-r", "-0.5", "--tau", "1"], "restitution='-0.5'"),
    (["solve", "--rest", "-0.5", "--tau", "1"], "restitution='-0.5'"),  # abbreviated option
    (["solve", "--restitution", "-inf", "--tau", "1"], "restitution='-inf'"),
    (["solve", "--restitution", "0.5", "--tau", "1", "--q", "-1e3"], "q='-1e3'"),
    (["fixed-point", "--restitution", "-0.1"], "restitution='-0.1'"),
    (["convergence", "--restitution", "-0.5", "--out", "OUT"], "restitution=-0.5"),
    (["convergence", "--tau-max", "-5", "--out", "OUT"], "tau-max=-5.0"),
    (["simulate", "ulam", "--n", "100", "--restitution", "-0.5", "--tau", "1"],
     "restitution='-0.5'"),
    (["simulate", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1", "--seed", "-1"],
     "seed='-1'"),
    (["simulate", "lattice", "--n", "100", "--restitution", "0.5", "--tau", "-1,2"],
     "tau=[-1.0, 2.0]"),
    (["simulate", "md", "--n", "100", "--density", "1", "--restitution", "0.5", "--t", "-1,2"],
     "t=[-1.0, 2.0]"),
]


@pytest.mark.parametrize("argv, shown", NEGATIVE, ids=[" ".join(a) for a, _ in NEGATIVE])
def test_negative_values_reach_the_validation(argv, shown, capsys, tmp_path):
    # Without the rewrite argparse stops with "expected one argument" and never shows the value.
    argv = [str(tmp_path / "out") if a == "OUT" else a for a in argv]
    err = run_error(capsys, argv)
    assert shown in err
    assert "expected one argument" not in err
    assert not (tmp_path / "out").exists()


def test_join_negative_values_only_touches_values_of_value_options():
    parser = build_parser()
    argv = ["solve", "--tau", "-1,2", "--json", "-r", "-0.5", "--plot", "-x.png", "--q=-1",
            "--initial", "gaussian"]
    assert join_negative_values(parser, argv) == [
        "solve", "--tau=-1,2", "--json", "-r=-0.5", "--plot", "-x.png", "--q=-1",
        "--initial", "gaussian"]
    # flags take no value; nothing after "--" is rewritten
    assert join_negative_values(parser, ["solve", "--json", "-1", "--", "--tau", "-1"]) == [
        "solve", "--json", "-1", "--", "--tau", "-1"]
    # the subcommand decides: --n takes a value in simulate ulam and in fixed-point
    assert join_negative_values(parser, ["simulate", "ulam", "--n", "-5"]) == [
        "simulate", "ulam", "--n=-5"]
    # an option whose value is optional (nargs="?") keeps the next option as an option
    optional = argparse.ArgumentParser()
    optional.add_argument("--level", nargs="?")
    optional.add_argument("--x")
    assert join_negative_values(optional, ["--level", "--x", "3"]) == ["--level", "--x", "3"]
    assert join_negative_values(optional, ["--level", "-2"]) == ["--level=-2"]


# -- output paths are checked before any work -----------------------------------------------
@pytest.mark.parametrize("case", ["save-is-dir", "plot-is-dir", "save-no-parent", "same-file"])
def test_solve_bad_output_paths_write_nothing(case, capsys, tmp_path):
    folder = tmp_path / "existing"
    folder.mkdir()
    plot, save = tmp_path / "p.png", tmp_path / "s.npz"
    bad = {"save-is-dir": ("save", folder), "plot-is-dir": ("plot", folder),
           "save-no-parent": ("save", tmp_path / "missing" / "s.npz"),
           "same-file": ("save", plot)}[case]
    paths = {"plot": plot, "save": save, bad[0]: bad[1]}
    argv = ["solve", "--restitution", "0.5", "--tau", "1", "--resolution", "coarse", "--json",
            "--plot", str(paths["plot"]), "--save", str(paths["save"])]
    err = run_error(capsys, argv)
    assert f"{bad[0]}='{bad[1]}'" in err
    assert not plot.exists() and not save.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["existing"]
    assert list(folder.iterdir()) == []


@pytest.mark.parametrize("case", ["out-is-file", "under-a-file"])
def test_convergence_bad_out_writes_nothing(case, capsys, tmp_path):
    blocker = tmp_path / "file.txt"
    blocker.write_text("keep")
    out_dir = blocker if case == "out-is-file" else blocker / "sub"
    err = run_error(capsys, ["convergence", "--restitution", "0.5", "--resolutions", "coarse",
                             "--tau-max", "10", "--out", str(out_dir)])
    assert f"out='{out_dir}'" in err
    assert blocker.read_text() == "keep"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"]
