# pdgrain front door. `make demo` and `make test` do everything on a fresh Debian 12 machine.
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -G Ninja -DCMAKE_BUILD_TYPE=Release -DPD_ENABLE_ASSERTS=ON

.PHONY: all deps deps-test configure build test demo bench format format-check clean

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

demo: build
	@bash workflows/demo/run.sh $(BUILD)

SOURCES = $(shell find lib tools tests workflows -name '*.cpp' -o -name '*.hpp')

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
