"""Benchmark: the NumPy fast paths of the Ulam and lattice models against sequential C loops.

    python benchmarks/particles_ulam_lattice.py            # full run, about 1-2 minutes
    python benchmarks/particles_ulam_lattice.py --quick    # smaller sizes, a few seconds

Everything runs on ONE core: BLAS/OpenMP threads are set to 1 before NumPy is imported and the
process (and the C programs it starts) is pinned to one CPU.

1. Side by side at N = 1e6: collisions/s (Ulam, r = 0.5) and attempts/s (lattice, r = 0.5,
   constraint on) of the NumPy engines (``advance`` through the driver's stops, as ``simulate``
   runs them) and of ``benchmarks/particles_baseline.c`` compiled now with ``cc -O2``, in two
   variants: xoshiro256** random numbers (fast) and the C library's drand48().  Best of 5
   interleaved repetitions each.  The C loop is the discrete model (a fixed number of
   collisions / attempts); the NumPy engines run the exact continuous-time models (a Poisson
   number of events; the lattice also draws one Exp(1) clock per attempt).
2. Cost against N·τ: N = 1e4 … 1e7 at fixed N·τ, and τ × 1, 4, 16 at N = 1e5: seconds per unit
   of N·τ must stay flat.
3. Peak memory (``ru_maxrss`` of a fresh interpreter) of ``simulate`` at N = 1e7 with the
   histogram and the structure factor.
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

from particles.lattice import Lattice  # noqa: E402
from particles.ulam import Ulam  # noqa: E402

C_SOURCE = Path(__file__).resolve().parent / "particles_baseline.c"


def pin_one_core() -> int:
    cpu = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpu})
    return cpu


def compile_baselines(workdir: Path) -> dict[str, Path]:
    out = {}
    for name, flags in (("xoshiro", []), ("drand48", ["-DUSE_DRAND48"])):
        exe = workdir / f"baseline_{name}"
        subprocess.run(["cc", "-O2", *flags, "-o", str(exe), str(C_SOURCE), "-lm"], check=True)
        out[name] = exe
    return out


def run_c(exe: Path, model: str, n: int, count: int, seed: int = 1) -> float:
    """Seconds of the timed C loop."""
    text = subprocess.run(
        [str(exe), model, str(n), str(count), str(seed), "0.5"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return float(text.split()[0])


def run_numpy(engine, tau: float, seed: int = 1) -> tuple[float, int]:
    """Seconds and events (Ulam collisions or lattice attempts) to advance 0 -> tau."""
    rng = np.random.default_rng(seed)
    state = engine.initial_state(rng)
    start = time.perf_counter()
    while state.time < tau:
        state = engine.advance(state, min(engine.next_stop(state.time), tau), rng)
    seconds = time.perf_counter() - start
    events = state.attempts if engine.name == "lattice" else state.collisions
    return seconds, int(events)


def side_by_side(exes, n: int, tau: float, repeats: int) -> dict:
    results = {}
    for model, engine in (("ulam", Ulam(n, 0.5)), ("lattice", Lattice(n, 0.5))):
        per_unit = 0.5 if model == "ulam" else 1.0  # events per particle per unit τ
        count = int(per_unit * n * tau)
        best = {"numpy": 0.0, "xoshiro": 0.0, "drand48": 0.0}
        for rep in range(repeats):
            seconds, events = run_numpy(engine, tau, seed=rep + 1)
            best["numpy"] = max(best["numpy"], events / seconds)
            for name, exe in exes.items():
                best[name] = max(best[name], count / run_c(exe, model, n, count, seed=rep + 1))
        results[model] = {
            "n": n,
            "tau": tau,
            "numpy_per_s": best["numpy"],
            "c_xoshiro_per_s": best["xoshiro"],
            "c_drand48_per_s": best["drand48"],
            "ratio_vs_xoshiro": best["numpy"] / best["xoshiro"],
            "ratio_vs_drand48": best["numpy"] / best["drand48"],
        }
    return results


def scaling(sizes, work: float, taus_at_1e5) -> dict:
    out = {"ulam": [], "lattice": []}
    for model in out:
        cases = [(n, work / n) for n in sizes] + [(100_000, t) for t in taus_at_1e5]
        for n, tau in cases:
            # r = 0.99 for Ulam keeps the energy well above the round-off floor at τ up to 4e3.
            engine = Ulam(n, 0.99) if model == "ulam" else Lattice(n, 0.5)
            seconds, events = run_numpy(engine, tau)
            out[model].append(
                {
                    "n": n,
                    "tau": tau,
                    "seconds": seconds,
                    "ns_per_n_tau": 1e9 * seconds / (n * tau),
                    "events_per_s": events / seconds,
                }
            )
    return out


MEMORY_SNIPPET = """
import resource, sys
sys.path.insert(0, {root!r})
from particles.driver import simulate
from particles.{module} import {cls}
simulate({cls}({n}, 0.5), [{tau}], 0, progress=False, structure_factor=True)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


def peak_memory(n: int) -> dict:
    out = {}
    for model, module, cls, tau in (
        ("ulam", "ulam", "Ulam", 1.0),
        ("lattice", "lattice", "Lattice", 4.0),
    ):
        code = MEMORY_SNIPPET.format(root=str(ROOT), module=module, cls=cls, n=n, tau=tau)
        text = subprocess.run(
            [sys.executable, "-c", code], check=True, capture_output=True, text=True
        ).stdout
        out[model] = {"n": n, "tau": tau, "peak_rss_mb": int(text.split()[-1]) / 1024}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes (a smoke test)")
    parser.add_argument("--json", metavar="FILE", help="also write the numbers to FILE")
    args = parser.parse_args(argv)
    cpu = pin_one_core()
    if args.quick:
        n_main, tau_main, repeats = 100_000, 4.0, 2
        sizes, work, taus, mem_n = [10_000, 100_000], 1e6, [4.0, 16.0], 1_000_000
    else:
        n_main, tau_main, repeats = 1_000_000, 8.0, 5
        sizes, work, taus, mem_n = (
            [10_000, 100_000, 1_000_000, 10_000_000],
            4e7,
            [4.0, 16.0, 64.0],
            10_000_000,
        )
    with tempfile.TemporaryDirectory() as tmp:
        exes = compile_baselines(Path(tmp))
        report = {
            "cpu": cpu,
            "numpy": np.__version__,
            "side_by_side": side_by_side(exes, n_main, tau_main, repeats),
        }
    report["scaling"] = scaling(sizes, work, taus)
    report["memory"] = peak_memory(mem_n)

    print(f"# one core (cpu {cpu}), NumPy {np.__version__}")
    print(f"\n## side by side, events/s (best of {repeats})")
    print("| model | N | NumPy | C xoshiro | C drand48 | ratio vs xoshiro | ratio vs drand48 |")
    print("|---|---|---|---|---|---|---|")
    for model, r in report["side_by_side"].items():
        print(
            f"| {model} | {r['n']:.0e} | {r['numpy_per_s']:.3g} | {r['c_xoshiro_per_s']:.3g} "
            f"| {r['c_drand48_per_s']:.3g} | {r['ratio_vs_xoshiro']:.2f} "
            f"| {r['ratio_vs_drand48']:.2f} |"
        )
    print("\n## cost against N·tau")
    print("| model | N | tau | seconds | ns per unit N·tau | events/s |")
    print("|---|---|---|---|---|---|")
    for model, rows in report["scaling"].items():
        for r in rows:
            print(
                f"| {model} | {r['n']:.0e} | {r['tau']:g} | {r['seconds']:.3f} "
                f"| {r['ns_per_n_tau']:.1f} | {r['events_per_s']:.3g} |"
            )
    print("\n## peak memory")
    for model, r in report["memory"].items():
        print(
            f"- {model}: N = {r['n']:.0e}, tau = {r['tau']:g}: peak RSS {r['peak_rss_mb']:.0f} MB"
        )
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
