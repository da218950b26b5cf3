# Two entry points, each self-contained on a machine with python3 and pip.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench clean

$(BIN)/closedchain: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(BIN)/closedchain
	$(BIN)/closedchain report --output report.txt

test: $(BIN)/closedchain
	$(BIN)/python -m pytest -n auto

bench: $(BIN)/closedchain
	$(BIN)/python benchmarks/speed.py
	$(BIN)/python benchmarks/startup.py
	$(BIN)/python benchmarks/large_mechanisms.py

clean:
	rm -rf $(VENV) report.txt
