"""The package layers (issue 14): ``particles`` is the base and imports nothing from
``maxwell_kinetics``; no module of the project imports another that imports it back, directly or
around a circle.  Checked from the source with ``ast`` (every import statement, those inside
functions included), and by importing ``particles`` in a fresh interpreter."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("particles", "maxwell_kinetics")


def project_modules() -> dict[str, Path]:
    """Dotted name → file for every module of the two packages."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def imports_of(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The project modules that module ``name`` imports (``from a import b`` counts as an import
    of the module ``a.b`` where that is a module, else of ``a``)."""
    is_package = path.name == "__init__.py"
    package = name if is_package else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            targets = [f"{stem}.{alias.name}" if f"{stem}.{alias.name}" in modules else stem
                       for alias in node.names]
        else:
            continue
        for target in targets:
            while target and target not in modules:  # a name inside a module: its module
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


def import_graph() -> dict[str, set[str]]:
    modules = project_modules()
    return {name: imports_of(name, path, modules) for name, path in modules.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    sys.setrecursionlimit(10_000)
    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_the_checker_finds_a_cycle_and_a_package_edge():
    # the checker itself: a made-up graph with a circle of three, and the resolution of imports
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []
    graph = import_graph()
    assert "particles.persistence" in graph["particles.driver"]
    assert "particles.validation" in graph["maxwell_kinetics.solver"]


def test_no_import_cycles():
    assert cycles(import_graph()) == []


def test_particles_imports_nothing_from_maxwell_kinetics():
    graph = import_graph()
    upward = {name: sorted(t for t in targets if t.startswith("maxwell_kinetics"))
              for name, targets in graph.items() if name.startswith("particles")}
    assert {k: v for k, v in upward.items() if v} == {}


def test_import_particles_loads_neither_jax_nor_maxwell_kinetics():
    modules = [name for name in project_modules() if name.startswith("particles")]
    code = (
        "import importlib, sys\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('jax', 'maxwell_kinetics'))\n"
        "print(bad)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert done.stdout.strip() == "[]"


def test_no_test_loads_a_benchmark_by_path():
    for path in (ROOT / "tests").glob("*.py"):
        if path.name == Path(__file__).name:
            continue
        text = path.read_text()
        assert "spec_from_file_location" not in text, path.name


def test_importing_the_package_changes_no_global_configuration():
    # A library does not change global configuration when imported (issue 14): after importing
    # maxwell_kinetics and its solver, JAX's x64 flag and the environment are as they were.
    import os

    code = (
        "import os, jax, maxwell_kinetics, maxwell_kinetics.solver, maxwell_kinetics.cli\n"
        "print(jax.config.jax_enable_x64, os.environ.get('JAX_ENABLE_X64'))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "JAX_ENABLE_X64"}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT, env=env)
    assert done.stdout.strip() == "False None"
