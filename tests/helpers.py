"""Helpers shared by the test files (imported as ``from helpers import ...``).

* :func:`run_json` / :func:`run_error` call the command line in-process through
  ``maxwell_kinetics.app.cli.main``;
* :func:`edited_file` copies a saved file with some meta fields or arrays replaced, and by
  default signs it again with a valid content hash, so that a test can reach the consistency
  checks behind the hash (an edit that is not re-signed is refused by the hash alone).
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from particles import persistence

#: The repository's root folder.
ROOT = Path(__file__).resolve().parents[1]


def run_json(capsys, argv):
    """Run ``main(argv)``, check it printed exactly one JSON object on one line, return it."""
    from maxwell_kinetics.app.cli import main

    status = main(argv)
    captured = capsys.readouterr()
    assert status == 0, captured.err
    out = captured.out
    payload, end = json.JSONDecoder().raw_decode(out)
    assert out[end:].strip() == ""  # nothing after the one object
    assert out.count("\n") == 1
    assert isinstance(payload, dict)
    return payload


def run_error(capsys, argv, status: int = 2):
    """Run ``main(argv)`` expecting exit ``status``; return stderr (stdout must stay empty)."""
    from maxwell_kinetics.app.cli import main

    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    captured = capsys.readouterr()
    assert code == status, captured.err
    assert captured.out == ""
    return captured.err


def read_entries(path) -> tuple[dict, dict[str, np.ndarray]]:
    """(meta, arrays) of a saved ``.npz`` read without any check (for tests that edit files)."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {key: data[key] for key in data.files}
    meta = json.loads(str(arrays.pop("meta")[()]))
    return meta, arrays


def write_entries(path, meta: dict, arrays: dict, *, resign: bool = True):
    """Write ``meta`` and ``arrays`` as a raw ``.npz``; ``resign`` recomputes the content hash
    (a forged file that passes the hash), else the hash is left as it was."""
    meta = dict(meta)
    if resign and "sha256" in meta:
        meta["sha256"] = persistence.digest(meta, arrays)
    with open(path, "wb") as fh:
        np.savez(fh, meta=np.array(json.dumps(meta)), **arrays)
    return path


def edited_file(src, dst, meta=None, arrays=None, *, resign: bool = True):
    """Copy the saved file ``src`` to ``dst`` with ``meta`` entries and ``arrays`` replaced."""
    header, content = read_entries(src)
    header.update(meta or {})
    content.update(arrays or {})
    return write_entries(dst, header, content, resign=resign)


def zip_names(path) -> list[str]:
    with zipfile.ZipFile(path) as zf:
        return zf.namelist()
