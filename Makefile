# ccedi: two commands on a fresh machine with Python 3.11 and pip.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test bench clean

$(STAMP): pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --upgrade pip
	$(BIN)/pip install -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/ccedi study --paper --out reports

# two pytest-xdist workers (the CI machine has 2 cores), whole test files per worker so that
# each module-scoped fixture (an FE run shared by several tests) is computed once
test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadfile

bench: $(STAMP)
	$(BIN)/python benchmarks/fea_speed.py

clean:
	rm -rf $(VENV) *.egg-info .pytest_cache
