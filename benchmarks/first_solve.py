"""The first ``solve()`` of a fresh Python process, cold store then warm (the library default).

    python benchmarks/first_solve.py              # one cold/warm pair
    python benchmarks/first_solve.py --repeat 3   # three pairs (the table keeps the mins)

Each pair: a new empty store folder (``MAXWELL_KINETICS_CACHE``), one fresh Python process that
runs the README's example solve without any call to ``compile_cache`` (cold: it traces, compiles
and fills the store), then a fresh process that runs it again (warm: it loads the executables).
Timed in each process: the first ``solve()`` call alone (after the imports), and the whole
process.  Also one process with ``MAXWELL_KINETICS_CACHE=off`` (the opt-out).  Prints a
Markdown table with the load average and writes benchmarks/first_solve.json.
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

#: The README's example, timed around the first solve() only.
CODE = """
import json, time
from maxwell_kinetics import solve
start = time.perf_counter()
sol = solve(0.5, "gaussian", tau=[1, 5], resolution="coarse", progress=False)
print(json.dumps({"solve": time.perf_counter() - start}))
"""


def _run(cache: str) -> dict:
    env = dict(os.environ, MAXWELL_KINETICS_CACHE=cache)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CODE], check=True, env=env,
                          capture_output=True, text=True)
    return {"process": time.perf_counter() - start, **json.loads(done.stdout)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    pairs = []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory() as folder:
            cold = _run(folder)
            warm = _run(folder)
        pairs.append({"cold": cold, "warm": warm})
    off = _run("off")
    best = {side: {k: min(p[side][k] for p in pairs) for k in ("solve", "process")}
            for side in ("cold", "warm")}
    out = {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "load_average": os.getloadavg(), "cpus": os.cpu_count(), "pairs": pairs,
        "off": off, "best": best,
        "ratio_solve": best["warm"]["solve"] / best["cold"]["solve"],
        "ratio_process": best["warm"]["process"] / best["cold"]["process"],
    }
    (HERE / "first_solve.json").write_text(json.dumps(out, indent=1) + "\n")
    print(f"load average {out['load_average']}, {out['cpus']} CPUs, {args.repeat} pair(s)\n")
    print("| | cold store (s) | warm store (s) | warm / cold | store off (s) |")
    print("|---|---|---|---|---|")
    for key in ("solve", "process"):
        print(f"| first solve() {'call' if key == 'solve' else 'process, whole'} | "
              f"{best['cold'][key]:.2f} | {best['warm'][key]:.2f} | "
              f"{best['warm'][key] / best['cold'][key]:.2f} | {off[key]:.2f} |")


if __name__ == "__main__":
    main()
