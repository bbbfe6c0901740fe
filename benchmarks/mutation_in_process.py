"""Mutation run in one process over mutmut's ``mutants/`` copy (cwd = ``mutants/``, made by
``mutation_generate.py``): mutmut's trampolines read ``MUTANT_UNDER_TEST`` at every call, so
one Python process can switch from mutant to mutant between ``pytest.main`` calls, without a
fork or a fresh import per mutant.  Sound only where nothing computed under one mutant outlives
it: ``--cache-clear`` empties the module's function-level caches (``f.__dict__`` entries and
``lru_cache``s, and the sticky comparison's table) before every run, ``--jax-clear`` JAX's
compilation caches; survivors are then rerun in a fresh interpreter each
(``mutation_fresh.py``).

    python mutation_in_process.py MODULE OUT [--only GLOB,GLOB] [--cache-clear] [--jax-clear] \
        -- TEST_FILES

1. stats: every selected test runs once with MUTANT_UNDER_TEST=stats (the module's caches cleared
   before each test), recording which mutated functions it reaches and how long it takes;
2. control: the same tests, no mutant: must pass;
3. each mutant: the tests that reach its function, fastest first, -x, caches cleared before
   (when --cache-clear), a SIGALRM limit (RECHECK_LIMIT s, default 120) counted as a timeout.
Results: OUT (tab-separated: name, status, seconds), resumable.
"""
import contextlib
import fnmatch
import importlib
import io
import json
import os
import signal
import sys
import time

import pytest

sys.path.insert(0, os.getcwd())  # the mutated copy, before the installed packages

argv = sys.argv[1:]
sep = argv.index("--")
opts, test_args = argv[:sep], argv[sep + 1:]
module_name, out = opts[0], opts[1]
only = opts[opts.index("--only") + 1] if "--only" in opts else "*"
cache_clear = "--cache-clear" in opts
jax_clear = "--jax-clear" in opts
limit = int(os.environ.get("RECHECK_LIMIT", "120"))

mod = importlib.import_module(module_name)
assert mod.__file__.startswith(os.getcwd()), mod.__file__
from mutmut.state import state  # noqa: E402 (after the path is set)

meta = json.load(open(module_name.replace(".", "/") + ".py.meta"))
names = [n for n in meta["exit_code_by_key"]
         if any(fnmatch.fnmatch(n, g) for g in only.split(","))]


def clear_caches():
    if jax_clear:
        import jax
        jax.clear_caches()
    if not cache_clear:
        return
    for obj in list(vars(mod).values()):
        if callable(obj) and hasattr(obj, "cache_clear"):
            obj.cache_clear()
        d = getattr(obj, "__dict__", None)
        if callable(obj) and isinstance(d, dict):
            for k in [k for k in d if not (isinstance(k, str) and k.startswith("__"))]:
                del d[k]
    sc = sys.modules.get("particles.sticky_comparison")
    if sc is not None:
        sc._EXACT_CACHE.clear()


class Stats:
    def __init__(self):
        self.hits, self.dur = {}, {}
    def pytest_runtest_setup(self, item):
        clear_caches()
        state()._stats.clear()
    def pytest_runtest_teardown(self, item):
        self.hits[item.nodeid] = sorted(state()._stats)
    def pytest_runtest_logreport(self, report):
        self.dur[report.nodeid] = self.dur.get(report.nodeid, 0.0) + report.duration


class Clear:
    def pytest_sessionstart(self, session):
        clear_caches()


def run(args, plugins=()):
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = pytest.main(["-q", "-p", "no:cacheprovider", *args], plugins=list(plugins))
    return int(rc), buf.getvalue()


stats_file = os.environ.get("STATS", out + ".stats.json")
if os.path.exists(stats_file):
    s = json.load(open(stats_file))
    hits, dur = s["hits"], s["dur"]
else:
    os.environ["MUTANT_UNDER_TEST"] = "stats"
    st = Stats()
    t0 = time.time()
    rc, text = run(test_args, [st])
    print(f"stats rc={rc} in {time.time() - t0:.0f} s, {len(st.hits)} tests", flush=True)
    if rc != 0:
        print(text[-3000:])
        sys.exit(1)
    hits, dur = st.hits, st.dur
    json.dump({"hits": hits, "dur": dur}, open(stats_file, "w"))

os.environ["MUTANT_UNDER_TEST"] = ""
t0 = time.time()
rc, text = run(test_args, [Clear()])
print(f"control rc={rc} in {time.time() - t0:.0f} s", flush=True)
if rc != 0:
    print(text[-3000:])
    sys.exit(1)

done = set()
if os.path.exists(out):
    done = {l.split("\t")[0] for l in open(out)}


def _alarm(*_):
    raise TimeoutError("mutant ran past the limit")


signal.signal(signal.SIGALRM, _alarm)
with open(out, "a") as fh:
    for name in names:
        if name in done:
            continue
        func = name.partition("__mutmut_")[0]
        tests = sorted((t for t, h in hits.items() if func in h), key=lambda t: dur.get(t, 0))
        if not tests:
            fh.write(f"{name}\tno tests\t0\n")
            fh.flush()
            continue
        os.environ["MUTANT_UNDER_TEST"] = name
        t0 = time.time()
        signal.alarm(limit)
        try:
            rc, text = run(["-x", *tests], [Clear()])
            status = {0: "survived", 1: "killed"}.get(rc, f"rc{rc}")
            if "TimeoutError: mutant ran past the limit" in text:
                status = "timeout"
        except TimeoutError:
            status = "timeout"
        finally:
            signal.alarm(0)
        os.environ["MUTANT_UNDER_TEST"] = ""
        fh.write(f"{name}\t{status}\t{time.time() - t0:.1f}\n")
        fh.flush()
print("done", flush=True)
