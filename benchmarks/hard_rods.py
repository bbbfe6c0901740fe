"""Benchmarks of the velocity-space solver of the inelastic Boltzmann equation with rate
n|v − w|^γ (maxwell_kinetics/inelastic_boltzmann.py); results in benchmarks/README.md.

    python benchmarks/hard_rods.py convergence   # hard rods, r = 0.99, t = 10, 100, 400
    python benchmarks/hard_rods.py timing        # the t = 400 solve after compile
    python benchmarks/hard_rods.py maxwell       # gamma = 0 against the exact kurtosis
    python benchmarks/hard_rods.py mapped        # gamma = 0 to tau = 50 on a mapped grid
    python benchmarks/hard_rods.py mapped_order  # gamma = 1 on mapped grids: the order

Run under ``taskset -c 0`` for one core.
"""

from __future__ import annotations

import json
import math
import sys
import time

from maxwell_kinetics.inelastic_boltzmann import solve_boltzmann
from maxwell_kinetics.velocity_grid import MappedGrid, VelocityGrid


def convergence(points=(61, 81, 121, 161, 201, 241), half_width=6.0):
    rows = []
    for n in points:
        sol = solve_boltzmann(0.99, [10.0, 100.0, 400.0], grid=VelocityGrid(n, half_width))
        rows.append({"points": n, "h": sol.grid.h, "energy": sol.energy.tolist(),
                     "kurtosis": sol.kurtosis.tolist(), "seconds": sol.seconds,
                     "steps": sol.steps})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def timing(points=201, half_width=6.0, repeats=3):
    grid = VelocityGrid(points, half_width)
    first = solve_boltzmann(0.99, [400.0], grid=grid)  # compiles
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        sol = solve_boltzmann(0.99, [400.0], grid=grid)
        best = min(best, time.perf_counter() - start)
    out = {"points": points, "first_call_s": first.seconds, "after_compile_s": best,
           "kurtosis": float(sol.kurtosis[-1]), "energy": float(sol.energy[-1]),
           "steps": sol.steps}
    print(json.dumps(out), flush=True)
    return out


def maxwell(grids=((97, 12.0, (2.0,)), (193, 12.0, (2.0,)), (641, 40.0, (10.0, 50.0)))):
    """γ = 0, r = 0.5 against the exact kurtosis and the Fourier solver's P(x) (41 points of
    [−5, 5], resolution "fine")."""
    import numpy as np

    from maxwell_kinetics import solve

    rows = []
    for n, half_width, times in grids:
        sol = solve_boltzmann(0.5, list(times), exponent=0.0, grid=VelocityGrid(n, half_width))
        ref = solve(0.5, tau=list(times), resolution="fine", progress=False)
        x = np.linspace(-5.0, 5.0, 41)
        for k, t in enumerate(times):
            exact = -3 + 6 * math.exp(9 * t / 128)
            difference = np.max(np.abs(ref.density(x, tau=t)[1] - sol.density(x, t=t)[1]))
            rows.append({"points": n, "half_width": half_width, "tau": t,
                         "kurtosis": float(sol.kurtosis[k]), "exact": exact,
                         "relative_error": float(sol.kurtosis[k]) / exact - 1,
                         "max_density_difference": float(difference),
                         "edge_mass": float(sol.edge_mass[k]), "seconds": sol.seconds})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def mapped(grids=((401, 2e5, 0.1), (561, 2e5, 0.07)), times=(10.0, 50.0)):
    """γ = 0, r = 0.5 on mapped grids c = a sinh(s) against the exact kurtosis and the Fourier
    solver's P(x) (41 points of [−5, 5], resolution "fine"), as :func:`maxwell`."""
    import numpy as np

    from maxwell_kinetics import solve

    ref = solve(0.5, tau=list(times), resolution="fine", progress=False)
    x = np.linspace(-5.0, 5.0, 41)
    rows = []
    for n, half_width, core in grids:
        grid = MappedGrid(n, half_width, core)
        sol = solve_boltzmann(0.5, list(times), exponent=0.0, grid=grid)
        for k, t in enumerate(times):
            exact = -3 + 6 * math.exp(9 * t / 128)
            difference = np.max(np.abs(ref.density(x, tau=t)[1] - sol.density(x, t=t)[1]))
            rows.append({"points": n, "half_width": half_width, "core_spacing": core,
                         "step_s": grid.step, "tau": t, "kurtosis": float(sol.kurtosis[k]),
                         "exact": exact, "relative_error": float(sol.kurtosis[k]) / exact - 1,
                         "max_density_difference": float(difference),
                         "edge_mass": float(sol.edge_mass[k]), "seconds": sol.seconds,
                         "steps": sol.steps})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def mapped_order(points=(41, 61, 81, 121, 161), half_width=12.0, restitution=0.8, t=2.0):
    """Hard rods (γ = 1) on mapped grids of one map (a and S fixed: core spacing ∝ 1/(N − 1))
    against a fine uniform grid (321 points on ±8): the order of the kink correction with the
    local spacing."""
    ref = solve_boltzmann(restitution, [t], grid=VelocityGrid(321, 8.0), rtol=1e-11, atol=1e-14)
    rows = []
    for n in points:
        grid = MappedGrid(n, half_width, 0.24 * 40 / (n - 1))
        sol = solve_boltzmann(restitution, [t], grid=grid, rtol=1e-11, atol=1e-14)
        rows.append({"points": n, "core_spacing": grid.core_spacing, "step_s": grid.step,
                     "kurtosis": float(sol.kurtosis[-1]),
                     "kurtosis_difference": float(sol.kurtosis[-1] - ref.kurtosis[-1]),
                     "energy_difference": float(sol.energy[-1] - ref.energy[-1]),
                     "seconds": sol.seconds})
        print(json.dumps(rows[-1]), flush=True)
    return rows


if __name__ == "__main__":
    {"convergence": convergence, "timing": timing, "maxwell": maxwell, "mapped": mapped,
     "mapped_order": mapped_order}[sys.argv[1]]()
