"""Write ``reproducing.md`` from a results folder of ``maxwell-kinetics reproduce``.

The folder (config value ``results_dir``) holds ``summary.json`` (or ``summary_default.json``)
and one ``<name>.png`` per comparison, as written by ``make demo``.  For each comparison the page
gives what it tests (the first paragraph of its module's docstring), its figure, and every
fitted number of the summary with its uncertainty and the expected value.  Nothing is typed by
hand, so the page cannot disagree with the run it shows.
"""

from __future__ import annotations

import importlib
import json
import math
import shutil
from pathlib import Path


def _fmt(x) -> str:
    if isinstance(x, bool) or x is None:
        return str(x)
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return str(x)
        return f"{x:.4g}"
    return str(x)


def _value(entry) -> tuple[str, str] | None:
    """(measured ± uncertainty, expected) of a summary entry, or None when it is not a number."""
    if isinstance(entry, (int, float)) and not isinstance(entry, bool):
        return _fmt(entry), ""
    if isinstance(entry, dict):
        measured = None
        for key in ("slope", "value", "estimate", "mean", "exponent", "measured"):
            if key in entry:
                measured = entry[key]
                break
        if isinstance(measured, list) and len(measured) == 2:
            measured, unc = measured
        else:
            unc = entry.get("uncertainty", entry.get("stderr"))
        if isinstance(measured, (int, float)) and not isinstance(measured, bool):
            text = _fmt(measured) + (f" ± {_fmt(unc)}" if isinstance(unc, (int, float)) else "")
            expected = entry.get("expected", entry.get("exact", ""))
            return text, _fmt(expected) if expected != "" else ""
    return None


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _rows(key: str, value, depth: int) -> list[str]:
    """Table rows of one summary entry: a fit (value ± uncertainty, expected), a number, a short
    list of numbers, or (two levels deep) a dict of those."""
    got = _value(value)
    if got is not None:
        return [f"| `{key}` | {got[0]} | {got[1]} |"]
    if isinstance(value, list) and 0 < len(value) <= 12 and all(map(_is_number, value)):
        return [f"| `{key}` | {', '.join(_fmt(v) for v in value)} | |"]
    if isinstance(value, dict) and depth < 2:
        rows = []
        for sub, item in value.items():
            rows += _rows(f"{key}.{sub}", item, depth + 1)
        return rows
    return []


def _claim(name: str) -> str:
    try:
        module = importlib.import_module(f"maxwell_kinetics.app.comparisons._{name}")
    except ImportError:
        return ""
    doc = (module.__doc__ or "").strip().split("\n\n")[0]
    return " ".join(doc.split()).replace("``run`` computes, ``plot`` draws.", "").strip()


def render(results: Path, figures_out: Path) -> str:
    summary_path = next((results / n for n in ("summary.json", "summary_default.json")
                         if (results / n).exists()), None)
    lines = ["# Reproducing the paper", "",
             "This page is generated at build time from the `summary.json` and the figures of "
             "`maxwell-kinetics reproduce` (what `make demo` runs); it shows every comparison "
             "with the paper {cite}`baldassarri2002`, its figure, and each fitted number with its "
             "uncertainty (standard error over seeds or fit, as recorded in the summary) and the "
             "expected value where the summary records one (4 significant digits here; the full "
             "values are in the summary).", ""]
    if summary_path is None:
        return "\n".join(lines + [f"No results found in `{results}`.", ""])
    summary = json.loads(summary_path.read_text())
    provenance = summary.get("provenance", "")
    seconds = summary.get("seconds")
    lines += [f"- results folder: `{results.name}/{summary_path.name}`",
              f"- size: `{summary.get('size', '?')}`"]
    if seconds is not None:
        lines.append(f"- run time of `reproduce`: {seconds:.0f} s")
    if provenance:
        lines.append(f"- provenance: {provenance}")
    lines.append("")
    figures_out.mkdir(parents=True, exist_ok=True)
    for i, (name, entry) in enumerate(summary.get("comparisons", {}).items(), 1):
        lines += [f"## {i}. {name.replace('_', ' ').capitalize()}", ""]
        claim = _claim(name)
        if claim:
            lines += [claim, ""]
        png = results / f"{name}.png"
        if png.exists():
            shutil.copyfile(png, figures_out / png.name)
            lines += [f"```{{figure}} _generated/{png.name}", f":alt: {name}", "", "```", ""]
        rows = []
        for key, value in entry.items():
            if key != "parameters":
                rows += _rows(key, value, 0)
        if rows:
            lines += ["| quantity | measured | expected |", "|---|---|---|", *rows, ""]
        params = entry.get("parameters")
        if isinstance(params, dict):
            text = ", ".join(f"{k} = {json.dumps(v)}" for k, v in params.items()
                             if len(json.dumps(v)) < 40)
            lines += [f"Parameters: {text}.", ""]
    return "\n".join(lines) + "\n"


def write_page(app) -> None:
    src = Path(app.srcdir)
    text = render(Path(app.config.results_dir), src / "_generated")
    page = src / "reproducing.md"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


def setup(app):
    app.add_config_value("results_dir", "", "env")
    app.connect("builder-inited", write_page)
    return {"parallel_read_safe": True, "version": "1"}
