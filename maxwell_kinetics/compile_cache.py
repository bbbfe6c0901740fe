"""A persistent cache of the solver's compiled executables, shared by the processes of one user.

Without it every new process compiles the kinetic solver again (seconds in 1D, about 15 s in 2D
and 3D).  With it, the first process writes the solver's two big functions (``advance`` and
``output`` of the kinetic scheme), compiled ahead of time, to disk as serialized executables
(:func:`call`), and the next processes load them instead: a warm process neither traces nor
compiles them, and does not even import diffrax.  The velocity-space solver of
:mod:`maxwell_kinetics.inelastic_boltzmann` keeps its four functions there too (its time
integration, right-hand side, steady residual and Jacobian:
:mod:`maxwell_kinetics._boltzmann_compiled`).  Everything else is compiled by ``jax.jit`` as
usual (small functions, milliseconds each).

The cache is on by default, in Python and on the command line alike: the first solve of a
process turns it on in :func:`configured_path` unless :func:`enable` or :func:`disable` was called
before.  ``MAXWELL_KINETICS_CACHE=off`` is the one opt-out for both; on the command line
``--no-cache`` also turns it off for one run (:mod:`maxwell_kinetics.app.cache_options`), and
in Python :func:`disable` for the rest of the
process.  Neither changes any JAX setting: JAX's own persistent compilation cache is never
switched on (nor off) by this module.

Where
    ``$MAXWELL_KINETICS_CACHE`` when set to a path (a relative path is taken from the working
    folder at :func:`enable`); else ``$XDG_CACHE_HOME/maxwell-kinetics/jax`` when
    ``XDG_CACHE_HOME`` is an absolute path; else ``~/.cache/maxwell-kinetics/jax``.
    ``MAXWELL_KINETICS_CACHE`` set to ``0``, ``off``, ``no``, ``false`` or ``none`` turns the
    cache off; ``1``, ``on``, ``yes``, ``true`` or an empty value mean the default folder.
    Entries live in one sub-folder per (jax, jaxlib, machine, CPU) combination, so that
    different versions or machines sharing a home folder never read each other's executables.
    Deleting the folder is always safe; entries not loaded for :data:`UNUSED_DAYS` days (those
    of an older version of the code or of a library) are removed when a process turns the cache
    on.

Safety
    * An executable is written to the folder only after its serialized form was loaded back
      and run once, in place of the executable just compiled, and gave a result: a blob that
      does not run (an executable that XLA serializes incompletely, e.g. one that JAX's own
      persistent cache, switched on by the user, served instead of compiling) is never stored;
      the run goes on with the compiled executable.
    * An entry that loads but fails when it runs is deleted, and the call is compiled again:
      the result is that of a fresh compile, and the fresh executable replaces the entry.
    * Each entry is written to a temporary file and renamed into place, so a reader sees a
      whole entry or none, and two processes that start at once (and both compile) both succeed;
      the second rename replaces an equivalent entry.
    * Each entry carries a header and a SHA-256 of its key and content.  An entry that fails the
      check (truncated, garbage, renamed from another key, written by another program, larger
      than :data:`MAX_ENTRY_BYTES`, or not owned by the current user) is never given to JAX: it
      is deleted and compiled again, and the fresh executable replaces it.
    * Only regular files are read: a symbolic link, a FIFO, a device or a folder with an
      entry's name is skipped without being opened for reading (a FIFO would block the reader
      forever), and the next write replaces it (a folder stays).
    * A folder that cannot be used (a file is in the way, a symbolic-link loop, it cannot be
      written) gives one warning line on stderr, and the run goes on without the cache.  A
      write that fails later (a full disk) is skipped silently.
    * The checksum guards against damage, not against an attacker: like JAX's cache, the folder
      is trusted (loading an executable runs its code), so it is created readable and writable
      by its owner only.

This module uses JAX's public API only: ``jax.jit(...).lower(...).compile()``,
``jax.experimental.serialize_executable`` and, for the key, ``jax.config.values``.
"""

from __future__ import annotations

import hashlib
import os
import platform
import re
import stat
import sys
import tempfile
import time
import zlib
from pathlib import Path

__all__ = ["ENV", "MAX_ENTRY_BYTES", "UNUSED_DAYS", "default_path", "configured_path", "enable",
           "disable", "active_path", "current_choice", "restore_choice", "call"]

# The command-line glue moved out of this module: importing a name of it from here raises an
# ImportError naming its new home (it is not re-exported: each name has one home).
_MOVED = {name: "maxwell_kinetics.app.cache_options"
          for name in ("add_option", "from_args", "end_command")}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"maxwell_kinetics.compile_cache.{name} moved to {_MOVED[name]}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

#: The environment variable that names the cache folder (or turns the cache off).
ENV = "MAXWELL_KINETICS_CACHE"
#: Entries larger than this (bytes) are damaged by definition: never read, deleted.  The
#: solver's executables weigh about 0.1 MB in 1D and a few MB in 3D.
MAX_ENTRY_BYTES = 256 * 2**20
#: Entries that no process has loaded (or written) for this many days are removed when a
#: process turns the cache on.
UNUSED_DAYS = 30
_OFF_WORDS = frozenset({"0", "off", "no", "false", "none"})
_ON_WORDS = frozenset({"1", "on", "yes", "true"})
_MAGIC = b"maxwell-kinetics jax executable v1\n"
_DIGEST = 32
_SUFFIX = ".entry"
_STALE_TMP_SECONDS = 3600.0

# "decided": enable() or disable() was called (by the user, the command line, or the first
# call() that turned the cache on by default); until then call() enables it.
_state: dict = {"path": None, "store": None, "root": None, "decided": False}
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
    it turns the cache off, :func:`default_path` when it is empty or says on), else
    :func:`default_path`.

    Returns
    -------
    pathlib.Path or None
        The folder, or None when the environment variable turns the cache off.
    """
    value = os.environ.get(ENV, "").strip()
    if not value or value.lower() in _ON_WORDS:
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
        shown = str(root) if str(root).isprintable() else repr(str(root))  # one line
        shown = shown if len(shown) <= 200 else shown[:200] + "..."
        print(f"maxwell-kinetics: warning: compilation cache {shown} is not usable ({reason}); "
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
    _remove_stale(folder)
    return None


def _remove_stale(folder: Path) -> None:
    """Remove temporary files older than an hour (left by killed writers) and entries that no
    process has loaded for :data:`UNUSED_DAYS` days (those of an older version of the code or
    of a library: without this the folder would grow with every upgrade)."""
    now = time.time()
    for pattern, age in ((".tmp-*", _STALE_TMP_SECONDS), ("*" + _SUFFIX, UNUSED_DAYS * 86400.0)):
        for path in folder.glob(pattern):
            try:
                info = os.lstat(path)
                if not stat.S_ISDIR(info.st_mode) and now - info.st_mtime > age:
                    path.unlink()
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


class _Store:
    """The entries of one folder: atomic writes, checked reads of regular files only."""

    def __init__(self, path: Path):
        self._path = path
        self._read: dict[str, tuple[int, int]] = {}  # key -> (device, inode) of the entry read

    def _file(self, key: str) -> Path:
        name = key if re.fullmatch(r"[A-Za-z0-9_.\-]{1,200}", key) else (
            "h-" + hashlib.sha256(key.encode()).hexdigest())
        return self._path / (name + _SUFFIX)

    def get(self, key: str) -> bytes | None:
        """The content stored under ``key``; None when there is none, or it is not a regular
        file (left alone), or it fails the checks (then it is removed)."""
        path = self._file(key)
        try:
            if not stat.S_ISREG(os.lstat(path).st_mode):
                return None  # a link, FIFO, device or folder: never opened
            flags = (os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOFOLLOW", 0)
                     | getattr(os, "O_CLOEXEC", 0))
            fd = os.open(path, flags)
        except OSError:
            return None
        try:
            info = os.fstat(fd)
            if not stat.S_ISREG(info.st_mode):  # replaced between lstat and open
                return None
            data = None
            if info.st_uid == os.getuid() and info.st_size <= MAX_ENTRY_BYTES:
                with os.fdopen(os.dup(fd), "rb") as fh:
                    data = fh.read(MAX_ENTRY_BYTES + 1)
        except OSError:
            return None
        finally:
            os.close(fd)
        value = _open(key, data) if data is not None and len(data) <= MAX_ENTRY_BYTES else None
        if value is None:  # damaged or foreign: never trusted; removed, then rebuilt
            self._remove(path, (info.st_dev, info.st_ino))
        else:
            self._read[key] = (info.st_dev, info.st_ino)
            try:  # used now: kept another UNUSED_DAYS days
                os.utime(path, follow_symlinks=False)
            except (OSError, NotImplementedError):
                pass
        return value

    def drop(self, key: str) -> None:
        """Remove the entry that :meth:`get` returned for ``key`` (it failed when it ran),
        unless another process has replaced it since."""
        if key in self._read:
            self._remove(self._file(key), self._read.pop(key))

    @staticmethod
    def _remove(path: Path, identity: tuple[int, int]) -> None:
        try:
            info = os.lstat(path)
            if (info.st_dev, info.st_ino) == identity:  # not already replaced by a writer
                os.unlink(path)
        except OSError:
            pass

    def put(self, key: str, value: bytes) -> None:
        """Store ``value`` under ``key`` (a temporary file renamed into place); a failure (a
        full disk, a removed folder, a folder in the way) is skipped."""
        tmp = None
        try:
            fd, tmp = tempfile.mkstemp(dir=self._path, prefix=".tmp-")
            with os.fdopen(fd, "wb") as fh:
                fh.write(_seal(key, value))
            os.replace(tmp, self._file(key))
            tmp = None
        except OSError:
            pass  # the run goes on, uncached
        finally:
            if tmp is not None:
                try:
                    os.unlink(tmp)
                except OSError:
                    pass


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
    """A text that identifies the static part (a dataclass) of a compiled function, or None when
    it cannot (a ``law`` field with a user's characteristic function: its code is not part of
    any key)."""
    from dataclasses import fields

    from particles.initial import LAWS

    parts = []
    for f in fields(static):
        value = getattr(static, f.name)
        if f.name == "law":
            if LAWS.get(value.name) is not value:
                return None
            value = "law:" + value.name
        else:
            value = repr(value)
        parts.append(f"{f.name}={value}")
    return ";".join(parts)


def _jax_settings() -> str:
    """The backend, its device and every JAX setting with a stable text (``jax.config.values``,
    public: a superset of those that change a trace, so a setting that changes nothing only
    costs a compile, never a wrong executable)."""
    import enum

    import jax

    plain = (bool, int, float, str, type(None), enum.Enum, tuple)
    values = getattr(jax.config, "values", None)
    if isinstance(values, dict):
        settings = [f"{k}={v!r}" for k, v in sorted(values.items()) if isinstance(v, plain)]
    else:  # a JAX without the public table: the x64 switch at least
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


def _bind_lapack() -> None:
    """Bind jaxlib's LAPACK kernels, once per process, before an executable is loaded.

    jaxlib binds them (to SciPy's LAPACK) only when JAX lowers a linear-algebra operation for
    the CPU; an executable loaded from the cache calls them without any lowering, and in a
    process that has lowered none it crashes (a segmentation fault: the velocity-space solver's
    ``jnp.linalg.solve``).  Lowering one small LU (no compilation) binds them, as
    ``jax.export`` does before it runs a deserialized function.
    """
    if _state.get("lapack"):
        return
    import jax

    if jax.default_backend() == "cpu":
        jax.jit(jax.lax.linalg.lu).lower(jax.ShapeDtypeStruct((2, 2), "float32"))
    _state["lapack"] = True


def _load_compiled(blob: bytes):
    """A compiled executable from an entry's content (checked already); None when it fails."""
    import pickle

    from jax.experimental import serialize_executable

    try:
        _bind_lapack()
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


def _try(blob: bytes, args: tuple):
    """``(result, executable)``: the executable of ``blob`` run on ``args`` and waited for (an
    executable that cannot run fails here, not later when its result is read); ``(None,
    None)`` when it does not load or raises when it runs."""
    import jax

    loaded = _load_compiled(blob)
    if loaded is None:
        return None, None
    try:
        return jax.block_until_ready(loaded(*args)), loaded
    except Exception:  # noqa: BLE001 - whatever fails here, the blob is not used
        return None, None


def call(name: str, function, jitted, static, args: tuple):
    """``jitted(static, *args)``, where ``jitted`` is ``jax.jit(function, static_argnums=0)``;
    with the cache on, through an executable compiled ahead of time and kept in the cache.

    A warm process loads the executable and neither traces nor compiles.  The key hashes
    ``name``, the static part, the shapes and dtypes of ``args``, the backend and JAX's trace
    settings (``_jax_settings``) and a hash of the project's sources and of the versions of the
    libraries that trace the scheme (``_code_fingerprint``).  The first call of a loaded entry
    in a process is waited for: an entry that does not load, or that raises when it runs, is
    deleted and the call is compiled afresh.  The first call of a process in which neither
    :func:`enable` nor :func:`disable` was called turns the cache on (:func:`enable`, which
    honours ``MAXWELL_KINETICS_CACHE=off``).  A fresh executable is serialized, loaded back and
    run in its place; only when that run succeeds is the serialized form stored (else the
    compiled executable gives the result, and nothing is stored).  With the cache off, or a
    static part without a key (a user's law), ``jitted`` runs as it is.

    Parameters
    ----------
    name : str
        Name of the function in the cache key (e.g. ``"step"``).
    function : callable
        The Python function ``function(static, *args)`` that ``jitted`` wraps.
    jitted : callable
        ``jax.jit(function, static_argnums=0)``.
    static : object
        The static (hashable) first argument.
    args : tuple
        The array arguments (never donated: a failed run leaves them intact).

    Returns
    -------
    object
        What ``function(static, *args)`` returns (JAX arrays).

    Raises
    ------
    Exception
        Whatever a freshly compiled executable raises when it runs (never an error of a
        cache entry).
    """
    if not _state["decided"]:
        enable()  # the default: on in configured_path(), unless MAXWELL_KINETICS_CACHE=off
    store = _state.get("store")
    token = _static_token(static) if store is not None else None
    if token is None:
        return jitted(static, *args)
    key = _exported_key(name, token, args)
    # Executables that ran in this process, with the blob that is known to load and run (None
    # when there is none): per cache folder, and by key alone (an executable that ran here for
    # another folder is stored there, not compiled again).  A loaded executable is never
    # serialized again: XLA may serialize it incompletely.
    in_folder = _state.setdefault("compiled", {})
    any_folder = _state.setdefault("compiled_any", {})
    compiled = in_folder.get((_state["path"], key))
    if compiled is not None:
        return compiled(*args)
    known = any_folder.get(key)
    if known is not None:
        compiled, blob = known
        if blob is not None:
            store.put(key, blob)
        in_folder[(_state["path"], key)] = compiled
        return compiled(*args)
    blob = store.get(key)
    if blob is not None:
        out, loaded = _try(blob, args)
        if loaded is not None:
            in_folder[(_state["path"], key)] = loaded
            any_folder[key] = (loaded, blob)
            return out
        store.drop(key)  # it does not load, or it fails when it runs: compiled afresh
    import jax

    compiled = jax.jit(lambda *a: function(static, *a)).lower(*args).compile()
    blob = _dump_compiled(compiled)
    out, loaded = (None, None) if blob is None else _try(blob, args)
    if loaded is None:  # not serializable, or not whole: kept in memory only
        blob = None
        out = compiled(*args)
    else:
        store.put(key, blob)  # loaded back and run: whole
        compiled = loaded
    in_folder[(_state["path"], key)] = compiled
    any_folder[key] = (compiled, blob)
    return out


def active_path() -> Path | None:
    """The folder of entries in use in this process (None when the cache is off).

    Returns
    -------
    pathlib.Path or None
        The sub-folder that :func:`enable` set up, or None.
    """
    return _state["path"]


def enable(path: str | os.PathLike | None = None) -> Path | None:
    """Turn the cache on in this process; returns the folder of entries in use.

    ``path`` is the cache folder (default :func:`configured_path`); entries go to a
    sub-folder of it named after the jax and jaxlib versions and the machine.  A cache turned
    off by ``$MAXWELL_KINETICS_CACHE`` (``path`` None) returns None; an unusable folder prints
    one warning line on stderr and returns None.  Either way the solver runs as before,
    uncached.  No JAX setting changes (JAX's own persistent cache stays as the user set it);
    only :func:`call` uses the folder, until :func:`disable`.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The cache folder; None means :func:`configured_path`.  A relative path is taken from
        the working folder now.

    Returns
    -------
    pathlib.Path or None
        The folder of entries in use, or None when the cache stays off.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``path`` when it is neither None nor a non-empty path (a number, a bool, ``""``,
        which would put the cache in the working folder), before anything changes.
    """
    if path is not None and (not isinstance(path, (str, os.PathLike))
                             or not str(os.fspath(path)).strip()):
        from particles.validation import InvalidArgumentError

        raise InvalidArgumentError("path", path, "a folder path (a non-empty str or "
                                   "os.PathLike) or None")
    _state["decided"] = True
    root = Path(path).expanduser() if path is not None else configured_path()
    if root is None:
        disable()
        return None
    root = root.absolute()
    folder = root / _namespace()
    if _state["path"] == folder:
        return folder
    disable()
    reason = _prepare(folder)
    if reason is not None:
        _warn_once(root, reason)
        return None
    _state["path"], _state["store"], _state["root"] = folder, _Store(folder), root
    return folder


def disable() -> None:
    """Turn off the cache that :func:`enable` turned on (also the default one of the first
    solve: after ``disable()`` the process stays uncached until :func:`enable`)."""
    _state["path"], _state["store"], _state["decided"] = None, None, True


def current_choice() -> tuple:
    """The cache's state as :func:`restore_choice` takes it back: the root folder in use (None
    when off) and whether :func:`enable` or :func:`disable` was called in this process (until
    then the first solve turns the cache on by default).

    Returns
    -------
    tuple
        ``(root or None, decided)``; opaque to callers.
    """
    return (_state["root"] if _state["path"] else None, bool(_state["decided"]))


def restore_choice(choice: tuple) -> None:
    """Put back a state from :func:`current_choice` (the command line does so when a subcommand
    run in-process ends).

    Parameters
    ----------
    choice : tuple
        What :func:`current_choice` returned.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``choice`` for anything but such a pair (a root folder or None, and a bool),
        before anything changes.
    """
    if not (isinstance(choice, tuple) and len(choice) == 2 and isinstance(choice[1], bool)
            and (choice[0] is None or isinstance(choice[0], (str, os.PathLike)))):
        from particles.validation import InvalidArgumentError

        raise InvalidArgumentError("choice", choice, "what current_choice() returned: (a root "
                                   "folder or None, a bool)")
    root, decided = choice
    if root is None:
        disable()
    else:
        enable(root)
    _state["decided"] = decided
