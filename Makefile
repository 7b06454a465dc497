# synsculpt — the user's entry point.
#
#   make                  set up (Debian packages), build, run the demo archive (manifests/demo.toml)
#   make run MANIFEST=manifests/X.toml [DATASET_ROOT=...] -jN   the pipeline on any archive
#   make run|release ... CLUSTER=slurm   every job of the plan as an srun step (README: SLURM)
#   make cluster-up | cluster-down   a single-node SLURM cluster on this machine (root; for trying and CI)
#   make release MANIFEST=manifests/X.toml   the archive's dataset release: a deterministic tar with robot motions,
#                         exports, quality table and datasheet (syn-release; check one with syn-release verify)
#   make compose SCRIPT=manifests/scripts/X.toml [LIBRARY=outputs/demo/library.h5]   a scripted motion,
#                         evaluated and exported (outputs/compose/X.*)
#   make studio [LIBRARY=outputs/demo/library.h5 SCRIPT=... PORT=8080]   the SynSculptor studio: compose from
#                         the library in the browser (http://127.0.0.1:8080/), load and save compose scripts
#   make bench-archive [ARCHIVE_HOURS=3 ARCHIVE_SUBJECTS=20 ARCHIVE_PROTOCOL=paper|throughput]   generate a large archive from the CMU trials
#                         and run the whole pipeline on it: wall time and frames/s per stage
#   make report [MANIFEST=manifests/X.toml]   the archive's offline HTML report: the paper's figures, per-trial
#                         plots and a 3-D player (outputs/NAME/report/index.html); redraws only what changed
#   make watch MOTION="A.h5 B.h5" [MODEL=... ROBOT_MAP=...]   any motion files (a ground-mode fall's --fall-record,
#                         a stage's output) in the report's 3-D player, with feet and root heights (outputs/watch/)
#   make project [LIBRARY=... STYLE=walk]   the paper's text-to-motion experiment on the HumanML3D and MDM
#                         joints in ../shared/datasets/humanml3d: before/after table in outputs/project/
#   make ground-sweep [SIMULATE_FLAGS="--balance-gain 4" CMU_BVH=... RUNS=16]   syn-simulate's ground mode on every
#                         CMU walk onto the G1: up, or when it fell, per walk, and how many stay up (outputs/ground-sweep/);
#                         RUNS=N: N runs with a gain moved at the rounding level, per walk in how many it stayed up
#   make test             build and run every test (ctest)
#   make bench            Google Benchmark programs: per-call times and frames per second per stage
#   make sanitize-test    the test suite on an ASan+UBSan build (clang, -O1, line tables)
#   make fuzz-smoke       each format reader's libFuzzer target for FUZZ_SECONDS (clang)
#
# Variables: BUILD_DIR (build), BUILD_TYPE (Release), JOBS (nproc), CMAKE_FLAGS, CLUSTER (local | slurm;
# with slurm also CPUS_<stage> and SRUN_FLAGS, see tools/slurm/launch.mk).

SHELL := /bin/bash
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
FUZZ_SECONDS ?= 30
BIN := $(BUILD_DIR)/bin

# Everything synsculpt needs, as Debian 12 packages. Nothing is downloaded at build time.
DEBIAN_PACKAGES := cmake g++ make libeigen3-dev libsimbody-dev libceres-dev libsuitesparse-dev libhdf5-dev \
  nlohmann-json3-dev libcli11-dev libtomlplusplus-dev libtinyxml2-dev libssl-dev libgtest-dev libbenchmark-dev \
  libcpp-httplib-dev pkg-config \
  python3 python3-matplotlib python3-h5py
# Only for `make report` (npm fetches three.js once, into tools/report/node_modules) and its headless-browser
# test (tests/report). nodesource's nodejs ships its own npm: install Debian's npm only when npm is missing.
REPORT_PACKAGES := nodejs chromium
# Only for `make fuzz-smoke`: libFuzzer ships with clang's runtime.
FUZZ_PACKAGES := clang libclang-rt-14-dev
# Only for `make cluster-up` (installed by tools/slurm/cluster-up.sh, which waits for the dpkg lock).
SLURM_PACKAGES := slurmctld slurmd slurm-client munge

.PHONY: all setup setup-fuzz setup-report report report-npm watch configure build test bench ground-sweep bench-archive demo run release compose studio project power-ratio sanitize-test fuzz-smoke clean print-packages cluster-up cluster-down check-cluster
.DEFAULT_GOAL := all

all: demo

print-packages:
	@echo $(DEBIAN_PACKAGES)

# Installs what is missing when run as root; otherwise prints the exact command and stops.
define install_missing
	@missing=$$(for package in $(1); do \
	  dpkg-query -W -f='$${Status}\n' $$package 2>/dev/null | grep -q 'install ok installed' || echo $$package; \
	done | tr '\n' ' '); \
	if [ -n "$${missing// }" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "make: installing Debian packages: $$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; \
	  else \
	    echo "make: missing Debian packages. Install them with:"; \
	    echo "  sudo apt-get install -y --no-install-recommends $$missing"; \
	    exit 1; \
	  fi; \
	fi
endef

setup:
	$(call install_missing,$(DEBIAN_PACKAGES))

setup-fuzz: setup
	$(call install_missing,$(FUZZ_PACKAGES))

setup-report: setup
	$(call install_missing,$(REPORT_PACKAGES) $(if $(shell command -v npm),,npm))

# cmake configures a new build directory, and configures an existing one again whenever CMAKE_FLAGS differ
# from the last ones given (recorded in $(BUILD_DIR)/cmake-flags): the cache keeps -D values, so
# `make test CMAKE_FLAGS=-DSYN_WERROR=ON` on an existing build directory used to build without -Werror.
# Empty CMAKE_FLAGS keep what the cache has.
CONFIGURE_COMMAND = cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS)
configure: setup
	@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ] || \
	    { [ -n "$(strip $(CMAKE_FLAGS))" ] && [ "$$(cat $(BUILD_DIR)/cmake-flags 2>/dev/null)" != "$(strip $(CMAKE_FLAGS))" ]; }; then \
	  echo "$(CONFIGURE_COMMAND)"; $(CONFIGURE_COMMAND) && echo "$(strip $(CMAKE_FLAGS))" > $(BUILD_DIR)/cmake-flags; \
	fi

build: configure
	cmake --build $(BUILD_DIR) -j$(JOBS)

# --no-tests=error: a build directory (or a -R pattern) with no tests fails instead of passing.
test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure --no-tests=error -j$(JOBS)

bench: build
	@# Three repetitions of at least a second each, reported as mean/median/stddev: a shared VM's
	@# neighbours move single runs by ±20 %.
	@for program in $(BIN)/*_benchmark; do echo "== $$(basename $$program)"; \
	  $$program --benchmark_counters_tabular=true --benchmark_min_time=1 --benchmark_repetitions=3 \
	    --benchmark_report_aggregates_only=true || exit 1; done

# A sanitizer finding exits with SANITIZER_EXIT_CODE, not 1: the tools exit 1 for bad data, and a CLI test that
# expects a refusal would otherwise take a leak or UB report for one. The variables reach every tool the tests
# run; tests/cli/sanitizer_exit_code_test.cpp checks that they are in effect.
SANITIZER_EXIT_CODE := 86
SANITIZER_ENVIRONMENT := ASAN_OPTIONS=exitcode=$(SANITIZER_EXIT_CODE):detect_leaks=1:abort_on_error=0 \
  LSAN_OPTIONS=exitcode=$(SANITIZER_EXIT_CODE) \
  UBSAN_OPTIONS=halt_on_error=1:exitcode=$(SANITIZER_EXIT_CODE):print_stacktrace=1
# Built with clang, as the fuzzers: under -fsanitize it compiles this code base in half of GCC's time (a cold
# build on 2 cores: 20 min against about 42, Eigen's decompositions most), and CI builds it from scratch. A
# build-sanitize configured with GCC (before 2026-11-28) is removed first: CMake deletes the whole cache when
# the compiler changes, -DSYN_SANITIZE=ON with it, and would build a plain Release there (so would any
# build-sanitize left that way).
SANITIZE_COMPILERS := -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
sanitize-test: setup-fuzz
	@if [ -f build-sanitize/CMakeCache.txt ] && ! { grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++$$' build-sanitize/CMakeCache.txt && \
	    grep -q '^SYN_SANITIZE:BOOL=ON$$' build-sanitize/CMakeCache.txt; }; then \
	  echo "make: build-sanitize is not a clang sanitizer build; removing it"; rm -rf build-sanitize; fi
	$(SANITIZER_ENVIRONMENT) $(MAKE) test BUILD_DIR=build-sanitize BUILD_TYPE=Debug \
	  CMAKE_FLAGS="$(SANITIZE_COMPILERS) -DSYN_SANITIZE=ON -DSYN_BENCH=OFF $(CMAKE_FLAGS)"

# Every tests/fuzz/*_fuzzer runs FUZZ_SECONDS from its seeds (tests/fuzz/seeds/NAME) and fails the target on
# any finding: a crash, an escaped exception, a leak, UB (the fuzz build has -fno-sanitize-recover=all), an
# input slower than FUZZ_TIMEOUT seconds, or no fuzzer built at all; JOBS fuzzers at a time, each a process on
# its own core (tests/fuzz/run_smoke.sh). Each log is kept whole in
# $(FUZZ_BUILD_DIR)/logs/NAME.log; its tail is printed on failure, the artifact in $(FUZZ_BUILD_DIR)/artifacts/.
FUZZ_BUILD_DIR ?= build-fuzz
FUZZ_TIMEOUT ?= 10
fuzz-smoke: setup-fuzz
	CC=clang CXX=clang++ cmake -S . -B $(FUZZ_BUILD_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSYN_FUZZ=ON -DSYN_BENCH=OFF
	cmake --build $(FUZZ_BUILD_DIR) -j$(JOBS) --target fuzzers
	tests/fuzz/run_smoke.sh $(FUZZ_BUILD_DIR) $(FUZZ_SECONDS) $(FUZZ_TIMEOUT) $(JOBS)

# ---- manifest-driven runs ---------------------------------------------------------
# `make run MANIFEST=manifests/X.toml [DATASET_ROOT=...] -jN`: syn-plan checks the manifest and writes
# outputs/<name>/rules.mk (parameter stamps change only when parameters do); make then runs exactly the
# jobs whose inputs, parameters or stage binaries changed, in parallel.
MANIFEST ?= manifests/demo.toml
OUTPUTS ?= outputs
MANIFEST_NAME = $(shell sed -n 's/^name *= *"\(.*\)".*/\1/p' $(MANIFEST) | head -n 1)
MANIFEST_VERSION = $(shell sed -n 's/^version *= *"\(.*\)".*/\1/p' $(MANIFEST) | head -n 1)

# CLUSTER=slurm: the same rules, each job started as an srun step (tools/slurm/launch.mk); -jN is then how
# many steps are queued or running at once.
CLUSTER ?= local
ifeq ($(filter local slurm,$(CLUSTER)),)
  $(error CLUSTER=$(CLUSTER): expected local or slurm)
endif
LAUNCHER_RULES = $(if $(filter slurm,$(CLUSTER)),-f tools/slurm/launch.mk)

check-cluster:
	@$(if $(filter slurm,$(CLUSTER)),sinfo -h >/dev/null || { echo "make: CLUSTER=slurm but sinfo does not answer \
	  (on this machine: sudo make cluster-up)" >&2; exit 1; })

run: build check-cluster
	@$(BIN)/syn-plan $(MANIFEST) -o $(OUTPUTS)/$(MANIFEST_NAME)/rules.mk --outputs $(OUTPUTS) $(if $(DATASET_ROOT),--dataset-root $(DATASET_ROOT))
	@$(MAKE) --no-print-directory -j$(JOBS) -f $(OUTPUTS)/$(MANIFEST_NAME)/rules.mk $(LAUNCHER_RULES) SYN_BIN=$(BIN) all
	@echo "make: $(MANIFEST_NAME): all jobs up to date in $(OUTPUTS)/$(MANIFEST_NAME)/"

# ---- reproducible release ------------------------------------------------------------
# $(OUTPUTS)/NAME/release/NAME-VERSION.tar, written by syn-release (tools/release): per trial the robot motion,
# the manifest's [release] exports, synergies, metrics and contact flags; quality.csv; the datasheet README.md
# (robot and URDF licence, parameters, trial table, totals, export columns, capture licences); libraries,
# summaries, parameter stamps, the manifest, provenance and SHA256SUMS. The tar is deterministic (sorted
# names, mtime 0, owner 0), so the same inputs give the same SHA-256. Check one with
# `syn-release verify TAR [--rebuild]`.
release: run
	@rm -rf $(OUTPUTS)/$(MANIFEST_NAME)/release
	@$(BIN)/syn-release build $(MANIFEST) --outputs $(OUTPUTS) $(if $(DATASET_ROOT),--dataset-root $(DATASET_ROOT)) | sed 's/^/make: /'

demo:
	@$(MAKE) --no-print-directory run MANIFEST=manifests/demo.toml

# ---- ground mode on the shared CMU walks (issue 18) -------------------------------------
SIMULATE_FLAGS ?=
RUNS ?= 1
ground-sweep: build
	@CMU_BVH=$(CMU_BVH) JOBS=$(JOBS) RUNS=$(RUNS) tools/dev/ground_sweep.sh $(BIN) $(OUTPUTS)/ground-sweep $(SIMULATE_FLAGS)

# ---- scale: a generated archive -------------------------------------------------------
CMU_BVH ?= ../shared/datasets/cmu_bvh
ARCHIVE_HOURS ?= 3
ARCHIVE_SUBJECTS ?= 20
ARCHIVE_PROTOCOL ?= paper
bench-archive: build check-cluster
	@gen=$(OUTPUTS)/archive-captures; start=$$(date +%s.%N); \
	$(BIN)/syn-archive $(CMU_BVH)/*/*.bvh --index $(CMU_BVH)/index.csv --subjects $(ARCHIVE_SUBJECTS) \
	  --hours $(ARCHIVE_HOURS) --protocol $(ARCHIVE_PROTOCOL) -o $$gen 2>&1 | grep -v skipped; \
	generated=$$(date +%s.%N); \
	$(BIN)/syn-plan $$gen/archive.toml -o $(OUTPUTS)/archive/rules.mk --outputs $(OUTPUTS) && \
	$(MAKE) --no-print-directory -j$(JOBS) -f $(OUTPUTS)/archive/rules.mk $(LAUNCHER_RULES) SYN_BIN=$(BIN) all > $(OUTPUTS)/archive/progress.log || exit 1; \
	end=$$(date +%s.%N); frames=$$(sed -n 's/^# frames: //p' $$gen/archive.toml); \
	echo "bench-archive: $(ARCHIVE_SUBJECTS) subjects, $(ARCHIVE_HOURS) h, $$frames frames at 120 Hz, -j$(JOBS)"; \
	awk -v g="$$start" -v s="$$generated" -v e="$$end" 'BEGIN{printf "  generate  %8.1f s wall\n  pipeline  %8.1f s wall\n", s-g, e-s}'; \
	awk -v frames=$$frames '{cpu[$$1]+=$$(NF-1); jobs[$$1]++} END{printf "  %-10s %6s %10s %14s\n","stage","jobs","cpu s","frames/s/core"; \
	  for (st in cpu) printf "  %-10s %6d %10.1f %14.0f\n", st, jobs[st], cpu[st], (st=="library"||st=="summary") ? 0 : frames/cpu[st]}' \
	  $(OUTPUTS)/archive/progress.log | sort

# ---- report ----------------------------------------------------------------------------
# `make report MANIFEST=...`: tools/report/report.py plan writes outputs/NAME/report/rules.mk (one target per
# figure, per trial and for the page, each depending on exactly the files it reads and the scripts that draw
# it), then make redraws what changed. The page works offline, from file:// too: three.js comes from npm
# (package-lock.json pins it) and is copied into the report folder.
# npm ci runs when node_modules is missing or was installed from another package-lock.json (npm gives the
# files it unpacks a fixed 1985 mtime, so their dates say nothing).
REPORT_LOCK := tools/report/node_modules/.installed-package-lock.json
report-npm:
	@cmp -s tools/report/package-lock.json $(REPORT_LOCK) || { \
	  command -v npm >/dev/null || { echo "make: report needs npm (make setup-report, as root)"; exit 1; }; \
	  echo "make: npm ci in tools/report (three.js, playwright-core)"; \
	  (cd tools/report && npm ci --no-audit --no-fund --loglevel=error) && \
	  cp tools/report/package-lock.json $(REPORT_LOCK); }

# Debian's python3 (python3-matplotlib, python3-h5py), whatever else is first on PATH.
REPORT_PYTHON ?= /usr/bin/python3
report: run report-npm
	@$(REPORT_PYTHON) tools/report/report.py plan --manifest $(MANIFEST) --outputs $(OUTPUTS) --bin $(BIN)
	@$(MAKE) --no-print-directory -j$(JOBS) -f $(OUTPUTS)/$(MANIFEST_NAME)/report/rules.mk SYN_BIN=$(BIN) all
	@echo "make: $(MANIFEST_NAME): report in $(OUTPUTS)/$(MANIFEST_NAME)/report/index.html"

# `make watch MOTION="A.h5 [B.h5 ...]" [MODEL=URDF ROBOT_MAP=MAP WATCH_DIR=outputs/watch]`: any motion files (a
# ground-mode fall's --fall-record, a simulated motion beside its kinematic input, one stage output) in the
# report's 3-D player, with each foot's and the root's height by the report's own FK (tools/report/watch.py).
MODEL ?= datasets/robots/unitree_g1/g1_29dof.urdf
ROBOT_MAP ?= manifests/robots/g1.toml
WATCH_DIR ?= $(OUTPUTS)/watch
watch: report-npm
	@[ -n "$(MOTION)" ] || { echo 'make: watch needs MOTION="FILE.h5 ..."'; exit 2; }
	@$(REPORT_PYTHON) tools/report/watch.py $(MOTION) --model $(MODEL) --robot-map $(ROBOT_MAP) -o $(WATCH_DIR)

# ---- text-to-motion projection ---------------------------------------------------------
# Each [T,22,3] joints file is ingested and retargeted with the humanml3d22 marker set, then projected.
T2M_ROOT ?= ../shared/datasets/humanml3d
T2M_INPUTS ?= derived/mdm_sample0_joints_T22x3 derived/mdm_sample1_joints_T22x3 derived/mdm_sample2_joints_T22x3 new_joints_012314
STYLE ?= walk
project: build
	@if [ ! -f $(LIBRARY) ]; then $(MAKE) --no-print-directory demo; fi
	@out=$(OUTPUTS)/project; mkdir -p $$out; \
	printf '%-28s %12s %12s %12s %12s\n' input sliding_raw sliding_proj 'W/kg_raw' 'W/kg_proj' > $$out/summary.txt; \
	for input in $(T2M_INPUTS); do name=$$(basename $$input); log=$$out/$$name.log; \
	  $(BIN)/syn-ingest $(T2M_ROOT)/$$input.npy -o $$out/$$name.markers.h5 2> $$log && \
	  $(BIN)/syn-retarget $$out/$$name.markers.h5 -o $$out/$$name.motion.h5 --model $(COMPOSE_MODEL) --robot-map $(COMPOSE_MAP) \
	    --markerset manifests/markersets/humanml3d22.toml 2>> $$log && \
	  $(BIN)/syn-project $$out/$$name.motion.h5 --library $(LIBRARY) --style $(STYLE) --model $(COMPOSE_MODEL) \
	    --robot-map $(COMPOSE_MAP) -o $$out/$$name.projected.motion.h5 2>> $$log && \
	  for motion in $$name $$name.projected; do \
	    $(BIN)/syn-evaluate $$out/$$motion.motion.h5 --model $(COMPOSE_MODEL) --robot-map $(COMPOSE_MAP) --samples 0 \
	      -o $$out/$$motion.metrics.json 2>> $$log || exit 1; done || { cat $$log; exit 1; }; \
	  python3 -c 'import json, sys; raw, proj = (json.load(open(f))["trial"] for f in sys.argv[2:]); \
	    print("%-28s %12.4f %12.4f %12.4f %12.4f" % (sys.argv[1], raw["foot_sliding_ratio"], proj["foot_sliding_ratio"], \
	    raw["mean_power_w_per_kg"], proj["mean_power_w_per_kg"]))' $$name $$out/$$name.metrics.json \
	    $$out/$$name.projected.metrics.json >> $$out/summary.txt; \
	done; cat $$out/summary.txt; echo "make: before/after table in $$out/summary.txt (metrics: syn-evaluate)"

# ---- human vs robot power ----------------------------------------------------------------
# Every trial of MANIFEST (its markers from `make run`) retargeted onto a human model and onto each robot of
# POWER_ROBOTS (hrp4c: the paper's HRP-4C; g1: Unitree G1), all with the same syn-retarget and syn-evaluate
# flags: mean mechanical power sum_actuated |tau u| / total mass (W/kg; a free base's six velocities are not
# motors and do not count) per trial and robot in outputs/NAME/power-ratio/power_ratio.csv, then per motion
# class: trials, human W/kg, each robot's W/kg and robot/human (ratio of the class means). On walks, the
# human's hip / knee / ankle share of sagittal leg joint power beside the published shares. The paper
# (OpenSim's muscle model for the human) reports humans 3.3x more efficient than HRP-4C.
# HUMAN_MODEL=deleva (default): syn-human's de Leva (1996) model for the manifest's [human] height, mass and
#   sex; without a height, each trial's own (syn-human --height-from-markers on its markers); without a
#   mass or sex, de Leva's reference male (73.0 kg) with a warning in the trial's human log.
# HUMAN_MODEL=paper: the paper's human URDF (HUMANOID_SYNERGIES), the HRP-4C tree with placeholder inertias
#   of 1 kg m^2 on every link: they dominate its torques (syn-retarget warns), so its W/kg are not a human's.
HUMAN_MODEL ?= deleva
POWER_ROBOTS ?= hrp4c g1
HUMANOID_SYNERGIES ?= ../shared/datasets/robots/humanoid_synergies
# A key of the manifest's [human] table, or nothing.
human_param = $(shell awk -v key=$(1) '/^\[/ {section = $$0} section == "[human]" {line = $$0; sub(/\#.*/, "", line); \
  n = split(line, kv, "="); gsub(/[ \t"]/, "", kv[1]); gsub(/[ \t"]/, "", kv[2]); if (n == 2 && kv[1] == key) print kv[2]}' $(MANIFEST))
HUMAN_FLAGS = $(foreach key,height mass sex,$(if $(call human_param,$(key)),--$(key) $(call human_param,$(key))))
power-ratio: run
	@if [ "$(HUMAN_MODEL)" = paper ] || echo " $(POWER_ROBOTS) " | grep -q ' hrp4c '; then \
	  if [ ! -f $(HUMANOID_SYNERGIES)/HRP4c_optitrack_model.urdf ]; then \
	    echo "make: power-ratio needs the paper's models in $(HUMANOID_SYNERGIES) (HUMANOID_SYNERGIES=...)"; exit 1; fi; fi
	@out=$(OUTPUTS)/$(MANIFEST_NAME)/power-ratio; mkdir -p $$out; \
	markerset=$$(sed -n 's/^markerset *= *"\(.*\)".*/\1/p' $(MANIFEST) | head -n 1); \
	case "$(HUMAN_MODEL)" in \
	  deleva) ;; \
	  paper) echo "make: HUMAN_MODEL=paper: placeholder inertias (1 kg m^2 per link) dominate that model's torques";; \
	  *) echo "make: HUMAN_MODEL must be deleva or paper"; exit 2;; \
	esac; \
	synergies=; for trial in $(OUTPUTS)/$(MANIFEST_NAME)/trials/*/; do synergies="$$synergies $$trial/synergies.h5"; done; \
	for body in human $(POWER_ROBOTS); do \
	  case $$body in \
	    human) ;; \
	    hrp4c) model=$(HUMANOID_SYNERGIES)/HRP4c_optitrack_model.urdf; map=manifests/robots/hrp4c.toml;; \
	    g1) model=datasets/robots/unitree_g1/g1_29dof.urdf; map=manifests/robots/g1.toml;; \
	    *) echo "make: unknown robot '$$body' in POWER_ROBOTS (hrp4c, g1)"; exit 2;; \
	  esac; metrics=; \
	  for trial in $(OUTPUTS)/$(MANIFEST_NAME)/trials/*/; do id=$$(basename $$trial); log=$$out/$$id.$$body.log; : > $$log; \
	    if [ $$body = human ] && [ "$(HUMAN_MODEL)" = paper ]; then \
	      model=$(HUMANOID_SYNERGIES)/human_optitrack_model.urdf; map=manifests/robots/hrp4c.toml; \
	    elif [ $$body = human ]; then model=$$out/$$id.human.urdf; map=$$out/$$id.human.toml; \
	      $(BIN)/syn-human $(HUMAN_FLAGS) $(if $(call human_param,height),,--height-from-markers $$trial/markers.h5) \
	        -o $$model --robot-map-out $$map 2>> $$log || { cat $$log; exit 1; }; \
	    fi; \
	    $(BIN)/syn-retarget $$trial/markers.h5 -o $$out/$$id.$$body.motion.h5 --model $$model --robot-map $$map \
	      --markerset $$markerset 2>> $$log && \
	    $(BIN)/syn-evaluate $$out/$$id.$$body.motion.h5 --model $$model --robot-map $$map \
	      -o $$out/$$id.$$body.metrics.json 2>> $$log || { cat $$log; exit 1; }; \
	    metrics="$$metrics $$out/$$id.$$body.metrics.json"; \
	  done; \
	  if [ $$body = human ]; then human=$$metrics; continue; fi; \
	  $(BIN)/syn-summary $$synergies --table power-ratio --robot-name $$body --metrics $$metrics --human-metrics $$human \
	    -o $$out/power_ratio.$$body.csv 2> $$out/summary.log || { cat $$out/summary.log; exit 1; }; \
	done; \
	set -- $(POWER_ROBOTS); { head -n 1 $$out/power_ratio.$$1.csv; \
	  for body in $(POWER_ROBOTS); do tail -n +2 $$out/power_ratio.$$body.csv; done; } > $$out/power_ratio.csv; \
	awk -F, -v robots="$(POWER_ROBOTS)" -v human_model="$(HUMAN_MODEL)" 'NR > 1 { \
	    class[$$3] = 1; if ($$4 == first) { n[$$3]++; human[$$3] += $$5 } robot[$$3, $$4] += $$6; \
	    if ($$4 == first && $$3 == "walk" && $$8 != "") { walks++; hip += $$8; knee += $$9; ankle += $$10 } } \
	  BEGIN { count = split(robots, names, " "); first = names[1]; \
	    printf "  %-16s %6s %12s", "class", "trials", "human W/kg"; \
	    for (r = 1; r <= count; r++) printf " %10s %13s", names[r] " W/kg", names[r] "/human"; printf "\n" } \
	  END { for (c in class) { row = sprintf("  %-16s %6d %12.3f", c, n[c], human[c] / n[c]); \
	      for (r = 1; r <= count; r++) { mean = robot[c, names[r]] / n[c]; row = row sprintf(" %10.3f %13.2f", mean, mean / (human[c] / n[c])) } \
	      print row | "sort" } close("sort"); \
	    printf "  (human: %s model; the paper reports HRP-4C / human = 3.3; per-trial logs in the table folder)\n", human_model; \
	    if (walks > 0) printf "  human sagittal leg power on %d walks (|tau u|, positive and negative): hip %.0f %%, knee %.0f %%, ankle %.0f %%\n" \
	      "  published (positive work, walking 2.0 m/s; Farris & Sawicki 2012, J. R. Soc. Interface 9:110): hip 44 %%, knee 17 %%, ankle 39 %%\n", \
	      walks, 100 * hip / walks, 100 * knee / walks, 100 * ankle / walks }' $$out/power_ratio.csv; \
	echo "make: per-trial table in $$out/power_ratio.csv"

# ---- compose scripts -------------------------------------------------------------------
# The script's motion goes through syn-evaluate like any retargeted trial, and out as robot CSV and .mot.
SCRIPT ?= manifests/scripts/dance_phrase.toml
LIBRARY ?= $(OUTPUTS)/demo/library.h5
COMPOSE_MODEL ?= datasets/robots/unitree_g1/g1_29dof.urdf
COMPOSE_MAP ?= manifests/robots/g1.toml
compose: build
	@if [ ! -f $(LIBRARY) ]; then $(MAKE) --no-print-directory demo; fi
	@name=$$(basename $(SCRIPT) .toml); out=$(OUTPUTS)/compose; mkdir -p $$out; \
	$(BIN)/syn-compose $(SCRIPT) --library $(LIBRARY) -o $$out/$$name.motion.h5 && \
	$(BIN)/syn-evaluate $$out/$$name.motion.h5 --model $(COMPOSE_MODEL) --robot-map $(COMPOSE_MAP) -o $$out/$$name.metrics.json && \
	$(BIN)/syn-export $$out/$$name.motion.h5 -o $$out/$$name.csv --format robot-csv --model $(COMPOSE_MODEL) --rate 30 && \
	$(BIN)/syn-export $$out/$$name.motion.h5 -o $$out/$$name.mot --model $(COMPOSE_MODEL)

# ---- the studio ----------------------------------------------------------------------------
# `make studio [LIBRARY=...] [SCRIPT=...] [PORT=8080]`: syn-studio on the library (the demo's by default), its page at
# http://127.0.0.1:PORT/ until Ctrl-C. The page's three.js comes from the report's npm install.
PORT ?= 8080
studio: build report-npm
	@if [ ! -f $(LIBRARY) ]; then $(MAKE) --no-print-directory demo; fi
	$(BIN)/syn-studio --library $(LIBRARY) --model $(COMPOSE_MODEL) --robot-map $(COMPOSE_MAP) --script $(SCRIPT) --port $(PORT)

# ---- a single-node SLURM cluster --------------------------------------------------------
# Packages, munge key, a cgroup-free slurm.conf for this host, daemons started without systemd; idempotent;
# returns when sinfo answers. cluster-down stops the daemons (packages, config and state stay).
cluster-up:
	@SLURM_PACKAGES="$(SLURM_PACKAGES)" tools/slurm/cluster-up.sh

cluster-down:
	@tools/slurm/cluster-down.sh

clean:
	rm -rf $(BUILD_DIR) build-sanitize $(FUZZ_BUILD_DIR) outputs
