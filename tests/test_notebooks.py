"""The notebooks in notebooks/: stored without outputs, and their code runs at the small size.

Each notebook calls one comparison of ``maxwell_kinetics.app.comparisons`` and then draws and prints
from its result.  The comparison itself is computed once per test session (the ``comparison``
fixture, shared with the comparison tests): here each notebook's code runs in this process with
that comparison's function answering from the session's result, so everything the notebook does
after the call runs for real against the real result.  Every notebook also runs end to end in a
plain Jupyter kernel (no backend or display hook set for it), and each of its figure cells must
show an image there.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
#: ``comparisons.NAME(comparisons.default_size())``: the one call each notebook makes.
CALL = re.compile(r"comparisons\.(\w+)\(comparisons\.default_size\(\)\)")

#: The notebooks of the paper's figures, one comparison each; the others are tutorials.
PAPER = [p for p in NOTEBOOKS if CALL.search(p.read_text())]
#: The tutorials, built on the public API step by step.
TUTORIALS = [p for p in NOTEBOOKS if p not in PAPER]

pytestmark = pytest.mark.slow


def _code(path) -> str:
    import nbformat

    nb = nbformat.read(path, as_version=4)
    return "\n".join(cell.source for cell in nb.cells if cell.cell_type == "code")


def test_notebooks_are_stored_without_outputs():
    import nbformat

    for path in NOTEBOOKS:
        nb = nbformat.read(path, as_version=4)
        for cell in nb.cells:
            if cell.cell_type == "code":
                assert not cell.outputs and cell.execution_count is None, path.name


@pytest.mark.parametrize("path", PAPER, ids=[p.stem for p in PAPER])
def test_notebook_code_runs_on_its_comparison(path, comparison, monkeypatch):
    import matplotlib.pyplot as plt

    from maxwell_kinetics.app import comparisons

    code = _code(path)
    names = CALL.findall(code)
    assert len(names) == 1 and names[0] in comparisons.__all__, names
    result = comparison(names[0])  # before the function is replaced
    monkeypatch.setenv("MAXWELL_KINETICS_SMALL", "1")
    calls = []

    def from_the_session(size, *args, **kwargs):
        calls.append(size)
        return result

    monkeypatch.setattr(comparisons, names[0], from_the_session)
    exec(compile(code, str(path), "exec"), {"__name__": "__notebook__"})  # noqa: S102
    assert calls == ["small"]  # default_size() honours the small-size switch
    plt.close("all")


def _is_figure_cell(cell) -> bool:
    """A code cell whose last line shows a figure: an expression ending in ``.figure()``,
    ``figure(...)`` or ``fig`` (a cell that ends in ``;`` shows nothing and is no figure cell)."""
    lines = [line for line in cell.source.strip().splitlines() if line.strip()]
    last = lines[-1].strip() if lines else ""
    return bool(re.search(r"(\bfig\b|figure\(.*\)|\bplot_\w+\(.*\))$", last))


def execute(path, timeout=600, compile_store=None):
    """Run ``path`` headless in a fresh Jupyter kernel as plain Jupyter would (no backend and no
    display hook set for it) at the small size, the checkout on the path; the executed notebook.
    ``compile_store``: the folder of the project's compile store for the kernel (a user's
    default is a store of their own; None: the tests' setting, off).
    """
    import nbformat
    from nbclient import NotebookClient

    env = dict(os.environ)
    if compile_store is not None:
        env["MAXWELL_KINETICS_CACHE"] = str(compile_store)
    env.pop("MPLBACKEND", None)
    env["MAXWELL_KINETICS_SMALL"] = "1"
    paths = [str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    env["PYTHONPATH"] = os.pathsep.join(paths)
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(nb, timeout=timeout, kernel_name="python3", resources={
        "metadata": {"path": str(path.parent)}})
    client.km = client.create_kernel_manager()
    with client.setup_kernel(env=env):
        for index, cell in enumerate(nb.cells):
            client.execute_cell(cell, index)
    return nb


#: Run by a separate Python process per notebook (``execute`` there, the executed notebook
#: written to a file), so that several kernels run at once.
_RUNNER = """
import sys
from pathlib import Path

import nbformat

sys.path.insert(0, sys.argv[1])
from test_notebooks import execute

nbformat.write(execute(Path(sys.argv[2]), compile_store=sys.argv[4]), sys.argv[3])
"""


@pytest.fixture(scope="module")
def executed_notebooks(tmp_path_factory):
    """Every notebook executed headless (``execute``), as many at once as there are cores (at
    most 4; each kernel computes on one core for most of its run, so on 2 cores this halves the
    wall time of the whole set): ``{path: (returncode, executed file, log)}``.  The kernels
    share one compile store in a folder of this run (as a user's kernels share theirs), so a
    solver compiled by one notebook is loaded by the next."""
    import subprocess
    import sys
    from concurrent.futures import ThreadPoolExecutor

    folder = tmp_path_factory.mktemp("executed_notebooks")
    store = tmp_path_factory.mktemp("compile_store")

    def run(path):
        out, log = folder / path.name, folder / f"{path.stem}.log"
        with open(log, "w") as f:
            try:
                rc = subprocess.run([sys.executable, "-c", _RUNNER, str(Path(__file__).parent),
                                     str(path), str(out), str(store)], stdout=f,
                                    stderr=subprocess.STDOUT, timeout=900).returncode
            except subprocess.TimeoutExpired:
                rc = "timeout (900 s)"
        return path, (rc, out, log)

    workers = max(1, min(4, os.cpu_count() or 1))
    with ThreadPoolExecutor(max_workers=workers) as pool:
        return dict(pool.map(run, NOTEBOOKS))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_headless_with_its_figures_inline(path, executed_notebooks):
    """Executed headless in a plain kernel, each figure cell holds a PNG and no cell prints an
    error or anything on stderr (no progress lines: the default progress shows nothing where no
    bar can be drawn)."""
    import nbformat

    rc, out, log = executed_notebooks[path]
    assert rc == 0, f"{path.name} did not run ({rc}):\n{log.read_text()[-3000:]}"
    nb = nbformat.read(out, as_version=4)
    code = [cell for cell in nb.cells if cell.cell_type == "code"]
    figure_cells = [cell for cell in code if _is_figure_cell(cell)]
    assert figure_cells, f"{path.name} has no figure cell"
    for cell in figure_cells:
        images = [o for o in cell.outputs if "image/png" in o.get("data", {})]
        assert len(images) >= 1, (path.name, cell.source)
    for cell in code:
        for output in cell.outputs:
            assert output["output_type"] != "error", (path.name, cell.source)
            assert output.get("name") != "stderr", (path.name, output.get("text", "")[:500])
            if path in TUTORIALS:  # a tutorial prints no more than ~40 lines at once
                text = output.get("text", "") or output.get("data", {}).get("text/plain", "")
                assert text.count("\n") <= 40, (path.name, text[:300])
