# The two commands of the README: `make run` (the viewer) and `make test`; `make mutate` tests
# the tests of a change (mutation testing, see docs/mutation-testing.md).
VENV   ?= .venv
PY     := $(VENV)/bin/python
UV     := python3 -m uv
SCENE  ?= gantry
HOST   ?= 127.0.0.1
PORT   ?= 8080
DOCS_PORT ?= 8000

.PHONY: setup run demo docs test lint typecheck pytest bench journey mutate clean

$(VENV)/.installed: pyproject.toml
	@$(UV) --version >/dev/null 2>&1 || python3 -m pip install --quiet --disable-pip-version-check uv
	$(UV) venv --quiet --allow-existing $(VENV)
	$(UV) pip install --quiet --python $(VENV)/bin/python -e ".[all,test]"
	@touch $@

# the optional compiled build (mypyc), beside the sources, rebuilt when a compiled source
# changed; pure Python where there is no C compiler
setup: $(VENV)/.installed
	@$(PY) -m mcl.build --if-stale mcl plc scenes

# the viewer starts at once: at 1x pure Python is fast enough, and a fresh compiled build is
# used when there is one (make setup, make test and make bench build it)
run: $(VENV)/.installed
	$(PY) -m viewer --scene $(SCENE) --host $(HOST) --port $(PORT)

demo: $(VENV)/.installed
	$(PY) -m scenes run $(SCENE)

# the documentation site (mkdocs.yml) on this machine only, rebuilt as its pages change
docs: $(VENV)/.installed
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs serve --dev-addr $(HOST):$(DOCS_PORT)

# ruff, then the layers and the extras' boundaries ([tool.importlinter] in pyproject.toml), then
# the documentation site built strictly into .build/site (a broken link or reference fails)
lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/lint-imports
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --quiet --site-dir .build/site

typecheck: setup
	$(VENV)/bin/mypy

# the browser tests first, alone (headless Chromium renders the 3-D view in software and needs
# the cores; beside physics tests its input events starve), then the rest of the suite in the
# active mode, then again in pure Python when the active one is compiled: the tests of the
# compiled packages (mcl, plc, scenes) without those marked `once`, whose subject does
# not change with the mode (the viewer's, the docs' and the journey's tests drive those packages
# from above: they run in the first pass)
pytest: setup
	$(PY) -m pytest -n 0 -m browser
	$(PY) -m pytest -n auto --dist loadgroup -m "not browser"
	@if $(PY) -c "import mcl, sys; sys.exit(not mcl.COMPILED)"; then \
		echo "== the tests of mcl, plc and scenes in pure Python (the browser, viewer, docs and"; \
		echo "   journey tests and those marked once have a subject the same in both modes)"; \
		MCL_PURE_PYTHON=1 $(PY) -m pytest -n auto --dist loadgroup -m "not browser and not once" \
			tests/mcl tests/plc tests/scenes; fi

test: lint typecheck pytest

# a new user's journey through every machine in headless Chromium (about 2 minutes a machine):
# a screenshot per step in .build/journey/ (OUT=DIR), MACHINES=a,b for some; DOCS=1 also
# writes the documentation's pictures (docs/images/machines/, docs/images/viewer.png),
# PICTURES=1 takes only those (each machine's demo a few steps in)
journey: setup
	$(PY) -m tests.journey $(if $(OUT),--out $(OUT)) $(if $(MACHINES),--machines $(MACHINES)) \
		$(if $(DOCS),--docs) $(if $(PICTURES),--pictures)

bench: setup
	$(PY) -m tests.benchmarks.machines
	$(PY) -m tests.benchmarks.servo_cycle
	$(PY) -m tests.benchmarks.gantry
	$(PY) -m tests.benchmarks.flying_shear
	$(PY) -m tests.benchmarks.press
	$(PY) -m tests.benchmarks.viewer
	$(PY) -m tests.benchmarks.trace
	$(PY) -m tests.benchmarks.st
	$(PY) -m tests.benchmarks.bridge
	$(PY) -m tests.benchmarks.cam_table
	$(PY) -m tests.benchmarks.arcs
	$(PY) -m tests.benchmarks.delta_picker

# mutation testing of the modules a change touched (against the merge base with main, or BASE),
# or of MODULES (whole, or with BASE their changed lines), only inside FUNCTIONS if given; the
# tests that exercise them, or TESTS; JOBS mutants at once (all cores)
MUTATE := $(if $(BASE),--base $(BASE)) $(if $(MODULES),--modules $(MODULES)) \
	$(if $(FUNCTIONS),--functions $(FUNCTIONS)) $(if $(TESTS),--tests $(TESTS)) \
	$(if $(JOBS),--jobs $(JOBS))
mutate: $(VENV)/.installed
	$(PY) -m tests.mutate $(strip $(MUTATE))

clean:
	-@$(PY) -m mcl.build --clean 2>/dev/null
	rm -rf $(VENV) .build .mypy_cache .ruff_cache .import_linter_cache
