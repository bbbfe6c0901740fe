"""The notebooks in notebooks/: their layout, stored without outputs, and each run headless at the
small size.

Layout: ``NN_name.ipynb``, numbered from 01 without gaps, the tutorials first (:data:`TUTORIALS`),
then the paper's figures.  The first cell is markdown: the title, numbered as the file, and the
measured run time of the default size with the load of the machine.  The first code cell holds
the parameters (upper-case names) and is the only cell that reads ``MAXWELL_KINETICS_SMALL``:
``SMALL`` is set from it, and the parameters differ between the two sizes.  That cell is run here
in this process under both settings (cheap: it only assigns values).

Every notebook also runs end to end in a fresh plain Jupyter kernel (no backend or display hook
set for it) at the small size, as a user's ``MAXWELL_KINETICS_SMALL=1 jupyter nbconvert
--execute`` would; each of its figure cells must show a PNG, no cell may show an error or write
to stderr, no output may hold more than 40 lines, and no cell may show more than one progress
bar.  The kernels run as many at once as there are cores (at most 4) and share one compile store
of the run, as a user's kernels share theirs.  The physics the notebooks show is not judged here
(the comparisons' own tests judge it); at the small size their runs are tiny.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
#: The tutorials, built on the public API step by step; they lead, numbered 01-04.
TUTORIALS = [p for p in NOTEBOOKS if p.stem in ("01_solve_master_equation",
                                                 "02_exact_scaling_solution",
                                                 "03_kinetic_vs_particles",
                                                 "04_rate_vs_correlations")]
SWITCH = "MAXWELL_KINETICS_SMALL"
#: The longest output a notebook may print at once, in lines.
MAX_OUTPUT_LINES = 40
#: A progress bar in an executed notebook: tqdm's notebook widget.
WIDGET = "application/vnd.jupyter.widget-view+json"

pytestmark = pytest.mark.slow


def _read(path):
    import nbformat

    return nbformat.read(path, as_version=4)


def _code_cells(path) -> list:
    return [cell for cell in _read(path).cells if cell.cell_type == "code"]


def test_notebooks_are_stored_without_outputs():
    for path in NOTEBOOKS:
        for cell in _code_cells(path):
            assert not cell.outputs and cell.execution_count is None, path.name


def test_notebooks_are_numbered_with_the_tutorials_first():
    assert len(TUTORIALS) == 4
    numbers = [int(re.fullmatch(r"(\d\d)_[a-z0-9_]+", p.stem).group(1)) for p in NOTEBOOKS]
    assert numbers == list(range(1, len(NOTEBOOKS) + 1)), [p.name for p in NOTEBOOKS]
    assert NOTEBOOKS[: len(TUTORIALS)] == TUTORIALS
    for number, path in zip(numbers, NOTEBOOKS, strict=True):
        first = _read(path).cells[0]
        assert first.cell_type == "markdown", path.name
        assert first.source.startswith(f"# {number}. "), (path.name, first.source[:60])


def test_first_cell_states_the_run_time_of_the_default_size():
    for path in NOTEBOOKS:
        text = " ".join(_read(path).cells[0].source.split())
        assert re.search(r"default size[^.]*?\d+(\.\d+)? ?(s|min)\b", text), path.name
        assert re.search(r"load average \d", text), path.name
        assert SWITCH in text, path.name


def _parameters(path, monkeypatch, small: bool) -> dict:
    """The upper-case names of ``path``'s first code cell, run with the switch on or off."""
    if small:
        monkeypatch.setenv(SWITCH, "1")
    else:
        monkeypatch.delenv(SWITCH, raising=False)
    names: dict = {}
    exec(compile(_code_cells(path)[0].source, str(path), "exec"), names)  # noqa: S102
    return {k: v for k, v in names.items() if k.isupper()}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_parameters_lead_and_honour_the_small_size_switch(path, monkeypatch):
    """The first code cell alone reads the switch and sets every size; the small size changes
    some of them.  No comparison is called by its size and nothing is dumped as JSON: the
    notebooks do the physics in front of the reader."""
    cells = _code_cells(path)
    assert SWITCH in cells[0].source, path.name
    for cell in cells[1:]:
        assert SWITCH not in cell.source and "SMALL =" not in cell.source, (path.name, cell.source)
    code = "\n".join(cell.source for cell in cells)
    assert "default_size(" not in code and "json.dumps" not in code, path.name
    small, default = (_parameters(path, monkeypatch, s) for s in (True, False))
    assert small["SMALL"] is True and default["SMALL"] is False, path.name
    assert small.keys() == default.keys(), path.name
    changed = [k for k in small if k != "SMALL" and repr(small[k]) != repr(default[k])]
    assert changed, f"{path.name}: no parameter depends on {SWITCH}"


#: The functions of the API that draw a progress bar unless told not to (``progress=None``, their
#: default, shows one per call in a notebook).
PROGRESS_CALLS = {"simulate", "solve", "solve_fourier", "lattice_at_energy", "lattice_runs",
                  "md_runs", "sticky_runs", "ulam_snapshots", "run_ensemble",
                  "sample_cooling_state"}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_every_call_that_draws_progress_says_whether_to(path):
    """A notebook shows one progress bar per call or none: each call of a function that draws
    one passes ``progress`` (the notebooks pass False; a kernel without ipywidgets would not
    show the bars that the headless run below counts)."""
    import ast

    for cell in _code_cells(path):
        for node in ast.walk(ast.parse(cell.source)):
            if not isinstance(node, ast.Call):
                continue
            name = getattr(node.func, "id", None) or getattr(node.func, "attr", None)
            if name in PROGRESS_CALLS:
                assert any(k.arg == "progress" for k in node.keywords), (
                    path.name, ast.unparse(node)[:120])


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
    env[SWITCH] = "1"
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
    most 4; each kernel computes on one core for most of its run):
    ``{path: (returncode, executed file, log, seconds)}``.  The kernels
    share one compile store in a folder of this run (as a user's kernels share theirs), so a
    solver compiled by one notebook is loaded by the next."""
    import subprocess
    import sys
    import time
    from concurrent.futures import ThreadPoolExecutor

    folder = tmp_path_factory.mktemp("executed_notebooks")
    store = tmp_path_factory.mktemp("compile_store")

    def run(path):
        out, log = folder / path.name, folder / f"{path.stem}.log"
        start = time.perf_counter()
        with open(log, "w") as f:
            try:
                rc = subprocess.run([sys.executable, "-c", _RUNNER, str(Path(__file__).parent),
                                     str(path), str(out), str(store)], stdout=f,
                                    stderr=subprocess.STDOUT, timeout=900).returncode
            except subprocess.TimeoutExpired:
                rc = "timeout (900 s)"
        return path, (rc, out, log, time.perf_counter() - start)

    workers = max(1, min(4, os.cpu_count() or 1))
    with ThreadPoolExecutor(max_workers=workers) as pool:
        return dict(pool.map(run, NOTEBOOKS))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs_headless_with_its_figures_inline(path, executed_notebooks):
    """Executed headless in a plain kernel at the small size, each figure cell holds a PNG, no
    cell shows an error or writes to stderr, no output holds more than 40 lines, and no cell
    shows more than one progress bar."""
    rc, out, log, seconds = executed_notebooks[path]
    assert rc == 0, f"{path.name} did not run ({rc}, {seconds:.0f} s):\n{log.read_text()[-3000:]}"
    code = [cell for cell in _read(out).cells if cell.cell_type == "code"]
    figure_cells = [cell for cell in code if _is_figure_cell(cell)]
    assert figure_cells, f"{path.name} has no figure cell"
    for cell in figure_cells:
        images = [o for o in cell.outputs if "image/png" in o.get("data", {})]
        assert len(images) >= 1, (path.name, cell.source)
    for cell in code:
        bars = [o for o in cell.outputs if WIDGET in o.get("data", {})]
        assert len(bars) <= 1, (path.name, len(bars), cell.source)
        for output in cell.outputs:
            assert output["output_type"] != "error", (path.name, cell.source)
            assert output.get("name") != "stderr", (path.name, output.get("text", "")[:500])
            text = output.get("text", "") or output.get("data", {}).get("text/plain", "")
            assert text.count("\n") <= MAX_OUTPUT_LINES, (path.name, text[:300])
