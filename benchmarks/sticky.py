"""Sticky-gas benchmark: wall time per output time and peak memory of ``particles/sticky.py``.

    python benchmarks/sticky.py                     # N = 1e4, 1e5, 1e6, 1e7
    python benchmarks/sticky.py --sizes 10000 100000 --json
    python benchmarks/sticky.py --cli --sizes 10000000 100000000   # the command line, whole

Each N runs in its own subprocess (so the peak resident memory, ``ru_maxrss``, is that N's):
draw the MD initial state (unit Gaussian velocities, density 1, seed 0), then compute the
state at 20 output times, log-spaced in t ∈ [1, 10⁴], each directly from the initial data
(``StickyGas.advance``).  Reported: the time of the draw, the mean and the largest wall time per
output time, E t^{2/3} at t = 10, 100 and 1000 (the times of the grid nearest to them) and the
peak resident memory of the process (including the interpreter and NumPy/SciPy, about 0.1 GB).

``--cli`` times the whole command ``maxwell-kinetics simulate sticky --n N --density 1 --t
<the 20 times> --json`` instead (draw, the 20 states, energies, cluster counts and the final
histogram), in a child process whose wall time and peak resident memory (``wait4``) are
reported.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from particles.sticky import StickyGas, StickyParams  # noqa: E402

TIMES = np.geomspace(1.0, 1e4, 20)


def one(n: int) -> dict:
    engine = StickyGas(StickyParams(n, 1.0))
    t0 = time.perf_counter()
    s0 = engine.initial_state(np.random.default_rng(0))
    draw = time.perf_counter() - t0
    per_time, scaled, clusters = [], [], []
    for t in TIMES:
        t0 = time.perf_counter()
        s = engine.advance(s0, float(t))
        per_time.append(time.perf_counter() - t0)
        scaled.append(float(np.mean(s.velocities**2) * t ** (2 / 3)))
        clusters.append(int(s.starts.size))
        del s
    pick = {str(t): scaled[int(np.argmin(np.abs(np.log(TIMES / t))))] for t in (10, 100, 1000)}
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2  # KiB -> GiB
    return {
        "n": n,
        "draw_s": draw,
        "per_time_mean_s": float(np.mean(per_time)),
        "per_time_max_s": float(np.max(per_time)),
        "total_s": draw + float(np.sum(per_time)),
        "peak_rss_gib": rss,
        "E_t23": pick,
        "clusters_last": clusters[-1],
    }


def command_line(n: int) -> dict:
    """Wall time and peak memory of ``maxwell-kinetics simulate sticky`` at N = ``n``."""
    import os

    times = ",".join(f"{t:.6g}" for t in TIMES)
    exe = Path(sys.executable).with_name("maxwell-kinetics")
    cmd = [str(exe), "simulate", "sticky", "--n", str(n), "--density", "1", "--t", times,
           "--json", "--no-progress"]
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        raise SystemExit(f"{cmd[:4]} failed with status {status}")
    result = json.loads(out)
    return {"n": n, "wall_s": wall, "peak_rss_gib": usage.ru_maxrss / 1024**2,
            "bytes_per_particle": usage.ru_maxrss * 1024 / n,
            "clusters_last": result["clusters"][-1], "energy_last": result["energy"][-1]}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[10**4, 10**5, 10**6, 10**7])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--cli", action="store_true", help="time the whole command line")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(one(args.one)))
        return
    if args.cli:
        for n in args.sizes:
            r = command_line(n)
            print(json.dumps(r) if args.json else
                  f"N={n:>10d}  simulate sticky, 20 times: {r['wall_s']:.1f} s, peak "
                  f"{r['peak_rss_gib']:.2f} GiB ({r['bytes_per_particle']:.0f} bytes/particle)",
                  flush=True)
        return
    rows = []
    for n in args.sizes:
        out = subprocess.run([sys.executable, __file__, "--one", str(n)], check=True,
                             capture_output=True, text=True)
        rows.append(json.loads(out.stdout))
        if not args.json:
            r = rows[-1]
            print(f"N={n:>9d}  draw {r['draw_s']:.3f} s  per time {r['per_time_mean_s']:.3f} s "
                  f"(max {r['per_time_max_s']:.3f})  total {r['total_s']:.2f} s  "
                  f"peak {r['peak_rss_gib']:.2f} GiB  E t^2/3 {r['E_t23']}", flush=True)
    if args.json:
        print(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
