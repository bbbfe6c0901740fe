"""Sphinx configuration of the maxwell-kinetics documentation.

Generated at build time (never edited by hand, git-ignored):

* ``api/*.rst`` from the ``__all__`` of every package face (:mod:`_ext.apigen`);
* ``reproducing.md`` from a ``make demo`` results folder, and ``_generated/measured_results.md``
  (the body of ``results.md``) from it and the ``--full`` summary (:mod:`_ext.results`);
* ``tutorials/*.ipynb``, copies of ``notebooks/``.

Notebooks: ``nb_execution_mode`` is ``cache`` by default (executed once at the small size,
``MAXWELL_KINETICS_SMALL=1``, then cached in ``_build/.jupyter_cache``); the tests build with
``-D nb_execution_mode=off``.

Maths: MathJax 3 from the ``sphinx-mathjax-offline`` extension (a docs dependency) is copied
into ``_static/mathjax``, so that the site renders its equations without a network.
"""

import os
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MAXWELL_KINETICS_SMALL", "1")
# The notebooks' kernels start with _ext/kernel_startup.py (figures shown after each cell);
# IPython's folder for the build lives in _build.
_ipython = HERE / "_build" / ".ipython"
(_ipython / "profile_default" / "startup").mkdir(parents=True, exist_ok=True)
(_ipython / "profile_default" / "startup" / "00-figures.py").write_bytes(
    (HERE / "_ext" / "kernel_startup.py").read_bytes())
os.environ["IPYTHONDIR"] = str(_ipython)

from mathtext import typeset  # noqa: E402

import maxwell_kinetics  # noqa: E402

project = "maxwell-kinetics"
author = "the maxwell-kinetics authors"
copyright = "2026, " + author
release = version = maxwell_kinetics.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",
    "sphinx.ext.intersphinx",
    "myst_nb",
    "sphinxarg.ext",
    "sphinxcontrib.bibtex",
    "sphinx_copybutton",
    "apigen",
    "results",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "figures/full/*.json",
                    "_generated/*.md"]  # generated pages' bodies, included by their page
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3

nb_execution_mode = "cache"
nb_execution_timeout = 300
nb_execution_cache_path = str(HERE / "_build" / ".jupyter_cache")
nb_execution_raise_on_error = True
# Progress lines go to stderr; the tutorials show the results and figures only.
nb_output_stderr = "remove"

autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_default_options = {"members": True, "show-inheritance": True}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

bibtex_bibfiles = ["references.bib"]
bibtex_default_style = "plain"

intersphinx_mapping = {}

nitpicky = True
# Nitpicky on the project's own names; types of other libraries and prose in type fields
# (``float``, ``array_like``, ``numpy.ndarray``) are not checked.
nitpick_ignore_regex = [
    (r"py:.*", r"(?!particles|maxwell_kinetics).*"),
    (r"py:.*", r".*\._[a-z].*"),
]
# A dataclass field without a doc comment of its own (described in the class docstring).
nitpick_ignore = [("py:attr", "particles.driver.RunResult.final_state")]

html_theme = "pydata_sphinx_theme"
html_title = f"maxwell-kinetics {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # The guide, the tutorials, the paper and both references in the header; the rest under
    # "More".
    "header_links_before_dropdown": 6,
    "secondary_sidebar_items": ["page-toc"],
}
# The top-level pages have no sub-pages: no empty "Section Navigation" column on them.
html_sidebars = {"*": []}
html_static_path = ["_static"]
html_css_files = ["custom.css"]
# Straight "--speed" stays two hyphens; quotes and ellipses are still typographic.
smartquotes_action = "qe"
copybutton_prompt_text = r"\$ |>>> "
copybutton_prompt_is_regexp = True

apigen_faces = [
    "maxwell_kinetics",
    "particles",
    "particles.observables",
    "particles.driver",
    "particles.ensemble",
    "particles.md",
    "particles.models",
    "particles.sticky",
    "particles.sticky_observables",
    "particles.sticky_exact",
    "particles.sticky_comparison",
    "particles.sticky_chunks",
    "maxwell_kinetics.app.comparisons",
]
# The application is a package of its own: its names are documented under its faces.
apigen_layers = ["maxwell_kinetics.app"]
# The most used names lead their face's page, in this order.
apigen_first = ["solve", "Solution", "MaxwellModel", "SolverOptions", "simulate", "RunResult",
                "Ulam", "Lattice", "MDEngine", "StickyGas", "Histogram", "rescaled_histogram"]
# The faces whose one page would be too long to read (over 8000 words; the docs tests check
# every API page) are split into one page per concept: (page, title, the modules whose names
# it documents).  A name of a module no entry lists stays on the face's own page (the
# errors, and the names the face shares with another).
apigen_split = {
    "maxwell_kinetics": [
        ("solver", "The kinetic solver",
         ["maxwell_kinetics.solver", "maxwell_kinetics.solution", "maxwell_kinetics.methods",
          "maxwell_kinetics.grid", "maxwell_kinetics.moments"]),
        ("models", "Collision models and initial laws",
         ["maxwell_kinetics.model", "particles.initial"]),
        ("hard_rods", "The hard-rod Boltzmann equation",
         ["maxwell_kinetics.inelastic_boltzmann", "maxwell_kinetics.boltzmann_solution",
          "maxwell_kinetics.velocity_grid"]),
        ("exact", "Exact results, tails, rates and steady states",
         ["maxwell_kinetics.exact", "maxwell_kinetics.tails", "maxwell_kinetics.stationary",
          "maxwell_kinetics.linear_rates", "maxwell_kinetics.driven"]),
    ],
    "particles": [
        ("kinetic_models", "The Ulam model, the lattice and the collision kernels",
         ["particles.ulam", "particles.lattice", "particles.sphere_kernels"]),
        ("md_and_sticky", "Molecular dynamics and the sticky gas",
         ["particles.md.*", "particles.sticky"]),
        ("runs", "Running a simulation and its results",
         ["particles.driver.*", "particles.initial", "particles.persistence",
          "particles.validation"]),
        ("observables", "Observables", ["particles.observables"]),
    ],
    "maxwell_kinetics.app.comparisons": [
        ("registry", "The comparison and its registry",
         ["maxwell_kinetics.app.comparisons.base"]),
        ("comparisons", "The comparisons of the paper",
         ["maxwell_kinetics.app.comparisons._*"]),
        ("runs_and_predictions", "Particle runs, kinetic predictions and analysis",
         ["maxwell_kinetics.app.comparisons.particle_runs",
          "maxwell_kinetics.app.comparisons.kinetic_predictions",
          "maxwell_kinetics.app.comparisons.analysis"]),
    ],
}
# The results shown on "Reproducing the paper": $MAXWELL_KINETICS_DOCS_RESULTS, else the
# results/ folder of a local `make demo` when it has a summary, else the `make demo` run whose
# summary and figures are kept in docs/figures.
results_dir = os.environ.get("MAXWELL_KINETICS_DOCS_RESULTS") or (
    str(ROOT / "results") if (ROOT / "results" / "summary.json").exists()
    else str(HERE / "figures"))

# The paper's sizes on "Measured results" (beside the default size of results_dir): the
# summary of `reproduce --full`, its figures in the folder full/ next to it.
results_full = str(HERE / "figures" / "summary_full.json")

# The notebooks are copied from notebooks/ so that the tutorials are the same files; a copy
# whose notebook is gone (renamed or removed) is deleted, so the sidebar lists only the
# notebooks of notebooks/, in the order of their numbers (tutorials/index.md).
_tutorials = HERE / "tutorials"
_notebooks = sorted((ROOT / "notebooks").glob("*.ipynb"))
for _stale in sorted(_tutorials.glob("*.ipynb")):
    if _stale.name not in {_nb.name for _nb in _notebooks}:
        _stale.unlink()
for _nb in _notebooks:
    _dest = _tutorials / _nb.name
    if not _dest.exists() or _dest.read_bytes() != _nb.read_bytes():
        _dest.write_bytes(_nb.read_bytes())


# Docstrings are written in plain mathematical text: |x| is an absolute value, not a
# reStructuredText substitution, and e^{−λτ} is typeset (mathtext.typeset).  Escape the bars
# outside ``literals`` and :math:`roles`.
_LITERAL = re.compile(r"(``.*?``|:[a-z:]+:`[^`]*`|`[^`]*`)")


def _escape_bars(app, what, name, obj, options, lines):
    for i, line in enumerate(lines):
        parts = _LITERAL.split(typeset(line))
        for j in range(0, len(parts), 2):
            parts[j] = re.sub(r"(?<!\\)\|", r"\\|", parts[j])
            parts[j] = re.sub(r"(?<=\w)_(?=[^\w{`]|$)", r"\\_", parts[j])
        lines[i] = "".join(parts)


def setup(app):
    app.connect("autodoc-process-docstring", _escape_bars)
