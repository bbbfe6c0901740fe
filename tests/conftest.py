"""Fixtures shared by the test files; plain helpers live in ``helpers.py``.

* ``comparison(name)``: the comparison ``maxwell_kinetics.app.comparisons.<name>`` at the small
  size, computed once per test session and shared by every test that reads it (the comparison tests
  and the notebooks);
* the persistent compilation cache is off during the tests (its own tests turn it on);
* under pytest-xdist (``make test`` runs ``-n auto --dist loadgroup``) each test file goes to
  one worker as a whole (its module-scoped fixtures are computed once), and every test that
  reads the session's ``comparison`` fixture goes to one worker together (the comparisons are
  computed once per run, as in a plain run): :func:`pytest_itemcollected`.
"""

from __future__ import annotations

import pytest

#: The xdist group of the tests that read the session-scoped ``comparison`` fixture.
COMPARISONS_GROUP = "comparisons"


def pytest_itemcollected(item):
    """Give each test an ``xdist_group``: ``comparisons`` for the tests that read the
    ``comparison`` fixture (computed once per worker, so all of them share one worker), else
    its file (module-scoped fixtures such as a built site, executed notebooks or a solved
    problem are computed once).  With ``--dist loadgroup`` a group runs on one worker; without
    xdist the marks do nothing.  Done as each test is collected: xdist reads the marks in its
    own ``pytest_collection_modifyitems``, which runs before a conftest's."""
    if "comparison" in getattr(item, "fixturenames", ()):
        group = COMPARISONS_GROUP
    else:
        group = item.nodeid.split("::", 1)[0]
    item.add_marker(pytest.mark.xdist_group(group))


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
