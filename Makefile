# Entry points. `make demo` and `make test` work on a fresh Debian machine as root.
BUILD_TYPE ?= Release
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
# Warnings are errors in CI (CI=true), plain warnings elsewhere.
WERROR ?= $(if $(CI),ON,OFF)
DEMO_OUT ?= out/demo
DATA ?= ../shared/data

CMAKE_FLAGS = -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DHYDRA_MULTI_WERROR=$(WERROR)

.PHONY: all deps build test test-sanitize test-crash fuzz demo bench bench-robust bench-sim bench-frontend bench-backend bench-journal bench-bandwidth bench-viewer bench-hydra bench-scale bench-online viewer-screenshot format clean

all: build

deps:
	@./scripts/install_deps.sh

build: deps
	@cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) -- --no-print-directory
	@echo "built $(BUILD_DIR)/hydra-multi ($(BUILD_TYPE))"

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# The crash test: KILLS (200) random kill points of the station, a robot or both, seeded by
# CRASH_SEED (random unless given; printed, so that a failure can be replayed).
test-crash: build
	@$(BUILD_DIR)/hydra-multi simulate --preset tiny --seed 4 --out out/crash-test/tiny --quiet > /dev/null
	@bash tests/apps/crash_test.sh $(BUILD_DIR)/hydra-multi out/crash-test/tiny out/crash-test/run $(or $(KILLS),200) $(CRASH_SEED)

# Every libFuzzer target for SECONDS (60) each under ASan and UBSan (RUNS=N: until N executions,
# at most SECONDS), built with clang in its own folder (fuzz/README.md); the table goes to
# out/fuzz/summary.md.
fuzz: deps
	@CXX=clang++ CC=clang cmake -S . -B build-fuzz -DHYDRA_MULTI_FUZZ=ON -DHYDRA_MULTI_BUILD_TESTS=OFF \
	  -DHYDRA_MULTI_VIEWER_PAGE=OFF -DCMAKE_BUILD_TYPE=Debug > /dev/null
	@cmake --build build-fuzz -j $(JOBS) --target $(addprefix fuzz_,dsgb_records binary_payloads json \
	  spark_json spark_binary g2o protocol connection) -- --no-print-directory
	@RUNS=$(RUNS) ./scripts/fuzz.sh build-fuzz out/fuzz $(or $(SECONDS),60) $(JOBS) $(DATA)

# Every test again under AddressSanitizer and UndefinedBehaviorSanitizer (Debug, own build folder).
test-sanitize: deps
	@cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Debug -DHYDRA_MULTI_SANITIZE=ON \
	  -DHYDRA_MULTI_WERROR=$(WERROR) > /dev/null
	@cmake --build build-sanitize -j $(JOBS) -- --no-print-directory
	@cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS)

# Benchmarks print time and accuracy figures (always Release).
bench: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DHYDRA_MULTI_WERROR=$(WERROR) > /dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_pgo -- --no-print-directory
	@$(BUILD_DIR)/bench/bench_pgo $(DATA)

# Robust estimation on real data and injected outliers (several minutes).
bench-robust: build
	@./scripts/bench_robust.sh $(BUILD_DIR)/hydra-multi $(DATA)

# Every simulated preset: generation time, size, drift and aliasing (SEEDS="1 2 3" for more).
SEEDS ?= 1
bench-sim: build
	@./scripts/bench_simulate.sh $(BUILD_DIR)/hydra-multi out/bench-sim "$(SEEDS)"

# The frontend (processor and loop-closure detection) on every team preset: loop closures and
# time per update (SEED=2 for another seed).
SEED ?= 1
bench-frontend: build
	@./scripts/bench_frontend.sh $(BUILD_DIR)/hydra-multi out/bench-frontend $(SEED)

# One backend round on the final state of a dataset, stage by stage (DATASET=DIR, CONFIG=FILE).
DATASET ?= out/demo/office-3
bench-backend: build
	@$(BUILD_DIR)/bench/bench_backend $(DATASET) $(if $(CONFIG),--config $(CONFIG))

# The online maps of every team preset against the truth, a backend round every EVERY updates
# (ONLINE_SEEDS="1 2", EVERY=20 for others): rounds with a wrong map, rounds keeping wrong loop
# closures, their ATE. About 2 minutes with the defaults.
ONLINE_SEEDS ?= 1 2 3 4 5
EVERY ?= 10
bench-online: build
	@./scripts/bench_online.sh $(BUILD_DIR)/hydra-multi $(BUILD_DIR)/bench/bench_backend out/bench-online "$(ONLINE_SEEDS)" $(EVERY)

# The station's journal appending a dataset's updates with synchronous=FULL and =NORMAL
# (DATASET=DIR).
bench-journal: build
	@$(BUILD_DIR)/bench/bench_journal $(DATASET)

# Bytes of a dataset's updates per robot and category against full resends, and zstd on them
# (DATASET=DIR).
bench-bandwidth: build
	@$(BUILD_DIR)/bench/bench_bandwidth $(DATASET)

# The station at team scale: office-3 with 2-20 robots at scales 1-3 (TEAMS="2x1 10x2 ...": a
# subset), each simulated and run with the robots at SCALE_SPEED times real time (0: as fast as
# the frontend takes them); per team graph size, backend time per round and stage, frontend time,
# peak memory, accuracy, backend time against graph size as SVG, and issue 22's targets met or
# not. Runs already made at that speed are reused (REDO=1: not).
TEAMS ?=
SCALE_SPEED ?= 10
bench-scale: build
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_scale -- --no-print-directory
	@./scripts/bench_scale.sh $(BUILD_DIR)/hydra-multi $(BUILD_DIR)/bench/bench_scale out/bench-scale $(SEED) "$(TEAMS)" $(SCALE_SPEED)

# The station under load: 10 robots (scale 2) at ten times real time and 20 (scale 2) in real
# time, each robot its own process, into one station on loopback (LOAD_TEAMS="RxS@SPEED ...",
# SEED=N; about 35 minutes with the defaults).
LOAD_TEAMS ?= 10x2@10 20x2@1
bench-load: build
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_load -- --no-print-directory
	@./scripts/bench_load.sh $(BUILD_DIR)/hydra-multi $(BUILD_DIR)/bench/bench_load out/bench-load $(SEED) "$(LOAD_TEAMS)"

# What the station makes of office-3 when the robots speak as Hydra robots (whole Spark-DSG graphs
# over ZeroMQ) against our protocol and the file replay, with the bytes each sent (SEED=N,
# HYDRA_SPEED=X: robot time, 10 by default; about 6 minutes).
HYDRA_SPEED ?= 10
bench-hydra: build
	@./scripts/bench_hydra.sh $(BUILD_DIR)/hydra-multi out/bench-hydra $(SEED) $(HYDRA_SPEED)

# The viewer in headless chromium on a 10-robot run's graph (VIEWER_RUN=DIR; made when missing,
# about 11 minutes): first frame, frames per second while orbiting, bytes, lag.
VIEWER_RUN ?= out/viewer-bench/office-3-r10-run
bench-viewer: build
	@./scripts/bench_viewer.sh $(BUILD_DIR)/hydra-multi $(VIEWER_RUN)

# The README's screenshot of the viewer (VIEWER_SHOT_RUN=DIR: a finished run's output folder).
VIEWER_SHOT_RUN ?= out/demo/office-3-run
viewer-screenshot: build
	@node scripts/viewer_screenshot.mjs --bin $(BUILD_DIR)/hydra-multi --web web \
	  --run $(VIEWER_SHOT_RUN) --out docs/viewer-office-3.png

demo: build
	@./scripts/demo.sh $(BUILD_DIR)/hydra-multi $(DATA) $(DEMO_OUT)

format:
	@find src tests -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	@rm -rf $(BUILD_DIR) build-sanitize out
