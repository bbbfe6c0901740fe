"""One concept per module of ``particles``: every public name has one home, a name that moved
out of a module is refused there with an ImportError naming its new home (never re-exported,
never a bare AttributeError), and no module grows past 800 lines."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import particles

ROOT = Path(particles.__file__).resolve().parent

# Every name moved when the modules were split, by old module: (name, new home).  Written out
# here (not read from the modules) so that a name dropped from a module's table is caught.
MOVED = {
    "particles.sticky": [
        *[(n, "particles.sticky_observables") for n in (
            "clusters", "cluster_mass_distribution", "profile_x", "profile_i", "total_momentum",
            "displacements", "velocity_tail_exponent")],
        *[(n, "particles.sticky_exact") for n in (
            "chernoff_density", "displacement_scale", "CHERNOFF_VARIANCE", "exact_shock_density",
            "exact_mass_density", "exact_velocity_density", "exact_eulerian_velocity_density",
            "exact_velocity_survival", "exact_velocity_tail_exponent", "exact_asymptotes",
            "exact_moments")],
        *[(n, "particles.sticky_comparison") for n in (
            "EXACT_W_EDGES", "ExactLawComparison", "exact_law_runs")],
    ],
    "particles.ulam": [
        *[(n, "particles.pair_schedule") for n in (
            "draw_pairs", "collide_in_order", "collide_sequential", "collide_in_order_vectors",
            "collide_sequential_vectors")],
        *[(n, "particles.ulam_kinematics") for n in (
            "AngularDraws", "ANGULAR_MODELS", "draw_angles", "collision_directions",
            "collide_vectors", "collide_complex", "plane_transfer")],
    ],
    "particles.validation": [
        *[(n, "particles.parsing") for n in (
            "parse_float_list", "parse_name_list", "parse_int", "parse_count", "parse_seed")],
        *[(n, "particles.paths") for n in (
            "check_path", "file_kind", "output_target", "check_output_file", "check_output_dir")],
        *[(n, "particles.workers") for n in ("max_workers", "check_workers")],
    ],
}
CASES = [(old, name, new) for old, moves in MOVED.items() for name, new in moves]


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


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_unknown_name_is_still_an_attribute_error(old):
    module = importlib.import_module(old)
    assert not hasattr(module, "no_such_name")
    with pytest.raises(ImportError, match="cannot import name"):
        exec(f"from {old} import no_such_name", {})


def test_the_public_face_keeps_its_names():
    # The face exported these before the split; each still resolves, from its one home.
    for name in ["StickyGas", "StickyParams", "StickyState", "Ulam", "UlamState",
                 "InvalidArgumentError", "simulate", "energy", "FileFormatError"]:
        assert name in particles.__all__
        assert getattr(particles, name) is not None
    assert particles.StickyGas.__module__ == "particles.sticky"
    assert particles.Ulam.__module__ == "particles.ulam"
    assert particles.InvalidArgumentError.__module__ == "particles.validation"


def _modules():
    return sorted(p for p in ROOT.rglob("*.py") if "__pycache__" not in p.parts)


def _dotted(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def test_no_module_is_over_800_lines():
    long = {_dotted(p): n for p in _modules()
            if (n := len(p.read_text().splitlines())) > 800}
    assert not long, long


def _defined_and_imported(tree: ast.Module) -> tuple[set[str], set[str]]:
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
    return defined, imported


def test_every_public_name_of_a_module_is_defined_there():
    # A module that is not a package face (__init__) lists in __all__ only what it defines:
    # a name re-exported from another module would have two homes.
    misplaced = []
    for path in _modules():
        if path.name == "__init__.py":
            continue
        module = importlib.import_module(_dotted(path))
        defined, imported = _defined_and_imported(ast.parse(path.read_text()))
        misplaced += [f"{module.__name__}.{name}" for name in getattr(module, "__all__", [])
                      if name not in defined or name in imported]
    assert not misplaced, misplaced


def test_sticky_and_its_exact_laws_share_no_name():
    sticky = importlib.import_module("particles.sticky")
    exact = importlib.import_module("particles.sticky_exact")
    assert not set(sticky.__all__) & set(exact.__all__)
    assert not set(exact.__all__) & set(vars(sticky))
