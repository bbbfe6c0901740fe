"""One concept per module of ``maxwell_kinetics``: no module grows past 800 lines, every public
name of a module is defined there (one home), and a name that moved out of a module is refused
there with an ImportError naming its new home (never re-exported, never a bare AttributeError)."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import maxwell_kinetics

ROOT = Path(maxwell_kinetics.__file__).resolve().parent

# Every name moved when a module was split, by old module: (name, new home).  Written out here
# (not read from the modules) so that a name dropped from a module's table is caught.
MOVED = {
    "maxwell_kinetics.model": [(n, "maxwell_kinetics.angular")
                               for n in ("AngularLaw", "angular_law", "ANGULAR_MODELS")],
    "maxwell_kinetics.compile_cache": [(n, "maxwell_kinetics.app.cache_options")
                                       for n in ("add_option", "from_args", "end_command")],
    "maxwell_kinetics.inelastic_boltzmann": [
        (n, "maxwell_kinetics.velocity_grid")
        for n in ("VelocityGrid", "MappedGrid", "default_grid", "initial_values",
                  "EXTENT_TOLERANCE", "RESOLUTION_TOLERANCE", "MAX_SPACING", "MAX_POINTS")],
}
CASES = [(old, name, new) for old, moves in MOVED.items() for name, new in moves]


def _modules():
    return sorted(p for p in ROOT.rglob("*.py") if "__pycache__" not in p.parts)


def _dotted(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def test_no_module_is_over_800_lines():
    long = {_dotted(p): n for p in _modules()
            if (n := len(p.read_text().splitlines())) > 800}
    assert not long, long


@pytest.mark.parametrize(("old", "name", "new"), CASES,
                         ids=[f"{old}.{name}" for old, name, _ in CASES])
def test_a_moved_deep_import_names_its_new_home(old, name, new):
    with pytest.raises(ImportError, match=rf"^{old}\.{name} moved to {new}\.{name}$"):
        exec(f"from {old} import {name}", {})
    with pytest.raises(ImportError, match=rf"moved to {new}\.{name}$"):
        getattr(importlib.import_module(old), name)
    home = importlib.import_module(new)
    assert name in home.__all__
    assert hasattr(home, name)
    assert name not in vars(importlib.import_module(old))  # not re-exported: one home


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_unknown_name_is_still_an_attribute_error(old):
    module = importlib.import_module(old)
    assert not hasattr(module, "no_such_name")
    with pytest.raises(ImportError, match="cannot import name"):
        exec(f"from {old} import no_such_name", {})


def test_every_public_name_of_a_library_module_is_defined_there():
    # A module that is not a package face (__init__) lists in __all__ only what it defines:
    # a name re-exported from another module would have two homes.
    misplaced = []
    for path in _modules():
        if path.name == "__init__.py" or "app" in path.relative_to(ROOT).parts:
            continue
        tree = ast.parse(path.read_text())
        defined, imported = set(), set()
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                defined.add(node.name)
            elif isinstance(node, ast.Assign):
                defined.update(t.id for t in node.targets if isinstance(t, ast.Name))
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                defined.add(node.target.id)
            elif isinstance(node, ast.ImportFrom):
                imported.update(a.asname or a.name for a in node.names)
        module = importlib.import_module(_dotted(path))
        misplaced += [f"{module.__name__}.{name}" for name in getattr(module, "__all__", [])
                      if name not in defined or name in imported]
    assert not misplaced, misplaced


@pytest.mark.parametrize(("statement", "says"), [
    ("from maxwell_kinetics.statistics import ks_distance",
     r"ks_distance was removed: .* ks of particles\.observables\.Histogram\.distance"),
    ("from particles.ensemble import MAX_SEED", r"MAX_SEED is particles\.validation\.SEED_MAX"),
    ("from particles.ensemble.spec import MAX_SEED",
     r"MAX_SEED is particles\.validation\.SEED_MAX"),
])
def test_a_retired_name_says_what_replaces_it(statement, says):
    """Names retired rather than moved (the histogram distance's one home; the seed's one bound)
    raise an ImportError saying what replaces them, not a bare 'cannot import name'."""
    with pytest.raises(ImportError, match=says):
        exec(statement, {})
    module = importlib.import_module(statement.split()[1])
    assert not hasattr(module, "no_such_name")
