"""The notebooks in notebooks/: stored without outputs, and their code runs at the small size.

Each notebook calls one comparison of ``maxwell_kinetics.app.comparisons`` and then draws and prints
from its result.  The comparison itself is computed once per test session (the ``comparison``
fixture, shared with the comparison tests): here each notebook's code runs in this process with
that comparison's function answering from the session's result, so everything the notebook does
after the call runs for real against the real result.  Every notebook also runs end to end in a
plain Jupyter kernel, each figure cell showing an image there: ``test_notebooks_headless.py``.
"""

from __future__ import annotations

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
