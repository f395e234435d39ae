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
