"""What every subcommand shares on the way out: the one-JSON-object contract, the checks of
output paths made before any work, and the progress switch.

No command module imports :mod:`maxwell_kinetics.app.cli`; they all import this module, and the CLI
imports the command modules (imports run one way).
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

from particles import persistence
from particles.paths import check_output_dir as _check_output_dir
from particles.paths import check_output_file, file_kind, output_target
from particles.validation import InvalidArgumentError

__all__ = ["emit_json", "clean_json", "check_outputs", "check_image_path", "check_output_dir",
           "check_files_in", "is_png", "read_json_file", "MAX_JSON_BYTES", "progress_enabled"]


def clean_json(obj):
    """Replace non-finite floats by None (and NumPy scalars by Python ones) for strict JSON.

    Parameters
    ----------
    obj : object
        A float, a NumPy scalar, or a dict, list or tuple of such (nested); anything else is
        returned as it is.

    Returns
    -------
    object
        The same structure with NaN and ±inf replaced by ``None``, tuples as lists and dict keys
        as strings.
    """
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): clean_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean_json(v) for v in obj]
    if hasattr(obj, "item") and getattr(obj, "shape", None) == ():
        return clean_json(obj.item())
    return obj


def emit_json(payload: dict) -> None:
    """Print one JSON object on one line (the ``--json`` contract).

    Parameters
    ----------
    payload : dict
        The object to print; it must be strict JSON (no NaN or infinity: see
        :func:`clean_json`), else ``json.dump`` raises ``ValueError``.
    """
    json.dump(payload, sys.stdout, allow_nan=False)
    sys.stdout.write("\n")
    sys.stdout.flush()


def _image_formats() -> set[str]:
    from matplotlib.backend_bases import FigureCanvasBase

    return set(FigureCanvasBase.get_supported_filetypes())


def check_image_path(path, name: str) -> Path:
    """An output image: a writable file path whose suffix is a format matplotlib can write.

    Parameters
    ----------
    path : str or os.PathLike
        The image file to be written.
    name : str
        The argument's name, for the error message.

    Returns
    -------
    pathlib.Path
        The checked path.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If the suffix is not an image format matplotlib writes, or (from
        ``check_output_file``) the file cannot be written in its folder.
    """
    out = check_output_file(path, name)
    suffix = out.suffix.lower().lstrip(".")
    formats = _image_formats()
    if suffix not in formats:
        raise InvalidArgumentError(
            name, str(path), "an image file name ending in one of ." + ", .".join(sorted(formats))
        )
    return out


def check_output_dir(path, name: str) -> Path:
    """An output folder: :func:`particles.paths.check_output_dir` (an existing writable
    directory or one that can be created; nothing is created here), and names short enough for
    the file system (:func:`particles.persistence.check_name_length`).

    Parameters
    ----------
    path : str or os.PathLike
        The folder.
    name : str
        The argument's name, for the error message.

    Returns
    -------
    pathlib.Path
        ``path`` as a ``Path``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the argument, for a folder that cannot be used or created.
    """
    persistence.check_name_length(path, name)  # first: a name too long fails os.stat
    return _check_output_dir(path, name)


def _file_path(path, name: str) -> Path:
    """A path for a file: names the file system takes, and no trailing ``/`` (which names a
    folder; ``Path`` would drop it and write a file of the folder's name)."""
    out = persistence.check_name_length(path, name)
    if os.fspath(path).endswith(os.sep):
        raise InvalidArgumentError(name, str(path), "a file path, not a folder (it ends in '/')")
    return out


def _same_file(a: Path, b: Path) -> bool:
    """True when ``a`` and ``b`` name one file once symlinks are resolved.  (Two hard links of
    one file are two names: a write renames a new file onto one of them and leaves the other.)"""
    return a.resolve() == b.resolve()


def check_outputs(*, inputs: dict | None = None, images: dict | None = None, **files) -> dict:
    """Check every output path before any work: each is a file in an existing, writable folder
    (``images``: also a format matplotlib can write), with names the file system takes (at
    most ``NAME_MAX`` bytes a name) and no trailing ``/``, and no two outputs, nor an output
    and an input (``inputs``, e.g. ``resume``), name the same file (through a symlink too);
    ``None`` entries are skipped.  A checkpoint file may be the same file as the one resumed
    from.  The outputs' names are then given to :func:`particles.persistence.name_outputs`, so
    that a write that fails later (a full disk) names the user's option.

    Parameters
    ----------
    inputs : dict, optional
        ``{argument name: path or None}`` of files to be read, which no output may overwrite.
    images : dict, optional
        ``{argument name: path or None}`` of images to be written.
    **files
        ``argument name=path or None`` of other files to be written.

    Returns
    -------
    dict
        ``{argument name: pathlib.Path}`` of the outputs given.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the argument, if an output path cannot be written (or an image's format is not
        supported, or a name is too long), two outputs name the same file, or an output would
        overwrite an input.
    """
    given = {**(images or {}), **files}
    for name, path in given.items():  # first: a name too long makes os.stat raise
        if path is not None:
            _file_path(path, name)
    outputs = {}
    for name, path in (images or {}).items():
        if path is not None:
            outputs[name] = check_image_path(path, name)
    for name, path in files.items():
        if path is not None:
            outputs[name] = check_output_file(path, name)
    seen: list[tuple[str, Path]] = []
    for name, path in outputs.items():
        for other, known in seen:
            if _same_file(path, known):
                raise InvalidArgumentError(
                    name, str(path), f"a different file from --{other.replace('_', '-')}"
                )
        seen.append((name, path))
    for name, path in (inputs or {}).items():
        if path is None:
            continue
        for other, known in seen:
            if other != "checkpoint" and _same_file(Path(path), known):
                raise InvalidArgumentError(
                    other, str(known),
                    f"a different file from --{name} (it would be overwritten)",
                )
    persistence.name_outputs({path: name for name, path in outputs.items()})
    return outputs


def is_png(path) -> str | None:
    """Why ``path`` is not a PNG image (``None`` when it starts with the PNG signature).

    Parameters
    ----------
    path : str or os.PathLike
        An existing file.

    Returns
    -------
    str or None
        The reason, or ``None``.
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError as exc:
        return f"it cannot be read: {exc.strerror or exc}"
    return None if head == b"\x89PNG\r\n\x1a\n" else "it is not a PNG image"


#: The largest JSON file of ours that is read back (a summary is a few hundred kB).
MAX_JSON_BYTES = 64 * 2**20


def read_json_file(path):
    """The JSON value in the file ``path`` (at most :data:`MAX_JSON_BYTES`), read to tell
    whether a file is one of ours.

    Parameters
    ----------
    path : str or os.PathLike
        An existing file.

    Returns
    -------
    object
        The decoded JSON value.

    Raises
    ------
    ValueError
        With the reason, if the file cannot be read, is larger than the cap or is not JSON
        (UTF-8).
    """
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_JSON_BYTES + 1)
    except OSError as exc:
        raise ValueError(f"it cannot be read: {exc.strerror or exc}") from None
    if len(data) > MAX_JSON_BYTES:
        raise ValueError(f"it is larger than {MAX_JSON_BYTES} bytes")
    try:
        return json.loads(data)
    except ValueError as exc:  # JSONDecodeError, UnicodeDecodeError
        raise ValueError(f"it is not valid JSON: {exc}") from None


def check_files_in(folder, files: dict, name: str) -> dict:
    """Check, before any work, the files a command writes into the output folder ``folder``
    under names of its own choosing: each name fits the file system, nothing but a regular
    file (or nothing) is at its place (:func:`particles.paths.output_target`), and a file
    already there is one this program wrote, by the check given for it: a file the program did
    not write is never replaced.

    Parameters
    ----------
    folder : str or os.PathLike
        The output folder (it need not exist yet).
    files : dict
        ``{file name: check or None}``; ``check(path)`` returns the reason why an existing file
        is not one of ours, or ``None``.
    name : str
        The folder's argument name, for the error message.

    Returns
    -------
    dict
        ``{file name: pathlib.Path}`` of the files in ``folder``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming the argument and the file, if one cannot be written or a file that is not ours
        is in the way.
    """
    folder = Path(folder)
    out = {}
    for filename, check in files.items():
        path = folder / filename
        persistence.check_name_length(path, name)
        target = output_target(path, name)
        if check is not None and file_kind(target) == "regular file":
            reason = check(target)
            if reason:
                raise InvalidArgumentError(
                    name, str(path),
                    f"a folder whose {filename} was written by maxwell-kinetics, which this "
                    f"run replaces ({reason}; it is left as it is: move it or choose another "
                    f"--{name})",
                )
        out[filename] = path
    return out


def progress_enabled(args) -> bool:
    """Progress on stderr unless ``--no-progress`` or ``--json`` was given.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options; missing ``no_progress`` or ``json`` attributes count as not given.

    Returns
    -------
    bool
        Whether to show progress.
    """
    if getattr(args, "no_progress", False):
        return False
    return not getattr(args, "json", False)
