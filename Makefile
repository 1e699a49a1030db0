# The two set-up commands of the README: `make demo` and `make test`. Both install what is
# missing (Debian 12 packages, via scripts/install-deps), build, and run.
BUILD ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps configure build test demo bench fuzz format clean

all: build

deps:
	scripts/install-deps

configure: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD) -j$(JOBS)

# The fuzzers' corpora are replayed under the sanitizers too (scripts/fuzz --replay). That and
# the benchmarks' build, which no test needs, run beside ctest at the lowest priority: in the
# time its serial tests (the simulated station's, one at a time) leave a core idle.
test: build
	nice -n 19 sh -c 'cmake --build $(BUILD) -j$(JOBS) --target benchmarks && \
	  scripts/fuzz --replay' >$(BUILD)/beside-tests.log 2>&1 & beside=$$!; \
	(cd $(BUILD) && ctest --output-on-failure -j$(JOBS)); tests=$$?; \
	wait $$beside; built=$$?; tail -n 20 $(BUILD)/beside-tests.log; \
	if [ $$built -ne 0 ]; then echo "make test: benchmarks or fuzz replay failed ($(BUILD)/beside-tests.log)" >&2; fi; \
	[ $$tests -eq 0 ] && [ $$built -eq 0 ]

demo: build
	scripts/demo $(BUILD)

bench: build
	cmake --build $(BUILD) -j$(JOBS) --target benchmarks
	scripts/bench $(BUILD)

# Each fuzzer for FUZZ_SECONDS; what finds new coverage joins fuzz/corpus/.
FUZZ_SECONDS ?= 60
fuzz: deps
	scripts/fuzz $(FUZZ_SECONDS)

format:
	clang-format -i $$(git ls-files '*.h' '*.cc')

clean:
	rm -rf $(BUILD)
