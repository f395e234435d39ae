# Two entry points (README quick start): `make reproduce` and `make test`.
# Both create .venv on first use, so a fresh clone needs only Python >= 3.10 and pip.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= results

.PHONY: reproduce test test-slow bench clean

$(BIN)/fricctl: pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

# --force: `make reproduce` is the request to (re)write $(OUT); `fricctl reproduce` alone refuses a
# non-empty folder (with --force it replaces only the files an earlier run wrote there)
reproduce: $(BIN)/fricctl
	MPLBACKEND=Agg $(BIN)/fricctl reproduce --seeds 10 --out $(OUT) --force

test: $(BIN)/fricctl
	MPLBACKEND=Agg $(BIN)/python -m pytest -q

test-slow: $(BIN)/fricctl
	MPLBACKEND=Agg $(BIN)/python -m pytest -q -m slow

bench: $(BIN)/fricctl
	MPLBACKEND=Agg $(BIN)/python benchmarks/run_all.py

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info

# `make book`: the book as a static site in $(BOOK)/html (docs/conf.py; FRICCTL_FAST=1 make book
# for the short version).  Every build executes the chapters afresh (-E) and runs
# `fricctl reproduce` into $(BOOK)/reproduce; a cell error or a Sphinx warning fails it.
# BOOK_SEEDS=N: training seeds of the claims (default 10, fast 2); BOOK_ONLY=01,05: execute only
# those chapters (a quick look); BOOK_REPRODUCE=reuse: keep the claims of the previous build.
BOOK ?= build/book
BOOK_SEEDS ?=
BOOK_ONLY ?=
BOOK_REPRODUCE ?= run
SPHINXOPTS ?=
BOOK_FLAGS = -E -W --keep-going -T -d $(BOOK)/doctrees -D fricctl_reproduce_dir=$(abspath $(BOOK))/reproduce \
	-D fricctl_reproduce=$(BOOK_REPRODUCE) $(if $(BOOK_SEEDS),-D fricctl_reproduce_seeds=$(BOOK_SEEDS)) \
	$(if $(BOOK_ONLY),-D fricctl_book_only=$(BOOK_ONLY))

.PHONY: book

$(VENV)/.book-installed: $(BIN)/fricctl pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test,book]'
	touch $@

book: $(VENV)/.book-installed
	rm -rf $(BOOK)/html
	$(BIN)/python -m sphinx -b html $(BOOK_FLAGS) $(SPHINXOPTS) docs $(BOOK)/html
	@echo "The book is in $(BOOK)/html; open it with: python -m webbrowser $(abspath $(BOOK))/html/index.html"
