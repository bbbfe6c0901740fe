"""One meaning per symbol on the user's pages: q is the wave number of the rescaled transform
G(q, τ), never 1 − p (which the pages write out, or fold into λ = p(1 − p)); p is (1 + r)/2."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted([*ROOT.glob("docs/*.md"), *ROOT.glob("docs/guide/*.md"), ROOT / "README.md"])
NOTEBOOKS = sorted(ROOT.glob("notebooks/*.ipynb"))

#: q defined as 1 − p (TeX or plain), or p defined as (1 − r)/2.
WRONG = [re.compile(r"q\s*(=|\\equiv|≡)\s*1\s*(-|−)\s*p\b"),
         re.compile(r"p\s*=\s*\\?(t?frac\{1\s*(-|−)\s*r\}\{2\}|\(1\s*(-|−)\s*r\)\s*/\s*2)")]


def _texts():
    for page in PAGES:
        yield page.name, page.read_text()
    for notebook in NOTEBOOKS:
        cells = json.loads(notebook.read_text())["cells"]
        yield notebook.name, "\n".join("".join(c["source"]) for c in cells)


def test_q_is_the_wave_number_and_p_is_one_plus_r_over_two_everywhere():
    found = [(name, m.group(0)) for name, text in _texts() for rule in WRONG
             for m in rule.finditer(text)]
    assert found == []


def test_the_rules_catch_the_spellings_they_are_for():
    for text in ("We write $q = 1-p$", "q = 1 − p", r"$p = \frac{1-r}{2}$", "p = (1 − r)/2",
                 "$p = (1-r)/2$"):
        assert any(rule.search(text) for rule in WRONG), text
    for text in (r"G(pq)\,G((1-p)q)", "p = (1 + r)/2", r"p = \frac{1+r}{2}"):
        assert not any(rule.search(text) for rule in WRONG), text
