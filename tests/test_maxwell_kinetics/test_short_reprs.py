"""The results a user prints show one line each, not their arrays: a run's repr printed every
velocity and the histogram's every edge (hundreds of lines at N = 100)."""

from __future__ import annotations

import numpy as np

from maxwell_kinetics.solver import solve_fourier
from particles import Ulam, simulate


def test_a_run_its_histogram_and_a_solution_print_one_short_line():
    run = simulate(Ulam(n=100, restitution=0.5), [0.0, 1.0], seed=1, progress=False)
    assert repr(run) == (f"RunResult(model='ulam', n=100, seed=1, 2 times tau = 0..1, "
                         f"energy {run.energy[-1]:.6g} at the last)")
    assert repr(run.histogram) == (f"Histogram(120 bins on [-6, 6], samples=100, "
                                   f"v0={run.histogram.v0:.6g})")
    sol = solve_fourier(0.5, "gaussian", tau=[0.5, 1.0], resolution="coarse", progress=False)
    assert repr(sol) == ("Solution(restitution=0.5, initial='gaussian', dimension=1, "
                         "resolution='coarse', 2 times tau = 0.5..1)")
    for shown in (repr(run), repr(run.histogram), repr(sol)):
        assert "\n" not in shown and "array(" not in shown and len(shown) < 200
    assert np.isfinite(run.energy[-1])  # the value shown is the run's own
