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
# `fricctl reproduce` into $(BOOK)/reproduce (the default bench: the claims page) and
# `fricctl reproduce --bench literal` into $(BOOK)/reproduce-literal (the literal bench's columns
# of its summary table); a cell error or a Sphinx warning fails it.
# BOOK_SEEDS=N: training seeds of the claims (default 10, fast 2); BOOK_ONLY=01,05: execute only
# those chapters (a quick look); BOOK_REPRODUCE=reuse: keep the claims of the previous build.
# BOOK_JOBS=N: how many chapters (and the reproduce step) execute at once (default: the CPUs
# available; 1: reproduce first, then myst-nb executes the chapters one by one).
BOOK ?= build/book
BOOK_SEEDS ?=
BOOK_ONLY ?=
BOOK_JOBS ?=
BOOK_REPRODUCE ?= run
SPHINXOPTS ?=
BOOK_FLAGS = -E -W --keep-going -T -d $(BOOK)/doctrees -D fricctl_reproduce_dir=$(abspath $(BOOK))/reproduce \
	-D fricctl_reproduce=$(BOOK_REPRODUCE) $(if $(BOOK_SEEDS),-D fricctl_reproduce_seeds=$(BOOK_SEEDS)) \
	$(if $(BOOK_ONLY),-D fricctl_book_only=$(BOOK_ONLY)) $(if $(BOOK_JOBS),-D fricctl_book_jobs=$(BOOK_JOBS))

.PHONY: book

$(VENV)/.book-installed: $(BIN)/fricctl pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test,book]'
	touch $@

book: $(VENV)/.book-installed
	rm -rf $(BOOK)/html
	$(BIN)/python -m sphinx -b html $(BOOK_FLAGS) $(SPHINXOPTS) docs $(BOOK)/html
	@echo "The book is in $(BOOK)/html; open it with: python -m webbrowser $(abspath $(BOOK))/html/index.html"

# `make book-pdf`: the whole book as one PDF, $(BOOK)/latex/fricctl.pdf -- Sphinx's LaTeX builder
# on the notebooks the HTML build executed (`make book` runs first when there is no HTML book;
# no chapter is executed twice: FRICCTL_FAST=1 make book book-pdf gives the fast PDF; a notebook
# executed from other chapter code or other fricctl sources than today's fails it), then
# latexmk with XeLaTeX.  LaTeX comes from Debian's packages, installed here when we are root
# and apt-get exists; anywhere else the target says so and stops without failing.
LATEX_PACKAGES = texlive-latex-recommended texlive-latex-extra texlive-fonts-recommended \
	texlive-xetex latexmk lmodern fonts-freefont-otf poppler-utils
LATEX_CHECK = command -v latexmk >/dev/null && command -v xelatex >/dev/null && \
	kpsewhich tabulary.sty >/dev/null && fc-list | grep -q FreeSerif

.PHONY: book-pdf

book-pdf: $(VENV)/.book-installed
	@if ! ( $(LATEX_CHECK) ); then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "book-pdf: installing LaTeX from Debian: $(LATEX_PACKAGES)"; \
	    { apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
	      --no-install-recommends $(LATEX_PACKAGES); } || { \
	      echo "book-pdf: skipped: apt-get could not install LaTeX (no network or no such packages)"; \
	      exit 0; }; \
	  else \
	    echo "book-pdf: skipped: no LaTeX (latexmk, xelatex, texlive-latex-extra, FreeFont), and it"; \
	    echo "  cannot be installed here (needs root and apt-get). Install: $(LATEX_PACKAGES)"; \
	    exit 0; \
	  fi; \
	fi; \
	test -f $(BOOK)/html/index.html || $(MAKE) book || exit 1; \
	rm -rf $(BOOK)/latex; \
	$(BIN)/python -m sphinx -b latex -E -W --keep-going -T -d $(BOOK)/doctrees-latex \
	  -D nb_execution_mode=off -D fricctl_executed_notebooks=$(abspath $(BOOK))/html/_sources/chapters \
	  -D fricctl_reproduce=reuse -D fricctl_reproduce_dir=$(abspath $(BOOK))/reproduce \
	  $(SPHINXOPTS) docs $(BOOK)/latex || exit 1; \
	$(MAKE) -C $(BOOK)/latex LATEXMKOPTS="-silent -interaction=nonstopmode" all-pdf || exit 1; \
	echo "The book is in $(BOOK)/latex/fricctl.pdf"
