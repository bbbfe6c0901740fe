"""File-system checks of paths given by the user, made before any work is done: a path is a
path, what exists there, where an output is written (a symlink followed, a device refused), an
output file in a writable directory, an output folder that exists or can be created.

A failure raises :class:`particles.validation.InvalidArgumentError` naming the argument.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from .validation import InvalidArgumentError

__all__ = [
    "check_path",
    "file_kind",
    "output_target",
    "check_output_file",
    "check_output_dir",
]


def check_path(path, name: str) -> Path:
    """Check a file-system path: a non-empty ``str`` or an ``os.PathLike``.

    Anything else (None, a number, a list) is refused here instead of failing deep inside with a
    ``TypeError``.  Nothing is looked up on disk.

    Parameters
    ----------
    path : str or os.PathLike
        The path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a non-empty string or path-like object (naming ``name``).
    """
    if isinstance(path, (str, os.PathLike)) and str(path) != "":
        return Path(path)
    raise InvalidArgumentError(name, path, "a file path (str or os.PathLike)")


def file_kind(path) -> str | None:
    """Say what exists at ``path``, without following a final symlink.

    Parameters
    ----------
    path : str or os.PathLike
        The path to inspect (with ``os.lstat``).

    Returns
    -------
    str or None
        ``None`` when nothing exists there (or a parent component is not a directory), otherwise
        one of ``"regular file"``, ``"directory"``, ``"symlink"``, ``"character device"``,
        ``"block device"``, ``"FIFO"``, ``"socket"`` or ``"special file"``.
    """
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None
    except OSError:  # e.g. a component that is a file: nothing can exist there
        return None
    for test, kind in ((stat.S_ISREG, "regular file"), (stat.S_ISDIR, "directory"),
                       (stat.S_ISLNK, "symlink"), (stat.S_ISCHR, "character device"),
                       (stat.S_ISBLK, "block device"), (stat.S_ISFIFO, "FIFO"),
                       (stat.S_ISSOCK, "socket")):
        if test(mode):
            return kind
    return "special file"


def output_target(path, name: str) -> Path:
    """Find the file that an output written to ``path`` replaces.

    That is ``path`` itself, or the file a symlink (or a chain of them) points to, so that a link
    stays a link and its target is written.  A dangling link is resolved to the file it names,
    which is then created.  Writing replaces the file by a rename, which would turn a device, FIFO
    or socket into a regular file (as root, ``/dev/null`` itself), so those are refused; to
    discard an output, leave the option out.

    Parameters
    ----------
    path : str or os.PathLike
        The output path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        The path to write (the symlink's target when ``path`` is a symlink).

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a path (:func:`check_path`), is an existing directory or a link to one,
        or is anything but a regular file or a new path: a character or block device
        (``/dev/null`` included), a FIFO, a socket (naming ``name``, the path and what it is).
    """
    out = check_path(path, name)
    target = Path(os.path.realpath(out)) if file_kind(out) == "symlink" else out
    kind = file_kind(target)
    if kind == "directory":
        shown = "a symlink to a directory" if target != out else "an existing directory"
        raise InvalidArgumentError(name, str(path), f"a file path, not {shown}")
    if kind not in (None, "regular file"):
        via = f" (through the symlink to {target})" if target != out else ""
        raise InvalidArgumentError(
            name, str(path),
            f"a regular file or a new path, not a {kind}{via}: output is written to a new file "
            "and renamed into place, which would replace it",
        )
    return target


def check_output_file(path, name: str) -> Path:
    """Check an output file before any work is done, so that a bad path fails at once.

    The file must be a regular file or a new path (:func:`output_target`: never a device, a FIFO,
    a socket or a directory; a symlink is followed), in an existing, writable directory.

    Parameters
    ----------
    path : str or os.PathLike
        The output path.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as given (not the symlink's target).

    Raises
    ------
    particles.InvalidArgumentError
        If :func:`output_target` refuses the path, or its directory does not exist or is not
        writable (naming ``name``).
    """
    out = check_path(path, name)
    target = output_target(out, name)
    if not target.parent.is_dir() or not os.access(target.parent, os.W_OK):
        raise InvalidArgumentError(name, str(path), "a file in an existing, writable directory")
    return out


def check_output_dir(path, name: str) -> Path:
    """Check an output folder: an existing writable directory (or a symlink to one), or one that can
    be created.

    A folder that does not exist yet is accepted when its nearest existing ancestor is a writable
    directory.  Nothing is created here.

    Parameters
    ----------
    path : str or os.PathLike
        The folder.
    name : str
        The argument name shown in the error.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.InvalidArgumentError
        If ``path`` is not a path, something other than a directory exists there (a file, a
        device, a FIFO, a socket, a dangling symlink: the error names what), the directory is not
        writable, or it cannot be created (naming ``name``).
    """
    out = check_path(path, name)
    if out.exists() or file_kind(out) is not None:
        if not out.is_dir():
            kind = file_kind(Path(os.path.realpath(out))) or "dangling symlink"
            raise InvalidArgumentError(name, str(path), f"a writable directory, not a {kind}")
        if not os.access(out, os.W_OK):
            raise InvalidArgumentError(name, str(path), "a writable directory")
        return out
    ancestor = out.absolute().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir() or not os.access(ancestor, os.W_OK):
        raise InvalidArgumentError(
            name, str(path), "a directory that can be created (under a writable directory)"
        )
    return out
