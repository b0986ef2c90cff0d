# Fresh machine: `make demo` and `make test` create .venv/, install the project
# (editable; `make test` with its test extra) and run.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# PYTHONWARNINGS: setuptools' advice on editable installs with a package_dir (demos/ installs as thermolimb_demos)
# is for people who import from the checkout's parent folder; it is not a problem here, so installs print nothing
PIP := PYTHONWARNINGS=ignore $(BIN)/python -m pip install --quiet
DEMO_STAMP := $(VENV)/.installed-demo
TEST_STAMP := $(VENV)/.installed-test
OUT ?= out

.PHONY: demo test test-slow test-other-blas bench install clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# the suite and what its demos need (MuJoCo for the thermal audit; no test tools; PyTorch, Ray and Stable-Baselines3
# only with their extras)
$(DEMO_STAMP): setup.cfg pyproject.toml | $(BIN)/python
	$(PIP) -e ".[mujoco]"
	touch $(DEMO_STAMP)

# the suite with its test extra (pytest, hypothesis, and the optional backends the tests exercise)
$(TEST_STAMP): setup.cfg pyproject.toml | $(BIN)/python
	$(PIP) -e ".[test,mujoco]"
	touch $(TEST_STAMP) $(DEMO_STAMP)

install: $(DEMO_STAMP)

demo: $(DEMO_STAMP)
	$(BIN)/thermolimb demo all --quick --quiet --out $(OUT)
	$(BIN)/thermolimb report $(OUT)

# every core (pytest-xdist); a test file stays on one worker (--dist loadfile), so the demos' tests share each
# demo's quick run
PYTEST := $(BIN)/python -m pytest -q -n auto --dist loadfile

# the default run (well under ten minutes on two cores); the long runs marked slow are `make test-slow`, and CI runs
# both (.ci/run)
test: $(TEST_STAMP)
	$(BIN)/ruff check --quiet .
	$(PYTEST) -m "not slow"

test-slow: $(TEST_STAMP)
	$(PYTEST) -m slow

# the robot rollouts again under another OpenBLAS kernel (an older generic one), as some machines select it: a test
# that depends on the BLAS kernel fails here, not on a user's machine (CI runs it)
BLAS_KERNEL := $(if $(filter x86_64,$(shell uname -m)),Prescott,ARMV8)
ROLLOUTS := tests/test_hexapod_control.py tests/test_humanoid_recovery.py tests/test_protection_robots.py \
	tests/test_endurance.py
test-other-blas: $(TEST_STAMP)
	OPENBLAS_CORETYPE=$(BLAS_KERNEL) $(PYTEST) -m "not slow" $(ROLLOUTS)

bench: $(TEST_STAMP)
	$(BIN)/python benchmarks/identification.py
	$(BIN)/python benchmarks/diagnose.py
	$(BIN)/python benchmarks/wrench.py
	$(BIN)/python benchmarks/thermal_ik.py
	$(BIN)/python benchmarks/envs.py
	$(BIN)/python benchmarks/protection.py
	$(BIN)/python benchmarks/hidden_effects.py
	$(BIN)/python benchmarks/travel.py

clean:
	rm -rf $(VENV) $(OUT) *.egg-info
