"""What every subcommand shares on the way out: the one-JSON-object contract, the checks of
output paths made before any work, and the progress switch.

No command module imports :mod:`maxwell_kinetics.cli`; they all import this module, and the CLI
imports the command modules (imports run one way).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from particles.validation import InvalidArgumentError, check_output_dir, check_output_file

__all__ = ["emit_json", "clean_json", "check_outputs", "check_image_path", "check_output_dir",
           "progress_enabled"]


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


def check_outputs(*, inputs: dict | None = None, images: dict | None = None, **files) -> dict:
    """Check every output path before any work: each is a file in an existing, writable folder
    (``images``: also a format matplotlib writes), and no two outputs, nor an output and an
    input (``inputs``, e.g. ``resume``), name the same file; ``None`` entries are skipped.
    A checkpoint file may be the same file as the one resumed from.

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
        supported), two outputs name the same file, or an output would overwrite an input.
    """
    outputs = {}
    for name, path in (images or {}).items():
        if path is not None:
            outputs[name] = check_image_path(path, name)
    for name, path in files.items():
        if path is not None:
            outputs[name] = check_output_file(path, name)
    seen: dict[Path, str] = {}
    for name, path in outputs.items():
        key = path.resolve()
        if key in seen:
            raise InvalidArgumentError(
                name, str(path), f"a different file from --{seen[key].replace('_', '-')}"
            )
        seen[key] = name
    for name, path in (inputs or {}).items():
        if path is None:
            continue
        key = Path(path).resolve()
        clash = [o for o, p in seen.items() if p != "checkpoint" and o == key]
        if clash:
            raise InvalidArgumentError(
                seen[clash[0]], str(outputs[seen[clash[0]]]),
                f"a different file from --{name} (it would be overwritten)",
            )
    return outputs


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
