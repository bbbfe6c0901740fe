"""Regressions against the past: the flagship workloads on an earlier commit and on the working
tree, side by side in one run.

    python benchmarks/regressions.py                       # against the last release, 3 rounds
    python benchmarks/regressions.py --baseline HEAD~5 --repeats 5
    python benchmarks/regressions.py --only sticky ulam --json

The baseline (default :data:`DEFAULT_BASELINE`, the 0.2.0 release) is exported with
``git archive`` into a temporary folder; nothing in the repository is checked out or changed.
Both trees run with this interpreter and its installed dependencies, each first on
``PYTHONPATH`` (checked: each imports its own ``particles`` and ``maxwell_kinetics``).

Every workload is one command-line call (the console entry point's module of that tree), run
in a child process from an empty folder: its wall time, and its peak resident memory from
``wait4`` (``ru_maxrss``, the child alone).  The rounds are interleaved (round k runs every
workload on both trees, the order of the two trees alternating from round to round, so a
slow period of a shared machine falls on both) and the best of the rounds is kept: the least
time and the least peak memory.  The ratio is working tree / baseline.

A workload whose command the baseline does not have (its parser refuses it, exit 2) is run on
the working tree alone and reported without a ratio.  A workload that fails on either tree
(any exit status but 0, or 3 for ``reproduce``, whose 3 means "a claim disagrees") stops the
script with exit 2.  Exit 1 when any ratio passes ``--limit`` (default 1.1), else 0.

Workloads (:data:`WORKLOADS`): the Fourier solve (d = 1, and d = 2, 3 to τ = 1000 on the
default grid), the hard-rod solve, Ulam, lattice and MD at
N = 10⁶, the sticky gas at N = 10⁷ with 20 output times, and ``reproduce --small`` of the
comparisons both trees have (``--only``; a comparison added since the baseline is new work, not
a regression).  Its time is judged on the comparisons whose summaries have the same keys and
the same parameters in both trees, verdicts and timings aside (a comparison that gained outputs
or whose preset changed, more seeds say, does more work: shown, not judged; with none alike,
the whole run's time); each comparison's own time comes from
``summary.json``.  The solves run with ``--no-cache`` (each
call compiles: the baseline's compile store is not this tree's).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parent

#: The 0.2.0 release (the last commit of its round of work; the repository has no tags).
DEFAULT_BASELINE = "0538c3c"

#: Twenty output times, log-spaced in t ∈ [1, 10^3.8] (the sticky workload).
STICKY_TIMES = ",".join(f"{t:.6g}" for t in np.logspace(0.0, 3.8, 20))

#: name → the command line's arguments.  ``{out}`` is the child's own empty folder.
WORKLOADS: dict[str, list[str]] = {
    "fourier_solve": ["solve", "--restitution", "0.5", "--tau", "1,10,100", "--json",
                      "--no-progress", "--no-cache"],
    "isotropic_solve_2d": ["solve", "--restitution", "0.5", "--tau", "1,100,1000",
                           "--dimension", "2", "--json", "--no-progress", "--no-cache"],
    "isotropic_solve_3d": ["solve", "--restitution", "0.5", "--tau", "1,100,1000",
                           "--dimension", "3", "--json", "--no-progress", "--no-cache"],
    "hard_rod_solve": ["solve", "--rate", "relative_velocity", "--restitution", "0.5",
                       "--t", "1,5,20", "--json", "--no-progress", "--no-cache"],
    "ulam_1e6": ["simulate", "ulam", "--n", "1000000", "--restitution", "0.5",
                 "--tau", "10,20,40", "--seed", "1", "--json"],
    "lattice_1e6": ["simulate", "lattice", "--n", "1000000", "--restitution", "0.5",
                    "--tau", "10,20,40", "--seed", "1", "--json"],
    "md_1e6": ["simulate", "md", "--n", "1000000", "--density", "1", "--restitution", "0.9",
               "--delta", "1e-3", "--t", "1,2", "--seed", "1", "--json"],
    "sticky_1e7": ["simulate", "sticky", "--n", "10000000", "--density", "1",
                   "--t", STICKY_TIMES, "--seed", "1", "--json"],
    "reproduce_small": ["reproduce", "--small", "--out", "{out}", "--json", "--no-progress",
                        "--no-cache", "--only", "{common_comparisons}"],
}

#: Exit statuses that mean the command ran (``reproduce``: 3 = a claim disagrees).
OK_STATUS = {"reproduce_small": (0, 3)}


def export(ref: str, into: Path) -> str:
    """Export commit ``ref`` of the repository into ``into`` (``git archive``); its full hash."""
    full = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--verify", ref + "^{commit}"],
                          capture_output=True, text=True)
    if full.returncode != 0:
        sys.exit(f"regressions.py: --baseline {ref!r} is not a commit of {REPO}")
    archive = subprocess.run(["git", "-C", str(REPO), "archive", full.stdout.strip()],
                             capture_output=True, check=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    return full.stdout.strip()


def cli_module(tree: Path) -> str:
    """The module of the tree's console entry point (it moved into ``app`` after 0.2.0)."""
    if (tree / "maxwell_kinetics" / "app" / "cli.py").exists():
        return "maxwell_kinetics.app.cli"
    return "maxwell_kinetics.cli"


def environment(tree: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(tree) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def comparisons(tree: Path) -> list[str]:
    """The names of the tree's comparisons (``reproduce`` runs them all)."""
    code = ("import json\n"
            "try:\n    from maxwell_kinetics.app.comparisons import COMPARISONS\n"
            "except ImportError:\n    from maxwell_kinetics.comparisons import COMPARISONS\n"
            "print(json.dumps(list(COMPARISONS)))")
    out = subprocess.run([sys.executable, "-c", code], env=environment(tree),
                         cwd=tempfile.gettempdir(), capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def check_imports(tree: Path) -> None:
    """Refuse to measure a tree whose children would import another copy of the packages."""
    code = ("import particles, maxwell_kinetics; "
            "print(particles.__file__, maxwell_kinetics.__file__)")
    out = subprocess.run([sys.executable, "-c", code], env=environment(tree),
                         cwd=tempfile.gettempdir(), capture_output=True, text=True,
                         check=True).stdout.split()
    for path in out:
        if not Path(path).resolve().is_relative_to(tree.resolve()):
            sys.exit(f"regressions.py: {tree} imports {path}, not its own packages")


def measure(tree: Path, args: list[str], common: str) -> tuple[int, float, float, str, dict]:
    """Run the tree's command line with ``args`` in a new empty folder: (exit status, wall
    seconds, peak resident memory in GB, the last lines of stderr, and for ``reproduce`` each
    comparison's ``(seconds, sorted keys of its summary, its parameters as JSON)``).
    ``common``: the comparisons both trees have, comma-separated."""
    with tempfile.TemporaryDirectory(prefix="mk-regression-") as cwd:
        argv = [a.replace("{out}", str(Path(cwd) / "out"))
                .replace("{common_comparisons}", common) for a in args]
        with tempfile.TemporaryFile() as err:
            start = time.perf_counter()
            child = subprocess.Popen([sys.executable, "-m", cli_module(tree), *argv], cwd=cwd,
                                     env=environment(tree), stdin=subprocess.DEVNULL,
                                     stdout=subprocess.DEVNULL, stderr=err)
            _, status, usage = os.wait4(child.pid, 0)
            seconds = time.perf_counter() - start
            child.returncode = os.waitstatus_to_exitcode(status)
            err.seek(0)
            tail = err.read().decode(errors="replace").strip().splitlines()[-3:]
        parts = {}
        summary = Path(cwd) / "out" / "summary.json"
        if summary.is_file():
            for key, entry in json.loads(summary.read_text())["comparisons"].items():
                # its outputs, less the verdicts (judged from the others, in microseconds;
                # every comparison gained them since 0.2.0) and the timing
                # and its parameters (a preset that changed, more seeds say, does more work:
                # not a regression either)
                parts[key] = (float(entry["seconds"]),
                              sorted(set(entry) - {"verdicts", "seconds", "solver_seconds"}),
                              json.dumps(entry.get("parameters"), sort_keys=True))
    return child.returncode, seconds, usage.ru_maxrss * 1024 / 1e9, "\n".join(tail), parts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--baseline", default=DEFAULT_BASELINE,
                        help=f"the earlier commit (default {DEFAULT_BASELINE}, the 0.2.0 release)")
    parser.add_argument("--repeats", type=int, default=3, help="rounds; the best is kept (3)")
    parser.add_argument("--only", nargs="+", choices=sorted(WORKLOADS), metavar="WORKLOAD",
                        help="run these workloads only: " + ", ".join(WORKLOADS))
    parser.add_argument("--limit", type=float, default=1.1,
                        help="exit 1 when a time or memory ratio passes it (1.1)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--out", type=Path, help="also write the JSON object to this file")
    opts = parser.parse_args(argv)
    if opts.repeats < 1:
        parser.error(f"--repeats must be >= 1, got {opts.repeats}")
    names = opts.only or list(WORKLOADS)

    with tempfile.TemporaryDirectory(prefix="mk-baseline-") as tmp:
        base = Path(tmp)
        commit = export(opts.baseline, base)
        trees = {"baseline": base, "working_tree": REPO}
        for tree in trees.values():
            check_imports(tree)
        both = set(comparisons(base))
        common = [name for name in comparisons(REPO) if name in both]
        best: dict[str, dict[str, dict[str, float]]] = {n: {} for n in names}
        missing: dict[str, str] = {}
        for round_ in range(opts.repeats):
            order = list(trees) if round_ % 2 == 0 else list(trees)[::-1]
            for name in names:
                for label in order:
                    if label == "baseline" and name in missing:
                        continue
                    status, seconds, gb, tail, parts = measure(trees[label], WORKLOADS[name],
                                                               ",".join(common))
                    if status == 2 and label == "baseline" and round_ == 0:
                        missing[name] = tail  # the baseline's parser refuses the command
                        continue
                    if status not in OK_STATUS.get(name, (0,)):
                        print(f"regressions.py: {name} failed on the {label} (exit {status}):\n"
                              f"{tail}", file=sys.stderr)
                        return 2
                    old = best[name].get(label)
                    best[name][label] = {
                        "seconds": seconds if old is None else min(old["seconds"], seconds),
                        "peak_gb": gb if old is None else min(old["peak_gb"], gb),
                        "parts": {key: (value if old is None or key not in old["parts"]
                                        else (min(value[0], old["parts"][key][0]), value[1]))
                                  for key, value in parts.items()},
                    }
                    if not opts.json:
                        print(f"  round {round_ + 1}: {name:16s} {label:12s} {seconds:8.2f} s "
                              f"{gb:6.2f} GB", file=sys.stderr, flush=True)

    rows, worst = [], 0.0
    for name in names:
        new, old = best[name]["working_tree"], best[name].get("baseline")
        row = {"workload": name, "command": " ".join(WORKLOADS[name]),
               "seconds": new["seconds"], "peak_gb": new["peak_gb"],
               "baseline_seconds": None, "baseline_peak_gb": None,
               "time_ratio": None, "memory_ratio": None}
        if old is not None:
            row.update(baseline_seconds=old["seconds"], baseline_peak_gb=old["peak_gb"],
                       time_ratio=new["seconds"] / old["seconds"],
                       memory_ratio=new["peak_gb"] / old["peak_gb"])
            judged = row["time_ratio"]
            if new["parts"]:  # reproduce: judge the comparisons whose outputs are the same
                same = [k for k in new["parts"] if k in old["parts"]
                        and new["parts"][k][1:] == old["parts"][k][1:]]
                row["comparisons"] = {
                    k: {"seconds": new["parts"][k][0], "baseline_seconds": old["parts"][k][0],
                        "same_outputs": k in same} for k in new["parts"] if k in old["parts"]}
                base_sum = sum(old["parts"][k][0] for k in same)
                if base_sum > 0:
                    judged = sum(new["parts"][k][0] for k in same) / base_sum
                    row["same_output_time_ratio"] = judged
                else:  # nothing comparable: judged on the whole run's time
                    row["same_output_time_ratio"] = None
            worst = max(worst, judged, row["memory_ratio"])
        else:
            row["baseline_refused"] = missing.get(name, "")
        rows.append(row)
    result = {"baseline": commit, "repeats": opts.repeats, "limit": opts.limit,
              "common_comparisons": common,
              "load_average": os.getloadavg(), "cores": os.cpu_count(), "workloads": rows,
              "passed": worst <= opts.limit}
    if opts.out is not None:
        opts.out.write_text(json.dumps(result, indent=1) + "\n")
    if opts.json:
        print(json.dumps(result))
    else:
        print(f"working tree against {commit[:10]}, best of {opts.repeats} "
              f"(load average now {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
        print(f"{'workload':16s} {'time s':>8s} {'base s':>8s} {'ratio':>6s} "
              f"{'peak GB':>8s} {'base GB':>8s} {'ratio':>6s}")
        for r in rows:
            if r["time_ratio"] is None:
                print(f"{r['workload']:16s} {r['seconds']:8.2f} {'-':>8s} {'-':>6s} "
                      f"{r['peak_gb']:8.2f} {'-':>8s} {'-':>6s}   (not in the baseline)")
            else:
                print(f"{r['workload']:16s} {r['seconds']:8.2f} {r['baseline_seconds']:8.2f} "
                      f"{r['time_ratio']:6.3f} {r['peak_gb']:8.2f} {r['baseline_peak_gb']:8.2f} "
                      f"{r['memory_ratio']:6.3f}")
                for key, part in r.get("comparisons", {}).items():
                    note = ("" if part["same_outputs"]
                            else "   (outputs or preset changed: not judged)")
                    print(f"  {key:14.14s} {part['seconds']:8.2f} {part['baseline_seconds']:8.2f} "
                          f"{part['seconds'] / part['baseline_seconds']:6.3f}{note}")
                if r.get("same_output_time_ratio") is not None:
                    print(f"  {'judged':14s} {'':17s} {r['same_output_time_ratio']:6.3f}   "
                          "(the comparisons with the same outputs)")
                elif "same_output_time_ratio" in r:
                    print("  no comparison has the same outputs: judged on the whole time")
        print("passed" if result["passed"] else f"FAILED: a ratio passes {opts.limit}")
    return 0 if result["passed"] else 1


if __name__ == "__main__":
    sys.exit(main())
