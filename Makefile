# The two commands of the README: `make run` (the viewer) and `make test`.
VENV   ?= .venv
PY     := $(VENV)/bin/python
UV     := python3 -m uv
SCENE  ?= gantry
HOST   ?= 127.0.0.1
PORT   ?= 8080

.PHONY: setup run demo test lint typecheck pytest bench clean

$(VENV)/.installed: pyproject.toml
	@$(UV) --version >/dev/null 2>&1 || python3 -m pip install --quiet --disable-pip-version-check uv
	$(UV) venv --quiet --allow-existing $(VENV)
	$(UV) pip install --quiet --python $(VENV)/bin/python -e ".[test]"
	@touch $@

setup: $(VENV)/.installed

run: setup
	$(PY) -m viewer --scene $(SCENE) --host $(HOST) --port $(PORT)

demo: setup
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
	$(PY) -m tests.benchmarks.viewer

clean:
	rm -rf $(VENV) .mypy_cache .ruff_cache
