"""Reference docstrings: every public function, class and method of the two packages documents
its parameters, what it returns and what it raises, in the numpy style the API reference is
built from.

"Public" is every name in the ``__all__`` of every module (faces and submodules), and the public
methods those classes define themselves.  The rules, read from the code so that they cannot
drift from it:

- a callable whose signature has parameters has a ``Parameters`` section naming each of them
  (a dataclass may name its fields under ``Attributes`` instead);
- a function or method whose body returns a value has a ``Returns`` section (``Yields`` for a
  generator);
- a function, method or constructor whose body raises (``raise X``, not a bare re-raise) has a
  ``Raises`` section.

One test per module, so that ``pytest -k particles.ulam`` checks one module.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import pkgutil
import re
import textwrap

import pytest

PACKAGES = ["particles", "maxwell_kinetics"]
SECTION = re.compile(r"^([A-Z][A-Za-z ]+)\n-{3,}$", re.M)
ENTRY = re.compile(r"^(\*{0,2}[A-Za-z_]\w*(?:\s*,\s*\*{0,2}[A-Za-z_]\w*)*)\s*(?::.*)?$")


def _modules() -> list[str]:
    names = []
    for root in PACKAGES:
        package = importlib.import_module(root)
        names.append(root)
        for info in pkgutil.walk_packages(package.__path__, root + "."):
            if not info.name.rsplit(".", 1)[-1].startswith("_"):
                names.append(info.name)
    return names


def sections(doc: str) -> dict[str, str]:
    """Section title -> its text, for a numpy-style docstring."""
    found = list(SECTION.finditer(doc))
    out = {}
    for i, match in enumerate(found):
        end = found[i + 1].start() if i + 1 < len(found) else len(doc)
        out[match.group(1).strip()] = doc[match.end():end]
    return out


def documented_names(text: str) -> set[str]:
    """The names an entry line of a Parameters/Attributes section lists (unindented lines)."""
    names = set()
    for line in text.splitlines():
        if not line or line[0].isspace():
            continue
        match = ENTRY.match(line.strip())
        if match:
            names |= {n.strip().lstrip("*") for n in match.group(1).split(",")}
    return names


def _body_nodes(func) -> list[ast.AST]:
    """The AST nodes of ``func``'s own body (nested functions and classes excluded)."""
    try:
        source = textwrap.dedent(inspect.getsource(func))
    except (OSError, TypeError):
        return []
    tree = ast.parse(source)
    top = next((n for n in ast.walk(tree)
                if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))), None)
    if top is None:
        return []
    nodes, stack = [], list(top.body)
    while stack:
        node = stack.pop()
        nodes.append(node)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        stack.extend(ast.iter_child_nodes(node))
    return nodes


def _returns_value(nodes) -> bool:
    return any(isinstance(n, ast.Return) and n.value is not None
               and not (isinstance(n.value, ast.Constant) and n.value.value is None)
               for n in nodes)


def _yields(nodes) -> bool:
    return any(isinstance(n, (ast.Yield, ast.YieldFrom)) for n in nodes)


def _raises(nodes) -> bool:
    return any(isinstance(n, ast.Raise) and n.exc is not None
               and not (isinstance(n.exc, ast.Name) and n.exc.id == "NotImplementedError")
               for n in nodes)


def _parameters(obj) -> list[str]:
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p for p in signature.parameters if p not in ("self", "cls")]


def problems(qualname: str, obj, *, method_of=None) -> list[str]:
    """What the docstring of ``obj`` lacks under the rules of this module."""
    doc = inspect.getdoc(obj) if method_of is None else (obj.__doc__ or "")
    doc = inspect.cleandoc(doc or "")
    if not doc:
        return [f"{qualname}: no docstring"]
    found = sections(doc)
    out = []
    if inspect.isclass(obj):
        code = [getattr(obj, n) for n in ("__init__", "__post_init__")
                if inspect.isfunction(vars(obj).get(n))
                and vars(obj)[n].__module__ == obj.__module__]  # not typing.Protocol's
        nodes = [n for f in code for n in _body_nodes(f)]
        wanted = _parameters(obj) if not issubclass(obj, BaseException) or code else []
        if getattr(obj, "_is_protocol", False):
            wanted = []  # a protocol is not constructed
        listed = documented_names(found.get("Parameters", ""))
        if dataclasses.is_dataclass(obj):
            listed |= documented_names(found.get("Attributes", ""))
        missing = [p for p in wanted if p not in listed]
        if missing:
            out.append(f"{qualname}: Parameters lacks {missing}")
        if _raises(nodes) and "Raises" not in found:
            out.append(f"{qualname}: raises but has no Raises section")
        return out
    func = inspect.unwrap(obj)
    nodes = _body_nodes(func)
    listed = documented_names(found.get("Parameters", ""))
    missing = [p for p in _parameters(func) if p not in listed]
    if missing:
        out.append(f"{qualname}: Parameters lacks {missing}")
    if _yields(nodes):
        if "Yields" not in found:
            out.append(f"{qualname}: yields but has no Yields section")
    elif _returns_value(nodes) and "Returns" not in found:
        out.append(f"{qualname}: returns a value but has no Returns section")
    if _raises(nodes) and "Raises" not in found:
        out.append(f"{qualname}: raises but has no Raises section")
    return out


def _assignments() -> dict[str, list[tuple[str, object]]]:
    """Each public class or function once, under the module that checks it: where it is
    defined when that module is public, else the first module (in walk order) that exports it."""
    if "a" in _CACHE:
        return _CACHE["a"]
    modules = _modules()
    public = set(modules)
    out: dict[str, list] = {m: [] for m in modules}
    seen: set[int] = set()
    for module_name in modules:
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", []):
            obj = getattr(module, name)
            if not (inspect.isclass(obj) or inspect.isfunction(obj)) or id(obj) in seen:
                continue
            if not getattr(obj, "__module__", "").startswith(tuple(PACKAGES)):
                continue
            seen.add(id(obj))
            home = obj.__module__ if obj.__module__ in public else module_name
            out[home].append((f"{obj.__module__}.{obj.__qualname__}", obj))
    _CACHE["a"] = out
    return out


def _public(module_name: str):
    """(qualified name, object, owning class or None) of the public callables checked here."""
    for qualname, obj in _assignments()[module_name]:
        yield qualname, obj, None
        if inspect.isclass(obj):
            for attr, value in vars(obj).items():
                if attr.startswith("_"):
                    continue
                func = value.__func__ if isinstance(value, (classmethod, staticmethod)) else value
                if inspect.isfunction(func):
                    yield f"{qualname}.{attr}", func, obj


_CACHE: dict[str, object] = {}


@pytest.mark.parametrize("module_name", _modules())
def test_reference_docstrings(module_name):
    found = []
    for qualname, obj, owner in _public(module_name):
        found += problems(qualname, obj, method_of=owner)
    assert not found, "\n" + "\n".join(found)


def test_the_rules_can_fail():
    # The checker itself: a docstring without the sections is reported, one with them is not.
    def bad(x, y=1):
        """Add."""
        if x < 0:
            raise ValueError(x)
        return x + y

    def good(x, y=1):
        """Add.

        Parameters
        ----------
        x, y : float
            The terms.

        Returns
        -------
        float

        Raises
        ------
        ValueError
            If ``x`` is negative.
        """
        if x < 0:
            raise ValueError(x)
        return x + y

    assert len(problems("bad", bad)) == 3
    assert problems("good", good) == []
