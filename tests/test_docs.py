"""The documentation: the site builds with warnings as errors, the API reference lists every
public name, and the code of the README and of the getting-started page runs."""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
def _faces() -> list[str]:
    """The package faces the API reference is built from (``apigen_faces`` of docs/conf.py)."""
    import ast

    tree = ast.parse((DOCS / "conf.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "apigen_faces":
            return ast.literal_eval(node.value)
    raise AssertionError("docs/conf.py has no apigen_faces")


FACES = _faces()


@pytest.fixture(scope="module")
def built_site(tmp_path_factory):
    """The site built with -W (warnings are errors) and -n (nitpicky: every cross-reference to
    the project's names must resolve); the notebooks are not executed here (``make docs`` runs
    them).  About 10 s."""
    out = tmp_path_factory.mktemp("html")
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "html",
         "-D", "nb_execution_mode=off", "-d", str(out / ".doctrees"), str(DOCS), str(out)],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    return out


def test_site_builds_with_warnings_as_errors(built_site):
    for page in ["index", "getting_started", "theory", "reproducing", "cli", "api/index",
                 "performance", "changelog", "cite", "tutorials/index"]:
        assert (built_site / f"{page}.html").is_file(), page
    # The CLI reference is generated from the parser: every subcommand is on the page.
    import argparse

    from maxwell_kinetics.app.cli import build_parser

    cli = (built_site / "cli.html").read_text()
    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    assert len(sub.choices) >= 8
    for name in sub.choices:
        assert f'id="maxwell-kinetics-{name}"' in cli, name

def test_maths_render_without_a_network(built_site):
    # MathJax is served from the site itself: every page with maths loads the local copy and
    # nothing from a CDN
    assert (built_site / "_static" / "mathjax" / "tex-chtml.js").is_file()
    theory = (built_site / "theory.html").read_text()
    assert 'src="_static/mathjax/tex-chtml.js"' in theory
    for page in built_site.rglob("*.html"):
        assert "cdn.jsdelivr" not in page.read_text(errors="replace"), page


def test_every_public_name_is_in_the_api_reference(built_site):
    from sphinx.util.inventory import InventoryFile

    with open(built_site / "objects.inv", "rb") as stream:
        inventory = InventoryFile.load(stream, "", lambda base, uri: uri)
    documented = set()
    for role, entries in inventory.items():
        if role.startswith("py:"):
            documented.update(entries)
    missing = [f"{face}.{name}" for face in FACES
               for name in importlib.import_module(face).__all__
               if f"{face}.{name}" not in documented]
    assert not missing, missing


def _python_blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


@pytest.mark.parametrize("page", ["README.md", "docs/index.md", "docs/getting_started.md",
                                  "docs/guide/sticky.md", "docs/guide/particles.md",
                                  "docs/guide/kernels.md",
                                  "docs/guide/ensembles.md", "docs/guide/reproducibility.md",
                                  "docs/guide/errors.md"])
def test_code_examples_run(page, tmp_path, monkeypatch, capsys):
    from particles.kernels import KERNELS

    blocks = _python_blocks(ROOT / page)
    assert blocks, f"no ```python block in {page}"
    monkeypatch.chdir(tmp_path)
    registered = dict(KERNELS)
    try:
        for block in blocks:  # as a script (the ensemble example runs under its __main__ guard)
            exec(compile(block, page, "exec"), {"__name__": "__main__"})
    finally:  # a kernel an example registers is not left for the tests that list the registry
        KERNELS.clear()
        KERNELS.update(registered)
    assert capsys.readouterr().out.strip()  # the examples print their results


def test_readme_is_short():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 150


def test_no_references_to_outside_documents():
    # Conventions are stated in the project's words: no external spec sections, no issue numbers.
    pattern = re.compile("SP" + r"EC\b|\b[Ii]ssue \d+")
    hits = []
    for folder in ["particles", "maxwell_kinetics", "tests", "notebooks", "docs"]:
        for path in (ROOT / folder).rglob("*"):
            if path.suffix not in (".py", ".ipynb", ".md", ".rst") or "_build" in path.parts:
                continue
            for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                if pattern.search(line):
                    hits.append(f"{path.relative_to(ROOT)}:{n}")
    assert not hits, hits


class _ProseText(HTMLParser):
    """The text a reader sees in a built page's article, without code (``<pre>``, ``<code>``,
    literals) and without typeset maths (MathJax's ``math`` spans and divs)."""

    _SKIP_TAGS = {"pre", "code", "script", "style", "math"}
    _SKIP_CLASSES = {"math", "highlight", "pre"}
    _VOID = {"br", "img", "hr", "meta", "link", "input", "col", "area", "base", "wbr", "source"}

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.open: list[tuple[str, bool, bool]] = []  # (tag, skipped, article)
        self.skip = self.article = 0
        self.parts: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag in self._VOID:
            return
        classes = set((dict(attrs).get("class") or "").split())
        skip = tag in self._SKIP_TAGS or bool(classes & self._SKIP_CLASSES)
        self.open.append((tag, skip, tag == "article"))
        self.skip += skip
        self.article += tag == "article"

    def handle_endtag(self, tag):
        if all(name != tag for name, _, _ in self.open):
            return  # a stray end tag closes nothing
        while self.open:
            name, skip, article = self.open.pop()
            self.skip -= skip
            self.article -= article
            if name == tag:
                break

    def handle_data(self, data):
        if self.article and not self.skip:
            self.parts.append(data)


def _prose(page: Path) -> str:
    parser = _ProseText()
    parser.feed(page.read_text(errors="replace"))
    return " ".join(parser.parts)


# What a user page must not hold in its prose: a commit hash (a word of 7 to 40 hex digits with
# both a digit and a letter, not the digits of a number such as 1.80e-35), raw TeX (maths is
# typeset, in $...$ or :math:), and words about the development of the code.
_PAGE_FAULTS = {
    "commit hash": re.compile(
        r"(?<![\w.\-+])(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}(?![\w\-+])"),
    "raw TeX": re.compile(r"\^\{|_\{|\\(?:frac|sqrt|mathrm|langle|rangle|int|sum|alpha|beta|gamma"
                          r"|lambda|tau|partial|cdot|left|right|infty|hat|tfrac|ln|exp)\b"),
    "development words": re.compile(r"\bVMs?\b|\bvCPUs?\b|\blent\b|\bthe issue\b|\bthis task\b",
                                    re.I),
}


def test_page_faults_are_found():
    # the scan finds each fault in a page (after a stray end tag too), and none in code or
    # typeset maths
    page = ("<article><p>Measured at 1a2b3c4 on this VM; e^{-x} and \\frac{1}{2}.</p>"
            "<pre>e^{-x} 1a2b3c4 VM</pre><code>x_{1}</code>"
            '<span class="math notranslate">\\(e^{-x}\\)</span>'
            "<p>q_min = 1.8048513878454153e-35, 10 runs</p></li><p>then t^{2/3}</p></article>")
    text = _ProseText()
    text.feed(page)
    prose = " ".join(text.parts)
    found = {kind: [m.group(0) for m in rule.finditer(prose)]
             for kind, rule in _PAGE_FAULTS.items()}
    assert found == {"commit hash": ["1a2b3c4"], "raw TeX": ["^{", "\\frac", "^{"],
                     "development words": ["VM"]}


def test_user_pages_hold_no_commit_hash_raw_tex_development_words_or_private_links(built_site):
    faults = []
    for page in sorted(built_site.rglob("*.html")):
        if {"_static", "_sources", "_modules"} & set(page.parts) or page.name in (
                "genindex.html", "search.html", "py-modindex.html"):
            continue
        html = page.read_text(errors="replace")
        for private in re.findall(r'href="[^"]*#[\w.]*\._[a-z][\w.]*"', html):
            faults.append(f"{page.relative_to(built_site)}: link to a private name: {private}")
        prose = _prose(page)
        for kind, rule in _PAGE_FAULTS.items():
            for m in rule.finditer(prose):
                context = prose[max(0, m.start() - 40):m.end() + 40].replace("\n", " ")
                faults.append(f"{page.relative_to(built_site)}: {kind}: ...{context}...")
    assert not faults, "\n".join(faults[:40]) + f"\n({len(faults)} in all)"


#: The most words an API page may hold, counted in its rendered text (the page's article as a
#: reader sees it, signatures and code included): a face with more is split into pages by
#: concept (``apigen_split`` of docs/conf.py).
API_PAGE_WORDS = 8000


class _ArticleText(HTMLParser):
    """The text of a page's ``<article>`` elements, and of its ``<body>`` (for a page without
    one), as the parser streams past (a tree of the whole page, as BeautifulSoup builds, took
    4.5 times as long for the same counts)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.inside = {"article": 0, "body": 0}
        self.text = {"article": [], "body": []}
        self.has_article = False

    def handle_starttag(self, tag, attrs):
        if tag in self.inside:
            self.inside[tag] += 1
            self.has_article |= tag == "article"

    def handle_endtag(self, tag):
        if self.inside.get(tag):
            self.inside[tag] -= 1

    def handle_data(self, data):
        for tag, depth in self.inside.items():
            if depth:
                self.text[tag].append(data)


def _rendered_words(page: Path) -> int:
    parser = _ArticleText()
    parser.feed(page.read_text(errors="replace"))
    parser.close()
    return len(" ".join(parser.text["article" if parser.has_article else "body"]).split())


def test_the_word_count_reads_the_article_only():
    """Words in the article are counted, the page's navigation around it is not; a page without
    an article counts its body, not its head."""
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder, "page.html")
        page.write_text("<html><head><title>t t t</title></head><body><nav>a b c</nav>"
                        "<article><h1>one two</h1><p>three &amp; <em>four</em></p></article>"
                        "<footer>x y</footer></body></html>")
        assert _rendered_words(page) == 5  # one two three & four
        page.write_text("<html><head><title>t t t</title></head><body><p>a b</p></body></html>")
        assert _rendered_words(page) == 2


def test_no_api_page_is_longer_than_8000_words(built_site):
    pages = sorted((built_site / "api").rglob("*.html"))
    counts = {page.relative_to(built_site).as_posix(): _rendered_words(page) for page in pages}
    # the count reads the documented names: the faces' pages and their sub-pages are there, and
    # the longest page holds thousands of words
    assert {f"api/{face.replace('.', '-')}.html" for face in FACES} <= set(counts)
    assert max(counts.values()) > 2000, counts
    too_long = {page: n for page, n in counts.items() if n > API_PAGE_WORDS}
    assert not too_long, too_long


_NUMBER = re.compile(r"(?<![\w.])[−-]?\d+(?:\.\d+)?(?:e[+−-]?\d+)?(?![\w.])")


def test_measured_results_come_from_the_summaries(built_site):
    """The page "Measured results" types no number by hand: its source has no digit outside the
    include of its generated body, and every number of the built page is one of the texts of
    the summaries' verdicts (measured ± σ, expected, counts) or of the comparisons' claims."""
    import json

    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import results
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    from maxwell_kinetics.app.comparisons.verdicts import expected_text, measured_text

    source = (DOCS / "results.md").read_text()
    assert "_generated/measured_results.md" in source
    assert not re.search(r"\d", source.replace("_generated/measured_results.md", ""))
    page = _prose(built_site / "results.html")
    allowed = []
    local = ROOT / "results" / "summary.json"  # the summary the site is built from (conf.py)
    default = local if local.exists() else DOCS / "figures" / "summary_default.json"
    for path in (default, DOCS / "figures" / "summary_full.json"):
        summary = json.loads(path.read_text())
        for name, entry in summary["comparisons"].items():
            allowed.append(results.claim_text(name))
            for v in results.summary_verdicts(name, entry) or []:
                allowed += [json.dumps(v, ensure_ascii=False), measured_text(v), expected_text(v)]
    known = set(_NUMBER.findall(" ".join(allowed)))
    shown = _NUMBER.findall(page)
    assert len(shown) > 100
    typed = sorted({n for n in shown if n not in known and not (n.isdigit() and int(n) <= 200)})
    assert not typed, typed[:40]
