# friction_sweep: every target sets up its own virtual environment first (nothing by hand).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp

.PHONY: demo test cubes bench bench-quick calibrate refresh-readme clean distclean help
.DELETE_ON_ERROR:

help:
	@echo "make demo   set up, simulate configs/demo.yaml (a rig in physical units), print its regimes, draw its map"
	@echo "            and its performance curve (the resonance peak against friction force, the optimum)"
	@echo "make test   set up, then run the whole test suite"
	@echo "make lint   ruff and mypy, as CI runs them (and .pre-commit-config.yaml)"
	@echo "make test-fast   only the tests not marked slow"
	@echo "make coverage    line coverage of friction_sweep, kernels run as Python (not part of make test)"
	@echo "make cubes  set up, then compute one cube per configs/fig*.yaml into results/"
	@echo "make bench  set up, then measure speed and scaling (results/bench/scale.md)"
	@echo "make figures / figures-quick / validate   the paper's figures; the rig's measured phases"
	@echo "make calibrate   calibrate the model to the rig's phases, in and out of sample (results/calibration/)"
	@echo "make refresh-readme   maintainers: make bench and make calibrate, then publish their tables in the README"
	@echo "                 and the measured accuracy calibration in friction_sweep/bench/calibration.json"
	@echo "make clean  remove results and caches; make distclean also removes $(VENV)"

$(STAMP): pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
	  { echo "friction_sweep needs Python >= 3.11: run make PYTHON=/path/to/python3.11"; exit 1; }
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[test,figures,lint,dask,calibrate]'
	touch $@

demo: $(STAMP)
	$(BIN)/fsweep run configs/demo.yaml --overwrite
	$(BIN)/fsweep plot results/demo.nc -o results/demo.png --overwrite
	$(BIN)/fsweep optimize configs/demo.yaml -o results/demo_performance.nc --plot results/demo_performance.png --overwrite
	@echo "demo: the cube is results/demo.nc (fsweep info results/demo.nc; friction_sweep.open_cube in Python),"
	@echo "      its regime map results/demo.png, its performance curve (the resonance peak against friction"
	@echo "      force, the optimum marked) results/demo_performance.png (the curve's data: results/demo_performance.nc)"

# the README's opening pictures: the demo's performance curve and its map (regenerate after a change that
# alters them)
docs/demo.png: configs/demo.yaml
	$(MAKE) demo
	cp results/demo.png $@

docs/demo_performance.png: configs/demo.yaml
	$(MAKE) demo
	cp results/demo_performance.png $@

# the whole suite on every core (pytest-xdist), a file's tests in one worker (their module fixtures: one cube each)
test: $(STAMP)
	$(BIN)/python -m pytest -q -n auto --dist loadfile

.PHONY: test-fast coverage lint

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/mypy

# the tests not marked slow (how long: README, "Development notes")
test-fast: $(STAMP)
	$(BIN)/python -m pytest -q -m "not slow"

# line coverage of the package, kernels included: numba's JIT off so that coverage sees the kernels run
# as Python (slow, hence -m "not slow"; tests too slow without the JIT are marked nojit_slow); not part of test
coverage: $(STAMP)
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -q -m "not slow and not nojit_slow" \
	  --cov=friction_sweep --cov-report=term-missing

# Targets a user runs write under results/ only; refresh-readme (maintainers) publishes what they measured.
# measures speed, scaling and what accuracy costs; the calibration `accuracy:` would read, measured here;
# where a cold compile of the demo's kernels spends its time (results/bench/compile_profile.md)
bench: $(STAMP)
	$(BIN)/python benchmarks/scale.py
	$(BIN)/python benchmarks/performance_curve.py --excitation joined
	$(BIN)/python benchmarks/performance_curve.py --excitation base
	$(BIN)/python benchmarks/performance_curve.py --structure
	$(BIN)/python benchmarks/structures.py
	$(BIN)/python benchmarks/structure_rk4.py
	$(BIN)/python benchmarks/one_engine.py
	$(BIN)/python benchmarks/peer_pyharm.py
	$(BIN)/python benchmarks/compile_profile.py
	$(BIN)/python benchmarks/harmonics.py --excitation base
	$(BIN)/python benchmarks/harmonics.py --excitation joined
	$(BIN)/python benchmarks/harmonics.py --structure
	$(BIN)/fsweep bench --calibrate --calibration results/bench/calibration.json -o results/bench/workprecision.nc --overwrite

# fsweep calibrate on the rig's data, then four folds out of sample (results/calibration/summary.md)
calibrate: $(STAMP)
	$(BIN)/python benchmarks/calibration_report.py

# maintainers: the README's measured tables and the shipped accuracy calibration, from a fresh bench and calibrate
refresh-readme: bench calibrate
	cp results/bench/calibration.json friction_sweep/bench/calibration.json
	$(BIN)/python benchmarks/readme_tables.py

bench-quick: $(STAMP)
	$(BIN)/python benchmarks/scale.py --quick
	$(BIN)/fsweep bench --quick -o results/bench/workprecision-quick.nc --overwrite

# one cube per figure spec; fsweep writes atomically, so an interrupted run leaves no partial file
FIG_SPECS := $(wildcard configs/fig*.yaml)
FIG_CUBES := $(patsubst configs/%.yaml,results/%.nc,$(FIG_SPECS))

results/%.nc: configs/%.yaml $(STAMP)
	$(BIN)/fsweep run $< -o $@ --overwrite --quiet

cubes: $(FIG_CUBES)

clean:
	rm -rf results .pytest_cache .hypothesis
	find . -path ./$(VENV) -prune -o -name __pycache__ -type d -prune -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV) *.egg-info

include figures.mk
