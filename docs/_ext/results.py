"""Write ``reproducing.md`` from a results folder of ``maxwell-kinetics reproduce``.

The folder (config value ``results_dir``) holds ``summary.json`` (or ``summary_default.json``)
and one ``<name>.png`` per comparison, as written by ``make demo``.  For each comparison the page
gives what it tests (the first paragraph of its module's docstring), its verdicts (one row per
claim: status, measured ± σ, expected and its source, tolerance), its figure at full width
(linked to the full-size image), and, folded, every fitted number of the summary with its
uncertainty and the expected value.  Nothing is typed by hand, so the page cannot disagree with
the run it shows: a summary written before the verdicts existed gets them from the same
``verdicts(summary)`` function that ``reproduce`` uses.
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


_STATUS = {"agrees": "agrees", "disagrees": "**disagrees**", "explained": "*explained*",
           "refuted": "**refuted**", "not measured": "*not measured*"}


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|")


def _verdicts(name: str, entry: dict) -> list[dict] | None:
    """The verdict records of a comparison's summary; computed with the comparison's own
    ``verdicts`` when the summary predates them; None when they cannot be had."""
    if isinstance(entry.get("verdicts"), list):
        return entry["verdicts"]
    try:
        module = importlib.import_module(f"maxwell_kinetics.app.comparisons._{name}")
        return [v.to_dict() for v in module.verdicts(entry)]
    except (ImportError, AttributeError, KeyError, TypeError, IndexError, ValueError):
        return None


def _verdict_rows(records: list[dict]) -> list[str]:
    from maxwell_kinetics.app.comparisons.verdicts import expected_text, measured_text

    rows = ["| status | claim | measured | expected | tolerance |", "|---|---|---|---|---|"]
    for v in records:
        status = _STATUS.get(v["status"], v["status"])
        claim = _cell(v["claim"])
        key = {"explained": "explanation", "refuted": "refutation",
               "not measured": "resolution"}.get(v["status"])
        e = v.get(key) if key else None
        if e is not None and "quantity" in e:
            claim += (f"<br>*why:* {_cell(v['why'])}: {_cell(e['quantity'])} = "
                      f"{measured_text(e)} against {expected_text(e)} ({_cell(e['source'])}), "
                      f"{_cell(e['tolerance_text'])}")
        elif v.get("why"):
            claim += f"<br>*why:* {_cell(v['why'])}"
        rows.append(f"| {status} | {claim} | {_cell(v['quantity'])}: {measured_text(v)} | "
                    f"{expected_text(v)} ({_cell(v['source'])}) | {_cell(v['tolerance_text'])} |")
    return rows


def _calibration(records: dict) -> list[str]:
    """The section "Calibration of the verdicts": how many statistical checks (those with a
    z = deviation / σ) lie beyond 1, 2 and 3σ against a standard normal's counts, for all of
    them and for the two-sided checks that agree, with the p-value of the count beyond 2σ and
    the two-sided agreeing checks beyond 2σ; empty when no check has a z."""
    from maxwell_kinetics.app.comparisons.calibration import z_calibration

    summaries = {name: {"verdicts": recs or []} for name, recs in records.items()}
    sets = [("every check with a z", z_calibration(summaries)),
            ("agreeing, two-sided (=)",
             z_calibration(summaries, statuses=["agrees"], relations=["equal"]))]
    if not sets[0][1]["n"]:
        return []

    def p_text(p):
        return "—" if p is None else f"{p:.2g}"

    lines = ["## Calibration of the verdicts", "",
             "If the standard errors σ are right, z = (measured − expected)/σ of a two-sided "
             "check is close to a standard normal: about 31.7 %, 4.6 % and 0.27 % of the checks "
             "lie beyond 1, 2 and 3σ. Observed (expected) counts, and the two-sided binomial "
             "p-value of the count beyond 2σ. Explained and refuted verdicts, and resolved "
             "differences (below, above, differs), are far from their value by design: the "
             "second row leaves them out.", "",
             "| checks | number | beyond 1σ | beyond 2σ | beyond 3σ | p-value (2σ) |",
             "|---|---|---|---|---|---|"]
    for label, c in sets:
        lines.append(f"| {label} | {c['n']} | " + " | ".join(
            f"{c['observed'][k]} ({c['expected'][k]:.2f})" for k in (1, 2, 3))
            + f" | {p_text(c['p_value'])} |")
    lines.append("")
    beyond = sets[1][1]["beyond_2sigma"]
    if beyond:
        lines += ["Agreeing two-sided checks beyond 2σ:", ""]
        lines += [f"- {b['comparison'].replace('_', ' ')}: {_cell(b['claim'])} "
                  f"(z = {b['z']:+.2f})" for b in beyond]
        lines.append("")
    return lines


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
             "with the paper {cite}`baldassarri2002`. Each comparison starts with its verdicts: "
             "one row per claim, the quantity measured with its standard error (over seeds or "
             "of a fit), the expected value and where it comes from (an exact result, the "
             "paper's number, another model), the tolerance, and the status: **agrees** "
             "(within the tolerance), **disagrees**, *explained* (the claim holds once a named "
             "measurement artefact is removed, shown by an independent check), **refuted** (the "
             "claim is false, and the run shows its cause) or *not measured* (this size cannot "
             "resolve it; the row names the size that does). Its figure follows "
             "(click it for the full-size image), then, folded, every fitted number of the "
             "summary with its uncertainty and the expected value where the summary records "
             "one (4 significant digits here; the full values are in the summary).", ""]
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
    comparisons = summary.get("comparisons", {})
    records = {name: _verdicts(name, entry) for name, entry in comparisons.items()}
    counts = {}
    for recs in records.values():
        for v in recs or []:
            counts[v["status"]] = counts.get(v["status"], 0) + 1
    if counts:
        lines += ["Verdicts of this run: " + ", ".join(
            f"{counts.get(s, 0)} {s}" for s in ("agrees", "explained", "refuted",
                                                 "not measured", "disagrees")) + ".", ""]
        lines += _calibration(records)
    for i, (name, entry) in enumerate(comparisons.items(), 1):
        lines += [f"## {i}. {name.replace('_', ' ').capitalize()}", ""]
        claim = _claim(name)
        if claim:
            lines += [claim, ""]
        if records[name]:
            lines += _verdict_rows(records[name]) + [""]
        else:
            lines += ["No verdicts: this summary does not hold the numbers they are made of.", ""]
        png = results / f"{name}.png"
        if png.exists():
            shutil.copyfile(png, figures_out / png.name)
            # A width makes Sphinx link the image to its full-size file.
            lines += [f"```{{figure}} _generated/{png.name}", f":alt: {name}", ":width: 100%",
                      "", "```", ""]
        rows = []
        for key, value in entry.items():
            if key not in ("parameters", "verdicts"):
                rows += _rows(key, value, 0)
        params = entry.get("parameters")
        if rows or isinstance(params, dict):
            lines += ["<details>", f"<summary>All numbers of {name}</summary>", ""]
            if rows:
                lines += ["| quantity | measured | expected |", "|---|---|---|", *rows, ""]
            if isinstance(params, dict):
                text = ", ".join(f"{k} = {json.dumps(v)}" for k, v in params.items()
                                 if len(json.dumps(v)) < 40)
                lines += [f"Parameters: {text}.", ""]
            lines += ["</details>", ""]
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
