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

.PHONY: run test bench system-deps

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[dev,cluster]'
	touch $@

run: $(BIN)/.installed
	$(BIN)/rigsim demo

system-deps:
	bash scripts/system-deps.sh

test: $(BIN)/.installed system-deps
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/lint-imports
	$(BIN)/pytest

bench: $(BIN)/.installed system-deps
	$(BIN)/python benchmarks/bearing.py
