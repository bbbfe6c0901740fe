"""The package layers: ``particles`` is the base and imports nothing from
``maxwell_kinetics``; no module of the project imports another that imports it back, directly or
around a circle.  Checked from the source with ``ast`` (every import statement, those inside
functions included), and by importing ``particles`` in a fresh interpreter."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

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
    assert "particles.persistence" in graph["particles.driver.result"]
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
    for path in (ROOT / "tests").rglob("*.py"):
        if path.name == Path(__file__).name:
            continue
        text = path.read_text()
        assert "spec_from_file_location" not in text, path.name


def test_importing_the_package_changes_no_global_configuration():
    # A library does not change global configuration when imported: after importing
    # maxwell_kinetics and its solver, JAX's x64 flag and the environment are as they were.
    import os

    code = (
        "import os, jax, maxwell_kinetics, maxwell_kinetics.solver, maxwell_kinetics.app.cli\n"
        "print(jax.config.jax_enable_x64, os.environ.get('JAX_ENABLE_X64'))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "JAX_ENABLE_X64"}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT, env=env)
    assert done.stdout.strip() == "False None"


#: The application: the subpackage that holds the command line, the comparisons with their
#: drawings and runs, the reproduction of the paper, the convergence study, plotting and the
#: output helpers.  The kinetic library (every other module of ``maxwell_kinetics``) and
#: ``particles`` never import it: the rule is stated by folder, so that a module added to the
#: application or to the library is covered without editing this test.
APPLICATION = "maxwell_kinetics.app"


def _is_application(name: str) -> bool:
    return name == APPLICATION or name.startswith(APPLICATION + ".")


def library_to_application(graph) -> dict[str, list[str]]:
    """Library modules (every module outside :data:`APPLICATION`, ``particles`` included) that
    import application modules, with what they import."""
    return {name: sorted(t for t in targets if _is_application(t))
            for name, targets in graph.items()
            if not _is_application(name) and any(_is_application(t) for t in targets)}


def test_the_application_is_a_folder_of_its_own():
    # the rule is by folder: the command line, the comparisons and reproduce live under it
    modules = project_modules()
    for name in ("cli", "commands", "commands.solve", "comparisons", "reproduce", "plotting",
                 "output", "convergence", "cache_options"):
        assert f"{APPLICATION}.{name}" in modules, name
    assert modules[APPLICATION] == ROOT / "maxwell_kinetics" / "app" / "__init__.py"


def test_the_library_never_imports_the_application():
    assert library_to_application(import_graph()) == {}


def test_the_application_checker_finds_a_library_module_that_plots():
    graph = {"maxwell_kinetics.tails": {"maxwell_kinetics.app.plotting"},
             "particles.sticky": {"maxwell_kinetics.app.comparisons.base"},
             "maxwell_kinetics.app.commands.solve": {"maxwell_kinetics.solver",
                                                     "maxwell_kinetics.app.output"},
             "maxwell_kinetics.application_notes": {"maxwell_kinetics.solver"}}
    assert library_to_application(graph) == {
        "maxwell_kinetics.tails": ["maxwell_kinetics.app.plotting"],
        "particles.sticky": ["maxwell_kinetics.app.comparisons.base"]}


def test_the_application_checker_reads_a_library_file_that_imports_the_app(tmp_path):
    # the checker end to end on source: a library module with a relative import of the app
    path = tmp_path / "tails.py"
    path.write_text("def f():\n    from .app.plotting import new_figure\n    return new_figure\n")
    modules = {"maxwell_kinetics.tails": path, "maxwell_kinetics.app.plotting": path,
               "maxwell_kinetics.app": path}
    graph = {"maxwell_kinetics.tails": imports_of("maxwell_kinetics.tails", path, modules)}
    assert library_to_application(graph) == {
        "maxwell_kinetics.tails": ["maxwell_kinetics.app.plotting"]}


MOVED = ["cli", "commands", "commands.solve", "comparisons", "comparisons.base", "reproduce",
         "plotting", "output", "convergence"]


@pytest.mark.parametrize("name", MOVED)
def test_an_old_path_of_a_moved_module_names_its_new_home(name):
    # in a fresh interpreter, so that no module already imported hides the old path; a module
    # below a moved package (commands.solve) is refused at its package, the first one imported
    moved = name.split(".")[0]
    code = (f"import importlib\ntry:\n    importlib.import_module('maxwell_kinetics.{name}')\n"
            "except ImportError as exc:\n    print(type(exc).__name__, exc)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert done.stdout.strip() == (
        f"ImportError maxwell_kinetics.{moved} moved to maxwell_kinetics.app.{moved}")


def test_the_old_paths_fail_in_every_import_form_and_the_face_keeps_its_names():
    import maxwell_kinetics
    from maxwell_kinetics.app import comparisons

    with pytest.raises(ImportError, match=r"^maxwell_kinetics\.comparisons moved to "
                                          r"maxwell_kinetics\.app\.comparisons$"):
        from maxwell_kinetics import comparisons as old  # noqa: F401
    with pytest.raises(ImportError, match=r"^maxwell_kinetics\.cli moved to "
                                          r"maxwell_kinetics\.app\.cli$"):
        import maxwell_kinetics.cli  # noqa: F401
    with pytest.raises(AttributeError, match=r"maxwell_kinetics\.reproduce moved to "
                                             r"maxwell_kinetics\.app\.reproduce"):
        maxwell_kinetics.reproduce  # noqa: B018
    assert maxwell_kinetics.COMPARISONS is comparisons.COMPARISONS
    assert maxwell_kinetics.Comparison is comparisons.Comparison
    # the finder refuses only the moved names (a look-alike is simply not found)
    with pytest.raises(ModuleNotFoundError, match="No module named 'maxwell_kinetics.outputs'"):
        import maxwell_kinetics.outputs  # noqa: F401


def private_uses(name: str, path: Path, modules: dict[str, Path]) -> list[str]:
    """Private names of other modules that module ``name`` uses: ``from m import _x`` where m is
    another project module (a private module itself, ``from . import _scheme``, is fine: its
    package owns it), and attribute reads ``obj._x`` on anything but ``self``, ``cls`` or a
    name the module defines (dunder names are not private)."""
    tree = ast.parse(path.read_text(), str(path))
    own = {node.name for node in ast.walk(tree)
           if isinstance(node, ast.FunctionDef | ast.ClassDef | ast.AsyncFunctionDef)}
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level + bool(node.module):
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
                    base = package.split(".") if node.level else []
                    base = base[: len(base) - (node.level - 1)] if node.level else []
                    target = ".".join(base + ([node.module] if node.module else []))
                    if f"{target}.{alias.name}" not in modules:  # a name, not a module
                        found.append(f"from {target} import {alias.name}")
        elif isinstance(node, ast.Attribute):
            attr = node.attr
            if not attr.startswith("_") or attr.startswith("__"):
                continue
            owner = node.value
            if isinstance(owner, ast.Name) and (owner.id in ("self", "cls") or owner.id in own):
                continue
            found.append(f"{ast.unparse(owner)}.{attr}")
    return found


#: Private names of other libraries that the project reads on purpose, with the reason.
THIRD_PARTY_PRIVATE = {
    # the CLI's errors name the option as typed and list a subcommand's choices: argparse keeps
    # both only in private attributes; os._exit is the standard library's exit without the
    # interpreter's shutdown (a solve's thread still inside JAX would abort it)
    "maxwell_kinetics.app.cli": {"parser._option_string_actions", "parser._actions",
                                 "argparse._SubParsersAction", "os._exit"},
}


def test_no_module_reads_another_modules_private_names():
    modules = project_modules()
    bad = {}
    for name, path in modules.items():
        uses = set(private_uses(name, path, modules)) - THIRD_PARTY_PRIVATE.get(name, set())
        if uses:
            bad[name] = sorted(uses)
    assert bad == {}


def test_the_private_name_checker_finds_both_kinds(tmp_path):
    path = tmp_path / "m.py"
    path.write_text("from .driver import _read_npz\nfrom . import _kinetic_scheme\n"
                    "def f(solution, self):\n    return solution._index(1), self._x\n")
    modules = {"particles.driver": path, "particles._kinetic_scheme": path}
    assert private_uses("particles.m", path, modules) == [
        "from particles.driver import _read_npz", "solution._index"]


#: The module that holds the kinetic collision models: the only one that writes out the kernel.
COLLISION_MODEL = "maxwell_kinetics.model"

#: The kernel written out, as ``ast.unparse`` spells it (docstrings and every other string
#: constant blanked, comments gone): the transfer fraction p = (1 + r)/2, λ = p(1 − p) =
#: (1 − r²)/4, the complement 1 − p of a variable or attribute named ``p``, and the sums
#: p^k + (1 − p)^k = 1 − kλ of the deviation source.
KERNEL_PATTERNS = {
    "transfer fraction": re.compile(r"0\.5 \* \(1(?:\.0)? \+ [\w.]+\)"
                                    r"|\(1(?:\.0)? \+ [\w.]+\) / 2\b"),
    "lambda": re.compile(r"\b([\w.]+) \* \(1(?:\.0)? - \1\)"
                         r"|\(1(?:\.0)? - [\w.]+ (?:\*\* 2|\* [\w.]+)\) / 4\b"
                         r"|0\.25 \* \(1(?:\.0)? - [\w.]+ (?:\*\* 2|\* [\w.]+)\)"),
    "complement 1 - p": re.compile(r"(?<![\w.])1(?:\.0)? - (?:\w+\.)?p\b(?!\s*\()"),
    "1 - k lambda": re.compile(r"(?<![\w.])1(?:\.0)? - [23](?:\.0)? \* (?:\w+\.)?lam\b"),
}


def kernel_rederivations(source: str) -> list[str]:
    """The kernel expressions (:data:`KERNEL_PATTERNS`) written out in ``source``'s code."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            node.value = ""
    code = ast.unparse(tree)
    return sorted({f"{kind}: {match.group(0)}" for kind, pattern in KERNEL_PATTERNS.items()
                   for match in pattern.finditer(code)})


#: Look-alikes of a kernel expression that are not the kernel, each by module and exactly as
#: :func:`kernel_rederivations` reports it: the Gauss–Jacobi change of variable η = (1 + x)/2 from
#: [−1, 1] to [0, 1] of the angular law's quadrature.  Any other match in these modules counts.
KERNEL_LOOKALIKES = {
    "maxwell_kinetics.angular": {"transfer fraction: 0.5 * (1.0 + x)"},
}


def kernel_rederiving_modules(sources: dict[str, str]) -> dict[str, list[str]]:
    """Kinetic (library) modules of ``maxwell_kinetics`` other than :data:`COLLISION_MODEL` that
    write out the kernel, with what they write (the :data:`KERNEL_LOOKALIKES` aside)."""
    out = {}
    for name, source in sources.items():
        if (not name.startswith("maxwell_kinetics") or _is_application(name)
                or name == COLLISION_MODEL):
            continue
        found = [f for f in kernel_rederivations(source)
                 if f not in KERNEL_LOOKALIKES.get(name, set())]
        if found:
            out[name] = found
    return out


def test_the_kernel_checker_finds_each_form():
    assert kernel_rederivations("p = 0.5 * (1.0 + r)\nq = (1 + restitution) / 2") == [
        "transfer fraction: (1 + restitution) / 2", "transfer fraction: 0.5 * (1.0 + r)"]
    assert kernel_rederivations("a = m.p * (1.0 - m.p)\nb = (1 - r ** 2) / 4\n"
                                "c = 0.25 * (1.0 - r * r)") == [
        "complement 1 - p: 1.0 - m.p", "lambda: (1 - r ** 2) / 4", "lambda: 0.25 * (1.0 - r * r)",
        "lambda: m.p * (1.0 - m.p)"]
    assert kernel_rederivations("g = x ** (1.0 - p)\nh = 1.0 - 3.0 * lam") == [
        "1 - k lambda: 1.0 - 3.0 * lam", "complement 1 - p: 1.0 - p"]
    # docstrings, strings, comments and look-alikes are not code of the kernel
    assert kernel_rederivations('"""p = (1 + r)/2"""\nx = "1 - p"  # p * (1 - p)\n'
                                "y = 1.0 - prob + 1 - p2 + 11 - p.q(1)") == []
    sources = {"maxwell_kinetics.tails": "lam = p * (1 - p)", COLLISION_MODEL: "lam = p * (1 - p)",
               "maxwell_kinetics.app.cli": "lam = p * (1 - p)"}
    assert kernel_rederiving_modules(sources) == {
        "maxwell_kinetics.tails": ["complement 1 - p: 1 - p", "lambda: p * (1 - p)"]}
    # a look-alike is excused only in its module and only as written there
    lookalike = "eta = 0.5 * (1.0 + x)"
    assert kernel_rederiving_modules({"maxwell_kinetics.angular": lookalike}) == {}
    assert kernel_rederiving_modules({"maxwell_kinetics.tails": lookalike}) == {
        "maxwell_kinetics.tails": ["transfer fraction: 0.5 * (1.0 + x)"]}
    assert kernel_rederiving_modules({"maxwell_kinetics.angular": "p = 0.5 * (1.0 + r)"}) == {
        "maxwell_kinetics.angular": ["transfer fraction: 0.5 * (1.0 + r)"]}


def test_only_the_collision_model_writes_out_the_kernel():
    sources = {name: path.read_text() for name, path in project_modules().items()}
    assert kernel_rederiving_modules(sources) == {}


#: The modules that hold the collision kernels, the only ones that may write out a collision
#: rate: the registry of kernels, the collision arithmetic and the kinetic models.
KERNEL_MODULES = {"particles.kernels", "particles.collision", COLLISION_MODEL}

#: A collision rate written out, as ``ast.unparse`` spells it (strings blanked): a relative
#: speed raised to a power (|v - w|^gamma, the variable ``g`` to any power but 2), and a
#: relative speed used as a thinning rate (over a bound, or compared with a mark times one).
RATE_PATTERNS = {
    "a power of a relative speed": re.compile(r"abs\([^()]*? - [^()]*?\) \*\* "
                                              r"|(?<![\w.])g \*\* (?!2\b)"),
    "a relative speed as a rate": re.compile(r"abs\([^()]*? - [^()]*?\) / "
                                             r"|\* [\w.]+ < (?:np\.)?abs\("),
    "the relative speed g of a pair": re.compile(r"(?<![\w.])g = (?:np\.)?abs\([^()]*? - "
                                                 r"|abs\(g, out=g\)"),
}

#: Look-alikes of a written-out rate, by module and exactly as :func:`rate_rederivations`
#: reports them: the drift of a fit between two halves of a sample, over the fit's value.
RATE_LOOKALIKES = {
    "maxwell_kinetics.scaling_tails": {
        "a relative speed as a rate: abs(halves[0] - halves[1]) / "},
}


def rate_rederivations(source: str) -> list[str]:
    """The rates (:data:`RATE_PATTERNS`) written out in ``source``'s code."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            node.value = ""
    code = ast.unparse(tree)
    return sorted({f"{kind}: {match.group(0)}" for kind, pattern in RATE_PATTERNS.items()
                   for match in pattern.finditer(code)})


def rate_rederiving_modules(sources: dict[str, str]) -> dict[str, list[str]]:
    """Library modules of both packages outside :data:`KERNEL_MODULES` that write out a
    collision rate, or (in ``particles``) the transfer of a collision, with what they write."""
    out = {}
    for name, source in sources.items():
        if _is_application(name) or name in KERNEL_MODULES:
            continue
        found = [f for f in rate_rederivations(source)
                 if f not in RATE_LOOKALIKES.get(name, set())]
        if name.startswith("particles"):
            found += [f for f in kernel_rederivations(source)
                      if f != "lambda: prob * (1.0 - prob)"]  # a binomial variance
        if found:
            out[name] = sorted(found)
    return out


def test_the_rate_checker_finds_each_form():
    assert rate_rederivations("k = np.abs(c[:, None] - c[None, :]) ** gamma\n"
                              "e = g ** (exponent + 2.0)\ne2 = g ** 2") == [
        "a power of a relative speed: abs(c[:, None] - c[None, :]) ** ",
        "a power of a relative speed: g ** "]
    assert rate_rederivations("a = abs(w[a] - w[b]) / bound\nhit = m * bound < np.abs(g)") == [
        "a relative speed as a rate: * bound < np.abs(",
        "a relative speed as a rate: abs(w[a] - w[b]) / "]
    assert rate_rederivations("g = abs(w[a] - w[b]) if rate is None else 1\n"
                              "np.abs(g, out=g)") == [
        "the relative speed g of a pair: abs(g, out=g)",
        "the relative speed g of a pair: g = abs(w[a] - "]
    assert rate_rederivations('"""g ** gamma"""\nx = "abs(v - w) / b"  # g ** 0.5') == []
    sources = {"particles.pair_schedule": "g = abs(w[a] - w[b]) / bound",
               "particles.kernels": "g = abs(v - w) ** 0.5",
               "particles.ulam": "p = (1 + r) / 2",
               "maxwell_kinetics.app.cli": "g ** gamma"}
    assert rate_rederiving_modules(sources) == {
        "particles.pair_schedule": ["a relative speed as a rate: abs(w[a] - w[b]) / ",
                                    "the relative speed g of a pair: g = abs(w[a] - "],
        "particles.ulam": ["transfer fraction: (1 + r) / 2"]}


def test_no_module_outside_the_kernels_writes_a_rate_or_a_transfer_out():
    sources = {name: path.read_text() for name, path in project_modules().items()}
    assert rate_rederiving_modules(sources) == {}


def private_library_imports(path: Path) -> list[str]:
    """Imports of a library's private modules (a dotted name with a part starting with ``_``,
    such as ``jax._src.config``), the project's own modules aside."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        for name in names:
            if name.split(".")[0] in ("maxwell_kinetics", "particles", "__future__"):
                continue
            if any(part.startswith("_") for part in name.split(".")[1:]):
                found.append(name)
    return found


def test_no_module_imports_a_private_module_of_another_library(tmp_path):
    bad = {name: uses for name, path in project_modules().items()
           if (uses := private_library_imports(path))}
    assert bad == {}
    # the checker itself: an import inside a function counts, the project's own do not
    probe = tmp_path / "m.py"
    probe.write_text("def f():\n    from jax._src.config import trace_context\n"
                     "from maxwell_kinetics import interrupt\nimport numpy.linalg\n")
    assert private_library_imports(probe) == ["jax._src.config"]
