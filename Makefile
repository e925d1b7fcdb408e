# dart_reach: two commands on a fresh machine with Python 3.11, 3.12 or 3.13 and make.
#   make demo   creates .venv, installs the package, trains and post-evaluates a small run
#   make test   creates .venv, installs the dev extras, runs the whole test suite
PY ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench skeleton clean notebooks screenshots scene-study pythons replication-50 replication-50x10 \
	replication-10 replication-report results full-budget full-budget-snapshots \
	levers-screen levers-train levers-evaluate levers-state levers-terms \
	campaign campaign-state campaign-snapshots campaign-phases

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[dev]"
	touch $@ $(VENV)/.installed

# The whole pipeline at a first-contact budget: the standard condition (pre -> gross -> fine),
# the post-evaluation of each replication's best robot under the four sensory conditions
# (section IV) and with the ball absent, beside 2 random genomes per phase, and the report:
# about 5 minutes on 2 cores.
DEMO_OUT := recordings/demo-standard
DEMO_REPORT := recordings/demo-standard-report.html
demo: $(VENV)/.installed
	$(BIN)/dart-reach reach --seconds 5
	$(BIN)/dart-reach train standard --generations 3 --replications 2 --trials 6 --record-every 1 \
		--out $(DEMO_OUT) $(if $(wildcard $(DEMO_OUT)/manifest.json),--resume,)
	$(BIN)/dart-reach evaluate $(DEMO_OUT) --sensors all --robots 1 --baseline 2
	$(BIN)/dart-reach report $(DEMO_OUT) --out $(DEMO_REPORT)
	@echo
	@echo "Results in $(DEMO_OUT):"
	@echo "  manifest.json        every setting, seed, version and the git revision"
	@echo "  generations.parquet  best/mean/min fitness per phase, replication and generation"
	@echo "  training.rrd         the same as Rerun time series (timeline: generation)"
	@echo "  phases/*/best/*.rrd  one trial of each replication's best individual per generation"
	@echo "  evaluation.parquet   one row per post-evaluation trial with the paper's measures"
	@echo "  evaluation/**/*.rrd  the trials of the best robot of the best replication"
	@echo "  evaluation/trial.rbl their layout in the viewer (scene, sensors, neurons, motors)"
	@echo "Watch a trial in the Rerun viewer (scene, sensors, neurons, motors, fitness):"
	@echo "  $(BIN)/rerun $$(ls $(DEMO_OUT)/evaluation/fine-*/normal/*/trial20-*.rrd | head -1) $(DEMO_OUT)/evaluation/trial.rbl"
	@echo "  $(BIN)/rerun $(DEMO_OUT)/training.rrd"
	@echo "Read the report (findings, provenance, training, Figs. 5-10) in a browser:"
	@echo "  $(abspath $(DEMO_REPORT))  (beside the run: a report never writes into a run)"
	@echo "Redraw the paper's figures 5-10 in Jupyter:"
	@echo "  make notebooks"

# The README's pictures (docs/images/*.png) from the demo run, rendered by the real Rerun viewer
# headless. Software Vulkan (Mesa's lavapipe) is the one system package it needs: installed
# here with apt-get where that is possible (as root on Debian/Ubuntu).
LAVAPIPE := /usr/share/vulkan/icd.d/lvp_icd.x86_64.json
screenshots: demo
	@test -f $(LAVAPIPE) || apt-get install -y -q --no-install-recommends mesa-vulkan-drivers \
		|| echo "install Mesa's Vulkan drivers (Debian: mesa-vulkan-drivers) to render headless"
	$(BIN)/python -m dart_reach.viewing.headless $(DEMO_OUT) docs/images

# Jupyter Lab on the analysis notebooks (installs the 'notebooks' extra on first use). As root
# (a container's user) Jupyter refuses to start without --allow-root: given there. Without a
# display no browser opens: Jupyter prints the address to open (from another machine, through
# ssh -L 8888:localhost:8888 HOST).
notebooks: $(VENV)/.installed-notebooks
	$(BIN)/jupyter lab notebooks/ $(if $(filter 0,$(shell id -u)),--allow-root)

$(VENV)/.installed-notebooks: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[notebooks]"
	touch $@

# The scene study of docs/results/scene-study.md: pre-reaching alone on each candidate scene, the same seeds,
# then the post-evaluation of the best 5 robots of each replication beside 10 random genomes
# (normal senses and the ball absent), and docs/results/scene-study/scene-study.md and .png.
# Resumable: run it again after an interruption. About 1 h per scene on 2 idle cores.
SCENES := near near-shoulder arm-length-shoulder
STUDY := recordings/scene-study
scene-study: $(VENV)/.installed
	for s in $(SCENES); do \
		$(BIN)/dart-reach train --model-version 1 docs/learning-check.toml --scene $$s --replications 2 \
			--generations 60 --trials 18 --seed 20 --record-every 0 --out $(STUDY)/$$s \
			$$(test -f $(STUDY)/$$s/manifest.json && echo --resume) || exit $$?; \
	done
	for s in $(SCENES); do for senses in normal no-ball; do \
		$(BIN)/dart-reach evaluate $(STUDY)/$$s --robots 5 --baseline 10 --sensors $$senses \
			--record none || exit $$?; \
	done; done
	$(BIN)/python -m reports.scene_study $(STUDY) docs/results/scene-study

# The longer replication of docs/results/replication.md: the standard condition and gross^,
# 50 generations per phase (gross^ 100), 4 replications, on the scene the scene study's rule fixed.
# Many hours of 2 cores: run it again after any interruption (it resumes), and commit the
# compact state under recordings/replication-50/ (docs/results/replication.md, "Resuming").
REPLICATION := recordings/replication-50
replication-50: $(VENV)/.installed
	$(BIN)/dart-reach train --model-version 1 standard gross-hat --generations 50 --replications 4 --seed 2013 \
		--scene arm-length-shoulder --record-every 5 --snapshot-every 5 --out $(REPLICATION) \
		$$(test -f $(REPLICATION)/manifest.json && echo --resume)

# Its stage 2, after stage 1 has trained: every condition of Fig. 10 at the scaled
# budget (10 generations per phase, 4 replications) on the same scene, so that F6 and F7 are
# run and every claim has a 10-generation point beside its 50-generation one. ~4 h of 2 cores;
# resumes like stage 1, its compact state tracked the same way.
FIG10 := recordings/replication-10
replication-10: $(VENV)/.installed
	$(BIN)/dart-reach train --model-version 1 standard gross-hat pre-h gross-h pre-star gross-hat-star fine-hat \
		fine-star --generations 10 --replications 4 --seed 2014 --scene arm-length-shoulder \
		--record-every 5 --snapshot-every 5 --out $(FIG10) \
		$$(test -f $(FIG10)/manifest.json && echo --resume)

# Ten replications, as the paper: the standard condition at 50 generations per phase and gross^
# at 100, on model version 1 and its scene, so that the replication can be the unit of every
# verdict and each transition merges the best 2 of each of the 10 replications (III-D). It took
# 28 h on 2 cores (docs/results/benchmarks.md); resumes like the others, its compact state
# tracked under recordings/replication-50x10/. It was started at a revision that pins neither
# numpy's BLAS kernels nor its dispatch: the variables do.
REPLICATION10 := recordings/replication-50x10
replication-50x10: $(VENV)/.installed
	OPENBLAS_CORETYPE=Haswell NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL AVX512_SPR AVX512F AVX512_SKX" \
		$(BIN)/dart-reach train --model-version 1 standard gross-hat --generations 50 --replications 10 --seed 2015 \
		--record-every 5 --snapshot-every 5 --out $(REPLICATION10) \
		$$(test -f $(REPLICATION10)/manifest.json && echo --resume)

# The paper's full budget: the standard condition at 500 generations per phase, 10
# replications, snapshots every 10 generations (and after 1, 2 and 5), recordings every 25.
# About 15,000 replication-generations, 100+ hours of 2 cores: it resumes from
# recordings/standard-500x10/ (its compact state is tracked) after every interruption. Paused
# at generation 258 while version 3's campaign (below) trains.
FULL := recordings/standard-500x10
full-budget: $(VENV)/.installed
	$(BIN)/dart-reach train --model-version 1 standard --generations 500 --replications 10 --seed 2016 \
		--snapshot-every 10 --record-every 25 --out $(FULL) \
		$$(test -f $(FULL)/manifest.json && echo --resume)

# Its pre-reaching snapshots post-evaluated while it trains (docs/results/
# pre-reaching-course.md): on a copy of the compact state in FULL_FROM (default the tracked one;
# the training holds its own directory's lock), every snapshot's best 5 under normal senses and
# 10 random genomes, every condition at the generations the claims are judged; only what is
# missing is evaluated; the judged snapshots' pre-reachers run again for Eq. 5's terms
# (docs/results/stillness.md). The tables come back into $(FULL); then `make results`.
FULL_FROM ?= $(FULL)
FULL_TABLES := development development.parquet baseline.parquet fitness-terms.parquet
FULL_COPY := $(or $(TMPDIR),/tmp)/dart-reach-full-budget-copy
JUDGED := 50,100,150,200,250
full-budget-snapshots: $(VENV)/.installed
	rm -rf $(FULL_COPY) && mkdir -p $(FULL_COPY)
	cp -r $(FULL_FROM)/manifest.json $(FULL_FROM)/generations.parquet $(FULL_FROM)/phases \
		$(FULL_COPY)/
	for t in $(FULL_TABLES); do \
		if [ -e $(FULL)/$$t ]; then cp -r $(FULL)/$$t $(FULL_COPY)/; fi; done
	$(BIN)/dart-reach evaluate $(FULL_COPY) --finished-only --development 5 --baseline 10
	$(BIN)/dart-reach evaluate $(FULL_COPY) --finished-only --development 5 \
		--development-sensors all --snapshots $(JUDGED)
	$(BIN)/python -m reports.stillness . --judged --run-dir $(FULL_COPY)
	rm -rf $(FULL)/development $(FULL)/development.parquet
	for t in $(FULL_TABLES); do \
		if [ -e $(FULL_COPY)/$$t ]; then cp -r $(FULL_COPY)/$$t $(FULL)/; fi; done

# The post-evaluation of the three runs (best 5 robots of every replication under the four
# senses and with the ball absent, 10 random genomes per phase, every snapshot's best 5) and the
# report over their budgets. Evaluating again adds only what is missing.
replication-report: $(VENV)/.installed
	for run in $(REPLICATION) $(FIG10) $(REPLICATION10); do \
		$(BIN)/dart-reach evaluate $$run --sensors all --robots 5 --baseline 10 \
			--development 5 || exit 1; done
	$(BIN)/dart-reach report $(REPLICATION) $(FIG10) $(REPLICATION10) --out recordings/replication-report.html

# The results docs (docs/results/templates/*.md rendered from the committed tables under
# recordings/, and scene-study/scene-study.md and .png); a test fails when they differ.
results: $(VENV)/.installed
	$(BIN)/python -m reports.scene_study $(STUDY) docs/results/scene-study > /dev/null
	$(BIN)/python -m reports.results .
	$(BIN)/python -m reports.levers

# The whole suite, one process per core (pytest-xdist). Each process takes its share of the test
# files in order, and one that runs out takes half of another's remaining tests (worksteal): a
# file mostly stays in one process (its module fixtures built once), and the processes end
# together (by whole files, one core sat idle for the last ~50 s of ~11 min, measured beside a
# training run). The slowest tests are listed at the end.
test: $(VENV)/.installed-dev
	$(BIN)/python -m pytest -q -n auto --dist worksteal --durations=15

bench: $(VENV)/.installed
	$(BIN)/dart-reach bench --json bench.json

# Regenerate skeletons/icub_upper_body.urdf; VISUOMANIP is the path of the iCubGazeboV2_5_visuomanip
# URDF (robotology/icub-models), which the package does not ship.
skeleton: $(VENV)/.installed-dev
	$(BIN)/python skeletons/build_skeleton.py $(VISUOMANIP)

# Install the package (a wheel, not editable) into a fresh venv under each Python 3.11-3.13
# found (python3.X on PATH, else pyenv's), run a tiny training in each and check that every
# interpreter gives the same fitness to the last digit. Venvs and runs in .venv-pythons/.
PYTHON_VERSIONS ?= 3.11 3.12 3.13
PYTHONS_DIR := .venv-pythons
pythons:
	@rm -rf $(PYTHONS_DIR) && mkdir -p $(PYTHONS_DIR)
	@for v in $(PYTHON_VERSIONS); do \
	  py=""; \
	  for c in "$$(command -v python$$v)" $(HOME)/.pyenv/versions/$$v*/bin/python$$v; do \
	    if [ -n "$$c" ] && "$$c" -c pass 2>/dev/null; then py="$$c"; break; fi; \
	  done; \
	  if [ -z "$$py" ]; then echo "Python $$v: not found, skipped"; continue; fi; \
	  d=$(PYTHONS_DIR)/$$v; \
	  "$$py" -m venv $$d && $$d/bin/python -m pip install -q . \
	  && $$d/bin/dart-reach train standard --generations 1 --replications 2 --trials 2 \
	       --steps 20 --workers 1 --record-every 0 --out $$d/run 2>$$d/train.log \
	  && $$d/bin/python -c "import polars as pl; t = pl.read_parquet('$$d/run/generations.parquet'); print(' '.join(repr(x) for x in t.sort('phase_key', 'replication')['best']))" > $$d/fitness.txt \
	  || { echo "Python $$v ($$py): FAILED, see $$d"; exit 1; }; \
	  echo "Python $$($$d/bin/python -c 'import platform; print(platform.python_version())'): installed, trained; best fitness per phase and replication: $$(cat $$d/fitness.txt)"; \
	done; \
	n=$$(cat $(PYTHONS_DIR)/*/fitness.txt | sort -u | wc -l); \
	if [ "$$n" -eq 1 ]; then echo "the same fitness under every interpreter"; \
	else echo "fitness differs between interpreters"; exit 1; fi

clean:
	rm -rf $(VENV) $(PYTHONS_DIR) *.egg-info bench.json

# The levers study (docs/results/levers.md, pre-registered): the screen without training (the
# best 2 robots of each replication of standard-500x10 at generation 250 under each lever: about
# 10 minutes per arm on 2 cores), then pre-reaching alone, 50 generations x 6 replications per
# arm, seed 2027 for every arm (resumable: run it again after an interruption; 1.6-2.7 h per
# arm on 2 cores), then the snapshots' post-evaluation.
LEVERS := recordings/levers
SCREEN_ARMS := today: far:--scene=beyond-arm-length self-collision:--self-collision=on \
	start-zero:--network-start=zero reflex-evolved:--reflex-inputs=evolved
levers-screen: $(VENV)/.installed
	for a in $(SCREEN_ARMS); do \
		$(BIN)/dart-reach screen $(FULL) --generation 250 --robots 2 --out $(LEVERS)/screen.parquet \
			--arm $${a%%:*} $$(echo $${a#*:} | tr ',' ' ') || exit $$?; \
	done
LEVER_ARMS := far:--scene=beyond-arm-length reflex-evolved:--reflex-inputs=evolved self-collision:--self-collision=on capped:--touch-pay=capped
levers-train: $(VENV)/.installed
	for a in $(LEVER_ARMS); do \
		$(BIN)/dart-reach train --model-version 1 docs/learning-check.toml --generations 50 --replications 6 \
			--seed 2027 --snapshot-every 10 --record-every 0 --out $(LEVERS)/$${a%%:*} \
			$$(echo $${a#*:} | tr ',' ' ') \
			$$(test -f $(LEVERS)/$${a%%:*}/manifest.json && echo --resume) || exit $$?; \
	done
# LEVERS_RUNS: where the arms' runs are (default here; the pinned checkout's recordings/levers
# to post-evaluate them where they train, with this checkout's CLI: version 1's trial is the same;
# run from that checkout, so that the tables' provenance names the run by its relative path)
LEVERS_RUNS ?= $(LEVERS)
levers-evaluate: $(VENV)/.installed
	for a in $(LEVER_ARMS); do \
		(cd $(LEVERS_RUNS)/../.. && $(CURDIR)/$(BIN)/dart-reach evaluate $(LEVERS)/$${a%%:*} \
			--finished-only --development 5 \
			--development-sensors normal,no-ball --snapshots 10,20,30,40,50) || exit $$?; \
	done
# Each arm's robots post-evaluated at 50 run again for Eq. 5's terms (once per arm), and the page.
levers-terms: $(VENV)/.installed
	$(BIN)/python -m reports.levers --terms
# The compact state of the levers arms trained in another checkout (the pinned worktree,
# LEVERS_FROM=its path): manifest, statistics, checkpoints, finals and snapshots, and the
# post-evaluation of the snapshots as far as it has gone (its parts), to commit.
levers-state:
	@test -n "$(LEVERS_FROM)" || { echo "give LEVERS_FROM=the checkout that trains the arms"; exit 2; }
	for d in $(LEVERS_FROM)/$(LEVERS)/*/; do a=$$(basename $$d); mkdir -p $(LEVERS)/$$a; \
		cp $$d/manifest.json $$d/generations.parquet $(LEVERS)/$$a/; \
		(cd $$d && find phases -name checkpoint.npz -o -name final.npz -o -path '*/snapshots/*.npz') | \
			while read f; do mkdir -p $(LEVERS)/$$a/$$(dirname $$f); cp $$d/$$f $(LEVERS)/$$a/$$f; done; \
		(cd $$d && find . -maxdepth 2 -name 'development.parquet' -o -path './development/part-*.parquet') | \
			while read f; do mkdir -p $(LEVERS)/$$a/$$(dirname $$f); cp $$d/$$f $(LEVERS)/$$a/$$f; done; \
	done

# The campaign (docs/results/campaign.md, pre-registered): the standard condition at the
# paper's design on model version 3, trained in the background from a pinned checkout and
# resumed after every interruption (run it again: it resumes); its cost so far and projected,
# from its own records: the page's section (c).
CAMPAIGN := recordings/campaign/standard-v3
campaign: $(VENV)/.installed
	$(BIN)/dart-reach train standard --model-version 3 --generations 500 --replications 10 \
		--seed 2031 --snapshot-every 10 --record-every 0 --yes --out $(CAMPAIGN) \
		$$(test -f $(CAMPAIGN)/manifest.json && echo --resume)
# The run's ledger recorded again, of the files here (each checked: dart-reach migrate).
campaign_ledger = rm -f $(CAMPAIGN)/ledger.json && $(BIN)/dart-reach migrate $(CAMPAIGN)
# Its compact state, from the checkout that trains it (CAMPAIGN_FROM=its path), to commit:
# manifest, statistics, checkpoints, finals and snapshots; then its ledger is made again here
# (dart-reach migrate), since the snapshots' post-evaluation is written here, not there.
campaign-state: $(VENV)/.installed
	@test -n "$(CAMPAIGN_FROM)" || { echo "give CAMPAIGN_FROM=the checkout that trains it"; exit 2; }
	mkdir -p $(CAMPAIGN)
	cd $(CAMPAIGN_FROM)/$(CAMPAIGN) && find . -type f \( -path ./manifest.json -o \
		-path ./generations.parquet -o -name checkpoint.npz -o -name final.npz \
		-o -path '*/snapshots/*.npz' \) | while read f; do \
		mkdir -p $(CURDIR)/$(CAMPAIGN)/$$(dirname $$f); cp $$f $(CURDIR)/$(CAMPAIGN)/$$f; done
	$(campaign_ledger)
# Its snapshots post-evaluated as they come (best 5, 45 positions, normal and ball absent),
# on a copy of the compact state (the training holds its directory's lock); the tables come
# back here. SNAPSHOTS=G,G,... evaluates those alone (default: all kept). A phase that has
# finished is post-evaluated first, as campaign-phases does it, and kept (only what is
# missing is evaluated: nothing while no phase is waiting).
CAMPAIGN_COPY := $(or $(TMPDIR),/tmp)/dart-reach-campaign-copy
# The phases' post-evaluation (best 5, 45 positions, the four senses and ball absent, 10 random
# genomes per phase) and the tables the targets below bring back.
CAMPAIGN_PHASES := --sensors all --robots 5 --baseline 10
CAMPAIGN_TABLES := evaluation baseline development
campaign_copy = rm -rf $(CAMPAIGN_COPY) && mkdir -p $(CAMPAIGN_COPY) && cp -r $(CAMPAIGN)/. $(CAMPAIGN_COPY)/
# The copy's tables $(1) (names without .parquet; one file, or parts in a folder once large)
# brought back here in place of these, with its ledger.
campaign_back = for t in $(1); do rm -rf $(CAMPAIGN)/$$t $(CAMPAIGN)/$$t.parquet; \
	for f in $(CAMPAIGN_COPY)/$$t $(CAMPAIGN_COPY)/$$t.parquet; do \
		if [ -e $$f ]; then cp -r $$f $(CAMPAIGN)/; fi; done; done; \
	cp $(CAMPAIGN_COPY)/ledger.json $(CAMPAIGN)/
campaign-snapshots: $(VENV)/.installed
	$(campaign_copy)
	$(BIN)/dart-reach evaluate $(CAMPAIGN_COPY) --finished-only $(CAMPAIGN_PHASES) \
		--development 5 --development-sensors normal,no-ball \
		$(if $(SNAPSHOTS),--snapshots $(SNAPSHOTS)) --record none
	$(call campaign_back,$(CAMPAIGN_TABLES))
# Its phases post-evaluated once each has finished, for the paper's phase claims
# (CAMPAIGN_PHASES; only what is missing is evaluated); then babbling before the touch of the final
# pre-reachers (claim A1, once); then the page and the summary, which judge a phase's claims
# once its post-evaluation is here.
campaign-phases: $(VENV)/.installed
	$(campaign_copy)
	$(BIN)/dart-reach evaluate $(CAMPAIGN_COPY) --finished-only $(CAMPAIGN_PHASES) --record none
	$(call campaign_back,$(CAMPAIGN_TABLES))
	$(BIN)/python -m reports.babbling_before_touch . --runs $(CAMPAIGN:recordings/%=%) --workers 2
	$(BIN)/python -m reports.campaign
	$(BIN)/python -m reports.results .
