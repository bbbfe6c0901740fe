"""Rerun the survivors of ``mutation_in_process.py`` in a fresh interpreter each (cwd =
``mutants/``): nothing computed under one mutant (caches, JAX compilations) can reach another.
The tests are those the stats run found reaching the mutated function, plus ``EXTRA``
(space-separated test ids written after the stats run).

    EXTRA="tests/...::test_new" python mutation_fresh.py STATS_JSON TSV OUT

With ``ONLY_EXTRA=1`` only the ``EXTRA`` tests run (the survivors already passed the others).
"""
import json
import os
import subprocess
import sys
import time

stats, tsv, out = sys.argv[1:4]
s = json.load(open(stats))
hits, dur = s["hits"], s["dur"]
done = set()
if os.path.exists(out):
    done = {l.split("\t")[0] for l in open(out)}
rows = [l.rstrip("\n").split("\t") for l in open(tsv)]
with open(out, "a") as fh:
    for name, status, _ in rows:
        if status != "survived" or name in done:
            continue
        func = name.partition("__mutmut_")[0]
        tests = sorted((t for t, h in hits.items() if func in h), key=lambda t: dur.get(t, 0))
        tests = os.environ.get("EXTRA", "").split() + tests  # tests written after the stats run
        if os.environ.get("ONLY_EXTRA"):  # survivors of the stats tests: the new tests alone
            tests = os.environ["EXTRA"].split()
        # parametrised ids can change with the tests' arguments: run the whole test function
        tests = list(dict.fromkeys(t.split("[")[0] for t in tests))
        env = dict(os.environ, MUTANT_UNDER_TEST=name, PYTHONPATH=os.getcwd())
        t0 = time.time()
        try:
            rc = subprocess.run([sys.executable, "-m", "pytest", "-x", "-q", "-p",
                                 "no:cacheprovider", *tests],
                                env=env, capture_output=True, timeout=600).returncode
            st = {0: "survived", 1: "killed"}.get(rc, f"rc{rc}")
        except subprocess.TimeoutExpired:
            st = "timeout"
        fh.write(f"{name}\t{st}\t{time.time() - t0:.1f}\n")
        fh.flush()
