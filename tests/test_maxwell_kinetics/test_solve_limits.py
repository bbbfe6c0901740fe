"""Limits of the kinetic solver's inputs: quadratures that would not fit in memory are refused
before any work (naming the user's argument), and hostile values in the arrays (booleans,
complex numbers, non-finite values) are refused by name."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import run_error

from maxwell_kinetics.solver import solve
from particles.validation import InvalidArgumentError


@pytest.fixture(scope="module")
def elastic():
    """r = 1: G = φ at every τ, computed without JAX (instant)."""
    return solve(1.0, "gaussian", [1.0], "coarse")


def test_node_count_grows_with_the_largest_value():
    from maxwell_kinetics.velocity import quadrature_nodes

    # panels of width min(1/2, pi/v) on [0, q_max], 16 nodes each
    assert quadrature_nodes(35.0, 1.0) == 70 * 16
    assert quadrature_nodes(35.0, 1e6) == pytest.approx(35.0 * 1e6 / np.pi * 16, rel=1e-6)
    assert quadrature_nodes(35.0, 1e6, radial=True) == quadrature_nodes(35.0, 1e6) + 48
    assert quadrature_nodes(35.0, np.inf) == np.inf


@pytest.mark.parametrize("x", [[0.0, 1e12], [1e300], [-1e12]])
def test_density_refuses_an_x_whose_quadrature_cannot_fit(elastic, x):
    # 1e12 would need ~1e14 nodes (~2e16 bytes): the old code raised a raw MemoryError
    with pytest.raises(InvalidArgumentError, match=r"argument x=.*\|x\| <= 9\.\d+e\+04"):
        elastic.density(x)


def test_speed_density_refuses_a_speed_whose_quadrature_cannot_fit(elastic):
    with pytest.raises(InvalidArgumentError, match=r"argument s=.*\|s\| <= "):
        elastic.speed_density([0.0, 1e12])


def test_largest_accepted_value_is_within_the_node_limit(elastic):
    from maxwell_kinetics.velocity import MAX_QUADRATURE_NODES, quadrature_nodes

    q_max = elastic.resolution.q_max
    x = 9e4
    assert quadrature_nodes(q_max, x) <= MAX_QUADRATURE_NODES
    assert quadrature_nodes(q_max, 2 * x) > MAX_QUADRATURE_NODES
    with pytest.raises(InvalidArgumentError):
        elastic.density([2 * x])


@pytest.mark.parametrize("x", [[True, 1.0], [1 + 2j], ["1"], [[1.0], [1.0, 2.0]],
                               np.array([np.nan])])
def test_density_refuses_values_that_are_not_finite_reals(elastic, x):
    with pytest.raises(InvalidArgumentError, match=r"argument x="):
        elastic.density(x)


@pytest.mark.parametrize("s", [[True], [0.5 + 1j], ["2"], [np.inf]])
def test_speed_density_refuses_values_that_are_not_finite_reals(elastic, s):
    with pytest.raises(InvalidArgumentError, match=r"argument s="):
        elastic.speed_density(s)


def test_cli_refuses_a_speed_too_large_before_the_solve(capsys, tmp_path):
    """Refused in well under a second, before JAX starts; the old code ran the solve, then
    raised a raw MemoryError (1e12) or took all the memory (1e6: 23.5 GB seen)."""
    out = tmp_path / "s.npz"
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--dimension", "3",
                             "--speed", "0,1,2,50,1e12", "--save", str(out)])
    assert err.count("\n") == 1
    assert "argument speed='0,1,2,50,1e12'" in err and "|speed| <= 9." in err
    assert not out.exists()


def test_cli_refuses_a_speed_density_of_more_than_a_day_unless_forced(capsys, tmp_path,
                                                                      monkeypatch):
    """The speed density's time counts in the day's budget: speeds near the quadrature's limit
    (9e4: ~1.7e7 nodes, ~35 s per time) at 3000 output times are about 29 h after a short
    solve (the old code ran them); --force lets a refused one through."""
    from maxwell_kinetics.app.cli import main
    from maxwell_kinetics.app.commands import solve as command

    out = tmp_path / "s.npz"
    with monkeypatch.context() as patch:  # the limit lowered to 1 µs: refused, then forced
        patch.setattr(command, "MAX_SOLVE_SECONDS", 1e-6)
        small = ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse", "--speed",
                 "0,1", "--no-progress", "--save", str(out)]
        assert "argument speed='0,1'" in run_error(capsys, small)
        assert not out.exists()
        assert main([*small, "--force"]) == 0
        assert out.exists()
        capsys.readouterr()
    out.unlink()
    taus = ",".join(str(k) for k in range(1, 3001))
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", taus, "--resolution", "coarse",
                             "--speed", "0,9e4", "--save", str(out)])
    assert "argument speed='0,9e4'" in err and "--force" in err and "h)" in err
    assert not out.exists()


def test_fixed_point_refuses_a_degree_of_more_than_a_day_unless_forced(monkeypatch):
    """Dense Gauss-Newton costs ~n³ (49 s at n = 1024): n = 20000 is ~4 days, refused naming
    n before any matrix is built; with the limit lowered to 1 µs a small degree is refused and
    force=True runs it (the old code had no time limit, only the memory check of the CLI)."""
    from maxwell_kinetics import stationary

    with monkeypatch.context() as patch:
        patch.setattr(stationary, "MAX_FIXED_POINT_SECONDS", 1e-6)
        with pytest.raises(InvalidArgumentError, match="argument n=16 "):
            stationary.fixed_point(0.5, n=16)
        assert stationary.fixed_point(0.5, n=16, force=True).n == 16
    # d = 2: in d = 1 a degree above 256 is refused anyway (ill-conditioned collocation)
    with pytest.raises(InvalidArgumentError, match=r"argument n=20000 .*days.*force=True"):
        stationary.fixed_point(0.5, n=20000, dimension=2)  # d = 1 caps n at MAX_DEGREE_1D


def test_fixed_point_cli_has_force(capsys, monkeypatch):
    """fixed-point takes --force, and its refusal of a long solve says --force (the library's
    message says force=True, which a command-line user cannot pass)."""
    from maxwell_kinetics import stationary
    from maxwell_kinetics.app.cli import main

    patch_limit = monkeypatch.setattr
    patch_limit(stationary, "MAX_FIXED_POINT_SECONDS", 1e-6)
    err = run_error(capsys, ["fixed-point", "-r", "0.5", "--n", "32"])
    assert "argument n=32 " in err and "pass --force" in err and "force=True" not in err
    assert main(["fixed-point", "-r", "0.5", "--n", "32", "--force", "--json"]) == 0


def test_solve_refuses_a_solve_of_more_than_a_day_unless_forced(monkeypatch):
    """solve() itself (not only the command line) refuses, before any work, a solve whose
    estimate exceeds the one-day budget, naming tau and the estimate; force=True runs it."""
    from maxwell_kinetics import grid
    from maxwell_kinetics.solver import solve

    finest = grid.get_resolution("finest")
    tau = 2.0 * grid.MAX_SOLVE_SECONDS / (finest.n * 1e-6)  # > one day at >= 1 us a node
    with monkeypatch.context() as patch:  # a tiny solve over a limit of 0 s: refused, or forced
        patch.setattr(grid, "MAX_SOLVE_SECONDS", 0.0)
        with pytest.raises(InvalidArgumentError, match=r"argument tau=1\.0 .*force=True"):
            solve(0.5, tau=[1.0], resolution="coarse")
        assert solve(0.5, tau=[1.0], resolution="coarse", force=True).tau.tolist() == [1.0]
    refused = r"argument tau=.*windows.*about .* h\).*force=True"
    with pytest.raises(InvalidArgumentError, match=refused):
        solve(0.5, tau=[tau], resolution="finest")


@pytest.mark.parametrize("value", ["no", "False", 0, 1, [], np.array([True])])
@pytest.mark.parametrize("name", ["force", "progress"])
def test_solve_force_and_progress_are_booleans(name, value):
    """``force='no'`` bypassed the one-day budget and ``progress='no'``
    showed the bar.  Both are refused by name before any work (r = 1 needs no JAX); so is
    a non-bool ``force`` of fixed_point and of the solve's budget."""
    import re

    from maxwell_kinetics import grid, stationary
    from particles.validation import shown

    match = re.escape(f"argument {name}={shown(value)} ")
    with pytest.raises(InvalidArgumentError, match=match):
        solve(1.0, "gaussian", [1.0], "coarse", **{name: value})
    if name == "force":
        with pytest.raises(InvalidArgumentError, match=match):
            stationary.fixed_point(0.5, n=16, force=value)
        with pytest.raises(InvalidArgumentError, match=match):
            grid.check_solve_budget(grid.get_resolution("coarse"), 1.0, 1, force=value)
        from maxwell_kinetics.app.comparisons.particle_runs import ParticleRuns

        with pytest.raises(InvalidArgumentError, match=match):
            ParticleRuns(force=value)


def test_solve_takes_true_false_and_none_as_before():
    for flag in (True, False, np.True_, np.False_):
        assert solve(1.0, "gaussian", [1.0], "coarse", force=flag, progress=flag).tau.size == 1
    assert solve(1.0, "gaussian", [1.0], "coarse", progress=None).tau.size == 1
    with pytest.raises(InvalidArgumentError, match=r"argument force=None "):
        solve(1.0, "gaussian", [1.0], "coarse", force=None)
