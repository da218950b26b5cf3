# Two entry points, each self-contained on a machine with python3 and pip.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test docs bench floors clean

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

# the suite against the lowest versions pyproject.toml admits of the core dependencies (each `>=X` as `==X.*`), in
# .venv-floors: a floor that no longer holds (an API newer than it) fails here, not on a user's machine
FLOORS = $(shell $(PYTHON) -c 'import re, tomllib; print(" ".join(re.sub(r">=([0-9.]+)$$", r"==\1.*", requirement) for requirement in tomllib.load(open("pyproject.toml", "rb"))["project"]["dependencies"]))')
floors:
	rm -rf .venv-floors && $(PYTHON) -m venv .venv-floors
	.venv-floors/bin/python -m pip install --quiet $(foreach requirement,$(FLOORS),'$(requirement)') 'pytest>=7' 'pytest-xdist>=3.8'
	.venv-floors/bin/python -m pip install --quiet --no-deps -e .
	.venv-floors/bin/python -m pytest -n auto

clean:
	rm -rf $(VENV) .venv-floors report.txt report.html docs/_build
