"""The velocity-space solve: a cost estimate before any work, and Ctrl-C honoured within 0.1 s
(the integration is one call of the time integrator, run in a worker thread)."""

from __future__ import annotations

import _thread
import signal
import threading
import time

import pytest

from maxwell_kinetics.app.cli import main
from maxwell_kinetics.inelastic_boltzmann import (
    SECONDS_PER_STEP_AND_PAIR,
    STEPS_PER_TAU_AND_STIFFNESS,
    estimate_seconds,
    solve_boltzmann,
)
from maxwell_kinetics.interrupt import join_abandoned
from maxwell_kinetics.velocity_grid import VelocityGrid, default_grid
from particles.kernels import RelativeVelocity
from particles.validation import InvalidArgumentError


def test_the_estimate_is_steps_times_pairs_for_gamma_zero_and_none_beyond():
    grid = default_grid(0.0)  # 401 points on +-40: stiffness 40/0.2 = 200
    steps = STEPS_PER_TAU_AND_STIFFNESS * 200.0 * 2.0 * 10.0  # n = 2, t = 10
    assert estimate_seconds(RelativeVelocity(0.5, 0.0), grid, 2.0, 10.0) == pytest.approx(
        steps * 401**2 * SECONDS_PER_STEP_AND_PAIR, rel=1e-12)
    assert estimate_seconds(RelativeVelocity(0.5, 1.0), default_grid(1.0), 1.0, 10.0) is None


def test_a_solve_of_more_than_a_day_is_refused_before_any_work_unless_forced(capsys):
    grid = VelocityGrid(1601, 160.0)  # 2.6e6 pairs, 120 steps per unit t: ~1 min per unit t
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError, match=r"about .* s\); fewer points") as info:
        solve_boltzmann(0.5, [5000.0], exponent=0.0, grid=grid)
    assert info.value.name == "t" and time.perf_counter() - start < 5
    with pytest.raises(InvalidArgumentError, match="force"):
        solve_boltzmann(0.5, [1.0], exponent=0.0, grid=grid, force="yes")
    assert main(["solve", "--kernel", "relative_velocity", "--exponent", "0", "-r", "0.5",
                 "--t", "5000", "--points", "1601", "--half-width", "160", "--json"]) == 2
    assert "--force" in capsys.readouterr().err


def test_ctrl_c_stops_a_velocity_space_solve_within_a_second():
    # a solve of several seconds (401 points, gamma = 0, t = 10: ~225 steps), interrupted
    # 0.5 s in by a KeyboardInterrupt in the main thread, as Ctrl-C delivers it
    # imports first: an interrupt that lands while the interpreter compiles a module's source
    # aborts CPython itself ("AST constructor recursion depth mismatch"), whatever the solver
    solve_boltzmann(0.5, [0.1], exponent=0.0, grid=VelocityGrid(81, 8.0))
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        _thread.interrupt_main()

    # Python's own SIGINT handler, whatever an earlier test of this process installed (dask's
    # job runner installs one that exits): interrupt_main calls the handler, as Ctrl-C does
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, interrupt)
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            solve_boltzmann(0.5, [10.0], exponent=0.0, grid=default_grid(0.0))
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    # within a second of the interrupt (the wait polls every 0.1 s); the solve alone takes
    # seconds (225 steps to t = 10 took 6.1 s at load 5), so a run to the end would fail this
    assert fired and time.perf_counter() - fired[0] < 1.0
    # the abandoned solve ends before the test does (a process that exits while it still
    # runs inside JAX aborts)
    assert join_abandoned(120.0)
