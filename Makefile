# pdgrain front door. `make demo` and `make test` do everything on a fresh Debian 12 machine.
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -G Ninja -DCMAKE_BUILD_TYPE=Release -DPD_ENABLE_ASSERTS=ON

.PHONY: all deps deps-test configure build test demo bench bench-lammps examples examples-run accuracy stability \
	install quick-python format format-check clean deps-asan asan-build test-asan fuzz ci

all: build

deps:
	@bash tools/install-deps.sh

# The tests also need Slurm and munge (the single-node Slurm test of workflows/sweep).
deps-test:
	@bash tools/install-deps.sh --slurm

$(BUILD)/build.ninja: | deps
	@mkdir -p $(BUILD)
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) > $(BUILD)/configure.log 2>&1 || \
	  { cat $(BUILD)/configure.log; exit 1; }

configure: deps $(BUILD)/build.ninja

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

test: deps-test build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The tools, the static libraries and headers with the CMake package (find_package(pdgrain)),
# data-schema/, the workflows and the Python module under PREFIX (README: "Using pdgrain as a
# library").
PREFIX ?= /usr/local
install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

demo: build
	@bash workflows/demo/run.sh $(BUILD)

# Every example's CI-sized `make quick` (each checks its number; examples/run_quick.sh finds every
# examples/*/Makefile with a quick: target). Outputs and logs in $(BUILD)/examples.
# `make examples-run` skips the build step.
examples: build
	@bash examples/run_quick.sh $(BUILD)/bin $(BUILD)/examples

examples-run:
	@bash examples/run_quick.sh $(BUILD)/bin $(BUILD)/examples

# Every examples/*/problem.py with --quick, in process through `import pdgrain` (issue 30);
# outputs in $(BUILD)/examples-python/<example>. ctest's pytest.pyexamples checks them against
# the pipeline.
quick-python: build
	@set -e; for p in examples/*/problem.py; do d=$$(basename $$(dirname $$p)); \
	  echo "== $$d"; PYTHONPATH=$(BUILD)/python PD_BIN_DIR=$(BUILD)/bin OMP_NUM_THREADS=1 \
	  /usr/bin/python3 $$p --quick --out $(BUILD)/examples-python/$$d; done

# Error against CPU time of the accuracy problems (workflows/accuracy: RESULTS.md, one PNG each;
# about 10 min of CPU, 20-30 min on 2 busy cores), then the time-step stability map when its
# workflow exists. ACCURACY_ARGS="--quick 2": the coarsest two levels only (about 1 min of CPU; tables in
# BUILD/accuracy/results, the committed ones untouched).
ACCURACY_ARGS ?=
accuracy: build
	@bash workflows/accuracy/run.sh $(BUILD) --before workflows/accuracy/before.json $(ACCURACY_ARGS)
	@$(MAKE) --no-print-directory stability

stability: build
	@if [ -f workflows/accuracy/stability/run.sh ]; then \
	  bash workflows/accuracy/stability/run.sh $(BUILD); \
	else echo "stability: workflows/accuracy/stability/run.sh not present, skipped"; fi

# ---- sanitizers and fuzzing (issue 13)
# One instrumented build (build-asan; clang 16 from Debian, `tools/install-deps.sh --fuzz`;
# -O1 -g1; the main `build` is untouched): every file is compiled once with AddressSanitizer +
# UBSan halting on the first report (-fno-sanitize-recover=all) and libFuzzer's coverage hooks
# (-fsanitize=fuzzer-no-link), so the same objects serve `make test-asan` (the four tools and the
# unit tests) and `make fuzz` (tests/fuzz: the harnesses only add libFuzzer's main at link).
# The one exception: vptr checks stay recoverable so that tests/asan/ubsan.supp can silence the
# reports inside CGAL's polygon-set headers; UBSAN_OPTIONS=halt_on_error=1 still halts on every
# other one. That alone is enough (measured with clang 16: the CGAL unit tests pass), but it is
# slow (Shapes.UChannelAndLens and AnnulusAndDrumWithBar took 164 s and 158 s under load; about
# 0.5 s in Release; probably the runtime handling each of the many suppressed reports), so
# region.cpp, the one file that reaches them, is compiled without the vptr check
# (PD_SANITIZE_CGAL_NO_VPTR; its effect on those times is not measured yet). OpenMP is off in
# this build (no libomp for clang 16 in Debian 12's default set).
ASAN_BUILD ?= build-asan
SAN_FLAGS = -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all \
  -fsanitize-recover=vptr -fno-omit-frame-pointer
SAN_TARGETS = pd-pack pd-partition pd-solve pd-post test_model test_mesh test_geometry test_h5 \
  test_solver test_contact test_post test_pipeline fuzz_scene fuzz_file
# What test-asan runs (CI-sized, see README): every unit test (label unit) but the longest physics
# tables, the pack -> partition -> solve -> post chain, the bad-input matrix (tests/cli) and the
# scene bad-input and fuzz-regression suites of tests/pack.
ASAN_LABELS ?= pipeline|cli
ASAN_EXCLUDE ?= ShapeMesh\.VolumesAndCentroidOfEveryShape|Csg3dStl\.SurfaceMeshInCsgAndMixedDimensions|Restitution\.Table|Accuracy\.(UniaxialStretchOfAPlate|CoulombFrictionOnAnIncline|WaveSpeedInABar)|Restitution\.UnequalDiscsStayHeadOn
ASAN_PYTEST ?= tests/pack/test_bad_input.py tests/pack/test_fuzz_regressions.py
SAN_SYMBOLIZER = /usr/bin/llvm-symbolizer
# Leaks are checked in the unit tests. The tools run with detect_leaks=0: Open MPI's components
# are dlclose()d at MPI_Finalize and what they keep shows up as leaks whose stacks (frame-pointer
# unwinding through libraries built without frame pointers) stop before any frame a suppression
# could match (tests/asan/lsan.supp covers most; fast_unwind_on_malloc=0 covers the rest at a
# high cost per malloc).
SAN_ASAN = strict_string_checks=1:check_initialization_order=1
SAN_ENV = ASAN_OPTIONS=detect_leaks=0:$(SAN_ASAN) \
  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/asan/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=$(CURDIR)/tests/asan/ubsan.supp \
  ASAN_SYMBOLIZER_PATH=$(SAN_SYMBOLIZER)
SAN_LEAKS = ASAN_OPTIONS=detect_leaks=1:$(SAN_ASAN)

deps-asan:
	@bash tools/install-deps.sh --slurm --fuzz

$(ASAN_BUILD)/build.ninja: | deps-asan
	@mkdir -p $(ASAN_BUILD)
	@CC=clang-16 CXX=clang++-16 cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=None \
	  -DPD_ENABLE_ASSERTS=ON -DPD_ENABLE_FUZZ=ON -DPD_ENABLE_OPENMP=OFF -DPD_SANITIZE_CGAL_NO_VPTR=ON \
	  "-DCMAKE_CXX_FLAGS=-O1 -g1 $(SAN_FLAGS)" "-DCMAKE_C_FLAGS=-O1 -g1 $(SAN_FLAGS)" \
	  "-DCMAKE_EXE_LINKER_FLAGS=$(SAN_FLAGS)" "-DCMAKE_SHARED_LINKER_FLAGS=$(SAN_FLAGS)" \
	  $(ASAN_CMAKE_FLAGS) > $(ASAN_BUILD)/configure.log 2>&1 || \
	  { cat $(ASAN_BUILD)/configure.log; rm -f $@; exit 1; }

# (SAN_ENV also here: gtest_discover_tests runs each unit-test binary at build time.)
asan-build: deps-asan $(ASAN_BUILD)/build.ninja
	@$(SAN_ENV) cmake --build $(ASAN_BUILD) -j $(JOBS) --target $(SAN_TARGETS)

test-asan: asan-build
	@cd $(ASAN_BUILD) && $(SAN_ENV) $(SAN_LEAKS) ctest --output-on-failure -j $(JOBS) -L unit \
	  -E '$(ASAN_EXCLUDE)'
	@cd $(ASAN_BUILD) && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -L '$(ASAN_LABELS)' \
	  -LE unit -E '$(ASAN_EXCLUDE)'
	@$(SAN_ENV) PD_BIN_DIR=$(CURDIR)/$(ASAN_BUILD)/bin PD_SOURCE_DIR=$(CURDIR) \
	  /usr/bin/python3 -m pytest -q -p no:cacheprovider $(ASAN_PYTEST)

# fuzz: each libFuzzer harness of build-asan for FUZZ_SECONDS on a copy of the stored corpus,
# after replaying the stored crash inputs (tests/fuzz/run.sh prints executions and findings).
FUZZ_SECONDS ?= 60

fuzz: asan-build
	@bash tests/fuzz/run.sh $(ASAN_BUILD) $(FUZZ_SECONDS)

# What CI runs (.ci/run): the format check, every test, the sanitizer subset, then each fuzz
# harness for FUZZ_SECONDS. Two builds: build (Release, g++) and build-asan (clang 16).
ci:
	@if command -v clang-format-14 >/dev/null; then $(MAKE) --no-print-directory format-check; fi
	@$(MAKE) --no-print-directory test
	@$(MAKE) --no-print-directory test-asan
	@$(MAKE) --no-print-directory fuzz

SOURCES = $(shell find lib tools tests workflows python -name '*.cpp' -o -name '*.hpp')

format:
	@clang-format-14 -i $(SOURCES)

format-check:
	@clang-format-14 --dry-run -Werror $(SOURCES)

clean:
	@rm -rf $(BUILD)

# Benchmarks (CPU time, best / median of several runs; tables of workflows/bench/RESULTS.md):
# the solver's hot paths with the naive bond loop side by side, then PeriDEM's decks.
bench: build
	@$(BUILD)/bin/solver_bench
	@/usr/bin/python3 workflows/bench/peridem/run.py --build $(BUILD)

# pdgrain against Debian's LAMMPS on LAMMPS' bench/POTENTIALS/in.peri (workflows/bench/lammps/;
# needs `apt-get install lammps`, a benchmark reference only: without `lmp` it says so, exit 2).
bench-lammps: build
	@/usr/bin/python3 workflows/bench/lammps/run.py --build $(BUILD)
