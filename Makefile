# spectrace: `make render` and `make test` set themselves up on a fresh machine.
# The virtual environment is .venv/ (made once, reinstalled only when pyproject.toml changes);
# a libLLVM >= 16 for Dr.Jit's LLVM backend is installed with apt-get when missing (as root).

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
SCENE  ?= scenes/showcase.xml
OUT    ?= out/showcase.exr
PYTEST_ARGS ?=

.PHONY: render test bench setup libllvm doctor clean

render: setup
	$(BIN)/spectrace render $(SCENE) -o $(OUT)

test: setup
	$(BIN)/python -m pytest $(PYTEST_ARGS)

bench: setup
	@set -e; for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b; done

doctor: setup
	$(BIN)/spectrace doctor

setup: $(STAMP) libllvm

libllvm: $(STAMP)
	@$(BIN)/python -m spectrace.llvm

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	@touch $@

clean:
	rm -rf out .pytest_cache
