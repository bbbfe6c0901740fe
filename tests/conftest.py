"""Fixtures shared by the test files; plain helpers live in ``helpers.py``.

* ``comparison(name)``: the comparison ``maxwell_kinetics.app.comparisons.<name>`` at the small
  size, computed once per test session and shared by every test that reads it (the comparison
  tests);
* the persistent compilation cache is off during the tests (its own tests turn it on);
* under pytest-xdist (``make test`` runs ``-n auto``) the tests are dealt to the workers by
  file (module-scoped fixtures such as a built site, executed notebooks or a solved problem
  are computed once), and every file that reads the session's ``comparison`` fixture goes to
  one worker together (the comparisons are computed once per run, as in a plain run), and so
  do the files that solve with the same compiled d = 2, 3 scheme (:data:`SHARED_COMPILATIONS`):
  :func:`pytest_xdist_make_scheduler`.
"""

from __future__ import annotations

import pytest

#: The work unit of the test files that read the session-scoped ``comparison`` fixture.
COMPARISONS_GROUP = "comparisons"

#: Test files that solve with the same static scheme of the d = 2, 3 solver (the compilation,
#: 10-25 s each, is the bulk of their time; r and the output times are data and do not
#: compile again): each group is one work unit, so one worker compiles each scheme once
#: instead of each worker compiling it for its file.  The names are the units' names.
SHARED_COMPILATIONS = {
    # d = 2 and 3, "uniform", default grid, 16 η nodes (kurtosis, speed density, the CLI)
    "tests/test_maxwell_kinetics/test_moments.py": "kinetic default grid, d = 2 and 3",
    "tests/test_maxwell_kinetics/test_speed_density.py": "kinetic default grid, d = 2 and 3",
    # d = 2, "hard", coarse grid, 16 η nodes (the default η rule, the CLI's solve)
    "tests/test_maxwell_kinetics/test_solver_isotropic.py": "kinetic coarse grid, d = 2 hard",
    "tests/test_maxwell_kinetics/commands/test_tails_steady_cli.py":
        "kinetic coarse grid, d = 2 hard",
    # d = 2, "uniform", coarse grid, 8 η nodes, "accurate" rule (the tails' fits, a record)
    "tests/test_maxwell_kinetics/test_scaling_tails.py": "kinetic coarse grid, d = 2 accurate",
    "tests/test_maxwell_kinetics/test_solution_drift.py": "kinetic coarse grid, d = 2 accurate",
}


def comparison_files(root) -> set[str]:
    """The test files (paths relative to ``root``, as in node ids) with a test or fixture
    that takes the ``comparison`` fixture: read from their source, since the scheduler of
    pytest-xdist sees node ids only."""
    import ast
    from pathlib import Path

    found = set()
    for path in Path(root, "tests").rglob("test_*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and any(
                    a.arg == "comparison" for a in node.args.args):
                found.add(path.relative_to(root).as_posix())
                break
    return found


def pytest_xdist_make_scheduler(config, log):
    """Deal the tests to the xdist workers by file, the files that read the ``comparison``
    fixture as one unit and each group of :data:`SHARED_COMPILATIONS` as one unit (xdist's own
    ``loadgroup`` relies on a suffix of the node id that pytest 9 no longer carries from its
    hook, so the units are made here)."""
    if config.getvalue("dist") not in ("loadfile", "loadgroup"):
        return None  # another mode asked for by name: xdist's own
    from xdist.scheduler import LoadScopeScheduling

    shared = comparison_files(config.rootpath)

    class ByFile(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            path = nodeid.split("::", 1)[0]
            if path in shared:
                return COMPARISONS_GROUP
            return SHARED_COMPILATIONS.get(path, path)

    return ByFile(config, log)


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
