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

# The fuzzers' corpora are replayed under the sanitizers too (scripts/fuzz --replay).
test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)
	scripts/fuzz --replay

demo: build
	scripts/demo $(BUILD)

bench: build
	scripts/bench $(BUILD)

# Each fuzzer for FUZZ_SECONDS; what finds new coverage joins fuzz/corpus/.
FUZZ_SECONDS ?= 60
fuzz: deps
	scripts/fuzz $(FUZZ_SECONDS)

format:
	clang-format -i $$(git ls-files '*.h' '*.cc')

clean:
	rm -rf $(BUILD)
