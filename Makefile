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

# The standard condition (pre -> gross -> fine) at a laptop budget: a few minutes on 2 cores.
DEMO_OUT := recordings/demo-standard
demo: $(VENV)/.installed
	$(BIN)/dart-reach reach --seconds 3
	$(BIN)/dart-reach train standard --generations 3 --replications 2 --trials 6 \
		--out $(DEMO_OUT) $(if $(wildcard $(DEMO_OUT)/manifest.json),--resume,)
	@echo
	@echo "Results in $(DEMO_OUT):"
	@echo "  manifest.json        every setting, seed, version and the git revision"
	@echo "  generations.parquet  best/mean/min fitness per phase, replication and generation"
	@echo "  phases/*/final.npz   final populations (numpy); phases/*/best.parquet (polars)"
	@echo "Look at the fitness curves with:"
	@echo "  $(BIN)/python -c \"import polars as pl; print(pl.read_parquet('$(DEMO_OUT)/generations.parquet'))\""

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
