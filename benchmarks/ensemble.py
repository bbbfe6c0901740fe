"""Benchmark: an ensemble of Ulam runs on 2 dask workers against the same runs serially.

    python benchmarks/ensemble.py            # 8 runs, N = 1e6, tau = 10, r = 0.5 (~1 minute)
    python benchmarks/ensemble.py --quick    # 8 runs, N = 1e5 (a few seconds)

BLAS/OpenMP threads are set to 1 before NumPy is imported (the workers inherit it).

1. Speedup: ``run_ensemble`` of 8 seeds on a ``LocalCluster`` of 2 single-threaded worker
   processes (started before the clock, connected with ``scheduler=ADDRESS``) against the same
   8 tasks with ``executor="serial"`` in this process (each writes its 8 tasks' files), and
   against a plain loop of ``simulate`` (no files).  Best of ``--repeat`` each; every repetition
   writes to a fresh folder.  The aggregates of the serial and dask runs are checked equal bit
   for bit.  Also the start-up time of the local cluster.
2. Scheduler overhead per task: ``client.submit`` of ``--empty`` tasks that do nothing, then
   waiting for all of them, on the same cluster: wall time / number of tasks.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from particles import persistence  # noqa: E402
from particles.driver import simulate  # noqa: E402
from particles.ensemble import FORMAT_VERSION, EnsembleSpec, local_cluster, run_ensemble  # noqa: E402
from particles.ulam import Ulam  # noqa: E402


def _noop(i):
    return i


def _aggregate(path):
    return persistence.load(path, "ensemble", (FORMAT_VERSION,)).arrays


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--n", type=float, default=None)
    parser.add_argument("--tau", type=float, default=10.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--empty", type=int, default=400)
    args = parser.parse_args(argv)
    n = int(args.n or (1e5 if args.quick else 1e6))
    spec = EnsembleSpec("ulam", {"n": n, "restitution": 0.5}, list(range(1, args.runs + 1)),
                        [args.tau])
    from distributed import Client

    out: dict = {"n": n, "tau": args.tau, "runs": args.runs, "workers": args.workers,
                 "cpus": os.cpu_count(), "load_average_before": os.getloadavg()}
    try:
        out["commit"] = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                                       capture_output=True, text=True).stdout.strip()
    except OSError:
        out["commit"] = None

    t0 = time.perf_counter()
    cluster = local_cluster(args.workers)  # the cluster run_ensemble makes
    client = Client(cluster)
    client.wait_for_workers(args.workers)
    out["cluster_start_s"] = time.perf_counter() - t0
    try:
        loop, serial, dask = [], [], []
        with tempfile.TemporaryDirectory() as tmp:
            for rep in range(args.repeat):
                t0 = time.perf_counter()
                for seed in spec.seeds:
                    simulate(Ulam(n, 0.5), spec.times, seed, progress=False)
                loop.append(time.perf_counter() - t0)
                s = run_ensemble(spec, Path(tmp) / f"serial{rep}", executor="serial",
                                 progress=False)
                serial.append(s.wall_seconds)
                d = run_ensemble(spec, Path(tmp) / f"dask{rep}",
                                 scheduler=cluster.scheduler_address, progress=False)
                dask.append(d.wall_seconds)
                assert d.ok and len(d.ran) == args.runs
                a, b = _aggregate(s.aggregate_path), _aggregate(d.aggregate_path)
                assert all(np.array_equal(a[k], b[k], equal_nan=True) for k in a)
        out.update(loop_s=min(loop), serial_s=min(serial), dask_s=min(dask),
                   speedup_vs_serial=min(serial) / min(dask), speedup_vs_loop=min(loop) / min(dask),
                   all_loop_s=loop, all_serial_s=serial, all_dask_s=dask)
        client.submit(_noop, -1, pure=False).result()  # warm
        t0 = time.perf_counter()
        futures = [client.submit(_noop, i, pure=False) for i in range(args.empty)]
        client.gather(futures)
        out["empty_tasks"] = args.empty
        out["overhead_per_task_ms"] = 1e3 * (time.perf_counter() - t0) / args.empty
    finally:
        client.close()
        cluster.close()
    out["load_average_after"] = os.getloadavg()
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
