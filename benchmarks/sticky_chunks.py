"""One large sticky gas as K chunks on a local Dask cluster: wall time and peak memory per
process of ``maxwell-kinetics simulate sticky --chunks K --workers W``.

    python benchmarks/sticky_chunks.py --n 1000000000 --chunks 20 --workers 2 --times 20

The command runs in a child process; every second the script reads the high-water mark of
resident memory (``VmHWM`` in ``/proc/PID/status``) of each of its descendants (the client, the
nanny processes and the workers) and reports the largest per process kind.  Output times:
``--times`` values log-spaced in t ∈ [1, 10⁴], density 1, unit Gaussian velocities, seed 0.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def descendants(pid: int) -> list[int]:
    """The PIDs of every process below ``pid`` (from the parent links of ``ps``)."""
    table = subprocess.run(["ps", "-eo", "pid=,ppid="], capture_output=True, text=True).stdout
    children: dict[int, list[int]] = {}
    for line in table.split("\n"):
        if line.strip():
            child, parent = (int(x) for x in line.split())
            children.setdefault(parent, []).append(child)
    out, todo = [], [pid]
    while todo:
        kids = children.get(todo.pop(), [])
        out += kids
        todo += kids
    return out


def high_water(pid: int) -> tuple[str, int] | None:
    try:
        with open(f"/proc/{pid}/status") as f:
            status = dict(line.split(":", 1) for line in f)
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return None
    kind = ("client" if "simulate" in cmd else
            "worker" if "spawn_main" in cmd else "other")  # nannies and workers are spawned
    return kind, int(status["VmHWM"].split()[0]) * 1024


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=10**9)
    ap.add_argument("--chunks", type=int, default=20)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--times", type=int, default=20)
    args = ap.parse_args()
    times = ",".join(f"{t:.6g}" for t in np.geomspace(1.0, 1e4, args.times))
    exe = Path(sys.executable).with_name("maxwell-kinetics")
    cmd = [str(exe), "simulate", "sticky", "--n", str(args.n), "--density", "1", "--t", times,
           "--chunks", str(args.chunks), "--workers", str(args.workers), "--json"]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    print(f"commit {commit}, load {os.getloadavg()[0]:.2f}: {' '.join(cmd[1:8])} ...", flush=True)
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE)
    peaks: dict[int, tuple[str, int]] = {}
    while proc.poll() is None:
        for pid in [proc.pid] + descendants(proc.pid):
            hw = high_water(pid)
            if hw is not None:
                peaks[pid] = (hw[0], max(hw[1], peaks.get(pid, ("", 0))[1]))
        time.sleep(1.0)
    out = proc.stdout.read()
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"the command failed with status {proc.returncode}")
    result = json.loads(out)
    by_kind: dict[str, list[float]] = {}
    for kind, peak in peaks.values():
        by_kind.setdefault(kind, []).append(peak / 1024**3)
    print(json.dumps({
        "n": args.n, "chunks": args.chunks, "workers": args.workers, "times": args.times,
        "wall_s": round(wall, 1), "peak_gib": {k: [round(x, 2) for x in sorted(v)]
                                              for k, v in by_kind.items()},
        "edge": result["edge"], "clusters_last": result["clusters"][-1],
        "energy_t23": [e * t ** (2 / 3) for e, t in zip(result["energy"], result["t"],
                                                         strict=True)][-3:],
    }))


if __name__ == "__main__":
    main()
