"""Compare the numbers of two ``summary.json`` files written by ``reproduce``.

Usage::

    python benchmarks/compare_summaries.py OLD/summary.json NEW/summary.json [--rtol 1e-9]
        [--show N] [--json]

Every numeric leaf (an int or a float, not a bool) is addressed by its path of keys and list
indices, e.g. ``comparisons/kinetic_theory/sup_error/3``.  Leaves under a key that names a wall
clock (``seconds``, ``*_seconds``) or a version (``version``, ``*_version``, ``versions``) are
skipped; the physical times of the runs (``time``, ``times``, ``md_time``, ...) are compared.
A leaf present in both files counts as equal when |new − old| ≤ rtol·max(|old|, |new|) (two NaNs
of the same path are equal, as are equal infinities), otherwise as different.  Leaves present in
one file only are counted as ``only_old`` or ``only_new``; a path that is a number in one file
and something else in the other counts in both.

Prints the four counts, then the differing leaves grouped by comparison (the second key), with
their relative change, largest first.  ``--json`` prints the same as one JSON object.  The exit
status is 0 (the comparison is reported, not judged).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

#: Keys whose leaves are wall-clock timings or versions, not results.
SKIPPED_KEY = re.compile(r"^(?:seconds|\w+_seconds|versions?|\w+_version)$")


def numeric_leaves(tree, path=()) -> dict[tuple, float]:
    """Path → value of every numeric leaf of ``tree`` (dicts and lists), skipped keys aside."""
    out = {}
    if isinstance(tree, dict):
        for key, value in tree.items():
            if SKIPPED_KEY.match(str(key)):
                continue
            out.update(numeric_leaves(value, (*path, str(key))))
    elif isinstance(tree, list):
        for i, value in enumerate(tree):
            out.update(numeric_leaves(value, (*path, i)))
    elif isinstance(tree, int | float) and not isinstance(tree, bool):
        out[path] = float(tree)
    return out


def relative_change(old: float, new: float) -> float:
    """|new − old| / max(|old|, |new|); 0 for equal values (NaN with NaN, equal infinities)."""
    if old == new or (math.isnan(old) and math.isnan(new)):
        return 0.0
    if not (math.isfinite(old) and math.isfinite(new)):
        return math.inf
    return abs(new - old) / max(abs(old), abs(new))


def compare(old: dict, new: dict, rtol: float = 1e-9) -> dict:
    """Counts and differing leaves of two parsed summaries (see the module docstring)."""
    a, b = numeric_leaves(old), numeric_leaves(new)
    both = a.keys() & b.keys()
    changes = {p: relative_change(a[p], b[p]) for p in both}
    different = {p: c for p, c in changes.items() if not c <= rtol}
    return {
        "equal": len(both) - len(different),
        "different": len(different),
        "only_old": sorted(a.keys() - b.keys(), key=str),
        "only_new": sorted(b.keys() - a.keys(), key=str),
        "differences": {p: (a[p], b[p], c) for p, c in different.items()},
    }


def _name(path) -> str:
    return "/".join(str(p) for p in path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--show", type=int, default=10,
                        help="differing leaves shown per comparison (default 10)")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    result = compare(json.loads(args.old.read_text()), json.loads(args.new.read_text()),
                     args.rtol)
    groups: dict[str, list] = {}
    for path, (o, n, c) in result["differences"].items():
        group = path[1] if len(path) > 1 and path[0] == "comparisons" else path[0]
        groups.setdefault(str(group), []).append((c, _name(path), o, n))
    if args.json:
        print(json.dumps({
            "rtol": args.rtol, "equal": result["equal"], "different": result["different"],
            "only_old": [_name(p) for p in result["only_old"]],
            "only_new": [_name(p) for p in result["only_new"]],
            "differences": {g: [{"path": p, "old": o, "new": n, "relative": c}
                                for c, p, o, n in sorted(rows, reverse=True)]
                            for g, rows in sorted(groups.items())}}, indent=1))
        return 0
    print(f"rtol {args.rtol:g}: equal {result['equal']}, different {result['different']}, "
          f"only old {len(result['only_old'])}, only new {len(result['only_new'])}")
    for group, rows in sorted(groups.items()):
        rows.sort(reverse=True)
        print(f"\n{group}: {len(rows)} different, largest relative change {rows[0][0]:.3g}")
        for c, p, o, n in rows[: args.show]:
            print(f"  {p}: {o!r} -> {n!r} ({c:.3g})")
    for label in ("only_old", "only_new"):
        if result[label]:
            print(f"\n{label.replace('_', ' ')}:")
            for p in result[label][: args.show * 5]:
                print(f"  {_name(p)}")
            if len(result[label]) > args.show * 5:
                print(f"  ... and {len(result[label]) - args.show * 5} more")
    return 0


if __name__ == "__main__":
    sys.exit(main())
