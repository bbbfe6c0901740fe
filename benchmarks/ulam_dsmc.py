"""Benchmark: the Ulam DSMC of the hard-rod Boltzmann equation (``rate="relative_velocity"``)
against the constant-rate Ulam, side by side in one run, on one core.

    python benchmarks/ulam_dsmc.py            # about 1-2 minutes
    python benchmarks/ulam_dsmc.py --quick    # N = 1e5, a few seconds

Each case runs ``advance`` through the driver's stops (as ``simulate`` does), best of
``--repeats`` interleaved repetitions:

* ``constant``: Ulam(N, r = 0.5), τ = 0 → 4 (N/2 collisions per unit τ): collisions/s.
* ``dsmc-start``: Ulam(N, r = 0.5, rate="relative_velocity", density = 1), t = 0 → 2 from the
  Gaussian: accepted collisions/s, candidates/s and the acceptance ⟨|g|⟩/B (B = max v − min v).
* ``dsmc-late``: the same at r = 0.9 from t = 20 (reached untimed) to t = 30, where the gas has
  cooled (~25 collisions per particle): how the acceptance and the throughput change as the
  distribution departs from the Gaussian.

Candidates are counted by wrapping the engine's round scheduler (no change to the engine).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import particles.ulam as ulam_module  # noqa: E402
from particles.ulam import Ulam  # noqa: E402

CANDIDATES = [0]
_fire = ulam_module.fire_rounds_thinned


def _counting_fire(v, pairs, marks, bound, p, first, occurrence):
    CANDIDATES[0] += len(pairs)
    return _fire(v, pairs, marks, bound, p, first, occurrence)


ulam_module.fire_rounds_thinned = _counting_fire


def run(engine, start_time: float, until: float, seed: int) -> dict:
    """Seconds, collisions and candidates of ``engine`` from ``start_time`` (reached untimed)
    to ``until``, advancing through the driver's stops."""
    rng = np.random.default_rng(seed)
    state = engine.initial_state(rng)
    while state.time < start_time:
        state = engine.advance(state, min(engine.next_stop(state.time), start_time), rng)
    before, CANDIDATES[0] = state.collisions, 0
    start = time.perf_counter()
    while state.time < until:
        state = engine.advance(state, min(engine.next_stop(state.time), until), rng)
    seconds = time.perf_counter() - start
    return {"seconds": seconds, "collisions": int(state.collisions - before),
            "candidates": CANDIDATES[0], "energy": float(np.mean(state.velocities**2))}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 1e5 instead of 1e6")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", help="write the results as JSON to this file")
    args = parser.parse_args(argv)
    cpu = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpu})
    n = 100_000 if args.quick else 1_000_000
    cases = {
        "constant": (Ulam(n, 0.5), 0.0, 4.0),
        "dsmc-start": (Ulam(n, 0.5, rate="relative_velocity"), 0.0, 2.0),
        "dsmc-late": (Ulam(100_000, 0.9, rate="relative_velocity"), 20.0, 30.0),
    }
    best: dict[str, dict] = {}
    for rep in range(args.repeats):
        for name, (engine, a, b) in cases.items():
            r = run(engine, a, b, seed=rep + 1)
            r["collisions_per_s"] = r["collisions"] / r["seconds"]
            r["candidates_per_s"] = r["candidates"] / r["seconds"]
            r["acceptance"] = r["collisions"] / r["candidates"] if r["candidates"] else None
            r["n"], r["from"], r["to"] = engine.n, a, b
            if name not in best or r["collisions_per_s"] > best[name]["collisions_per_s"]:
                best[name] = r
    ratio = best["constant"]["collisions_per_s"] / best["dsmc-start"]["collisions_per_s"]
    out = {"cpu": cpu, "repeats": args.repeats, "cases": best,
           "constant_over_dsmc_start": ratio}
    print(f"{'case':>11} {'N':>8} {'time':>11} {'collisions/s':>13} {'candidates/s':>13} "
          f"{'acceptance':>10}")
    for name, r in best.items():
        acc = "-" if r["acceptance"] is None else f"{r['acceptance']:.3f}"
        cand = "-" if not r["candidates"] else f"{r['candidates_per_s']:.3e}"
        print(f"{name:>11} {r['n']:>8} {r['from']:>5g}-{r['to']:<5g} "
              f"{r['collisions_per_s']:>13.3e} {cand:>13} {acc:>10}")
    print(f"constant-rate collisions/s over DSMC accepted collisions/s (start): {ratio:.1f}")
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
