# Two commands: `make demo` and `make test`. Both build their own .venv. `make test` also installs the package
# from a wheel into a fresh environment and runs it from outside the checkout (`make test-wheel`, .ci/wheel).
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test test-wheel test-all bench venv clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[all]"
	touch $(STAMP)

venv: $(STAMP)

demo: $(STAMP)
	$(PY) -m framework demo --out out

test: $(STAMP)
	$(PY) -m pytest -q -n auto --maxprocesses 4
	$(MAKE) --no-print-directory test-wheel

test-wheel: $(STAMP)
	PY=$(abspath $(PY)) .ci/wheel

test-all: $(STAMP)
	$(PY) -m pytest -q -n auto --maxprocesses 4 -m "slow or not slow"

bench: $(STAMP)
	$(PY) -m pip install --quiet tamaas
	$(PY) bench/summary.py
	$(PY) bench/rolling.py
	$(PY) bench/inclusion.py
	$(PY) bench/rolling_inclusion.py

clean:
	rm -rf $(VENV) out .pytest_cache .whl
