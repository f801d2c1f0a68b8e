# pdgrain front door. `make demo` and `make test` do everything on a fresh Debian 12 machine.
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -G Ninja -DCMAKE_BUILD_TYPE=Release -DPD_ENABLE_ASSERTS=ON

.PHONY: all deps deps-test configure build test demo bench examples examples-run accuracy stability \
	format format-check clean

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

# Every example's CI-sized `make quick` (each checks its number; examples/run_quick.sh finds every
# examples/*/Makefile with a quick: target). Outputs and logs in $(BUILD)/examples.
# `make examples-run` skips the build step.
examples: build
	@bash examples/run_quick.sh $(BUILD)/bin $(BUILD)/examples

examples-run:
	@bash examples/run_quick.sh $(BUILD)/bin $(BUILD)/examples

# Error against CPU time of the accuracy problems (workflows/accuracy: RESULTS.md, one PNG each;
# about 20-30 min on 2 cores), then the time-step stability map when its workflow exists.
accuracy: build
	@bash workflows/accuracy/run.sh $(BUILD) --before workflows/accuracy/before.json
	@$(MAKE) --no-print-directory stability

stability: build
	@if [ -f workflows/accuracy/stability/run.sh ]; then \
	  bash workflows/accuracy/stability/run.sh $(BUILD); \
	else echo "stability: workflows/accuracy/stability/run.sh not present, skipped"; fi

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
