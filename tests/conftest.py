"""Fixtures shared by the test files; plain helpers live in ``helpers.py``.

* ``comparison(name)``: the comparison ``maxwell_kinetics.app.comparisons.<name>`` at the small
  size, computed once per test session and shared by every test that reads it (the comparison tests
  and the notebooks);
* the persistent compilation cache is off during the tests (its own tests turn it on).
"""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def comparison():
    """``comparison(name)`` → ``maxwell_kinetics.app.comparisons.<name>("small", progress=False)``,
    computed on first use and kept for the session (the comparisons share one runner, as in
    ``reproduce``)."""
    from maxwell_kinetics.app import comparisons

    done = {}
    runner = comparisons.ParticleRuns()  # one runner: comparisons share their particle runs

    def get(name: str):
        if name not in done:
            done[name] = getattr(comparisons, name)("small", progress=False, runner=runner)
        return done[name]

    return get


@pytest.fixture
def fresh_interpreter_code():
    """Run Python code in a fresh interpreter and return its stdout (for import-time checks)."""
    import subprocess
    import sys

    def run(code: str) -> str:
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              check=True)
        return done.stdout

    return run


@pytest.fixture(scope="session", autouse=True)
def _compile_cache_off():
    """The command line turns the persistent compilation cache on by default.  During the tests
    it is off (``MAXWELL_KINETICS_CACHE=off``): the user's own cache is never touched, and a
    command run in-process reuses what the library calls of the same session compiled (the
    cache's executables are compiled apart from ``jax.jit``'s, so with it on every command would
    compile again).  The cache's own tests turn it on in folders of their own."""
    import os

    from maxwell_kinetics.compile_cache import ENV

    before = os.environ.get(ENV)
    os.environ[ENV] = "off"
    yield
    if before is None:
        os.environ.pop(ENV, None)
    else:
        os.environ[ENV] = before
