# Fresh machine: `make demo` and `make test` create .venv/, install the project
# (editable, with its test extra) and run.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= out

.PHONY: demo test test-fast bench install clean

$(STAMP): setup.cfg pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $(STAMP)

install: $(STAMP)

demo: $(STAMP)
	$(BIN)/thermolimb demo all --quick --out $(OUT)
	$(BIN)/thermolimb report $(OUT)

test: $(STAMP)
	$(BIN)/python -m pytest -q

test-fast: $(STAMP)
	$(BIN)/python -m pytest -q -m "not slow"

bench: $(STAMP)
	$(BIN)/python benchmarks/identification.py
	$(BIN)/python benchmarks/diagnose.py
	$(BIN)/python benchmarks/wrench.py
	$(BIN)/python benchmarks/thermal_ik.py
	$(BIN)/python benchmarks/envs.py
	$(BIN)/python benchmarks/protection.py
	$(BIN)/python benchmarks/hidden_effects.py

clean:
	rm -rf $(VENV) $(OUT) *.egg-info
