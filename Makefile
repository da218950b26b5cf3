# Two entry points, each self-contained on a machine with python3 and pip.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test docs bench clean

$(BIN)/closedchain: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,docs]'
	touch $@

demo: $(BIN)/closedchain
	$(BIN)/closedchain report --output report.txt --html report.html

# the suite; the docs build (warnings are errors, so they cannot rot) and their examples are among its tests
test: $(BIN)/closedchain
	$(BIN)/python -m pytest -n auto

# the docs alone, the gallery's scripts run in parallel
docs: $(BIN)/closedchain
	$(BIN)/python -m sphinx -j auto -W -q -b html docs docs/_build/html
	$(BIN)/python -m sphinx -W -q -b doctest docs docs/_build/doctest

bench: $(BIN)/closedchain
	$(BIN)/python benchmarks/speed.py
	$(BIN)/python benchmarks/startup.py
	$(BIN)/python benchmarks/large_mechanisms.py
	$(BIN)/python benchmarks/sweep.py

clean:
	rm -rf $(VENV) report.txt report.html docs/_build
