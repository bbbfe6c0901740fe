"""Run every comparison, write PNG figures and ``summary.json`` (the job behind
``maxwell-kinetics reproduce``, :mod:`maxwell_kinetics.app.commands.reproduce`).

The default size finishes in minutes on two cores (measured run times are in ``summary.json``);
``--full`` runs the paper's sizes where affordable; ``--small`` is the size of the tests.

``summary.json`` gathers the numbers of every comparison run into the folder at one size: a
run of some comparisons (``only``) replaces their entries and keeps the others, and the file is
rewritten after each comparison, so an interrupted or failed run keeps the numbers of those
finished.  Every file of the run is checked before the first comparison (:func:`plan_outputs`):
a summary made at another size that this run would not replace entirely, a ``summary.json``
that is not one of ours, or a figure or ``.npz`` in the way that this program did not write is
refused, naming the file, and left as it is.
"""

from __future__ import annotations

import json
import math
import tempfile
import time
from pathlib import Path

from particles import persistence
from particles.validation import InvalidArgumentError
from particles.workers import check_workers

from .output import check_files_in, check_output_dir, clean_json, is_png, read_json_file

#: The PNG text chunk that marks a figure written by :func:`run_all` (``Source``).
FIGURE_SOURCE = "maxwell-kinetics reproduce"

__all__ = ["prepare_output", "plan_outputs", "read_summary", "run_all", "SUMMARY",
           "is_our_figure", "FIGURE_SOURCE"]

#: The name of the summary file in the output folder.
SUMMARY = "summary.json"
#: The sizes a summary may be made at (``maxwell_kinetics.app.comparisons.SIZES``).
_SIZES = ("small", "default", "full")


def prepare_output(out, argument: str = "out") -> Path:
    """Create the output folder and prove that a file can be written in it, before any work;
    a failure raises ``InvalidArgumentError`` naming ``argument``.

    Parameters
    ----------
    out : str or os.PathLike
        The output folder; missing parents are created (and removed again on failure).
    argument : str, optional
        The argument's name for the error message (default ``"out"``).

    Returns
    -------
    pathlib.Path
        The folder, which exists and is writable.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If the folder cannot be created or a file cannot be written in it.
    """
    out = Path(out)
    created = [p for p in (out, *out.parents) if not p.exists()]
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as exc:
        for folder in created:  # nothing written: remove the folders made here
            try:
                folder.rmdir()
            except OSError:
                pass
        raise InvalidArgumentError(
            argument, str(out), f"a writable directory ({exc.strerror or exc})"
        ) from None
    return out


def read_summary(path, argument: str = "out") -> dict | None:
    """The ``summary.json`` at ``path`` if it is one this program wrote, ``None`` if there is
    none; anything else is refused (never replaced).

    Ours is a JSON object with ``size`` one of ``"small"``, ``"default"``, ``"full"`` and
    ``comparisons`` an object of objects (``{name: summary}``); other fields (``seconds``,
    ``provenance``, ...) are kept as they are.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    argument : str, optional
        The argument name errors report (default ``"out"``).

    Returns
    -------
    dict or None
        The summary, or ``None`` when nothing is at ``path``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument`` and the file, if it cannot be read, is not valid JSON or does not
        have the fields above.
    """
    path = Path(path)
    if not path.exists():
        return None

    def refuse(reason):
        return InvalidArgumentError(
            argument, str(path),
            f"a folder whose {path.name} is a summary of maxwell-kinetics reproduce ({reason}; "
            f"it is left as it is: move it or choose another --{argument})",
        )

    try:
        summary = read_json_file(path)
    except ValueError as exc:
        raise refuse(str(exc)) from None
    if not isinstance(summary, dict):
        raise refuse(f"it holds a JSON {type(summary).__name__}, not an object")
    if summary.get("size") not in _SIZES:
        raise refuse(f"its size is {summary.get('size')!r}, not one of {list(_SIZES)}")
    comparisons = summary.get("comparisons")
    if not isinstance(comparisons, dict) or not all(
            isinstance(v, dict) for v in comparisons.values()):
        raise refuse("its 'comparisons' is not an object of objects")
    return summary


def _is_comparison_file(path) -> str | None:
    """Why ``path`` is not a file written by ``Comparison.save`` (``None`` if it is one)."""
    try:
        meta = persistence.read_meta(path)
    except InvalidArgumentError as exc:
        return getattr(exc, "reason", str(exc))
    if meta.get("kind", "comparison") != "comparison":
        return f"it holds a {meta.get('kind')!r}, not a comparison"
    return None


def _png_text(path) -> dict[str, str]:
    """The tEXt chunks of a PNG (keyword → text), read up to the image data."""
    import struct

    out = {}
    with open(path, "rb") as fh:
        fh.read(8)
        while True:
            head = fh.read(8)
            if len(head) < 8:
                return out
            length, kind = struct.unpack(">I4s", head)
            if kind in (b"IDAT", b"IEND") or length > 1 << 20:
                return out
            data = fh.read(length)
            fh.read(4)  # CRC
            if kind == b"tEXt" and b"\0" in data:
                key, _, text = data.partition(b"\0")
                out[key.decode("latin-1")] = text.decode("latin-1")


def is_our_figure(path) -> str | None:
    """Why ``path`` is not a figure this program wrote (``None`` when it is): a PNG that carries
    the text chunk ``Source`` = :data:`FIGURE_SOURCE`, or, as figures written before that
    chunk did, one made by Matplotlib beside a comparison file of the same name.  A photo or any
    other PNG of that name is never replaced.

    Parameters
    ----------
    path : str or os.PathLike
        An existing file.

    Returns
    -------
    str or None
        The reason, or ``None``.
    """
    reason = is_png(path)
    if reason is not None:
        return reason
    try:
        text = _png_text(path)
    except OSError as exc:
        return f"it cannot be read: {exc.strerror or exc}"
    if text.get("Source") == FIGURE_SOURCE:
        return None
    sibling = Path(path).with_suffix(".npz")
    if (text.get("Software", "").startswith("Matplotlib") and sibling.is_file()
            and _is_comparison_file(sibling) is None):
        return None
    return "it is a PNG image this program did not write"


def plan_outputs(out, names, size: str, argument: str = "out",
                 force: bool = False) -> dict | None:
    """Check every file a run of the comparisons ``names`` at ``size`` writes into ``out``,
    before any work and without writing anything; return the summary already there (to be
    merged into) or ``None``.

    The folder must be usable (:func:`maxwell_kinetics.app.output.check_output_dir`); each
    ``<name>.png``, ``<name>.npz`` and ``summary.json`` must have a name the file system takes
    and be a regular file or nothing, an existing one written by this program (a figure of
    :func:`is_our_figure`, a file of ``Comparison.save``, a summary read by
    :func:`read_summary`); a summary made at another size is refused unless ``force`` (the
    default-size results of ``make demo`` are never replaced by a ``--small`` run by
    accident), and even then when this run would keep some of its comparisons.

    Parameters
    ----------
    out : str or os.PathLike
        The output folder (it need not exist yet).
    names : list of str
        The comparisons to run.
    size : str
        ``"small"``, ``"default"`` or ``"full"``.
    argument : str, optional
        The folder's argument name for error messages (default ``"out"``).
    force : bool, optional
        Replace a summary made at another size (every comparison it holds is run again).

    Returns
    -------
    dict or None
        The existing summary, or ``None``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument`` and the file in the way.
    """
    out = check_output_dir(out, argument)
    files = {}
    for name in names:
        files[f"{name}.png"] = is_our_figure
        files[f"{name}.npz"] = _is_comparison_file
    files[SUMMARY] = None  # read and checked below
    paths = check_files_in(out, files, argument)
    existing = read_summary(paths[SUMMARY], argument)
    if existing is not None and existing["size"] != size:
        if not force:
            raise InvalidArgumentError(
                argument, str(paths[SUMMARY]),
                f"a folder without results of another size: its {SUMMARY} holds "
                f"{len(existing['comparisons'])} comparisons at size {existing['size']!r}, "
                f"which this run at size {size!r} would replace (choose another --{argument}, "
                "or pass --force to replace them)",
            )
        kept = sorted(set(existing["comparisons"]) - set(names))
        if kept:
            shown = ", ".join(kept)
            raise InvalidArgumentError(
                argument, str(paths[SUMMARY]),
                f"a {SUMMARY} made at the size of this run ({size!r}): it holds {shown} at size "
                f"{existing['size']!r}, which this run would mix with (it is left as it is: "
                f"choose another --{argument}, or run at size {existing['size']!r})",
            )
    return existing


def _merged(existing: dict | None, size: str, done: dict, order) -> dict:
    """The summary to write: ``existing`` (if made at ``size``) with the entries of ``done``
    replaced, in the order of ``order`` (then any other names it holds)."""
    base = dict(existing) if existing is not None and existing["size"] == size else {}
    comparisons = dict(base.get("comparisons", {}))
    comparisons.update(done)
    ordered = {n: comparisons[n] for n in order if n in comparisons}
    ordered.update({n: v for n, v in comparisons.items() if n not in ordered})
    return {**base, "size": size, "comparisons": ordered}


def _write_summary(out: Path, size: str, done: dict, order, seconds: float,
                   replacing: str | None = None) -> dict:
    """Merge ``done`` into the ``summary.json`` of ``out`` as it is now and write it, under an
    ``flock`` on the folder: two runs of other comparisons into one folder at once (``--only a``
    and ``--only b`` in two terminals) both keep their entries.  A summary of another size than
    ``size`` found there (one that ``replacing`` does not name: a run of another size into the
    same folder wrote it meanwhile) is refused, not replaced.  Returns what was written."""
    import fcntl
    import os

    fd = os.open(out, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # released when fd is closed
        current = read_summary(out / SUMMARY)
        if current is not None and current["size"] not in (size, replacing):
            raise InvalidArgumentError(
                "out", str(out / SUMMARY),
                f"a folder that no run of another size writes at the same time: a run at size "
                f"{current['size']!r} wrote its {SUMMARY} while this one at size {size!r} ran "
                f"(its summary is kept; the figures and .npz of this run are in the folder)")
        summary = _merged(current, size, done, order)
        summary["seconds"] = seconds
        summary = clean_json(summary)
        persistence.write_text(out / SUMMARY, json.dumps(summary, indent=1, allow_nan=False),
                               "out")
    finally:
        os.close(fd)
    return summary


def run_all(out="results", size="default", only=None, progress=None, workers=None,
            force: bool = False) -> dict:
    """Run the comparisons (``only``: a list of names); write ``<name>.png``, ``<name>.npz``
    (:meth:`Comparison.save`: summary and figure data, reload with ``Comparison.load``) and
    ``summary.json``.

    Every output is checked before the first comparison runs (:func:`plan_outputs`: nothing is
    written, not even the folder, when one is refused).  ``summary.json`` is merged: the
    entries of the comparisons run replace theirs and the others stay; it is read again and
    rewritten after each comparison, under a lock on the folder (a run stopped half-way keeps
    the finished ones, and two runs of other comparisons into one folder at once keep both).

    With ``workers`` (an integer), or at ``size="full"``, the particle runs of fixed times go
    through the ensemble engine on dask (``workers`` processes; default one per core), one task
    file per run in ``<out>/runs``: a rerun after an interruption takes the finished runs from
    there, and the results equal the serial ones bit for bit.  More workers than
    :func:`particles.workers.max_workers` (4 × the CPUs) are refused unless ``force``.

    Parameters
    ----------
    out : str or os.PathLike, optional
        The output folder (default ``"results"``), created if needed.
    size : str, optional
        ``"small"`` (the tests' size), ``"default"`` (minutes) or ``"full"`` (the paper's sizes).
    only : list of str, optional
        Names of the comparisons to run (keys of ``COMPARISONS``); default all, in order.
    progress : bool or None, optional
        Print a line before and after each comparison, and let the comparisons show progress:
        None (default) on a terminal or in a notebook only, True always, False never.
    workers : int, optional
        Number of dask processes for the particle runs through the ensemble engine; default
        serial (except at ``size="full"``).
    force : bool, optional
        Allow more workers than :func:`particles.workers.max_workers`, and replace a summary
        made at another size (:func:`plan_outputs`).

    Returns
    -------
    dict
        The contents of ``summary.json``: ``size``, ``comparisons`` (``{name: summary}``, those
        of earlier runs at this size included), ``seconds`` (the wall-clock time of this run)
        and any other field an earlier summary held.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From the validators it calls: too many ``workers`` without ``force``, an unusable
        ``out`` folder, or a file in it that this run may not replace (:func:`plan_outputs`);
        :class:`particles.persistence.WriteError` (naming ``out``) if a file cannot be
        written after the work (a full disk).
    """
    import matplotlib.pyplot as plt

    from .comparisons import COMPARISONS, ParticleRuns

    names = list(COMPARISONS) if only is None else list(only)
    unknown = [n for n in names if n not in COMPARISONS]
    if unknown:
        raise InvalidArgumentError("only", unknown, "names among " + ", ".join(COMPARISONS))
    if size not in _SIZES:
        raise InvalidArgumentError("size", size, f"one of {list(_SIZES)}")
    check_workers(workers, "workers", force=force)
    existing = plan_outputs(out, names, size, force=force)
    replacing = None if existing is None else existing["size"]
    out = prepare_output(out)
    persistence.name_outputs({out / f: "out" for n in names for f in (f"{n}.png", f"{n}.npz")})
    ensemble = workers is not None or size == "full"
    runner = ParticleRuns(out / "runs" if ensemble else None, workers, force)
    done: dict = {}
    start = time.perf_counter()
    summary = _merged(existing, size, done, COMPARISONS)
    from particles.progress import progress_enabled

    announce = progress_enabled(progress)
    for name in names:
        if announce:
            print(f"[reproduce] {name} ...", flush=True)
        result = COMPARISONS[name](size, progress=progress, runner=runner)
        fig = result.figure()
        try:
            persistence.save_figure(fig, out / f"{name}.png", "out", dpi=110,
                                    metadata={"Source": FIGURE_SOURCE})
        finally:
            plt.close(fig)
        result.save(out / f"{name}.npz")
        done[name] = clean_json(result.summary)
        summary = _write_summary(out, size, done, COMPARISONS, time.perf_counter() - start,
                                 replacing)
        replacing = None  # replaced now: from here on only this size is ours
        if announce:
            seconds = result.summary.get("seconds", 0)
            seconds = seconds if isinstance(seconds, (int, float)) and math.isfinite(seconds) \
                else 0.0
            print(f"[reproduce] {name}: {seconds:.1f} s", flush=True)
    if not names:
        summary["seconds"] = time.perf_counter() - start
    return clean_json(summary)  # as written to summary.json
