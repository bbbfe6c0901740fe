"""Collisions per second of the Ulam model in d = 1, 2, 3 and driven, at N = 10⁶
(the 2D model within 2× of 1D).

    python benchmarks/ulam_dimensions.py [--n 1000000] [--tau 2] [--repeat 3]

Each configuration advances N particles from a unit Gaussian to τ (N τ / 2 collisions), best of
``repeat``, one process, one thread; the configurations alternate within each repetition so that
a change of machine load hits them alike.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import time
from pathlib import Path

import numpy as np

from particles.ulam import Ulam

CONFIGS = {
    "1D": {},
    "2D uniform": {"dimension": 2},
    "2D hard": {"dimension": 2, "angular": "hard"},
    "3D uniform": {"dimension": 3},
    "driven 1D": {"driving": 1.0},
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--tau", type=float, default=2.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    best = {name: float("inf") for name in CONFIGS}
    collisions = {}
    for _ in range(args.repeat):
        for name, kw in CONFIGS.items():
            engine = Ulam(args.n, 0.5, **kw)
            rng = np.random.default_rng(1)
            state = engine.initial_state(rng)
            t0 = time.perf_counter()
            new = engine.advance(state, args.tau, rng)
            best[name] = min(best[name], time.perf_counter() - t0)
            collisions[name] = new.collisions
    rate = {name: collisions[name] / best[name] for name in CONFIGS}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=Path(__file__).resolve().parents[1]).stdout.strip()
    print(json.dumps({"n": args.n, "tau": args.tau, "commit": commit,
                      "load_average": os.getloadavg(),
                      "collisions_per_second": rate,
                      "slower_than_1d": {k: rate["1D"] / v for k, v in rate.items()}}, indent=1))


if __name__ == "__main__":
    main()
