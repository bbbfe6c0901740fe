"""Write ``api/<face>.rst`` for every package face listed in ``apigen_faces``.

Every name in the face's ``__all__`` is documented under the face's own dotted name
(``particles.Ulam``), so that the API reference lists exactly the public names and cannot
forget one; the names of ``apigen_first`` (the most used) lead each page.  Every other public
module gets a page of its own under ``api/modules/``.  A name that two faces export
(``particles.simulate`` is ``particles.driver.simulate``) is documented in full under its home
face (:func:`_home_face`) and as an alias under the others.

A face listed in ``apigen_split`` (a page too long to read: every API page stays under 8000
words, which the docs tests check) is split into sub-pages, one per concept: each entry is
``(page, title, modules)``, and a name goes to the first entry with a pattern
(:func:`fnmatch.fnmatch`) matching the module that defines it; the face's own page keeps its
module docstring, a list of the sub-pages with their names, and the names no entry takes (a new
name lands there until it is given a concept).
"""

from __future__ import annotations

import fnmatch
import importlib
import inspect
import re
import sys
from pathlib import Path

from mathtext import typeset


def _directive(obj) -> str:
    if inspect.isclass(obj):
        return "autoexception" if issubclass(obj, BaseException) else "autoclass"
    if callable(obj):
        return "autofunction"
    return "autodata"


def _data_doc(face: str, name: str, obj) -> tuple[str, str]:
    """(defining module, ``#:`` comment) of a module-level constant exported by ``face``."""
    from sphinx.pycode import ModuleAnalyzer

    root = face.split(".")[0]
    candidates = [face] + sorted(m for m in list(sys.modules)
                                 if m.startswith(root + ".") and m != face)
    for modname in candidates:
        module = sys.modules.get(modname)
        if module is None or getattr(module, name, None) is not obj:
            continue
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except Exception:  # noqa: BLE001 - a module without source: no comment
            continue
        if ("", name) in docs:
            return modname, " ".join(docs[("", name)]).strip()
    return "", ""


def _data(face: str, name: str, obj) -> list[str]:
    where, doc = _data_doc(face, name, obj)
    lines = [f".. py:data:: {name}", ""]
    if doc:
        parts = re.split(r"(:math:`[^`]*`|``.*?``)", typeset(doc))
        parts[::2] = [part.replace("|", "\\|") for part in parts[::2]]
        lines += ["   " + "".join(parts), ""]
    if where and where != face:
        lines += [f"   Defined in ``{where}``.", ""]
    return lines


def _submodules(faces) -> list[str]:
    import pkgutil

    names = []
    for root in sorted({f.split(".")[0] for f in faces}):
        package = importlib.import_module(root)
        for info in pkgutil.walk_packages(package.__path__, root + "."):
            if info.name.rsplit(".", 1)[-1].startswith("_") or info.name in faces:
                continue
            names.append(info.name)
    return names


def face_names(face: str) -> list[str]:
    """The public names of ``face`` (its ``__all__``)."""
    return list(importlib.import_module(face).__all__)


def _ordered(names, first) -> list[str]:
    """``names`` with those listed in ``first`` (the most used) leading, in that order."""
    lead = [n for n in first if n in names]
    return lead + [n for n in names if n not in lead]


def _write(path: Path, lines: list[str]) -> None:
    text = "\n".join(lines) + "\n"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _home_face(module: str, faces, layers) -> str | None:
    """The shortest face that is a prefix of ``module``, a face inside a layer of ``layers``
    (``maxwell_kinetics.app``) only for a module of that layer and the other way round."""
    def within(name, prefix):
        return name == prefix or name.startswith(prefix + ".")

    layer = next((lay for lay in layers if within(module, lay)), None)
    candidates = [f for f in faces if within(module, f)
                  and (layer is None) == (not any(within(f, lay) for lay in layers))]
    return min(candidates, key=len) if candidates else None


def _defining_module(face: str, name: str, obj) -> str:
    """The module that defines ``obj`` (for a constant, the module whose ``#:`` comment
    documents it; "" when none is found)."""
    if inspect.isclass(obj) or inspect.isfunction(obj):
        return getattr(obj, "__module__", None) or ""
    return _data_doc(face, name, obj)[0]


def _split(face: str, names: list[str], entries) -> list[tuple[str, str, list[str]]]:
    """``(page, title, names)`` of each sub-page of ``face`` that takes a name, in the order of
    ``entries``: each name goes to the first entry one of whose patterns matches its defining
    module (:func:`_defining_module`); names no entry takes are left out (they stay on the
    face's page)."""
    module = importlib.import_module(face)
    taken: dict[str, list[str]] = {page: [] for page, _, _ in entries}
    for name in names:
        where = _defining_module(face, name, getattr(module, name))
        for page, _, patterns in entries:
            if where and any(fnmatch.fnmatch(where, pattern) for pattern in patterns):
                taken[page].append(name)
                break
    return [(page, title, taken[page]) for page, title, _ in entries if taken[page]]


def _entry(face: str, name: str, obj, seen: dict[int, str]) -> list[str]:
    """The reStructuredText that documents ``face.name``: in full at its home face, else as an
    alias of the name it is documented under."""
    simple = inspect.isclass(obj) or inspect.isfunction(obj)
    if simple and seen[id(obj)] != f"{face}.{name}":
        return [f".. py:data:: {name}", "",
                f"   The same object as :py:obj:`{seen[id(obj)]}`.", ""]
    if _directive(obj) == "autodata":
        return _data(face, name, obj)
    return [f".. {_directive(obj)}:: {name}", ""]


def write_api(app) -> None:
    out = Path(app.srcdir) / "api"
    (out / "modules").mkdir(parents=True, exist_ok=True)
    seen: dict[int, str] = {}
    index = ["API reference", "=============", "",
             "One page per package face (the names of its ``__all__``), the most used first; "
             "then one page per module.", "",
             ".. toctree::", "   :maxdepth: 1", ""]
    # an object two faces export is documented in full under its home face: the shortest face
    # that is a prefix of its module, the application (``apigen_layers``) counting as a
    # package of its own (``particles.InvalidArgumentError``, also exported by
    # ``maxwell_kinetics``; ``maxwell_kinetics.app.comparisons.Comparison``, also exported by
    # ``maxwell_kinetics``); else the first face that exports it
    faces = app.config.apigen_faces
    for at_home in (True, False):
        for face in faces:
            module = importlib.import_module(face)
            for name in module.__all__:
                obj = getattr(module, name)
                if not (inspect.isclass(obj) or inspect.isfunction(obj)) or id(obj) in seen:
                    continue
                home = _home_face(getattr(obj, "__module__", None) or "", faces,
                                  app.config.apigen_layers)
                if home == face or not at_home:
                    seen[id(obj)] = f"{face}.{name}"
    sub_pages: set[Path] = set()
    for face in app.config.apigen_faces:
        module = importlib.import_module(face)
        stem = face.replace('.', '-')
        index.append(f"   {stem}")
        title = f"``{face}``"
        lines = [title, "=" * len(title), "", f".. automodule:: {face}", "   :no-members:", "",
                 f".. currentmodule:: {face}", ""]
        names = _ordered(module.__all__, app.config.apigen_first)
        groups = _split(face, names, app.config.apigen_split.get(face, []))
        if groups:
            lines += ["The names of this face, by concept, one page each:", ""]
            toctree = [".. toctree::", "   :hidden:", ""]
            for page, sub_title, members in groups:
                refs = ", ".join(f":py:obj:`~{face}.{n}`" for n in members)
                lines += [f"- :doc:`{sub_title} <{stem}/{page}>`: {refs}", ""]
                toctree.append(f"   {stem}/{page}")
                head = f"{sub_title} (``{face}``)"
                sub = [head, "=" * len(head), "", f".. currentmodule:: {face}", ""]
                for name in members:
                    sub += _entry(face, name, getattr(module, name), seen)
                (out / stem).mkdir(exist_ok=True)
                _write(out / stem / f"{page}.rst", sub)
                sub_pages.add(out / stem / f"{page}.rst")
            lines += toctree + [""]
            taken = {n for _, _, members in groups for n in members}
            rest = [n for n in names if n not in taken]
            if rest:
                lines += ["Other names", "-----------", ""]
            names = rest
        for name in names:
            lines += _entry(face, name, getattr(module, name), seen)
        _write(out / f"{stem}.rst", lines)
    index.append("   modules/index")
    mods = ["Modules", "=======", "",
            "Every public module of the two packages, one page each, with its documented "
            "members; the package faces are the supported entry points.", "",
            ".. toctree::", "   :maxdepth: 1", ""]
    written = set()
    for modname in _submodules(app.config.apigen_faces):
        title = f"``{modname}``"
        page = [title, "=" * len(title), "", f".. automodule:: {modname}", "   :members:", ""]
        parent, _, leaf = modname.rpartition(".")
        importlib.import_module(modname)
        if not isinstance(getattr(importlib.import_module(parent), leaf, None), type(sys)):
            page.insert(-1, "   :no-index:")  # the face exports a function of this name
        _write(out / "modules" / f"{modname}.rst", page)
        written.add(f"{modname}.rst")
        mods.append(f"   {modname}")
    _write(out / "modules" / "index.rst", mods)
    _write(out / "index.rst", index)
    # pages of faces or modules that are no longer listed (a module moved) are generated
    # files: remove them
    faces = {f"{face.replace('.', '-')}.rst" for face in app.config.apigen_faces}
    for stale in out.glob("*.rst"):
        if stale.name not in faces | {"index.rst"}:
            stale.unlink()
    for stale in (out / "modules").glob("*.rst"):
        if stale.name not in written | {"index.rst"}:
            stale.unlink()
    for stale in out.glob("*/*.rst"):
        if stale.parent.name != "modules" and stale not in sub_pages:
            stale.unlink()


def _resolve(dotted: str):
    """The class, function or module a dotted name stands for, or None (also for data: two
    attributes may hold one value, e.g. ``None``, without being one object)."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None
        keep = inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj)
        return obj if keep else None
    return None


def _one_object_many_names():
    """Make the Python domain resolve a reference to an object documented under several names
    (a package face's ``particles.InvalidArgumentError`` and its home module's
    ``particles.validation.InvalidArgumentError``) to the face's name, instead of warning that
    more than one target was found; and a reference through a name that is not documented
    (``particles.sticky.StickyParams.to_dict``, documented as ``particles.StickyParams.to_dict``)
    to the documented name of the same object."""
    from sphinx.domains.python import PythonDomain

    original = PythonDomain.find_obj

    def find_obj(self, env, modname, classname, name, type, searchmode=0):
        matches = original(self, env, modname, classname, name, type, searchmode)
        if len(matches) > 1:
            resolved = [_resolve(full) for full, _ in matches]
            if resolved[0] is not None and all(r is resolved[0] for r in resolved):
                return [min(matches, key=lambda m: (m[0].count("."), m[0]))]
        if not matches and name and name.split(".")[0] in ("particles", "maxwell_kinetics"):
            target = _resolve(name)
            if target is not None:
                tail = "." + ".".join(name.split(".")[-2:])
                same = [(full, entry) for full, entry in self.objects.items()
                        if full.endswith(tail) and _resolve(full) is target]
                if same:
                    return [min(same, key=lambda m: (m[0].count("."), m[0]))]
        return matches

    PythonDomain.find_obj = find_obj


def setup(app):
    _one_object_many_names()
    app.add_config_value("apigen_faces", [], "env")
    app.add_config_value("apigen_first", [], "env")
    app.add_config_value("apigen_layers", [], "env")
    app.add_config_value("apigen_split", {}, "env")
    app.connect("builder-inited", write_api)
    return {"parallel_read_safe": True, "version": "1"}
