"""``ensemble --workers 64`` against ``--workers 2`` on a 2-task ensemble, side by side.

A local cluster never gets more workers than there are tasks left, so the two should cost the
same (target: 64 within 1.1x of 2).  Each repetition runs both commands as fresh processes, in
alternating order, into fresh folders; the table gives the median wall time of each and the
ratio of the medians.

    python benchmarks/workers.py [--repeat 3] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COMMAND = ["ensemble", "ulam", "--n", "1000", "--restitution", "0.5", "--tau", "1",
           "--seeds", "1-2", "--json", "--no-progress"]


def run(workers: int, out: Path) -> float:
    argv = [sys.executable, "-m", "maxwell_kinetics.app.cli", *COMMAND, "--workers", str(workers),
            "--out", str(out)]
    if workers > 4 * (os.cpu_count() or 1):
        argv.append("--force")
    start = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    times = {2: [], 64: []}
    root = Path(tempfile.mkdtemp(prefix="bench-workers-"))
    try:
        for i in range(args.repeat):
            order = (2, 64) if i % 2 == 0 else (64, 2)
            for w in order:
                times[w].append(run(w, root / f"w{w}-{i}"))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    med = {w: statistics.median(t) for w, t in times.items()}
    result = {"cpus": os.cpu_count(), "load": os.getloadavg()[0], "seconds": times,
              "median": med, "ratio_64_over_2": med[64] / med[2]}
    print(f"--workers 2: {med[2]:.2f} s, --workers 64: {med[64]:.2f} s (median of "
          f"{args.repeat}); ratio {med[64] / med[2]:.3f}; load {result['load']:.2f}")
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
