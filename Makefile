# Two commands do everything on a fresh machine: `make demo` and `make test`; `make docs`
# builds the documentation site into docs/_build/html; `make notebooks` installs Jupyter (the
# `notebooks` extra) and executes every notebook headless into $(NOTEBOOKS_OUT)/, and
# `make notebooks-open` opens notebooks/ in Jupyter.  `make demo` installs the project alone
# (no test or docs tools); it ends with the verdict table of `reproduce` and fails (exit 3)
# when a claim of the paper that the comparisons test disagrees with the run.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
RESULTS ?= results

NOTEBOOKS_OUT ?= notebooks_executed
# SMALL=1 runs the notebooks at the tests' size (seconds each) instead of their default size.
SMALL ?=

.PHONY: demo test test-full install lint bench clean docs notebooks notebooks-open mutants

$(PY):
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	touch $(STAMP)

install: $(STAMP)

DOCS_STAMP := $(VENV)/.installed-docs

$(DOCS_STAMP): pyproject.toml | $(STAMP)
	$(PY) -m pip install -q -e '.[docs]'
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)
	$(PY) -m sphinx -b html docs docs/_build/html

DEMO_STAMP := $(VENV)/.installed-demo

$(DEMO_STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e .
	touch $(DEMO_STAMP)

demo: $(DEMO_STAMP)
	$(VENV)/bin/maxwell-kinetics reproduce --out $(RESULTS)

NB_STAMP := $(VENV)/.installed-notebooks

$(NB_STAMP): pyproject.toml | $(PY)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[notebooks,xarray]'
	touch $(NB_STAMP)

notebooks: $(NB_STAMP)
	mkdir -p $(NOTEBOOKS_OUT)
	MAXWELL_KINETICS_SMALL=$(SMALL) $(VENV)/bin/jupyter nbconvert --to notebook --execute \
		--output-dir $(NOTEBOOKS_OUT) notebooks/*.ipynb

notebooks-open: $(NB_STAMP)
	$(VENV)/bin/jupyter notebook notebooks/

# The tests run on every core (pytest-xdist), dealt to the workers by file, the files that
# read the session's comparisons as one unit (tests/conftest.py).  `make test` deselects the
# tests marked `full` (long variants of checks the default set also makes); `make test-full`
# runs everything.  TEST_WORKERS=0 runs in one process.
TEST_WORKERS ?= auto
PYTEST_XDIST := -n $(TEST_WORKERS) --dist loadfile

test: install
	$(PY) -m pytest -q --durations=25 $(PYTEST_XDIST) -m "not full"

test-full: install
	$(PY) -m pytest -q --durations=25 $(PYTEST_XDIST)

lint: install
	$(VENV)/bin/ruff check maxwell_kinetics particles tests benchmarks

bench: install
	$(PY) benchmarks/solver.py timing
	$(PY) benchmarks/particles_ulam_lattice.py
	$(PY) benchmarks/md.py
	$(PY) benchmarks/compile_cache.py

# Mutation testing of the physics core (mutmut; configured in pyproject.toml [tool.mutmut]): not
# part of `make test`.  MUTANTS_ON: mutant-name globs (default: all of the configured modules,
# hours on 2 cores); e.g. make mutants MUTANTS_ON='particles.collision* particles.md.kernel*'.
MUTATION_STAMP := $(VENV)/.installed-mutation
MUTANTS_ON ?=
MUTANTS_CHILDREN ?= 2

$(MUTATION_STAMP): pyproject.toml | $(STAMP)
	$(PY) -m pip install -q -e '.[mutation]'
	touch $(MUTATION_STAMP)

mutants: $(MUTATION_STAMP)
	rm -rf mutants
	$(VENV)/bin/mutmut run --max-children $(MUTANTS_CHILDREN) $(MUTANTS_ON)
	$(VENV)/bin/mutmut results

clean:
	rm -rf $(VENV) $(RESULTS) $(NOTEBOOKS_OUT) build *.egg-info docs/_build docs/api docs/_generated mutants
