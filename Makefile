# Two commands do everything on a fresh machine: `make demo` and `make test`; `make docs`
# builds the documentation site into docs/_build/html.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
RESULTS ?= results

.PHONY: demo test install lint bench clean docs mutants

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

demo: install
	$(VENV)/bin/maxwell-kinetics reproduce --out $(RESULTS)

test: install
	$(PY) -m pytest -q

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
	rm -rf $(VENV) $(RESULTS) build *.egg-info docs/_build docs/api docs/_generated mutants
