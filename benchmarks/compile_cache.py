"""The persistent compilation cache: wall time of fresh processes, cold cache then warm.

    python benchmarks/compile_cache.py            # the three cases, one pair of runs each
    python benchmarks/compile_cache.py --repeat 2 # two pairs per case (the table keeps the mins)

For each case, side by side in one run: a new empty cache folder (``MAXWELL_KINETICS_CACHE``),
one fresh ``maxwell-kinetics`` process that fills it (cold), then a fresh process that reads it
(warm); with ``--repeat N``, N such pairs, each on a new folder, and the minimum of each.
Wall time is measured around the whole subprocess (interpreter start, imports, tracing,
compiling or loading, the solve).  Prints a Markdown table with the load average and
writes benchmarks/compile_cache.json.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

CASES = {
    "solve d=2 tau=100": ["solve", "-r", "0.5", "--dimension", "2", "--tau", "100"],
    "solve d=1 tau=100": ["solve", "-r", "0.5", "--dimension", "1", "--tau", "100"],
    "reproduce --small": ["reproduce", "--small"],
}


def _run(argv: list[str], cache: Path, workdir: Path) -> tuple[float, dict]:
    """Wall time of one fresh process; for ``reproduce``, also the seconds of each comparison
    (from its summary.json)."""
    env = dict(os.environ, MAXWELL_KINETICS_CACHE=str(cache))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    if argv[0] == "reproduce":
        argv = [*argv, "--out", str(workdir / "results")]
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "maxwell_kinetics.app.cli", *argv, "--json",
                    "--no-progress"], check=True, env=env, cwd=workdir, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    parts = {}
    if argv[0] == "reproduce":
        summary = json.loads((workdir / "results" / "summary.json").read_text())
        parts = {name: entry["seconds"] for name, entry in summary["comparisons"].items()
                 if isinstance(entry, dict) and "seconds" in entry}
    return wall, parts


def _entries(cache: Path) -> int:
    return sum(1 for _ in cache.rglob("*.entry"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=1,
                        help="cold/warm pairs per case (mins kept)")
    parser.add_argument("--only", default=None, help="comma-separated case names")
    args = parser.parse_args()
    names = list(CASES) if args.only is None else args.only.split(",")
    rows = []
    load_before = os.getloadavg()
    for name in names:
        colds, warms = [], []
        for _ in range(args.repeat):  # each repeat: a new empty cache, one cold run, one warm
            with tempfile.TemporaryDirectory() as tmp:
                tmp = Path(tmp)
                cache = tmp / "cache"
                colds.append(_run(CASES[name], cache, tmp))
                entries = _entries(cache)
                warms.append(_run(CASES[name], cache, tmp))
        (cold, cold_parts), (warm, warm_parts) = min(colds), min(warms)
        rows.append({"case": name, "cold_s": cold, "warm_s": warm, "ratio": warm / cold,
                     "entries": entries, "parts_cold_s": cold_parts, "parts_warm_s": warm_parts,
                     "all_cold_s": [c[0] for c in colds], "all_warm_s": [w[0] for w in warms]})
        print(f"{name}: cold {cold:.2f} s, warm {warm:.2f} s, ratio {warm / cold:.2f}",
              file=sys.stderr)
    load_after = os.getloadavg()
    print("| case | cold cache (s) | warm cache (s) | warm / cold | entries |")
    print("|---|---|---|---|---|")
    for row in rows:
        print(f"| `{row['case']}` | {row['cold_s']:.2f} | {row['warm_s']:.2f} | "
              f"{row['ratio']:.2f} | {row['entries']} |")
    print(f"load average (1, 5, 15 min) before {load_before[0]:.2f}, {load_before[1]:.2f}, "
          f"{load_before[2]:.2f}; after {load_after[0]:.2f}, {load_after[1]:.2f}, "
          f"{load_after[2]:.2f}")
    for row in rows:
        if row["parts_cold_s"]:
            print(f"\n`{row['case']}`, seconds of each comparison (cold, warm):")
            print("| comparison | cold | warm |\n|---|---|---|")
            for part, cold in row["parts_cold_s"].items():
                warm = row["parts_warm_s"].get(part, float("nan"))
                print(f"| {part} | {cold:.1f} | {warm:.1f} |")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=ROOT).stdout.strip()
    (HERE / "compile_cache.json").write_text(json.dumps({
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="minutes"),
        "commit": commit, "repeat": args.repeat, "load_before": load_before,
        "load_after": load_after, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
