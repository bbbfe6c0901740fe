"""Throughput of the cooling-state sampler
(:func:`particles.cooling_state_sample.sample_cooling_state`): speeds of the scaled cooling
state per second of one core, and how far out its tail is resolved
(the last shell of 0.25 before the first one with fewer than 100 speeds), in d = 2 and 3.
Results in benchmarks/README.md ("The tail from the DSMC").

    python benchmarks/cooling_state_sample.py                   # N = 1e5, 4 seeds, 20 snapshots
    python benchmarks/cooling_state_sample.py --seeds 16 --snapshots 40 --save /tmp/hcs
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from particles.cooling_state_sample import sample_cooling_state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--restitution", type=float, default=0.5)
    parser.add_argument("--dimensions", type=int, nargs="+", default=[2, 3])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--snapshots", type=int, default=20)
    parser.add_argument("--warmup", type=int, default=16)
    parser.add_argument("--save", type=Path, default=None,
                        help="write each sample as <save>_d<d>.json")
    args = parser.parse_args()
    for d in args.dimensions:
        start = time.perf_counter()
        sample = sample_cooling_state(args.n, args.restitution, dimension=d,
                                      seeds=range(args.seeds), snapshots=args.snapshots,
                                      warmup=args.warmup, progress=False)
        wall = time.perf_counter() - start
        shells = sample.density(5)
        short = np.flatnonzero(shells["counts"] < 100)
        resolved = float(shells["upper"][short[0] - 1]) if short.size and short[0] else 0.0
        chunks = args.seeds * (args.warmup + args.snapshots)
        out = {"dimension": d, "n": args.n, "seeds": args.seeds, "snapshots": args.snapshots,
               "speeds": sample.samples, "seconds": round(wall, 2),
               "speeds_per_second": round(sample.samples / wall),
               "seconds_per_chunk": round(wall / chunks, 4),
               "collisions_per_second": round(
                   chunks * args.n / 2 * sample.seed_values("collisions_per_snapshot")[0]
                   / wall),
               "resolved": resolved,
               "cooling_rate": sample.seed_values("cooling_rate"),
               "a2": sample.seed_values("a2")}
        print(json.dumps(out), flush=True)
        if args.save is not None:
            sample.save(f"{args.save}_d{d}.json")


if __name__ == "__main__":
    main()
