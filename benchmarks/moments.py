"""The cost of ``Solution.moments()`` against the solve it reads, side by side.

For each case the solve is run once to compile, then timed (best of ``--repeat``), and
``moments(orders=(2, 4, 6))`` on the same Solution is timed (best of 20 calls); the ratio is
moments / solve.

    python benchmarks/moments.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import time

from maxwell_kinetics.solver import solve

CASES = [  # (dimension, angular, restitution, saved τ)
    (1, "uniform", 0.5, [10.0, 50.0]),
    (1, "uniform", 0.5, [100.0]),
    (2, "uniform", 0.5, [100.0]),
    (2, "uniform", 0.2, [10.0, 40.0, 100.0, 200.0]),
    (3, "hard", 0.5, [100.0]),
]


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    print(f"commit {commit}, load {os.getloadavg()[0]:.2f}")
    print("| d | angular | r | τ saved | solve (s) | moments (ms) | moments / solve |")
    print("|---|---|---|---|---|---|---|")
    for d, angular, r, taus in CASES:
        def run(d=d, angular=angular, r=r, taus=taus):
            return solve(r, "gaussian", taus, dimension=d, angular=angular)

        sol = run()  # compile
        t_solve = best(run, args.repeat)
        t_mom = best(lambda: sol.moments(orders=(2, 4, 6)), 20)  # noqa: B023 (called at once)
        label = ", ".join(f"{t:g}" for t in taus)
        print(f"| {d} | {angular} | {r:g} | {label} | {t_solve:.3f} | {t_mom * 1e3:.2f} | "
              f"{t_mom / t_solve:.4f} |")


if __name__ == "__main__":
    main()
