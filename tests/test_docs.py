"""The documentation: the site builds with warnings as errors, the API reference lists every
public name, and the code of the README and of the getting-started page runs."""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
def _faces() -> list[str]:
    """The package faces the API reference is built from (``apigen_faces`` of docs/conf.py)."""
    import ast

    tree = ast.parse((DOCS / "conf.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "apigen_faces":
            return ast.literal_eval(node.value)
    raise AssertionError("docs/conf.py has no apigen_faces")


FACES = _faces()


@pytest.fixture(scope="module")
def built_site(tmp_path_factory):
    """The site built with -W (warnings are errors) and -n (nitpicky: every cross-reference to
    the project's names must resolve); the notebooks are not executed here (``make docs`` runs
    them).  About 10 s."""
    out = tmp_path_factory.mktemp("html")
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "html",
         "-D", "nb_execution_mode=off", "-d", str(out / ".doctrees"), str(DOCS), str(out)],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    return out


def test_site_builds_with_warnings_as_errors(built_site):
    for page in ["index", "getting_started", "theory", "reproducing", "cli", "api/index",
                 "performance", "changelog", "cite", "tutorials/index"]:
        assert (built_site / f"{page}.html").is_file(), page
    # The CLI reference is generated from the parser: every subcommand is on the page.
    import argparse

    from maxwell_kinetics.app.cli import build_parser

    cli = (built_site / "cli.html").read_text()
    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    assert len(sub.choices) >= 8
    for name in sub.choices:
        assert f'id="maxwell-kinetics-{name}"' in cli, name

def test_maths_render_without_a_network(built_site):
    # MathJax is served from the site itself: every page with maths loads the local copy and
    # nothing from a CDN
    assert (built_site / "_static" / "mathjax" / "tex-chtml.js").is_file()
    theory = (built_site / "theory.html").read_text()
    assert 'src="_static/mathjax/tex-chtml.js"' in theory
    for page in built_site.rglob("*.html"):
        assert "cdn.jsdelivr" not in page.read_text(errors="replace"), page


def test_every_public_name_is_in_the_api_reference(built_site):
    from sphinx.util.inventory import InventoryFile

    with open(built_site / "objects.inv", "rb") as stream:
        inventory = InventoryFile.load(stream, "", lambda base, uri: uri)
    documented = set()
    for role, entries in inventory.items():
        if role.startswith("py:"):
            documented.update(entries)
    missing = [f"{face}.{name}" for face in FACES
               for name in importlib.import_module(face).__all__
               if f"{face}.{name}" not in documented]
    assert not missing, missing


def _python_blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


@pytest.mark.parametrize("page", ["README.md", "docs/getting_started.md", "docs/guide/sticky.md",
                                  "docs/guide/ensembles.md", "docs/guide/reproducibility.md",
                                  "docs/guide/errors.md"])
def test_code_examples_run(page, tmp_path, monkeypatch, capsys):
    blocks = _python_blocks(ROOT / page)
    assert blocks, f"no ```python block in {page}"
    monkeypatch.chdir(tmp_path)
    for block in blocks:  # as a script (the ensemble example runs under its __main__ guard)
        exec(compile(block, page, "exec"), {"__name__": "__main__"})
    assert capsys.readouterr().out.strip()  # the examples print their results


def test_readme_is_short():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 150


def test_no_references_to_outside_documents():
    # Conventions are stated in the project's words: no external spec sections, no issue numbers.
    pattern = re.compile("SP" + r"EC\b|\b[Ii]ssue \d+")
    hits = []
    for folder in ["particles", "maxwell_kinetics", "tests", "notebooks", "docs"]:
        for path in (ROOT / folder).rglob("*"):
            if path.suffix not in (".py", ".ipynb", ".md", ".rst") or "_build" in path.parts:
                continue
            for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                if pattern.search(line):
                    hits.append(f"{path.relative_to(ROOT)}:{n}")
    assert not hits, hits
