# dart_reach: two commands on a fresh machine with Python 3.11 and make.
#   make demo   creates .venv, installs the package, runs the main job on its defaults
#   make test   creates .venv, installs the dev extras, runs the whole test suite
PY ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench skeleton clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[dev]"
	touch $@ $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/dart-reach reach

test: $(VENV)/.installed-dev
	$(BIN)/python -m pytest -q

bench: $(VENV)/.installed
	$(BIN)/dart-reach bench --json bench.json

# Regenerate skeletons/icub_upper_body.urdf; VISUOMANIP is the path of the iCubGazeboV2_5_visuomanip
# URDF (robotology/icub-models), which the package does not ship.
skeleton: $(VENV)/.installed-dev
	$(BIN)/python skeletons/build_skeleton.py $(VISUOMANIP)

clean:
	rm -rf $(VENV) *.egg-info bench.json
