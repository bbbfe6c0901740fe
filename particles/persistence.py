"""One way to save and load every file the project writes (NumPy only).

A file is an uncompressed ``.npz`` (zip) archive: one ``.npy`` entry per array plus a ``meta``
entry holding a JSON object with

* ``format``: ``"maxwell-kinetics"`` (the tag of this helper);
* ``kind``: what the file holds (``"result"``, ``"checkpoint"``, ``"solution"``,
  ``"comparison"``, ...), and ``version``, the kind's format version;
* ``sha256``: the SHA-256 of the content (the JSON of the other meta fields with sorted keys, then
  the SHA-256 of each array's name, dtype, shape and bytes, in the order of the sorted names), so
  an edited or damaged file is refused.  On loading, each array's digest is computed in a second
  thread while the next array is read (hashlib releases the GIL), which hides most of the cost of
  the check on two cores (``benchmarks/persistence.py``);
* the caller's own fields.

Writing goes to a temporary file in the same folder, then :func:`os.replace` renames it into place:
a reader never sees half a file, and a writer killed half-way leaves only a ``<name>.<random>.tmp``
(or, where that name would pass the file system's limit on the length of a name,
``.<hash of name>.<random>.tmp``: :func:`sibling_name`) that :func:`save` removes on a later write
to the same path (a temporary file that another writer still holds is left alone).  A write that
fails (disk full, a folder that became read-only, ...) removes its temporary file, leaves an
existing file of that name as it was and raises :class:`WriteError`, one line naming the file and
the reason.  The rename happens only onto a regular file or onto nothing (:func:`write_atomic`):
an output path that is a device (``/dev/null`` too), a FIFO, a socket or a directory is refused,
and a symlink is followed, so its target is replaced and the link stays.

Reading treats the file as untrusted: only regular files are opened (a FIFO would block); every
entry's ``.npy`` header (dtype and shape) is read and checked *before* its data is, so a zip bomb
or a header that declares a huge shape is refused without allocating; object arrays (which would
need pickle) are refused; an entry larger than its header says is refused; the total size is
capped (``max_bytes``, default the smaller of 8 GiB and half the memory available); then the hash
is verified.  Files in the formats of 0.1.0 (before this helper) load as ``legacy``: no hash.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import glob
import hashlib
import json
import os
import re
import stat
import tempfile
import zipfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .paths import check_path, file_kind, output_target
from .validation import InvalidArgumentError

__all__ = ["FileFormatError", "WriteError", "Loaded", "FORMAT_TAG", "save", "load", "digest",
           "write_atomic", "write_text", "save_figure", "read_meta", "sibling_name", "name_max",
           "check_name_length", "name_outputs"]

FORMAT_TAG = "maxwell-kinetics"
META = "meta"
#: Default cap on the bytes of all arrays of one file (data, after decompression).
DEFAULT_MAX_BYTES = 8 * 2**30
#: Cap on the JSON meta entry.
MAX_META_BYTES = 64 * 2**20
_RESERVED = ("format", "kind", "version", "sha256")
_ALLOWED_KINDS = "biufcUS"  # bool, int, uint, float, complex, str, bytes; never object


class _Refused(ValueError):
    """A reason of this module's own to refuse a file (reported without a type name)."""


class FileFormatError(InvalidArgumentError):
    """A file that cannot be read as the expected kind: names the file and the reason.

    A subclass of :class:`particles.validation.InvalidArgumentError`, so the CLI reports it as
    a bad argument (exit 2).

    Parameters
    ----------
    path : str or os.PathLike
        The file (kept as ``str`` in the attribute ``path``).
    reason : str
        Why it was refused (kept in the attribute ``reason``).
    argument : str, optional
        The name of the argument that gave the file (default ``"path"``).
    expected : str, optional
        What was expected, e.g. ``"a result file"`` (default ``"a file"``).
    """

    def __init__(self, path, reason: str, argument: str = "path", expected: str = "a file"):
        self.path = str(path)
        self.reason = reason
        super().__init__(argument, self.path, f"{expected} ({reason})")


class WriteError(InvalidArgumentError):
    """An output file that could not be written: names the file, the argument that gave it
    and the reason (``No space left on device``, ...); the file was left as it was (or absent).

    A subclass of :class:`particles.validation.InvalidArgumentError`, so a caller that catches
    bad arguments catches it too; ``exit_status`` is the command line's exit status: 3 when the
    file system failed the write (disk full, quota, I/O error: the work was done, the task
    failed), 2 when the path itself is unusable (a name too long, no permission, a read-only
    file system).

    Parameters
    ----------
    path : str or os.PathLike
        The file (kept as ``str`` in the attribute ``path``).
    error : OSError
        The failure (its ``errno`` is kept in the attribute ``errno``).
    argument : str, optional
        The argument that gave the file (default ``"path"``).
    """

    #: errno values of a file system that fails a write of a valid path.
    FAILED_WRITE = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.EFBIG})

    def __init__(self, path, error: OSError, argument: str = "path"):
        self.path = str(path)
        self.errno = error.errno
        reason = error.strerror or str(error) or type(error).__name__
        self.exit_status = 3 if error.errno in self.FAILED_WRITE else 2
        super().__init__(argument, self.path, "a file that can be written")
        self.args = (
            f"argument {argument}={_shown(self.path)!r}: cannot write the file: {reason} "
            "(it is left as it was)",
        )

    def __str__(self) -> str:
        return self.args[0]


def _shown(text: str, limit: int = 200) -> str:
    """``text``, cut to ``limit`` characters with an ellipsis (for error messages)."""
    return text if len(text) <= limit else text[:limit] + "..."


@dataclass(frozen=True)
class Loaded:
    """What :func:`load` returns: the meta fields, the arrays, the version and whether the
    file is a legacy one (written before the hash existed).

    Attributes
    ----------
    meta : dict
        The JSON meta fields (the reserved ``format``, ``kind``, ``version``, ``sha256`` too).
    arrays : dict of str to numpy.ndarray
        The arrays by name (read-only views of the file's bytes).
    version : int
        The kind's format version of the file.
    legacy : bool
        True for a file of the formats of version 0.1.0 (no hash checked).
    """

    meta: dict
    arrays: dict[str, np.ndarray] = field(repr=False)
    version: int
    legacy: bool = False


# --------------------------------------------------------------------------- hashing


def entry_digest(name: str, a: np.ndarray) -> bytes:
    """SHA-256 of one array: its name, dtype, shape and bytes (C order)."""
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"\0{name}\0{a.dtype.str}\0{a.shape}\0".encode())
    h.update(memoryview(a).cast("B") if a.size else b"")
    return h.digest()


def digest(meta: dict, arrays: dict[str, np.ndarray], entries: dict | None = None) -> str:
    """SHA-256 (hex) of ``meta`` (without ``sha256``) and ``arrays``: the JSON of the meta
    fields with sorted keys, then the :func:`entry_digest` of each array in the order of the
    sorted names (``entries`` may hold those already computed, e.g. while reading).

    Parameters
    ----------
    meta : dict
        The meta fields (a ``sha256`` key is ignored).
    arrays : dict of str to numpy.ndarray
        The arrays by name.
    entries : dict of str to bytes, optional
        Per-array digests already computed, by name.

    Returns
    -------
    str
        The hexadecimal SHA-256.
    """
    h = hashlib.sha256()
    fields = {k: v for k, v in meta.items() if k != "sha256"}
    h.update(json.dumps(fields, sort_keys=True, allow_nan=True).encode())
    for name in sorted(arrays):
        done = None if entries is None else entries.get(name)
        h.update(done if done is not None else entry_digest(name, arrays[name]))
    return h.hexdigest()


# --------------------------------------------------------------------------- writing


#: The user's names of the outputs of this command: {real path: argument}, set by
#: :func:`name_outputs`; a write whose caller names no argument (``"path"``) reports this one.
_ARGUMENT_OF: dict[str, str] = {}


def name_outputs(names: dict) -> None:
    """Say which argument gave each output path, so that an error of a write deep in the
    library (:meth:`Solution.save`, :meth:`RunResult.save`, whose argument is ``path``) names
    the user's option instead.  Replaces the names set before.

    Parameters
    ----------
    names : dict
        ``{path: argument name}``; paths are compared after resolving symlinks.
    """
    _ARGUMENT_OF.clear()
    for path, argument in names.items():
        _ARGUMENT_OF[os.path.realpath(path)] = str(argument)


def _argument(target, name: str) -> str:
    if name != "path":
        return name
    return _ARGUMENT_OF.get(os.path.realpath(target), name)


def name_max(folder) -> int:
    """The longest file name (bytes) the file system of ``folder`` takes (255 if unknown; the
    nearest existing ancestor is asked when ``folder`` does not exist yet).

    Parameters
    ----------
    folder : str or os.PathLike
        A folder.

    Returns
    -------
    int
        ``NAME_MAX`` of that file system.
    """
    folder = Path(os.path.abspath(folder))
    for candidate in (folder, *folder.parents):
        try:
            return int(os.pathconf(candidate, "PC_NAME_MAX"))
        except (OSError, ValueError):
            continue
    return 255


def check_name_length(path, name: str) -> Path:
    """Refuse a path with a component longer than its file system takes (``NAME_MAX`` bytes,
    255 on most) or longer than ``PATH_MAX`` in all, before any work (the write would fail
    with "File name too long" after it).

    Parameters
    ----------
    path : str or os.PathLike
        The output path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``name`` and the path, saying how long the offending name is.
    """
    path = check_path(path, name)
    limit = name_max(path.parent if str(path.parent) else ".")
    for part in path.parts:
        size = len(os.fsencode(part))
        if size > limit:
            raise InvalidArgumentError(
                name, str(path),
                f"file and folder names of at most {limit} bytes (one has {size})",
            )
    try:
        path_max = int(os.pathconf("/", "PC_PATH_MAX"))
    except (OSError, ValueError):
        path_max = 4096
    size = len(os.fsencode(path))
    if size >= path_max:
        raise InvalidArgumentError(name, str(path),
                                   f"a path of fewer than {path_max} bytes (it has {size})")
    return path


def sibling_name(target, suffix: str, reserve: int = 0) -> str:
    """A name in ``target``'s folder for a file that goes with ``target`` (a temporary file, a
    lock): ``<name><suffix>`` when that and ``reserve`` more bytes fit the file system's limit
    on names, otherwise the short ``.<hash of name><suffix>`` (16 hexadecimal digits of a
    SHA-256), so that a legal output name never makes its companion's name too long.

    Parameters
    ----------
    target : str or os.PathLike
        The output file.
    suffix : str
        What follows the name, e.g. ``".lock"``.
    reserve : int, optional
        Bytes the caller adds after the name (a random part and ``.tmp``), default 0.

    Returns
    -------
    str
        The companion's name (a name, not a path).
    """
    target = Path(target)
    folder = target.parent if str(target.parent) else Path(".")
    plain = target.name + suffix
    if len(os.fsencode(plain)) + reserve <= name_max(folder):
        return plain
    return "." + hashlib.sha256(os.fsencode(target.name)).hexdigest()[:16] + suffix


#: The random part mkstemp puts in a name (letters, digits and underscores; no dot).
_RANDOM = re.compile(r"[A-Za-z0-9_]+")
#: Bytes a temporary name adds after its prefix: mkstemp's random part (8 characters in
#: CPython; room for 16) and ``.tmp``.
_TMP_RESERVE = 16 + len(".tmp")


def _tmp_prefix(target: Path) -> str:
    return sibling_name(target, ".", _TMP_RESERVE)


def _clean_stale(path: Path) -> None:
    """Remove temporary files a killed writer of ``path`` left behind (``<name>.<random>.tmp``
    or its hashed form); one that a live writer holds (its ``flock``) is left alone, and so is
    the temporary file of another name (``<name>.<other>.<random>.tmp``)."""
    folder = path.parent if str(path.parent) else Path(".")
    for prefix in {_tmp_prefix(path), path.name + "."}:
        for stale in glob.glob(glob.escape(str(folder / prefix)) + "*.tmp"):
            middle = os.path.basename(stale)[len(prefix):-len(".tmp")]
            if not _RANDOM.fullmatch(middle):
                continue
            try:
                fd = os.open(stale, os.O_RDONLY | os.O_NOFOLLOW)
            except OSError:
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # held by a live writer: skip
                os.unlink(stale)
            except OSError:
                pass
            finally:
                os.close(fd)


def write_atomic(path, write, name: str = "path") -> Path:
    """Write a file atomically: ``write(fh)`` fills a temporary file (binary) in the target's
    folder, which is then renamed onto the target.  Returns ``path``.

    The target is :func:`particles.paths.output_target`: ``path`` itself, or the file a
    symlink names (the link stays a link).  The rename happens only onto a regular file or onto
    nothing: a directory, a device (``/dev/null`` included), a FIFO or a socket is refused with
    :class:`InvalidArgumentError` naming ``name``, before anything is written, and checked
    again just before the rename (nothing is replaced if one appeared meanwhile).  The
    temporary file's name (:func:`sibling_name`) never passes the file system's limit; the
    writer holds an ``flock`` on it, so that another writer's clean-up leaves it alone.

    Parameters
    ----------
    path : str or os.PathLike
        The output file.
    write : callable
        ``write(fh)`` writes the content to the open binary file ``fh``.
    name : str, optional
        The argument name errors report (default ``"path"``: then the name given to the path
        by :func:`name_outputs`, if any).

    Returns
    -------
    pathlib.Path
        ``path`` (as validated by :func:`particles.paths.check_path`).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``name``) for an invalid path (one ending in ``/`` too) or a target that is
        not a regular file.
    WriteError
        (argument ``name``) when the file system refuses the write (disk full, name too long,
        no permission, ...): the temporary file is removed and an existing file at ``path`` is
        left as it was.
    """
    given = path
    path = check_path(path, name)
    name = _argument(path, name)
    if os.fspath(given).endswith(os.sep):  # a folder's path: Path would drop the "/"
        raise InvalidArgumentError(name, str(given), "a file path, not a folder (it ends in '/')")
    target = output_target(path, name)
    directory = target.parent if str(target.parent) else Path(".")
    _clean_stale(target)
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=_tmp_prefix(target), suffix=".tmp",
                                   dir=directory)
        with os.fdopen(fd, "wb") as fh:
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)  # ours until renamed
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())  # a full disk is reported here, not after the rename
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file normal permissions
            if file_kind(target) not in (None, "regular file"):  # appeared while we wrote
                output_target(target, name)
            os.replace(tmp, target)
            tmp = None
    except OSError as exc:
        raise WriteError(path, exc, name) from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    return path


def save(path, kind: str, version: int, arrays: dict, meta: dict | None = None,
         argument: str = "path") -> Path:
    """Write ``arrays`` and ``meta`` to ``path`` atomically (:func:`write_atomic`: never onto a
    device, a FIFO, a socket or a directory; a symlink's target is written), with the format
    tag, ``kind``, ``version`` and the content hash.  Returns the path.

    Parameters
    ----------
    path : str or os.PathLike
        The output file (conventionally ``.npz``).
    kind : str
        What the file holds, e.g. ``"result"`` or ``"checkpoint"``.
    version : int
        The kind's format version.
    arrays : dict
        Named arrays of bool, integer, float, complex or string dtype (no object arrays).
    meta : dict, optional
        JSON-serialisable fields of the caller; must not use the reserved keys ``format``,
        ``kind``, ``version``, ``sha256``.
    argument : str, optional
        The argument name errors about ``path`` report (default ``"path"``).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    particles.InvalidArgumentError
        ``meta`` uses a reserved key; ``arrays`` holds an entry named ``meta`` or of an object
        dtype; ``path`` is invalid or not a writable regular-file target.
    WriteError
        When the file system refuses the write (:func:`write_atomic`).
    """
    path = check_path(path, argument)
    argument = _argument(path, argument)
    output_target(path, argument)  # refused before the content is hashed
    meta = dict(meta or {})
    clash = [k for k in _RESERVED if k in meta]
    if clash:
        raise InvalidArgumentError("meta", clash, f"no reserved keys {_RESERVED}")
    arrays = {str(k): np.asarray(v) for k, v in arrays.items()}
    for name, a in arrays.items():
        if name == META or a.dtype.kind not in _ALLOWED_KINDS:
            raise InvalidArgumentError("arrays", f"{name}: {a.dtype}", "named numeric arrays")
    header = {**meta, "format": FORMAT_TAG, "kind": kind, "version": int(version)}
    header["sha256"] = digest(header, arrays)
    text = json.dumps(header, allow_nan=True)
    return write_atomic(path, lambda fh: np.savez(fh, **{META: np.array(text)}, **arrays),
                        argument)


def write_text(path, text: str, name: str = "path") -> Path:
    """Write ``text`` (UTF-8) to ``path`` through :func:`write_atomic`.

    Parameters
    ----------
    path : str or os.PathLike
        The output file.
    text : str
        The content.
    name : str, optional
        The argument name errors report (default ``"path"``).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    return write_atomic(path, lambda fh: fh.write(text.encode()), name)


def save_figure(fig, path, name: str = "path", **kwargs) -> Path:
    """``fig.savefig`` through :func:`write_atomic` (format from the suffix; ``kwargs`` go to
    ``savefig``).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or os.PathLike
        The output file; its suffix chooses the format.
    name : str, optional
        The argument name errors report (default ``"path"``).
    **kwargs
        Passed on to ``fig.savefig``.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    path = check_path(path, name)
    fmt = path.suffix.lstrip(".").lower() or None
    return write_atomic(path, lambda fh: fig.savefig(fh, format=fmt, **kwargs), name)


# --------------------------------------------------------------------------- reading


def _read_exact(stream, size: int) -> bytearray:
    """Up to ``size`` bytes of ``stream`` into a writable buffer (shorter if the stream ends)."""
    buf = bytearray(size)
    view, pos = memoryview(buf), 0
    while pos < size:
        got = stream.readinto(view[pos : pos + (1 << 24)])
        if not got:
            del view
            return buf[:pos]
        pos += got
    del view
    return buf


def _npy_header(stream):
    """(dtype, shape, fortran_order) of an ``.npy`` stream, reading the header only."""
    version = np.lib.format.read_magic(stream)
    if version == (1, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_1_0(stream, max_header_size=10000)
    elif version in ((2, 0), (3, 0)):
        shape, fortran, dtype = np.lib.format.read_array_header_2_0(stream, max_header_size=10000)
    else:  # pragma: no cover - read_magic already refuses other versions
        raise _Refused(f"npy version {version}")
    return dtype, shape, fortran


def _entries(zf: zipfile.ZipFile) -> dict[str, zipfile.ZipInfo]:
    out = {}
    for info in zf.infolist():
        if not info.filename.endswith(".npy") or info.is_dir():
            raise _Refused(f"entry {info.filename!r} is not an array")
        name = info.filename[:-4]
        if name in out:
            raise _Refused(f"entry {info.filename!r} appears twice")
        out[name] = info
    return out


def _read_meta(zf, info, max_meta: int) -> tuple[str, dict]:
    with zf.open(info) as stream:
        dtype, shape, fortran = _npy_header(stream)
        if dtype.kind != "U" or shape != ():
            raise _Refused(f"the meta entry is {dtype} of shape {shape}, not a string")
        if dtype.itemsize > max_meta:
            raise _Refused(f"the meta entry declares {dtype.itemsize} bytes")
        raw = _read_exact(stream, dtype.itemsize)
    text = str(np.frombuffer(raw, dtype=dtype, count=1)[0])
    meta = json.loads(text)
    if not isinstance(meta, dict):
        raise _Refused("the meta entry is not a JSON object")
    return text, meta


def _legacy(kind: str, names: dict, zf) -> tuple[dict, int, str] | None:
    """(meta, version, meta entry name) of a file of 0.1.0 of ``kind``, or None."""
    if kind == "comparison" and "__skeleton__" in names:
        _, meta = _read_meta(zf, names["__skeleton__"], MAX_META_BYTES)
        if meta.get("format") == "maxwell_kinetics.Comparison/2":
            return meta, 2, "__skeleton__"
        return None
    if META not in names:
        return None
    _, meta = _read_meta(zf, names[META], MAX_META_BYTES)
    if kind in ("result", "checkpoint") and meta.get("kind") == kind and meta.get("format") == 1:
        return meta, 1, META
    if kind == "solution" and meta.get("format") == "maxwell_kinetics.Solution/1":
        return meta, 1, META
    return None


def read_meta(path, argument: str = "path") -> dict:
    """The meta fields of a file of this project, without reading its arrays (nor checking
    its hash): to tell whether an existing file is one of ours before replacing it.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    argument : str, optional
        The argument name errors report (default ``"path"``).

    Returns
    -------
    dict
        The JSON meta entry (``format``, ``kind``, ``version``, ...; a comparison of the
        0.1.0 format: its skeleton).

    Raises
    ------
    FileFormatError
        If the file cannot be read or is not a zip archive holding a meta entry of this
        project's format (tag ``maxwell-kinetics`` or a format of 0.1.0).
    """
    def fail(reason):
        return FileFormatError(path, reason, argument, "a file of maxwell-kinetics")

    path = check_path(path, argument)
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise fail("not a regular file")
        with open(path, "rb") as fh, zipfile.ZipFile(fh) as zf:
            names = _entries(zf)
            for entry in (META, "__skeleton__"):
                if entry in names:
                    _, meta = _read_meta(zf, names[entry], MAX_META_BYTES)
                    break
            else:
                raise _Refused("no meta entry")
    except FileFormatError:
        raise
    except _Refused as exc:
        raise fail(str(exc)) from None
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, SyntaxError,
            MemoryError, OverflowError, NotImplementedError, RuntimeError) as exc:
        raise fail(f"{type(exc).__name__}: {exc}") from None
    legacy = meta.get("format") in (1, "maxwell_kinetics.Solution/1",
                                    "maxwell_kinetics.Comparison/2")
    if meta.get("format") != FORMAT_TAG and not legacy:
        raise fail(f"format {meta.get('format')!r}, not {FORMAT_TAG!r}")
    return meta


def load(
    path,
    kind: str,
    versions,
    *,
    argument: str = "path",
    expected: str | None = None,
    max_bytes: int | None = None,
    check_entry=None,
) -> Loaded:
    """Read a file written by :func:`save` of ``kind`` and one of ``versions``.

    ``check_entry(name, dtype, shape, meta)`` may return a reason to refuse an entry from its
    header alone (before its data is read).  Every failure raises :class:`FileFormatError`
    naming ``argument``, the file and the reason; ``expected`` words what was expected
    (default: "a <kind> file of maxwell-kinetics").

    Parameters
    ----------
    path : str, os.PathLike or binary file
        The file, or an open binary file object.
    kind : str
        The kind the file must hold.
    versions : iterable of int
        The accepted format versions.
    argument : str, optional
        The argument name errors report (default ``"path"``).
    expected : str, optional
        Wording of what was expected, for error messages.
    max_bytes : int, optional
        Cap on the bytes of all arrays; default the smaller of 8 GiB and half the available
        memory.
    check_entry : callable, optional
        ``check_entry(name, dtype, shape, meta)`` returns a reason (str) to refuse an entry,
        or a false value to accept it.

    Returns
    -------
    Loaded
        The meta fields, arrays, version and legacy flag.

    Raises
    ------
    FileFormatError
        (argument ``argument``) for a missing or non-regular file, a wrong format, kind or
        version, an object or oversized or truncated entry, an entry refused by
        ``check_entry``, an unreadable archive, or a hash mismatch.
    """
    expected = expected or f"a {kind} file of maxwell-kinetics"
    versions = tuple(int(v) for v in versions)
    if max_bytes is None:
        from .budget import available_memory

        max_bytes = int(min(DEFAULT_MAX_BYTES, available_memory() / 2))
    max_bytes = int(max_bytes)

    def fail(reason):
        return FileFormatError(path, reason, argument, expected)

    if hasattr(path, "read"):  # an open binary file (a legacy comparison's nested solution)
        opened = contextlib.nullcontext(path)
    else:
        path = check_path(path, argument)
        try:
            st = os.stat(path)
        except FileNotFoundError:
            raise fail("no such file") from None
        except OSError as exc:
            raise fail(f"cannot be read: {exc.strerror or exc}") from None
        if not stat.S_ISREG(st.st_mode):
            raise fail("not a regular file")
        try:
            opened = open(path, "rb")
        except OSError as exc:  # no permission, vanished since the stat, ...
            raise fail(f"cannot be read: {exc.strerror or exc}") from None
    pool = ThreadPoolExecutor(max_workers=1)
    try:
        with opened as fh, zipfile.ZipFile(fh) as zf:
            names = _entries(zf)
            legacy = _legacy(kind, names, zf)
            if legacy is not None:
                meta, version, meta_name = legacy
            else:
                meta_name = META if META in names else "__skeleton__"
                if meta_name not in names:
                    raise _Refused("no meta entry: not a file of maxwell-kinetics")
                _, meta = _read_meta(zf, names[meta_name], MAX_META_BYTES)
                if "kind" in meta and meta["kind"] != kind:
                    raise _Refused(f"not a {kind} file (it holds a {meta['kind']!r})")
                if meta.get("format") != FORMAT_TAG or meta.get("kind") != kind:
                    raise _Refused(f"format {meta.get('format')!r}, not {FORMAT_TAG!r}")
                version = meta.get("version")
                if isinstance(version, bool) or not isinstance(version, int):
                    raise _Refused(f"version {version!r} is not an integer")
                if version not in versions:
                    newer = " (written by a newer version)" if version > max(versions) else ""
                    raise _Refused(f"version {version}{newer}, expected one of {list(versions)}")
            arrays = {}
            total = 0
            hashing = {}
            for name, info in names.items():
                if name == meta_name:
                    continue
                with zf.open(info) as stream:
                    dtype, shape, fortran = _npy_header(stream)
                    if dtype.kind not in _ALLOWED_KINDS or dtype.hasobject:
                        raise _Refused(f"entry {name!r} has dtype {dtype} (object arrays refused)")
                    count = int(np.prod(shape, dtype=object)) if shape else 1
                    nbytes = count * dtype.itemsize
                    total += nbytes
                    if total > max_bytes:
                        raise _Refused(
                            f"entry {name!r} declares shape {shape} of {dtype}: the arrays would "
                            f"exceed {max_bytes} bytes"
                        )
                    if check_entry is not None:
                        reason = check_entry(name, dtype, shape, meta)
                        if reason:
                            raise _Refused(f"entry {name!r}: {reason}")
                    raw = _read_exact(stream, nbytes)
                    if len(raw) != nbytes:
                        raise _Refused(f"entry {name!r} is truncated")
                    if stream.read(1):
                        raise _Refused(f"entry {name!r} holds more data than its header says")
                a = np.frombuffer(raw, dtype=dtype, count=count)
                if fortran:
                    a = a.reshape(shape[::-1]).T
                else:
                    a = a.reshape(shape)
                arrays[name] = a
                if legacy is None:  # hashed in a second thread meanwhile
                    hashing[name] = pool.submit(entry_digest, name, a)
    except FileFormatError:
        raise
    except _Refused as exc:
        raise fail(str(exc)) from None
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, SyntaxError,
            MemoryError, OverflowError, NotImplementedError, RuntimeError) as exc:
        raise fail(f"{type(exc).__name__}: {exc}") from None
    finally:
        pool.shutdown(wait=True)
    if legacy is not None:
        return Loaded(meta, arrays, version, legacy=True)
    entries = {name: future.result() for name, future in hashing.items()}
    if meta.get("sha256") != digest(meta, arrays, entries):
        raise fail("its contents do not match its hash (edited or damaged)")
    return Loaded(meta, arrays, version)

