"""MD benchmark: the NumPy light-cone engine against a sequential C event loop, side by side.

    python benchmarks/md.py                 # both regimes, default sizes (about a minute)
    python benchmarks/md.py --quick         # smaller N, a few seconds
    python benchmarks/md.py --json          # one JSON object on stdout

The C loop (``benchmarks/md_baseline.c``) is compiled here with ``cc -O2`` into a temporary
directory; it is a yardstick, not a dependency.  It uses the same formulas as
``particles/md/kernel.py`` in the same order, so runs from the same initial state are compared
bit for bit (``identical``).  Rates count pair collisions per second of the event loop only.

1. Homogeneous stage: N = 1e6, r = 0.9, delta = 1e-3, n = 1, t in [0, 2].  The sequential Python
   reference runs the first part [0, 0.5] of the same run (a heap of 1e6 pairs).
2. Clustered stage: r = 0.5, delta = 1e-4, n = 1, N = 2e4 (late times at N = 1e6 would take the
   C loop minutes to reach): the C loop brings the gas to t = 20 (about 1100 collisions per
   particle, E ~ 0.06 against E_Haff = 0.011), then all three engines run [20, 20.2].
   ``--clustered-r``, ``--clustered-t`` and ``--clustered-window`` change r and the window
   [T, T + W] (e.g. r = 0.99 late: ``--clustered-r 0.99 --clustered-t 6000 --clustered-window 2``).
   ``--critical-path`` also runs the window with vectorised passes only (the light-cone scheme's
   own count of rounds); ``--causal-depth`` replays it to count the fewest rounds any exact
   scheme needs, and describes its clusters (``causal_depth``, ``cluster_anatomy`` of
   :mod:`particles.md.analysis`).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import pstats
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from particles.md import MDEngine, MDParams, MDState  # noqa: E402
from particles.md.analysis import causal_depth, cluster_anatomy  # noqa: E402
from particles.observables import energy as _energy  # noqa: E402


def energy(state: MDState) -> float:
    return _energy(state.velocities)


def compile_baseline(workdir: Path) -> Path:
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise SystemExit("benchmarks/md.py: no C compiler (cc) found")
    exe = workdir / "md_baseline"
    subprocess.run([cc, "-O2", "-o", str(exe), str(HERE / "md_baseline.c"), "-lm"], check=True)
    return exe


def run_c(exe: Path, workdir: Path, params: MDParams, state: MDState, until: float):
    fin, fout = workdir / "in.bin", workdir / "out.bin"
    np.concatenate([state.positions, state.t_last, state.velocities]).tofile(fin)
    args = [str(exe), str(fin), str(fout), repr(params.reduced_length), repr(params.restitution)]
    args += [repr(params.delta), repr(float(until))]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout.split()
    count, seconds = int(out[0]), float(out[1])
    x, tl, v = np.fromfile(fout).reshape(3, params.n)
    return MDState(float(until), x, tl, v, state.collisions + count), count, seconds


def run_py(params, method, state, until, profile=False, **options):
    engine = MDEngine(params, method, **options)
    prof = cProfile.Profile() if profile else None
    start = time.perf_counter()
    if prof is not None:
        prof.enable()
    out = engine.advance(state, until)
    if prof is not None:
        prof.disable()
    seconds = time.perf_counter() - start
    top = None
    if prof is not None:
        buf = io.StringIO()
        pstats.Stats(prof, stream=buf).sort_stats("tottime").print_stats(8)
        top = buf.getvalue()
    return out, out.collisions - state.collisions, seconds, engine.stats, top


def same(a: MDState, b: MDState) -> bool:
    return bool(
        a.collisions == b.collisions
        and np.array_equal(a.velocities, b.velocities)
        and np.array_equal(a.positions, b.positions)
    )


def regime(
    exe,
    workdir,
    params,
    t_start,
    t_end,
    t_ref,
    seed,
    profile=False,
    critical_path=False,
    depth=False,
    **options,
):
    engine = MDEngine(params)
    s0 = engine.initial_state(np.random.default_rng(seed))
    row = {"n": params.n, "restitution": params.restitution, "delta": params.delta}
    row["window"] = [t_start, t_end]
    if t_start > 0:
        s0, count, secs = run_c(exe, workdir, params, s0, t_start)
        row["warmup_c"] = {"collisions": count, "seconds": secs, "energy": energy(s0)}
    sc, cc, csec = run_c(exe, workdir, params, s0, t_end)
    sf, cf, fsec, stats, top = run_py(params, "fast", s0, t_end, profile=profile, **options)
    row["c"] = {"collisions": cc, "seconds": csec, "rate": cc / csec}
    row["fast"] = {"collisions": cf, "seconds": fsec, "rate": cf / fsec, "stats": stats}
    row["ratio_fast_over_c"] = (cf / fsec) / (cc / csec)
    row["identical"] = same(sc, sf)
    row["elastic_fraction"] = stats["elastic"] / max(cf, 1)
    if critical_path:
        # vectorised passes only: the number of passes is the length of the longest causal
        # chain the light-cone scheme can see (an upper bound on the true one)
        sp, cp, psec, pstats, _ = run_py(params, "fast", s0, t_end, sequential_below=0)
        row["critical_path"] = {
            "passes": pstats["passes"],
            "collisions": cp,
            "seconds": psec,
            "identical": same(sc, sp),
        }
    if depth:
        row["anatomy"], block = cluster_anatomy(params, s0)
        row["causal_depth"] = causal_depth(params, s0, t_end, block)
    row["energy_end"] = energy(sf)
    if t_ref is not None:
        _, cr, rsec, _, _ = run_py(params, "reference", s0, t_ref)
        row["reference"] = {"collisions": cr, "seconds": rsec, "rate": cr / rsec, "until": t_ref}
        row["ratio_fast_over_reference"] = (cf / fsec) / (cr / rsec)
    if top is not None:
        row["profile"] = top
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 1e5 and 5e3 instead of 1e6 and 2e4")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--profile", action="store_true", help="cProfile the fast runs")
    ap.add_argument("--clustered-n", type=int, default=None)
    ap.add_argument("--sequential-below", type=int, default=64, help="MDEngine option (default 64)")
    ap.add_argument(
        "--critical-path",
        action="store_true",
        help="also run the clustered window with vectorised passes only (slow)",
    )
    ap.add_argument(
        "--causal-depth",
        action="store_true",
        help="also replay the clustered window to measure its causal depth (see causal_depth)",
    )
    ap.add_argument("--skip-homogeneous", action="store_true")
    ap.add_argument(
        "--no-reference",
        action="store_true",
        help="skip the sequential Python reference in the clustered run (long windows)",
    )
    ap.add_argument(
        "--clustered-t",
        type=float,
        default=20.0,
        help="start of the clustered window [T, T + W] (default 20; the C loop warms up to T)",
    )
    ap.add_argument("--clustered-r", type=float, default=0.5, help="restitution (default 0.5)")
    ap.add_argument(
        "--clustered-window", type=float, default=0.2, help="length W of the window (default 0.2)"
    )
    args = ap.parse_args(argv)
    n_h = 100_000 if args.quick else 1_000_000
    n_c = args.clustered_n or (5_000 if args.quick else 20_000)
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        exe = compile_baseline(workdir)
        options = {"profile": args.profile, "sequential_below": args.sequential_below}
        result = {}
        if not args.skip_homogeneous:
            result["homogeneous"] = regime(
                exe, workdir, MDParams(n_h, 1.0, 0.9, delta=1e-3), 0.0, 2.0, 0.5, 1, **options
            )
        result["clustered"] = regime(
            exe,
            workdir,
            MDParams(n_c, 1.0, args.clustered_r, delta=1e-4),
            args.clustered_t,
            args.clustered_t + args.clustered_window,
            None if args.no_reference else args.clustered_t + args.clustered_window,
            1,
            critical_path=args.critical_path,
            depth=args.causal_depth,
            **options,
        )
    if args.json:
        json.dump(result, sys.stdout, indent=1)
        print()
        return
    for name, row in result.items():
        print(
            f"== {name}: N={row['n']} r={row['restitution']} delta={row['delta']} "
            f"t in {row['window']}"
        )
        if "warmup_c" in row:
            w = row["warmup_c"]
            print(
                f"   warm-up (C): {w['collisions']} collisions, {w['seconds']:.2f} s, "
                f"E = {w['energy']:.4g}"
            )
        for key in ("c", "fast", "reference"):
            if key in row:
                r = row[key]
                print(
                    f"   {key:9s} {r['collisions']:>10d} collisions {r['seconds']:8.3f} s "
                    f"{r['rate']:10.3g} /s"
                )
        print(
            f"   fast/C = {row['ratio_fast_over_c']:.3f}   fast/reference = "
            f"{row.get('ratio_fast_over_reference', float('nan')):.2f}   identical to C: "
            f"{row['identical']}   E_end = {row['energy_end']:.5g}"
        )
        st = row["fast"]["stats"]
        print(
            f"   passes {st['passes']}, slabs {st['slabs']}, scalar-loop collisions "
            f"{st['sequential']} ({st['sequential_seconds']:.2f} s), of them in zero-gap bursts "
            f"{st['burst']}, elastic fraction {row['elastic_fraction']:.3f}"
        )
        if "critical_path" in row:
            cp = row["critical_path"]
            print(
                f"   vectorised passes only: {cp['passes']} passes for {cp['collisions']} "
                f"collisions ({cp['seconds']:.2f} s), identical to C: {cp['identical']}"
            )
        if "causal_depth" in row:
            cd = row["causal_depth"]
            print(
                f"   causal depth {cd['depth']} for {cd['collisions']} collisions: at most "
                f"{cd['per_round']:.1f} per round; as ghosts {cd['ghost_depth']} rounds for "
                f"{cd['inelastic']} inelastic ({cd['ghost_per_round']:.1f} per round); replay "
                f"matches the reference: {cd['replay_matches_reference']}"
            )
            an = row["anatomy"]
            print(
                f"   at the start: largest clusters (gaps < delta) {an['cluster_sizes']}, "
                f"largest soft blocks (velocities within delta) {an['soft_blocks']}, "
                f"{an['particles_in_soft_blocks_of_5_or_more']} particles in soft blocks of >= 5; "
                f"collisions inside those blocks {cd['in_blocks']} ({cd['in_blocks_elastic']} "
                f"elastic)"
            )
        if "profile" in row:
            print(row["profile"])


if __name__ == "__main__":
    main()
