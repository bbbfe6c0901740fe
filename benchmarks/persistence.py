"""The cost of the content hash when a checkpoint is loaded (at most 10 % of the load).

    python benchmarks/persistence.py [--n 1000000] [--repeats 7]

Writes a checkpoint of an MD run with N particles (state: positions, last-update times,
velocities; the records of 4 times and S(k) at the last), then times, best of ``repeats``:

* ``load``: ``particles.persistence.load`` (header checks, bounded reads, and the hash, whose
  per-array digests run in a second thread while the next array is read);
* ``unverified``: the same load with the hash switched off here (``entry_digest`` and
  ``digest`` replaced by stubs for this measurement only): the cost of verifying is
  ``load − unverified``;
* ``hash``: ``particles.persistence.digest`` over the loaded meta and arrays alone (serial);
* ``resume``: the whole resume path of the driver up to the first step (load, identity and
  consistency checks, state rebuild), for scale.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from unittest import mock

import numpy as np

from particles import persistence
from particles.driver import simulate
from particles.driver.checkpoint import Records, load_checkpoint, run_identity
from particles.md import MDEngine, MDParams
from particles.observables import rescaled_histogram


def best(f, repeats):
    out = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return min(out)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "md.ckpt"
        engine = MDEngine(MDParams(args.n, 1.0, 0.5, delta=1e-4))
        times = [0.05, 0.1, 0.15, 0.2]
        simulate(engine, times, 1, progress=False, checkpoint=path, structure_factor="last")
        size = path.stat().st_size
        loaded = persistence.load(path, "checkpoint", (1, 2))
        t_load = best(lambda: persistence.load(path, "checkpoint", (1, 2)), args.repeats)
        t_hash = best(lambda: persistence.digest(loaded.meta, loaded.arrays), args.repeats)
        with mock.patch.object(persistence, "entry_digest", lambda name, a: b""), \
                mock.patch.object(persistence, "digest",
                                  lambda meta, arrays, entries=None: meta["sha256"]):
            t_plain = best(lambda: persistence.load(path, "checkpoint", (1, 2)), args.repeats)
        edges = rescaled_histogram(np.array([1.0, -1.0]), None).edges
        identity = run_identity(engine, times, 1, edges, "last", False)  # S(k) at the last time

        def resume():
            records = Records(len(times), args.n, "last", False)
            load_checkpoint(path, engine, identity, records)

        t_resume = best(resume, args.repeats)
    print(f"N = {args.n}, file {size / 2**20:.1f} MiB, best of {args.repeats}")
    cost = t_load - t_plain
    print(f"load, verified {t_load * 1e3:.1f} ms; unverified {t_plain * 1e3:.1f} ms; cost of "
          f"the check {cost * 1e3:.1f} ms = {100 * cost / t_load:.1f} % of the load; "
          f"serial hash alone {t_hash * 1e3:.1f} ms; whole resume {t_resume * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
