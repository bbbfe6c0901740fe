"""The velocity-space (hard-rod) solver in the project's store of compiled executables
(:mod:`maxwell_kinetics.compile_cache`, :mod:`maxwell_kinetics._boltzmann_compiled`).

Fresh processes are the point of the store, so the checks run a small solve and a small scaling
state (61 points on ±6) in subprocesses: one with the store off (the reference), one with an
empty store (it traces and fills it), one with the filled store (it loads, traces nothing and
never imports diffrax).  Whether a process traced is read from ``_boltzmann_compiled.TRACES``.
The processes pin the hash of the sources in the key, so that an edit of the shared tree between
them cannot turn the warm process cold.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # fresh processes that start JAX and solve (a few seconds each)

_SOLVE = """
import hashlib, json, sys
import numpy as np
from maxwell_kinetics import _boltzmann_compiled, compile_cache
from maxwell_kinetics.inelastic_boltzmann import scaling_state, solve_boltzmann
from maxwell_kinetics.velocity_grid import VelocityGrid

def digest(x):
    return hashlib.sha256(np.ascontiguousarray(x).tobytes()).hexdigest()

# the sources' hash pinned: an edit of any source between the processes (another engineer's,
# in a shared tree) would otherwise change the keys (its effect is test_compile_cache's)
compile_cache._code_fingerprint = lambda: "the sources of this test"
folder = compile_cache.disable() if sys.argv[1] == "off" else compile_cache.enable(sys.argv[1])
grid = VelocityGrid(61, 6.0)
sol = solve_boltzmann(0.5, [0.0, 0.5, 2.0], grid=grid)
state = scaling_state(0.5, grid=grid, relaxation=3.0)
print(json.dumps({"folder": str(folder), "traces": dict(_boltzmann_compiled.TRACES),
                  "diffrax": "diffrax" in sys.modules, "steps": sol.steps,
                  "F": digest(sol.F), "energy": digest(sol.energy),
                  "energy_rate": digest(sol.energy_rate), "state": digest(state.F),
                  "iterations": state.iterations}))
"""

_ALL = {"solve": 1, "rates": 1, "steady": 1, "jacobian": 1}


def _start(mode: str, env: dict | None = None) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", _SOLVE, mode], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)


def _finish(proc: subprocess.Popen, timeout: float = 300) -> dict:
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise
    assert proc.returncode == 0, err
    assert err == "", err
    return json.loads(out)


def _entries(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.glob("*.entry"))}


def _numbers(report: dict) -> dict:
    return {k: report[k] for k in ("steps", "F", "energy", "energy_rate", "state",
                                   "iterations")}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The reports of a process without the store and of one with an empty store (run side
    by side), then of one with the store that the second filled: (off, cold, warm, folder,
    entries after the cold process)."""
    root = tmp_path_factory.mktemp("hard-rods") / "store"
    procs = [_start("off"), _start(str(root))]
    try:
        off, cold = (_finish(proc) for proc in procs)
    finally:
        for proc in procs:  # the other one, when one failed
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
    folder = Path(cold["folder"])
    filled = _entries(folder)
    warm = _finish(_start(str(root)))
    return off, cold, warm, folder, filled


def test_a_fresh_process_fills_the_store_with_the_four_functions(runs):
    off, cold, _, folder, filled = runs
    assert off["traces"] == _ALL and off["folder"] == "None"
    assert cold["traces"] == _ALL
    assert {name.split("-")[0] for name in filled} == {
        "aot_boltzmann_solve", "aot_boltzmann_rates", "aot_boltzmann_steady",
        "aot_boltzmann_jacobian"}
    assert folder.is_dir() and len(filled) == 4


def test_the_next_process_loads_them_and_traces_nothing(runs):
    _, _, warm, folder, filled = runs
    assert warm["traces"] == {}  # loaded: nothing traced, nothing compiled
    assert warm["diffrax"] is False  # not even imported
    assert _entries(folder) == filled  # nothing added or rewritten


def test_the_numbers_are_those_of_the_solve_without_the_store_bit_for_bit(runs):
    off, cold, warm, _, _ = runs
    assert _numbers(cold) == _numbers(off)
    assert _numbers(warm) == _numbers(off)
    assert off["iterations"] >= 1  # Newton ran: the Jacobian and the residual were used


def test_the_store_stays_off_under_maxwell_kinetics_cache_off(tmp_path):
    # the library's default (the store on) under MAXWELL_KINETICS_CACHE=off: no folder in use
    env = dict(os.environ, MAXWELL_KINETICS_CACHE="off", XDG_CACHE_HOME=str(tmp_path))
    script = ("import json; from maxwell_kinetics import compile_cache; "
              "from maxwell_kinetics.inelastic_boltzmann import solve_boltzmann; "
              "from maxwell_kinetics.velocity_grid import VelocityGrid; "
              "solve_boltzmann(0.5, [0.5], grid=VelocityGrid(61, 6.0)); "
              "print(json.dumps(str(compile_cache.active_path())))")
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout) == "None"
    assert not list(tmp_path.rglob("*.entry"))


def test_the_command_line_no_cache_keeps_the_store_empty(tmp_path):
    root = tmp_path / "store"
    env = dict(os.environ, MAXWELL_KINETICS_CACHE=str(root))
    cli = ("import sys; from maxwell_kinetics.app.cli import main; sys.exit(main(["
           "'solve', '--rate', 'relative_velocity', '--restitution', '0.5', '--t', '0.5', "
           "'--points', '61', '--half-width', '6', '--json', '--no-progress', '--no-cache']))")
    done = subprocess.run([sys.executable, "-c", cli], env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["t"] == [0.5]
    assert not list(root.rglob("*.entry"))
