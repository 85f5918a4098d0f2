# Two commands do all the set-up on a fresh machine:
#   make run    the service with the four simulated stands posting to it
#   make test   lint, types, import layering and the whole test suite
PYTHON ?= python3
# One BLAS thread: the bearing solver's banded factorisations slow down, not up, with more
# (docs/reynolds.md); the service parallelises over requests instead.
export OPENBLAS_NUM_THREADS ?= 1
export OMP_NUM_THREADS ?= 1
VENV ?= .venv
BIN := $(VENV)/bin
# roc-validator (the RO-Crate validator the .eln tests run) pins rich < 14, which
# import-linter refuses: it lives in a venv of its own, called by its CLI.
CRATE_VENV ?= .venv-crate

.PHONY: run test bench system-deps

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[dev,cluster]'
	touch $@

# A failed install is said in one line and tried again next time; the tests that need the
# validator then skip, saying so.
$(CRATE_VENV)/bin/.installed:
	$(PYTHON) -m venv $(CRATE_VENV)
	if $(CRATE_VENV)/bin/pip install --quiet 'roc-validator>=0.13,<0.14'; then touch $@; \
	else echo "roc-validator could not be installed: the .eln validation tests will skip"; fi

run: $(BIN)/.installed
	$(BIN)/rigsim demo

system-deps:
	bash scripts/system-deps.sh

test: $(BIN)/.installed $(CRATE_VENV)/bin/.installed system-deps
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/lint-imports
	$(BIN)/pytest -n auto --dist loadfile --durations=25

bench: $(BIN)/.installed system-deps
	$(BIN)/python benchmarks/bearing.py
