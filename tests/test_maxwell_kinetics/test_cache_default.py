"""The library uses the project's store of compiled executables by default, like the command
line, with ``MAXWELL_KINETICS_CACHE=off`` the one opt-out, and changes no JAX setting."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow  # four fresh processes that start JAX and solve (~10 s each)

_SOLVE = """
import json, sys
import jax
from maxwell_kinetics import _kinetic_scheme, compile_cache
from maxwell_kinetics.solver import solve
if sys.argv[1] == "disable":
    compile_cache.disable()
before = jax.config.jax_compilation_cache_dir
solve(0.5, "gaussian", tau=(1.0, 3.0), resolution="coarse", progress=False)
print(json.dumps({"traces": dict(_kinetic_scheme.TRACES),
                  "folder": str(compile_cache.active_path()),
                  "jax_cache_unchanged": jax.config.jax_compilation_cache_dir == before}))
"""


def _run(cache, mode="default") -> dict:
    env = dict(os.environ)
    env["MAXWELL_KINETICS_CACHE"] = str(cache)
    done = subprocess.run([sys.executable, "-c", _SOLVE, mode], env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _entries(folder):
    return sorted(p.name for p in folder.rglob("*") if p.is_file())


def test_a_plain_solve_fills_the_store_and_the_next_process_loads_it(tmp_path):
    cache = tmp_path / "cache"
    cold = _run(cache)  # no compile_cache.enable() anywhere
    assert cold["folder"].startswith(str(cache)) and cold["jax_cache_unchanged"]
    assert sum(cold["traces"].values()) > 0 and _entries(cache)
    warm = _run(cache)
    assert sum(warm["traces"].values()) == 0, warm  # loaded: nothing traced or compiled
    assert warm["jax_cache_unchanged"]


def test_the_variable_off_and_disable_keep_the_store_untouched(tmp_path):
    off = _run("off")
    assert off["folder"] == "None" and sum(off["traces"].values()) > 0
    cache = tmp_path / "cache"
    disabled = _run(cache, "disable")
    assert disabled["folder"] == "None" and not cache.exists()
