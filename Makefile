# The two commands of the README: `make run` and `make test`.
VENV   ?= .venv
PY     := $(VENV)/bin/python
UV     := python3 -m uv
SCENE  ?= gantry

.PHONY: setup run test lint typecheck pytest bench clean

$(VENV)/.installed: pyproject.toml
	@$(UV) --version >/dev/null 2>&1 || python3 -m pip install --quiet --disable-pip-version-check uv
	$(UV) venv --quiet --allow-existing $(VENV)
	$(UV) pip install --quiet --python $(VENV)/bin/python -e ".[test]"
	@touch $@

setup: $(VENV)/.installed

run: setup
	$(PY) -m scenes run $(SCENE)

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

typecheck: setup
	$(VENV)/bin/mypy

pytest: setup
	$(PY) -m pytest

test: lint typecheck pytest

bench: setup
	$(PY) -m tests.benchmarks.servo_cycle
	$(PY) -m tests.benchmarks.gantry

clean:
	rm -rf $(VENV) .mypy_cache .ruff_cache
