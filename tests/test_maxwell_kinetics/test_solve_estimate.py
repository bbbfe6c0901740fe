"""The cost of a solve, estimated before it starts: proportional to the windows and the grid
nodes, shown in the progress line, and refused above one day unless forced."""

from __future__ import annotations

import pytest
from helpers import run_error

from maxwell_kinetics.grid import (
    MAX_SOLVE_SECONDS,
    check_solve_budget,
    estimate_solve,
    get_resolution,
)
from particles.validation import InvalidArgumentError


def test_estimate_scales_with_windows_nodes_dimension_and_rule():
    coarse, fine = get_resolution("coarse"), get_resolution("fine")
    a = estimate_solve(coarse, 100.0, 1)
    assert a["windows"] == pytest.approx(50.0)
    assert estimate_solve(coarse, 400.0, 1)["seconds"] == pytest.approx(4 * a["seconds"])
    assert estimate_solve(fine, 100.0, 1)["seconds"] == pytest.approx(
        a["seconds"] * fine.n / coarse.n)
    two = estimate_solve(coarse, 100.0, 1, dimension=2)["seconds"]
    assert two > 2 * a["seconds"]  # the η quadrature makes d ≥ 2 dearer
    assert estimate_solve(coarse, 100.0, 1, dimension=2, angular_rule="accurate")["seconds"] > two


def test_refused_above_one_day_unless_forced():
    finest = get_resolution("finest")
    tau = 2.0 * MAX_SOLVE_SECONDS / (finest.n * 1e-6)  # > one day at any per-node cost ≥ 1 µs
    with pytest.raises(InvalidArgumentError, match=r"tau=.*24\.0 h.*--force"):
        check_solve_budget(finest, tau, 2)
    assert check_solve_budget(finest, tau, 2, force=True)["seconds"] > MAX_SOLVE_SECONDS
    assert check_solve_budget(finest, 1e5, 2)["seconds"] < MAX_SOLVE_SECONDS


def test_cli_refuses_a_solve_of_days(capsys, tmp_path):
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1e8", "--resolution", "finest",
                             "--save", str(tmp_path / "s.npz")])
    assert "tau=100000000.0" in err and "days" in err and "--force" in err
    assert not (tmp_path / "s.npz").exists()


def test_progress_line_shows_the_estimate(capsys):
    from maxwell_kinetics.app.cli import main

    assert main(["solve", "-r", "0.5", "--tau", "4", "--resolution", "coarse"]) == 0
    err = capsys.readouterr().err
    assert "solve r=0.5" in err and "estimate ~" in err


def test_solve_json_reports_the_estimate_and_it_grows_with_the_work(capsys):
    # estimate_seconds in solve --json: present, positive, the estimate of the grid and τ_max
    # that were solved (estimate_solve), ∝ τ_max (the windows); its growth with the grid nodes
    # is test_estimate_scales_with_windows_nodes_dimension_and_rule (a finer solve costs ~10 s).
    from helpers import run_json

    def estimate(tau, resolution):
        out = run_json(capsys, ["solve", "-r", "0.5", "--tau", tau, "--resolution", resolution,
                                "--json"])
        assert out["estimate_seconds"] > 0 and out["tau"][-1] == float(tau.split(",")[-1])
        return out["estimate_seconds"]

    short = estimate("1,2", "coarse")
    assert short == pytest.approx(estimate_solve(get_resolution("coarse"), 2.0, 2)["seconds"],
                                  rel=1e-12)
    longer = estimate("8", "coarse")
    assert longer == pytest.approx(4 * short, rel=1e-12)


def test_estimate_scales_with_the_eta_nodes_of_the_gain():
    # The ladder of the "fast" rule is 2, 3, 4, 6, 8, 12, 16, 12 nodes at 16 (angular_tiers):
    # at 64 every tier is exactly four times as large, so the gain's cost is 4 times as large.
    from maxwell_kinetics.angular_tiers import angular_nodes_per_state_node

    coarse = get_resolution("coarse")
    base = estimate_solve(coarse, 100.0, 1, dimension=2)
    four = estimate_solve(coarse, 100.0, 1, dimension=2, angular_nodes=64)
    assert four["seconds"] == pytest.approx(4 * base["seconds"], rel=1e-12)
    assert angular_nodes_per_state_node(coarse, "fast", 64) == pytest.approx(
        4 * angular_nodes_per_state_node(coarse, "fast", 16), rel=1e-12)
    # every state node has at least 2 η nodes and at most angular_nodes
    assert 2 <= angular_nodes_per_state_node(coarse, "accurate", 16) <= 16
    # by hand, "accurate" at 16 on the coarse grid (q_j = e^{−24 + 0.1 j}, 276 nodes): 2 nodes
    # below q = 1e-6 (j < ⌈(ln 1e-6 + 24)/0.1⌉ = 102), 16 up to q = 10 (j < ⌈(ln 10 + 24)/0.1⌉
    # = 264), 12 above: (102·2 + 162·16 + 12·12)/276
    assert (coarse.n, coarse.s_min, coarse.h) == (276, -24.0, 0.1)
    assert angular_nodes_per_state_node(coarse, "accurate", 16) == pytest.approx(
        (102 * 2 + 162 * 16 + 12 * 12) / 276, rel=1e-12)
    assert estimate_solve(coarse, 100.0, 1, dimension=1, angular_nodes=64) == estimate_solve(
        coarse, 100.0, 1)  # d = 1 has no η quadrature


def test_a_solve_with_too_many_eta_nodes_is_refused_by_name_before_any_quadrature():
    coarse = get_resolution("coarse")
    with pytest.raises(InvalidArgumentError, match=r"angular_nodes=1000000000.*memory"):
        check_solve_budget(coarse, 10.0, 2, dimension=2, angular_nodes=10**9)
    with pytest.raises(InvalidArgumentError, match=r"tau=.*angular_nodes=100000.*--force"):
        check_solve_budget(coarse, 1e6, 2, dimension=2, angular_nodes=10**5)
