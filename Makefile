# Entry points. Each target sets up what it needs on a fresh machine: the Python
# environment (.venv) and MicroPython's unix port built from Debian's source package.
#   make test    every test: unit + firmware-in-the-loop (what CI runs)
#   make hil     the firmware-in-the-loop scenarios, the timing-budget table and the
#                HTML report (build/hil/report.html)
#   make bench   real-time factor and link round trip; plant cost per quantum
#   make campaign [CAMPAIGN_WORKERS=2]   the showcase campaigns (docs/campaigns.md): the duct
#                robot's 20 tether-snag runs, the pool cleaner over 50 placements with
#                sonar dropouts; reports in build/campaign/<name>/campaign.html
#   make fuzz [FUZZ_SECONDS=60]   the frame codec fuzzed on CPython, then on MicroPython:
#                cases, exceptions, damaged frames accepted, the slowest case
#   make soak [HOURS=24]   the rover for 24 simulated hours: host and firmware memory at
#                the start and the end, and the growth (not part of make test)
#   make conformance   MicroPython's own tests on the plain port and in the loop (the
#                table: build/conformance/table.md; docs/shim.md); MPY=1.28: on that MicroPython
#                (built first: mpy-fil setup --micropython 1.28; docs/versions.md)
#   make dist    the wheel and sdist in build/dist/ (pip install in a user's repository: docs/ci.md)
#   make lint    ruff check and ruff format --check on everything (host, shim, firmware,
#                plant, tests); `make format` applies the formatter
#   make hil LONG=0   the same without the sweeps over many seeds (@pytest.mark.long)
#   make hil COVERAGE=1   the same on the line-tracing interpreter (built once, ~30 s): the
#                firmware's line and branch coverage in build/hil/coverage/ (docs/coverage.md)
#   make hil RIG=path/to/rig.toml   the in-the-loop tests beside that rig file (or its folder);
#                their report and artefacts in build/ beside it
#   make flash APP=rover [BOARD=esp32_devkitc] [PORT=/dev/ttyUSB0]   (or RIG=path/to/rig.toml)
#                compile with mpy-cross, copy what changed with mpremote, reset, show
#                the first lines; without PORT, to the virtual board (build/vboard/)
# MICROPYTHON=/path/to/micropython uses that interpreter instead of the build.

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
MP_BUILD := build/micropython/1.25.0+ds-1/micropython
MP_SETTRACE := $(MP_BUILD)-settrace

ifeq ($(origin MICROPYTHON),undefined)
MICROPYTHON := $(CURDIR)/$(MP_BUILD)
MP_DEP := $(MP_BUILD) $(MP_SETTRACE)
else
MP_DEP :=
endif
export MICROPYTHON
# Compiled Python kept in build/pycache, out of the source tree, even where the environment
# asks for none (PYTHONDONTWRITEBYTECODE): every mpy-fil a test starts would compile the
# harness again (0.55 s of its 1.2 s start on this machine).
export PYTHONPYCACHEPREFIX := $(CURDIR)/build/pycache
export PYTHONDONTWRITEBYTECODE :=

APP ?= rover

.PHONY: setup test hil bench campaign fuzz soak conformance lint format flash clean

setup: $(VENV)/.installed $(MP_DEP) build/drivers/.fetched
	@host/core/report_tools.sh
	@host/core/sandbox_tools.sh
	@$(PY) -m host.core.interpreter version

$(VENV)/.installed: pyproject.toml setup.py host/core/bootstrap.sh
	host/core/bootstrap.sh $(PYTHON) $(VENV)
	@touch $@

# published MicroPython drivers the tests run unchanged, pinned by hash (host/core/drivers.txt)
build/drivers/.fetched: host/core/drivers.txt host/core/drivers.py $(VENV)/.installed
	$(PY) -m host.core.drivers
	@touch $@

$(MP_BUILD): host/core/interpreter.py $(wildcard host/core/micropython/*.patch) host/core/micropython/manifest.py host/core/aptsources.py $(wildcard host/shim/cmod/*/*)
	$(PYTHON) -m host.core.interpreter build
	@touch $(MP_BUILD)

# (the default version's; another's is built on demand: mpy-fil setup --micropython VERSION,
# host/core/micropython/<version>/ holds its patches: docs/versions.md)

# the same build with line tracing, for firmware coverage (docs/coverage.md; about 35 s)
$(MP_SETTRACE): $(MP_BUILD)
	$(PYTHON) -m host.core.interpreter build settrace
	@touch $(MP_SETTRACE)

# the wheel and sdist a user's repository installs (docs/ci.md)
.PHONY: dist
dist: $(VENV)/.installed
	$(PY) -m build --no-isolation -o build/dist .

# (a test file to a worker: a file's module fixtures run once; one worker more than cores, since
# rigs also wait on the wall clock (process start-up, real-time runs, watchdogs); rigs record
# nothing, for speed: a failed test's rerun line, run as printed, keeps its whole trace folder;
# -rs: each skipped test with its reason; the temp folders of passed tests are removed)
WORKERS ?= $(shell echo $$(( $$(nproc) + 1 )))
test: setup
	$(PY) -m pytest -q -rs -n $(WORKERS) --dist loadfile --hil-keep none -o tmp_path_retention_policy=failed

# FIRMWARE=build/vboard/<board>/fs runs the scenarios from what was flashed there; on every
# core, a test to a worker (a module with module fixtures is one group: they run once), the
# report and the tables gathered from all of them; the long sweeps (many seeds, marked
# long) record nothing, their result lines and budgets still in the report (LONG=0 leaves them out)
LONG ?= 1
# RIG=path/to/rig.toml (or its folder): only the tests beside that rig file, everything
# written under build/ beside it; with none, the rig's own budgets as a test (host/pytest_plugin/hil_run.py)
hil: setup
	@$(PY) -m host.pytest_plugin.hil_run --workers $(WORKERS) --long $(LONG) --rig "$(RIG)" --firmware "$(FIRMWARE)" $(if $(COVERAGE),--coverage)

flash: setup
	@$(PY) -m host.device.flash --app $(or $(RIG),$(APP)) $(if $(BOARD),--board $(BOARD)) $(if $(PORT),--port $(PORT))

bench: setup
	$(PY) -m host.bench
	$(PY) -m sim_plant.plant_cost

CAMPAIGN_WORKERS ?= 2
campaign: setup
	$(VENV)/bin/mpy-fil campaign hil_tests/campaigns/duct_snag.toml --workers $(CAMPAIGN_WORKERS) --out build/campaign/duct_snag
	$(VENV)/bin/mpy-fil campaign hil_tests/campaigns/pool_placement.toml --workers $(CAMPAIGN_WORKERS) --out build/campaign/pool_placement
	MPY_FIL_SHOWCASES=1 CAMPAIGN_WORKERS=$(CAMPAIGN_WORKERS) $(PY) -m pytest -q -p no:cacheprovider hil_tests/test_campaign_showcases.py

FUZZ_SECONDS ?= 60
fuzz: setup
	$(PY) -m host.tests.codec_fuzz --seconds $(FUZZ_SECONDS)
	$(PY) -m host.tests.codec_fuzz --resync
	MICROPYPATH=.frozen $(MICROPYTHON) host/tests/codec_fuzz.py --seconds $(FUZZ_SECONDS)
	MICROPYPATH=.frozen $(MICROPYTHON) host/tests/codec_fuzz.py --resync

HOURS ?= 24
soak: setup
	$(PY) -m host.soak --hours $(HOURS)

conformance: setup
	$(PY) -m host.conformance $(if $(MPY),--micropython $(MPY) --table build/conformance/table-$(MPY).md,--table build/conformance/table.md)

lint: $(VENV)/.installed
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

format: $(VENV)/.installed
	$(VENV)/bin/ruff format .
	$(VENV)/bin/ruff check --select I --fix .

clean:
	rm -rf build $(VENV)
