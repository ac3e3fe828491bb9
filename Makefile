# spectrace: `make render` and `make test` set themselves up on a fresh machine.
# The virtual environment is .venv/ (made once, reinstalled only when pyproject.toml changes);
# a libLLVM >= 16 for Dr.Jit's LLVM backend is installed with apt-get when missing (as root).
# `make gallery` renders every scene and runs the notebooks at full size into docs/gallery/,
# `make studies` executes the notebooks to HTML under out/studies/, `make lab` opens them in
# JupyterLab (the `lab` extra, installed into .venv on first use).

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
LAB_STAMP := $(VENV)/.installed-lab
SCENE  ?= scenes/showcase.xml
OUT    ?= out/showcase.exr
PYTEST_ARGS ?=
GALLERY ?= docs/gallery
# JupyterLab refuses to start as root unless told to (these machines run as root).
LAB_FLAGS ?= $(if $(filter 0,$(shell id -u)),--allow-root,)

.PHONY: render test bench validate setup libllvm bytecode doctor gallery studies lab clean

render: setup
	$(BIN)/spectrace render $(SCENE) -o $(OUT)

test: setup
	$(BIN)/python -m pytest $(PYTEST_ARGS)

bench: setup
	@set -e; for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b; done

# The CIE 171:2006 case families at full size (the test suite runs them --quick).
validate: setup
	$(BIN)/spectrace validate -o out/validation

doctor: setup
	$(BIN)/spectrace doctor

setup: $(STAMP) libllvm bytecode

libllvm: $(STAMP)
	@$(BIN)/python -m spectrace.llvm

# The project's own modules compiled to __pycache__ (only those changed since): pip compiles
# what it installs, not an editable install's sources, and where PYTHONDONTWRITEBYTECODE is
# set (as on these machines) every command would compile them again at start-up (about
# 0.15 s of each command's 0.45 s).
bytecode: $(STAMP)
	@$(BIN)/python -m compileall -q spectrace plugins photometry spectral

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	@touch $@

# Every scene at its default settings (one spectrace render call: plugins registered once,
# kernels reused), then the small PNGs of the README:
# the scenes and the notebooks' key figures (the notebooks run at full size).
gallery: setup
	@mkdir -p out/gallery $(GALLERY)
	$(BIN)/spectrace render scenes/*.xml -o out/gallery/ -q
	$(BIN)/spectrace render scenes/shadow_acne.xml -D shadow_bias=0.01 -q \
		-o out/gallery/shadow_acne_biased.exr
	$(BIN)/python docs/make_gallery.py --renders out/gallery --out $(GALLERY)

# The notebooks executed at full size, as HTML pages for a browser (needs the `lab` extra,
# which brings nbconvert).
studies: setup $(LAB_STAMP)
	@mkdir -p out/studies
	$(BIN)/jupyter nbconvert --to html --execute --ExecutePreprocessor.timeout=1800 \
		--output-dir out/studies notebooks/*.ipynb

# JupyterLab on the notebooks folder (installed into .venv once).
lab: setup $(LAB_STAMP)
	$(BIN)/jupyter lab --notebook-dir=notebooks $(LAB_FLAGS)

$(LAB_STAMP): pyproject.toml $(STAMP)
	$(BIN)/python -m pip install --quiet -e ".[test,lab]"
	@touch $@

clean:
	rm -rf out .pytest_cache
