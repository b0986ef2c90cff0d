# Fresh machine: `make demo` and `make test` create .venv/, install the project
# (editable; `make test` with its test extra) and run.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
PIP := $(BIN)/python -m pip install --quiet
DEMO_STAMP := $(VENV)/.installed-demo
TEST_STAMP := $(VENV)/.installed-test
OUT ?= out

.PHONY: demo test test-fast bench install clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# the suite and what its demos need (no test tools; PyTorch, Ray and Stable-Baselines3 only with their extras)
$(DEMO_STAMP): setup.cfg pyproject.toml | $(BIN)/python
	$(PIP) -e .
	touch $(DEMO_STAMP)

# the suite with its test extra (pytest, hypothesis, and the optional backends the tests exercise)
$(TEST_STAMP): setup.cfg pyproject.toml | $(BIN)/python
	$(PIP) -e ".[test]"
	touch $(TEST_STAMP) $(DEMO_STAMP)

install: $(DEMO_STAMP)

demo: $(DEMO_STAMP)
	$(BIN)/thermolimb demo all --quick --out $(OUT)
	$(BIN)/thermolimb report $(OUT)

test: $(TEST_STAMP)
	$(BIN)/python -m pytest -q

test-fast: $(TEST_STAMP)
	$(BIN)/python -m pytest -q -m "not slow"

bench: $(TEST_STAMP)
	$(BIN)/python benchmarks/identification.py
	$(BIN)/python benchmarks/diagnose.py
	$(BIN)/python benchmarks/wrench.py
	$(BIN)/python benchmarks/thermal_ik.py
	$(BIN)/python benchmarks/envs.py
	$(BIN)/python benchmarks/protection.py
	$(BIN)/python benchmarks/hidden_effects.py

clean:
	rm -rf $(VENV) $(OUT) *.egg-info
