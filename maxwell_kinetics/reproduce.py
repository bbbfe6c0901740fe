"""``maxwell-kinetics reproduce``: run every comparison, write PNG figures and ``summary.json``.

    maxwell-kinetics reproduce [--out results] [--full | --small] [--only NAME,...] [--json]

The default size finishes in minutes on two cores (measured run times are in ``summary.json``);
``--full`` runs the paper's sizes where affordable; ``--small`` is the size of the tests.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

from particles.validation import InvalidArgumentError

__all__ = ["register", "run_all"]


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reproduce", help="reproduce the paper's figures and the kinetic-vs-particle comparisons",
        description="Run every comparison and write <out>/<name>.png, <out>/<name>.npz (data for "
        "Comparison.load) and <out>/summary.json.",
    )
    p.add_argument("--out", default="results", help="output folder (default results/)")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--full", action="store_true", help="the paper's sizes (hours)")
    size.add_argument("--small", action="store_true", help="the tests' size (a minute)")
    p.add_argument("--only", default=None, help="comma-separated comparison names")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=_handler)


def _clean(obj):
    """Replace non-finite floats by None so that the JSON is strict."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "item") and getattr(obj, "shape", None) == ():
        return _clean(obj.item())
    return obj


def run_all(out="results", size="default", only=None, progress=True) -> dict:
    """Run the comparisons (``only``: a list of names); write ``<name>.png``, ``<name>.npz``
    (:meth:`Comparison.save`: summary and figure data, reload with ``Comparison.load``) and
    ``summary.json``."""
    from .comparisons import COMPARISONS

    names = list(COMPARISONS) if only is None else list(only)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    summary = {"size": size, "comparisons": {}}
    start = time.perf_counter()
    for name in names:
        if progress:
            print(f"[reproduce] {name} ...", flush=True)
        result = COMPARISONS[name](size, progress=progress)
        fig = result.figure()
        fig.savefig(out / f"{name}.png", dpi=110)
        result.save(out / f"{name}.npz")
        import matplotlib.pyplot as plt

        plt.close(fig)
        summary["comparisons"][name] = _clean(result.summary)
        if progress:
            print(f"[reproduce] {name}: {result.summary.get('seconds', 0):.1f} s", flush=True)
    summary["seconds"] = time.perf_counter() - start
    with open(out / "summary.json", "w") as fh:
        json.dump(_clean(summary), fh, indent=1, allow_nan=False)
    return summary


def _handler(args) -> int:
    from .cli import emit_json
    from .comparisons import COMPARISONS

    only = None
    if args.only:
        only = [n.strip() for n in args.only.split(",") if n.strip()]
        bad = [n for n in only if n not in COMPARISONS]
        if bad:
            raise InvalidArgumentError("only", args.only, "names among " + ", ".join(COMPARISONS))
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise InvalidArgumentError("out", args.out, "a directory")
    size = "full" if args.full else "small" if args.small else "default"
    summary = run_all(out, size, only, progress=not args.json)
    if args.json:
        emit_json({"out": str(out), "size": size, "seconds": summary["seconds"],
                   "comparisons": sorted(summary["comparisons"])})
    else:
        print(f"wrote {out}/summary.json and {len(summary['comparisons'])} figures "
              f"in {summary['seconds']:.0f} s")
    return 0
