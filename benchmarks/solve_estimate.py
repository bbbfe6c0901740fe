"""The wall-time estimate that ``solve`` prints (``grid.estimate_solve``) against the measured
time of the same solve after compilation, side by side, for d = 1, 2, 3 and two grids.

    python benchmarks/solve_estimate.py [--tau 1000]
"""

from __future__ import annotations

import argparse
import os
import time

from maxwell_kinetics.grid import estimate_solve, get_resolution
from maxwell_kinetics.solver import solve


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tau", type=float, default=1000.0)
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.2f}; tau = {args.tau:g}, r = 0.5")
    print("| d | grid | nodes | estimate (s) | measured (s) | measured / estimate |")
    print("|---|---|---|---|---|---|")
    for d in (1, 2, 3):
        for name in ("coarse", "default"):
            grid = get_resolution(name)
            solve(0.5, "gaussian", [args.tau], grid, dimension=d)  # compile (same chunking)
            start = time.perf_counter()
            solve(0.5, "gaussian", [args.tau], grid, dimension=d)
            took = time.perf_counter() - start
            est = estimate_solve(grid, args.tau, 1, dimension=d)["seconds"]
            print(f"| {d} | {name} | {grid.n} | {est:.3g} | {took:.3g} | {took / est:.2f} |")


if __name__ == "__main__":
    main()
