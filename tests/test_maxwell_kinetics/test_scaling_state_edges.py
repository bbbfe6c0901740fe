"""A scaling state whose tail the grid cuts is never reported as converged: its kurtosis would
depend on the grid (rate |v − w|^0.1 at r = 0.5: 9.21 on ±12, 11.6 on ±24)."""

from __future__ import annotations

import json

import pytest

from maxwell_kinetics.app.cli import main
from maxwell_kinetics.inelastic_boltzmann import EDGE_TOLERANCE, scaling_state
from maxwell_kinetics.velocity_grid import VelocityGrid


def test_a_heavy_tail_cut_by_the_grid_is_flagged_and_a_resolved_one_is_not():
    cut = scaling_state(0.9, exponent=0.1, grid=VelocityGrid(121, 12.0))
    assert cut.residual < 1e-10  # Newton converged on this grid ...
    assert cut.reaches_edges and cut.edge_moment > 100 * EDGE_TOLERANCE  # ... which cuts it
    rods = scaling_state(0.5, grid=VelocityGrid(121, 12.0))
    assert not rods.reaches_edges and 0 < rods.edge_moment < EDGE_TOLERANCE


def test_fixed_point_exits_3_and_names_the_half_width_when_the_tail_reaches_the_ends(capsys):
    argv = ["fixed-point", "--kernel", "relative_velocity", "-r", "0.9", "--exponent", "0.1",
            "--points", "121", "--half-width", "12", "--json"]
    assert main(argv) == 3
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["converged"] is False and out["edge_moment"] > EDGE_TOLERANCE
    assert "widen --half-width (now 12)" in captured.err
    assert main(["fixed-point", "--kernel", "relative_velocity", "-r", "0.5", "--points", "121",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] is True and out["edge_moment"] == pytest.approx(2.4e-8, rel=0.1)


def test_a_relaxation_that_runs_out_of_steps_is_an_error_not_a_start_for_newton(monkeypatch):
    # The integrator's success flag was never read: Newton then started from wherever the
    # relaxation stopped.  Here the compiled solve reports a failure (as diffrax does when its
    # 10⁶ steps run out) and the call must say so instead of returning a state.
    import maxwell_kinetics.inelastic_boltzmann as ib

    functions = ib._Compiled.get()
    real = functions.solve

    def failing(*args):
        ys, _, steps = real(*args)
        return ys, False, steps

    monkeypatch.setattr(functions, "solve", failing)
    with pytest.raises(RuntimeError, match=r"relaxation to tau' = 3 failed.*shorter relaxation"):
        scaling_state(0.5, grid=VelocityGrid(61, 6.0), relaxation=3.0)
    monkeypatch.setattr(functions, "solve", real)
    assert scaling_state(0.5, grid=VelocityGrid(61, 6.0), relaxation=3.0).residual < 1e-10
