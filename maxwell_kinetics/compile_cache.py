"""A persistent cache of JAX's compiled executables, shared by the processes of one user.

Without it every new process compiles the kinetic solver again (seconds in 1D, about 15 s in 2D
and 3D).  With it, the first process writes each compiled executable to disk and the next ones
load it instead of compiling.  Two layers, in one folder:

* JAX's persistent compilation cache, with a checked store (below) in place of JAX's file
  cache: every function that JAX compiles; a warm process still traces (Python: seconds for
  the solver in 2D) and then loads instead of compiling.
* The solver's two big functions (``advance``, ``output`` of the kinetic scheme) compiled ahead
  of time and kept as serialized executables (:func:`call`): a warm process neither traces nor
  compiles them, and does not even import diffrax.

The command line turns the cache on for every subcommand that compiles (``solve``,
``fixed-point``, ``convergence``, ``reproduce``); ``--no-cache`` turns it off for one run.
The Python API leaves JAX's configuration alone until asked: :func:`enable` and :func:`disable`.

Where
    ``$MAXWELL_KINETICS_CACHE`` when set to a path; else ``$XDG_CACHE_HOME/maxwell-kinetics/jax``
    when ``XDG_CACHE_HOME`` is an absolute path; else ``~/.cache/maxwell-kinetics/jax``.
    ``MAXWELL_KINETICS_CACHE`` set to ``0``, ``off``, ``no``, ``false`` or ``none`` turns the
    cache off (an empty value means the default folder).  Entries live in one sub-folder per
    (jax, jaxlib, machine, CPU) combination, so that different versions or machines sharing a
    home folder never read each other's executables.  Deleting the folder is always safe.

Safety
    * Each entry is written to a temporary file and renamed into place, so a reader sees a
      whole entry or none, and two processes that start at once (and both compile) both succeed;
      the second rename replaces an equivalent entry.
    * Each entry carries a header and a SHA-256 of its key and content.  An entry that fails the
      check (truncated, garbage, renamed from another key, written by another program, or not
      owned by the current user) is never given to JAX: it is deleted and compiled again, and
      the fresh executable replaces it.  (JAX's own file cache hands anything that decompresses
      to XLA, and keeps a damaged entry forever.)
    * A folder that cannot be used (a file is in the way, or it cannot be written) gives one
      warning line on stderr, and the run goes on without the cache.
    * The checksum guards against damage, not against an attacker: like JAX's cache, the folder
      is trusted, so it is created readable and writable by its owner only.

This module relies on private names of ``jax._src.compilation_cache`` (``_cache``,
``_cache_initialized``, ``_cache_initialized_mutex``) to put the checked store in place of JAX's
file cache; when they are missing (another JAX), the cache stays off with one warning line, and
nothing else changes.
"""

from __future__ import annotations

import hashlib
import os
import platform
import re
import sys
import tempfile
import time
import zlib
from pathlib import Path

__all__ = ["ENV", "default_path", "configured_path", "enable", "disable", "active_path",
           "from_args", "end_command", "add_option", "call"]

#: The environment variable that names the cache folder (or turns the cache off).
ENV = "MAXWELL_KINETICS_CACHE"
_OFF_WORDS = frozenset({"0", "off", "no", "false", "none"})
_MAGIC = b"maxwell-kinetics jax executable v1\n"
_DIGEST = 32
_SUFFIX = ".entry"
_STALE_TMP_SECONDS = 3600.0

_state: dict = {"path": None, "saved": None, "store": None, "root": None}
_warned: set[str] = set()


def default_path() -> Path:
    """``$XDG_CACHE_HOME/maxwell-kinetics/jax`` (XDG_CACHE_HOME absolute), else
    ``~/.cache/maxwell-kinetics/jax``.

    Returns
    -------
    pathlib.Path
        The default cache folder (not created).
    """
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    base = Path(xdg) if xdg and os.path.isabs(xdg) else Path.home() / ".cache"
    return base / "maxwell-kinetics" / "jax"


def configured_path() -> Path | None:
    """The folder that :func:`enable` uses by default: ``$MAXWELL_KINETICS_CACHE`` (None when
    it turns the cache off), else :func:`default_path`.

    Returns
    -------
    pathlib.Path or None
        The folder, or None when the environment variable turns the cache off.
    """
    value = os.environ.get(ENV, "").strip()
    if not value:
        return default_path()
    if value.lower() in _OFF_WORDS:
        return None
    return Path(value).expanduser()


def _cpu_fingerprint() -> str:
    """A short hash of the CPU model and features: XLA compiles for the host CPU, so an
    executable from another machine (a shared home folder) could use missing instructions."""
    text = platform.processor() or ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if line.startswith(("flags", "model name", "Features", "CPU part")):
                    text += line
                elif not line.strip() and text:
                    break  # the first processor is enough
    except OSError:
        pass
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _namespace() -> str:
    import jax
    import jaxlib

    return (f"jax-{jax.__version__}_jaxlib-{jaxlib.__version__}_"
            f"{platform.machine() or 'unknown'}-{_cpu_fingerprint()}")


def _warn_once(root: Path, reason: str) -> None:
    key = f"{root}|{reason}"
    if key not in _warned:
        _warned.add(key)
        print(f"maxwell-kinetics: warning: compilation cache {root} is not usable ({reason}); "
              "running without it", file=sys.stderr)


def _prepare(folder: Path) -> str | None:
    """Create ``folder`` and check that it takes a file; None, or the reason it cannot."""
    try:
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
        if not folder.is_dir():
            return "not a folder"
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        return f"{type(exc).__name__}: {exc.strerror or exc}"
    _remove_stale_temporaries(folder)
    return None


def _remove_stale_temporaries(folder: Path) -> None:
    """Temporary files older than an hour are left by killed writers: remove them."""
    now = time.time()
    for tmp in folder.glob(".tmp-*"):
        try:
            if now - tmp.stat().st_mtime > _STALE_TMP_SECONDS:
                tmp.unlink()
        except OSError:
            pass


def _seal(key: str, value: bytes) -> bytes:
    return _MAGIC + hashlib.sha256(key.encode() + b"\0" + value).digest() + value


def _open(key: str, data: bytes) -> bytes | None:
    """The content of a sealed entry, or None when the header or the checksum is wrong."""
    head = len(_MAGIC)
    if len(data) < head + _DIGEST or not data.startswith(_MAGIC):
        return None
    digest, value = data[head:head + _DIGEST], data[head + _DIGEST:]
    if hashlib.sha256(key.encode() + b"\0" + value).digest() != digest:
        return None
    return value


def _store_class():
    from jax._src.compilation_cache_interface import CacheInterface

    class CheckedStore(CacheInterface):
        """JAX's cache interface over one folder: atomic writes, checked reads."""

        def __init__(self, path: Path):
            self._path = path

        def _file(self, key: str) -> Path:
            name = key if re.fullmatch(r"[A-Za-z0-9_.\-]{1,200}", key) else (
                "h-" + hashlib.sha256(key.encode()).hexdigest())
            return self._path / (name + _SUFFIX)

        def get(self, key: str) -> bytes | None:
            path = self._file(key)
            try:
                with open(path, "rb") as fh:
                    info = os.fstat(fh.fileno())
                    data = fh.read()
            except OSError:
                return None
            value = _open(key, data) if info.st_uid == os.getuid() else None
            if value is None:  # damaged or foreign: never trusted; removed, then rebuilt
                try:
                    if os.stat(path).st_ino == info.st_ino:  # not already replaced by a writer
                        os.unlink(path)
                except OSError:
                    pass
            return value

        def put(self, key: str, value: bytes) -> None:
            tmp = None
            try:
                fd, tmp = tempfile.mkstemp(dir=self._path, prefix=".tmp-")
                with os.fdopen(fd, "wb") as fh:
                    fh.write(_seal(key, value))
                os.replace(tmp, self._file(key))
                tmp = None
            except OSError:
                pass  # a full disk or a removed folder: the run goes on, uncached
            finally:
                if tmp is not None:
                    try:
                        os.unlink(tmp)
                    except OSError:
                        pass

        def clear(self) -> None:
            for entry in self._path.glob("*" + _SUFFIX):
                try:
                    entry.unlink()
                except OSError:
                    pass

    return CheckedStore


def _code_fingerprint() -> str:
    """A hash of the sources of this project (``maxwell_kinetics``, ``particles``) and of the
    versions of the libraries that trace the scheme: an exported computation is reused only
    by the same code."""
    if "code" not in _state:
        import importlib.metadata as md

        import particles

        digest = hashlib.sha256()
        for package in (Path(__file__).parent, Path(particles.__file__).parent):
            for source in sorted(package.rglob("*.py")):
                digest.update(str(source.relative_to(package.parent)).encode() + b"\0")
                digest.update(source.read_bytes())
        for dist in ("jax", "jaxlib", "diffrax", "equinox", "optimistix", "lineax", "numpy"):
            try:
                version = md.version(dist)
            except md.PackageNotFoundError:
                version = "-"
            digest.update(f"{dist}={version};".encode())
        _state["code"] = digest.hexdigest()
    return _state["code"]


def _static_token(static) -> str | None:
    """A text that identifies the static part of the scheme, or None when it cannot (a law
    with a user's characteristic function: its code is not part of any key)."""
    from dataclasses import fields

    from particles.initial import LAWS

    if LAWS.get(static.law.name) is not static.law:
        return None
    parts = []
    for f in fields(static):
        value = getattr(static, f.name)
        parts.append(f"{f.name}={'law:' + value.name if f.name == 'law' else repr(value)}")
    return ";".join(parts)


def _jax_settings() -> str:
    """The backend, its device and JAX's settings that change a trace (those that jit itself
    keys its traces on; values without a stable text are left out)."""
    import enum

    import jax

    try:
        from jax._src.config import trace_context

        plain = (bool, int, float, str, type(None), enum.Enum, tuple)
        settings = [repr(v) for v in trace_context() if isinstance(v, plain)]
    except Exception:  # noqa: BLE001 - another JAX: the public x64 switch at least
        settings = [repr(jax.config.jax_enable_x64)]
    device = jax.devices()[0]
    return f"{jax.default_backend()}:{device.device_kind}:{','.join(settings)}"


def _exported_key(name: str, token: str, args) -> str:
    import jax

    leaves, tree = jax.tree_util.tree_flatten(args)
    avals = [(getattr(x, "shape", ()), str(getattr(x, "dtype", type(x).__name__)),
              bool(getattr(x, "weak_type", False))) for x in leaves]
    text = f"{name}|{token}|{tree}|{avals}|{_jax_settings()}|{_code_fingerprint()}"
    return f"aot_{name}-" + hashlib.sha256(text.encode()).hexdigest()


def _load_compiled(blob: bytes):
    """A compiled executable from an entry's content (checked already); None when it fails."""
    import pickle

    from jax.experimental import serialize_executable

    try:
        serialized, in_tree, out_tree = pickle.loads(zlib.decompress(blob))
        return serialize_executable.deserialize_and_load(serialized, in_tree, out_tree)
    except Exception:  # noqa: BLE001 - whatever fails here, the entry is not used
        return None


def _dump_compiled(compiled) -> bytes | None:
    import pickle

    from jax.experimental import serialize_executable

    try:
        return zlib.compress(pickle.dumps(serialize_executable.serialize(compiled)), 1)
    except Exception:  # noqa: BLE001 - not serializable: kept in memory only
        return None


def call(name: str, function, jitted, static, args: tuple):
    """``jitted(static, *args)``, where ``jitted`` is ``jax.jit(function, static_argnums=0)``;
    with the cache on, through an executable compiled ahead of time and kept in the cache.

    A warm process loads the executable and neither traces nor compiles.  The key hashes
    ``name``, the static part, the shapes and dtypes of ``args``, the backend and JAX's trace
    settings (``_jax_settings``) and a hash of the project's sources (``_code_fingerprint``).
    An entry that does not load (checked, but from a JAX that cannot read it) is compiled again
    and replaced.  With the cache off, or a static part without a key (a user's law),
    ``jitted`` runs as it is.

    Parameters
    ----------
    name : str
        Name of the function in the cache key (e.g. ``"advance"``).
    function : callable
        The Python function ``function(static, *args)`` that ``jitted`` wraps.
    jitted : callable
        ``jax.jit(function, static_argnums=0)``.
    static : object
        The static (hashable) first argument.
    args : tuple
        The array arguments.

    Returns
    -------
    object
        What ``function(static, *args)`` returns (JAX arrays).
    """
    store = _state.get("store")
    token = _static_token(static) if store is not None else None
    if token is None:
        return jitted(static, *args)
    key = _exported_key(name, token, args)
    # Executables in memory: per cache folder (so that each folder gets its entries), and by
    # key alone (an executable compiled here for another folder is stored, not compiled again).
    in_folder = _state.setdefault("compiled", {})
    any_folder = _state.setdefault("compiled_any", {})
    compiled = in_folder.get((_state["path"], key))
    if compiled is None:
        blob = store.get(key)
        compiled = None if blob is None else _load_compiled(blob)
        if compiled is None:
            compiled = any_folder.get(key)
            if compiled is None:
                import jax

                compiled = jax.jit(lambda *a: function(static, *a)).lower(*args).compile()
            blob = _dump_compiled(compiled)
            if blob is not None:
                store.put(key, blob)
        in_folder[(_state["path"], key)] = any_folder[key] = compiled
    return compiled(*args)


def active_path() -> Path | None:
    """The folder of entries in use in this process (None when the cache is off).

    Returns
    -------
    pathlib.Path or None
        The sub-folder that :func:`enable` set up, or None.
    """
    return _state["path"]


def enable(path: str | os.PathLike | None = None) -> Path | None:
    """Turn the persistent cache on in this process; returns the folder of entries in use.

    ``path`` is the cache folder (default :func:`configured_path`); entries go to a
    sub-folder of it named after the jax and jaxlib versions and the machine.  A cache turned
    off by ``$MAXWELL_KINETICS_CACHE`` (``path`` None) returns None; an unusable folder prints
    one warning line on stderr and returns None.  Either way JAX runs as before, uncached.
    This changes JAX's global configuration for the process, until :func:`disable`.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The cache folder; None means :func:`configured_path`.

    Returns
    -------
    pathlib.Path or None
        The folder of entries in use, or None when the cache stays off.
    """
    root = Path(path).expanduser() if path is not None else configured_path()
    if root is None:
        disable()
        return None
    import jax

    folder = root / _namespace()
    if _state["path"] == folder:
        return folder
    disable()
    reason = _prepare(folder)
    if reason is not None:
        _warn_once(root, reason)
        return None
    from jax._src import compilation_cache as cc

    hooks = ("_cache", "_cache_initialized", "_cache_initialized_mutex", "reset_cache")
    if not all(hasattr(cc, name) for name in hooks):
        _warn_once(root, f"jax {jax.__version__} has no hook for it")
        return None
    options = ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs",
               "jax_persistent_cache_enable_xla_caches", "jax_enable_compilation_cache")
    _state["saved"] = {name: getattr(jax.config, name) for name in options}
    jax.config.update("jax_compilation_cache_dir", str(folder))
    jax.config.update("jax_enable_compilation_cache", True)
    # Every executable is kept: the small ones cost a few ms each to compile, and there are many.
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    # XLA's own GPU side caches would write files that bypass the checks: off.
    jax.config.update("jax_persistent_cache_enable_xla_caches", "none")
    cc.reset_cache()
    store = _store_class()(folder)
    with cc._cache_initialized_mutex:
        cc._cache = store
        cc._cache_initialized = True
    _state["path"], _state["store"], _state["root"] = folder, store, root
    return folder


def disable() -> None:
    """Turn off the cache that :func:`enable` turned on (JAX's previous settings come back);
    nothing happens when it is off."""
    if _state["path"] is None:
        return
    import jax
    from jax._src import compilation_cache as cc

    cc.reset_cache()
    for name, value in (_state["saved"] or {}).items():
        jax.config.update(name, value)
    _state["path"], _state["saved"], _state["store"] = None, None, None


def add_option(parser, compiles: bool = True) -> None:
    """Add ``--no-cache`` to a subcommand's parser.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand's parser.
    compiles : bool, default True
        False for a subcommand that compiles nothing (its help text says the option is
        accepted for uniformity).
    """
    text = ("do not use the persistent compilation cache (default: on, in "
            f"${ENV} or ~/.cache/maxwell-kinetics/jax)")
    if not compiles:
        text += "; this subcommand compiles nothing, the option is accepted for uniformity"
    parser.add_argument("--no-cache", action="store_true", help=text)


def from_args(args) -> Path | None:
    """The command line's rule: the cache on unless ``--no-cache``; call it after the input
    checks, right before the first JAX computation.  :func:`end_command` undoes it.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (its ``no_cache`` attribute, False when absent).

    Returns
    -------
    pathlib.Path or None
        What :func:`enable` returns, or None with ``--no-cache``.
    """
    _state.setdefault("before_command", _state["root"] if _state["path"] else None)
    if getattr(args, "no_cache", False):
        disable()
        return None
    return enable()


def end_command() -> None:
    """Put back the cache state from before :func:`from_args` (the command line calls it when
    a subcommand ends, so that a command run in-process leaves JAX as it found it)."""
    if "before_command" not in _state:
        return
    root = _state.pop("before_command")
    if root is None:
        disable()
    else:
        enable(root)
