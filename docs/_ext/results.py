"""Write ``reproducing.md`` from a results folder of ``maxwell-kinetics reproduce``.

The folder (config value ``results_dir``) holds ``summary.json`` (or ``summary_default.json``)
and one ``<name>.png`` per comparison, as written by ``make demo``.  For each comparison the page
gives what it tests (the first paragraph of its module's docstring), its verdicts (one row per
claim: status, measured ± σ, expected and its source, tolerance), its figure at full width
(linked to the full-size image), and, folded, every fitted number of the summary with its
uncertainty and the expected value.  Nothing is typed by hand, so the page cannot disagree with
the run it shows: a summary written before the verdicts existed gets them from the same
``verdicts(summary)`` function that ``reproduce`` uses.

Each comparison's section also gives its "Resolving power" (:func:`power_table`): per engine
parameter, the smallest relative error planted in it (``benchmarks/power.py``) that turns a
verdict to ``disagrees`` at ``--small`` (``figures/power_small.json``) and, where recorded, at
the default size (``figures/power_default.json``).
"""

from __future__ import annotations

import html
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


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|")


def summary_verdicts(name: str, entry: dict) -> list[dict] | None:
    """The verdict records of a comparison's summary; computed with the comparison's own
    ``verdicts`` when the summary predates them; None when they cannot be had."""
    recorded = entry.get("verdicts")
    # a summary of before the degrees of freedom were recorded gets its verdicts again from
    # the same numbers (statuses and z do not change; dof and σ's source are added)
    if isinstance(recorded, list) and all("combined_dof" in v for v in recorded):
        return recorded
    try:
        module = importlib.import_module(f"maxwell_kinetics.app.comparisons._{name}")
        return [v.to_dict() for v in module.verdicts(entry)]
    except (ImportError, AttributeError, KeyError, TypeError, IndexError, ValueError):
        return recorded if isinstance(recorded, list) else None


def _esc(text) -> str:
    return html.escape(" ".join(str(text).split()), quote=False)


def _z_cell(v: dict) -> str:
    z = v.get("deviation_in_sigma")
    if v["status"] == "not measured" or not isinstance(z, (int, float)) or not math.isfinite(z):
        return "—"
    return f"{z:+.1f}" if abs(z) < 999.5 else ("&gt; +999" if z > 0 else "&lt; −999")


def _dof_text(v: dict) -> str:
    """The law of a check's z: its degrees of freedom, and the trials of a largest |z|."""
    if not v.get("sigma") and not v.get("expected_sigma"):
        return "no standard error"
    dof = v.get("combined_dof")
    text = ("∞ (normal)" if dof is None else f"{dof:.3g} (Student's t)")
    if v.get("trials", 1) > 1:
        text += f", the largest |z| of {v['trials']}"
    return text


def _power_text(v: dict) -> str:
    """The smallest deviation this size resolves: the allowed deviation, also relative to the
    expected value."""
    allowed, expected = v.get("allowed"), v.get("expected")
    if not isinstance(allowed, (int, float)) or not allowed:
        return "exact comparison"
    text = f"deviations beyond {_fmt(allowed)}"
    if isinstance(expected, (int, float)) and expected:
        text += f" ({100 * allowed / abs(expected):.2g} % of the expected value)"
    return text


def _detail_rows(v: dict) -> list[tuple[str, str]]:
    from maxwell_kinetics.app.comparisons.verdicts import expected_text, measured_text

    rows = [("claim", _esc(v["claim"])), ("quantity", _esc(v["quantity"])),
            ("measured", _esc(measured_text(v))),
            ("expected", _esc(f"{expected_text(v)} ({v['source']})")),
            ("tolerance", _esc(f"{v['tolerance_text']} (allowed deviation "
                               f"{_fmt(v.get('allowed'))})")),
            ("σ from", _esc(v.get("sigma_source") or "not recorded")),
            ("degrees of freedom", _esc(_dof_text(v))),
            ("this size resolves", _esc(_power_text(v)))]
    key = {"explained": "explanation", "refuted": "refutation",
           "not measured": "resolution"}.get(v["status"])
    e = v.get(key) if key else None
    if v.get("why"):
        rows.append(("why", _esc(v["why"])))
    if e is not None and "quantity" in e:
        rows.append((key, _esc(f"{e['quantity']} = {measured_text(e)} against "
                                f"{expected_text(e)} ({e['source']}), {e['tolerance_text']}")))
    if v["status"] == "not measured" and v.get("measured_at"):
        where = v["measured_at"].strip()
        rows.append(("measured", _esc(f"on {where}")) if " " in where
                    else ("measured at", _esc(f"--{where}")))
    return rows


def _verdict_rows(records: list[dict]) -> list[str]:
    """The verdicts as a narrow table of expandable rows (HTML ``<details>``): each row's summary
    is the short claim, measured ± σ, expected, z and status; opened, it gives the claim, the
    quantity, the source, the tolerance, where σ comes from, its degrees of freedom and what
    this size resolves."""
    from maxwell_kinetics.app.comparisons.verdicts import expected_text, measured_text

    lines = ['<div class="verdicts">',
             '<div class="verdict-head"><span>claim</span><span>measured ± σ</span>'
             '<span>expected</span><span>z</span><span>status</span></div>']
    for v in records:
        status = v["status"]
        measured = "—" if status == "not measured" else _esc(measured_text(v))
        short = _esc(v.get("short") or v["claim"])
        details = "".join(f"<dt>{k}</dt><dd>{text}</dd>" for k, text in _detail_rows(v))
        lines.append(
            f'<details class="verdict status-{status.replace(" ", "-")}"><summary>'
            f'<span class="v-claim">{short}</span><span class="v-num">{measured}</span>'
            f'<span class="v-num">{_esc(expected_text(v))}</span>'
            f'<span class="v-num">{_z_cell(v)}</span>'
            f'<span class="v-status">{_esc(status)}</span></summary>'
            f"<dl>{details}</dl></details>")
    lines.append("</div>")
    return lines


def _calibration(records: dict) -> list[str]:
    """The section "Calibration of the verdicts": how many of the two-sided checks that agree
    lie beyond 1, 2 and 3σ, each z first under a normal law (as if its σ were exact), then
    under its own law (Student's t with the degrees of freedom of its σ, the largest of
    several values for a scan), against a calibrated set's counts; the binomial tail of the
    count beyond 2σ, the KS distance of the p-values from uniform and the rms z; and the
    checks still beyond 2σ.  Empty when no check has a z."""
    from maxwell_kinetics.app.comparisons.calibration import z_calibration

    summaries = {name: {"verdicts": recs or []} for name, recs in records.items()}
    chosen = {"statuses": ["agrees"], "relations": ["equal"]}
    sets = [("normal law (σ exact)", z_calibration(summaries, student=False, **chosen)),
            ("each z under its own law", z_calibration(summaries, **chosen))]
    if not sets[0][1]["n"]:
        return []

    def g(x):
        return "—" if x is None else f"{x:.2g}"

    lines = ["## Calibration of the verdicts", "",
             "If the standard errors σ are right, the two-sided checks that agree have "
             "p-values spread uniformly: about 31.7 %, 4.6 % and 0.27 % of them lie beyond 1, "
             "2 and 3σ. Most σ here come from 3 to 8 seeds: z = (measured − expected)/σ is then "
             "a Student's t with seeds − 1 degrees of freedom, not a normal variable, and a "
             "check that is the largest |z| over several times is the largest of that many. "
             "The second row converts each z to the normal z of its own p-value. Observed "
             "(expected) counts; the upper binomial tail of the count beyond 2σ; the "
             "Kolmogorov–Smirnov distance of the p-values from the uniform law (its p-value); "
             "the rms of the (normal) z, 1 when calibrated. Explained and refuted verdicts, and "
             "resolved differences (below, above, differs), are far from their value by design "
             "and are left out.", "",
             "| z taken under | checks | beyond 1σ | beyond 2σ | beyond 3σ | tail p (2σ) "
             "| KS (p) | rms z |", "|---|---|---|---|---|---|---|---|"]
    for label, c in sets:
        lines.append(f"| {label} | {c['n']} | " + " | ".join(
            f"{c['observed'][k]} ({c['expected'][k]:.2f})" for k in (1, 2, 3))
            + f" | {g(c['tail_p'])} | {g(c['ks'])} ({g(c['ks_p'])}) | {g(c['rms_z'])} |")
    lines.append("")
    beyond = sets[1][1]["beyond_2sigma"]
    if beyond:
        lines += ["Agreeing two-sided checks still beyond 2σ under their own law:", ""]
        for b in beyond:
            law = ("normal law" if b["dof"] is None
                   else f"Student's t, {b['dof']:.3g} dof: normal z {b['z_normal']:+.2f}")
            if b["trials"] > 1:
                law += f", the largest of {b['trials']}"
            lines.append(f"- {b['comparison'].replace('_', ' ')}: {_cell(b['claim'])} "
                         f"(z = {b['z']:+.2f}; {law})")
        lines.append("")
    return lines


def _percent(eps: float) -> str:
    return f"{100 * eps:.3g} %"


def _z_text(row: dict) -> str:
    """"claim" z = … (allowed …σ) of a power record's verdict."""
    text = f"“{_esc(row['claim'])}”"
    if isinstance(row.get("z"), (int, float)):
        text += f" z = {row['z']:+.3g}"
        if isinstance(row.get("allowance"), (int, float)):
            text += f" (allowed {row['allowance']:.3g}σ)"
    elif isinstance(row.get("ratio"), (int, float)):
        text += f" at {row['ratio']:.2g} of its tolerance"
    return text


def _moved_most(before: list[dict], after: list[dict]) -> tuple[dict, dict] | None:
    """Of the verdicts that agree without the error, the one (before, after) whose use of its
    allowance (``ratio``) the planted error changed most; None when none changed."""
    was = {r["claim"]: r for r in before
           if r.get("status") == "agrees" and isinstance(r.get("ratio"), (int, float))}
    pairs = [(was[r["claim"]], r) for r in after if r["claim"] in was
             and isinstance(r.get("ratio"), (int, float))]
    best = max(pairs, key=lambda p: abs(p[1]["ratio"] - p[0]["ratio"]), default=None)
    return best if best and best[1]["ratio"] != best[0]["ratio"] else None


def _changed(out: dict) -> str:
    """"; “claim” turns refuted (z = …)" for each other status change."""
    return "".join(f"; {_z_text(r)} turns {_esc(r['status'])}" for r in out.get("changed", [])
                   if r.get("status") in ("refuted", "explained"))


def _power_cell(runs: dict) -> str:
    """The smallest planted ε of ``runs`` (str(ε) → outcome) that turns a verdict to
    ``disagrees``; else, for the largest ε, the verdict it moved most (before and after,
    against its allowance).  Other status changes (to refuted, explained) are named."""
    planted = sorted((float(e), out) for e, out in runs.items() if float(e) > 0)
    if not planted:
        return "not run"
    for eps, out in planted:
        if out.get("disagrees"):
            note = f" ({_esc(out['planted'])})" if out.get("planted") else ""
            return (f"{_percent(eps)}{note}: "
                    + "; ".join(_z_text(r) for r in out["disagrees"]) + _changed(out))
    eps, out = planted[-1]
    note = f" ({_esc(out['planted'])})" if out.get("planted") else ""
    text = f"not at {_percent(eps)}{note}"
    after = out.get("verdicts") or []
    if after and all(r.get("status") == "not measured" for r in after):
        return text + ": every verdict is *not measured* at this size"
    moved = _moved_most((runs.get("0") or {}).get("verdicts", []), after)
    if moved and isinstance(moved[0].get("z"), (int, float)) and moved[1].get("allowance") \
            and isinstance(moved[1].get("z"), (int, float)):
        (b, a), name = moved, _esc(moved[1]["claim"])
        text += (f": it moves “{name}” most, from z = {b['z']:+.3g} to {a['z']:+.3g}, "
                 f"against {a['allowance']:.3g}σ allowed")
    elif moved:
        (b, a), name = moved, _esc(moved[1]["claim"])
        text += (f": it moves “{name}” most, from {b['ratio']:.2g} to {a['ratio']:.2g} of its "
                 f"tolerance")
    elif after and (runs.get("0") or {}).get("verdicts"):
        text += ": no verdict moves"
    elif out.get("largest"):
        text += ": closest " + _z_text(out["largest"])
    return text + _changed(out)


def power_table(name: str, small: dict, default: dict | None = None) -> list[str]:
    """The "Resolving power" list of comparison ``name``: per planted error, the smallest
    relative error that turns a verdict to ``disagrees`` at ``--small`` (from ``small``, the
    JSON of ``benchmarks/power.py``) and at the default size where ``default`` records one.
    A list, not a table: its entries are sentences, which a table's cells did not wrap (they
    ran off an 800 px page)."""
    entry = (small or {}).get("comparisons", {}).get(name)
    if not entry:
        return []
    lines = ["**Resolving power.** A relative error ε planted in one engine parameter; the "
             "smallest ε that turns a verdict to **disagrees**.", ""]
    if entry.get("no_plant"):
        return lines + [_esc(entry["no_plant"]), ""]
    names = (small or {}).get("plants", {})
    at_default = ((default or {}).get("comparisons", {}).get(name) or {}).get("plants", {})
    rows = []
    for plant, runs in entry.get("plants", {}).items():
        if not any(float(e) > 0 for e in runs):
            continue
        other = _power_cell(at_default[plant]) if plant in at_default else "—"
        rows.append(f"- **{_esc(names.get(plant, plant))}.** `--small`: {_power_cell(runs)}; "
                    f"default size: {other}")
    if not rows:
        return []
    return lines + [*rows, ""]


def _power(figures: Path) -> tuple[dict, dict]:
    """The power JSONs of ``figures`` (small, default; {} where absent)."""
    return tuple(json.loads(p.read_text()) if p.is_file() else {}
                 for p in (figures / "power_small.json", figures / "power_default.json"))


def claim_text(name: str) -> str:
    try:
        module = importlib.import_module(f"maxwell_kinetics.app.comparisons._{name}")
    except ImportError:
        return ""
    doc = (module.__doc__ or "").strip().split("\n\n")[0]
    return " ".join(doc.split()).replace("``run`` computes, ``plot`` draws.", "").strip()


def render(results: Path, figures_out: Path, power: tuple[dict, dict] | None = None) -> str:
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
    records = {name: summary_verdicts(name, entry) for name, entry in comparisons.items()}
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
        claim = claim_text(name)
        if claim:
            lines += [claim, ""]
        if records[name]:
            lines += _verdict_rows(records[name]) + [""]
        else:
            lines += ["No verdicts: this summary does not hold the numbers they are made of.", ""]
        if power:
            lines += power_table(name, *power)
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
    text = render(Path(app.config.results_dir), src / "_generated", _power(src / "figures"))
    page = src / "reproducing.md"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


def _summary(path: Path) -> dict:
    """The summary at ``path`` (a ``summary.json``, or a folder holding one), {} when none."""
    if path.is_dir():
        path = next((path / n for n in ("summary.json", "summary_default.json")
                     if (path / n).exists()), path / "summary.json")
    return json.loads(path.read_text()) if path.is_file() else {}


def render_measured(default: dict, full: dict, full_figures: Path, figures_out: Path) -> str:
    """The body of "Measured results": every verdict of the default-size summary ``default``
    beside the same claim's verdict in the ``--full`` summary ``full``, one table per
    comparison, and the figure of the full run where ``full_figures`` has one.  Every number
    comes from the two summaries (through the comparisons' own ``verdicts``)."""
    from maxwell_kinetics.app.comparisons.verdicts import expected_text, measured_text

    sizes = [("default size", default), ("paper's size (`--full`)", full)]
    records = [{name: summary_verdicts(name, entry) or []
                for name, entry in summary.get("comparisons", {}).items()}
               for _, summary in sizes]
    lines = []
    for (label, _), recs in zip(sizes, records, strict=True):
        counts: dict[str, int] = {}
        for v in (v for rs in recs.values() for v in rs):
            counts[v["status"]] = counts.get(v["status"], 0) + 1
        text = ", ".join(f"{n} {status}" for status, n in counts.items()) or "no verdicts"
        lines.append(f"- {label}: {len(recs)} comparisons, {text}")
    lines.append("")
    names = list(records[0]) + [n for n in records[1] if n not in records[0]]
    figures_out.mkdir(parents=True, exist_ok=True)
    for i, name in enumerate(names, 1):
        lines += [f"## {i}. {name.replace('_', ' ').capitalize()}", ""]
        claim = claim_text(name)
        if claim:
            lines += [claim, ""]
        at_full = {v["claim"]: v for v in records[1].get(name, [])}
        rows = [(v, at_full.pop(v["claim"], None)) for v in records[0].get(name, [])]
        rows += [(None, v) for v in at_full.values()]
        if rows:
            lines += ["| claim | default size | paper's size | expected |", "|---|---|---|---|"]
        for small, large in rows:
            either = small or large

            def cell(v, ran):
                if v is None:
                    return "—" if ran else "not run"
                if v["status"] == "not measured":
                    return "*not measured*"
                return f"{_cell(_esc(measured_text(v)))} ({v['status']})"

            lines.append(f"| {_cell(_esc(either.get('short') or either['claim']))} | "
                         f"{cell(small, name in records[0])} | {cell(large, name in records[1])} | "
                         f"{_cell(_esc(expected_text(either)))} |")
        lines.append("")
        png = full_figures / f"{name}.png"
        if name in records[1] and png.exists():
            shutil.copyfile(png, figures_out / f"full_{png.name}")
            lines += [f"```{{figure}} /_generated/full_{png.name}", f":alt: {name}, --full",
                      ":width: 100%", "", f"{name.replace('_', ' ')} at the paper's size", "```",
                      ""]
    return "\n".join(lines) + "\n"


def write_measured(app) -> None:
    """Write ``_generated/measured_results.md``, the body of "Measured results"
    (``results.md`` includes it), from the default summary of ``results_dir`` and the
    ``--full`` summary ``results_full``."""
    src = Path(app.srcdir)
    full = Path(app.config.results_full)
    text = render_measured(_summary(Path(app.config.results_dir)), _summary(full),
                           full.parent / "full", src / "_generated")
    page = src / "_generated" / "measured_results.md"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


def setup(app):
    app.add_config_value("results_dir", "", "env")
    app.add_config_value("results_full", "", "env")
    app.connect("builder-inited", write_page)
    app.connect("builder-inited", write_measured)
    return {"parallel_read_safe": True, "version": "1"}
