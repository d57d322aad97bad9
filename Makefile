# Two commands do all the set-up on a fresh Debian machine: `make run` and `make test`.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
HOST ?= 127.0.0.1
PORT ?= 8080
SLOSH_WERROR ?= OFF
CMAKE_FLAGS ?=
# The sanitizer build, which also holds the fuzzers (README "Fuzzing and sanitizers").
ASAN_DIR ?= build-asan
FUZZ_DIR ?= $(ASAN_DIR)
FUZZ_SECONDS ?= 60
FUZZ_SMOKE_SECONDS ?= 20
FUZZ_TARGETS ?=
# Leaks of third-party libraries only (Ipopt/MUMPS/gfortran): tests/sanitizers/lsan.supp.
SANITIZER_ENV := ASAN_OPTIONS=detect_stack_use_after_return=1:strict_string_checks=1 \
                 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitizers/lsan.supp:print_suppressions=0 \
                 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

.PHONY: all deps configure build build-slosh run test bench bench-check bench-budgets format \
        format-check clean test-asan fuzz-build fuzz fuzz-smoke

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release -DSLOSH_WERROR=$(SLOSH_WERROR) $(CMAKE_FLAGS)

configure: $(BUILD_DIR)/build.ninja

# Everything: the binary, the unit tests, the fuzz-corpus replays and the benchmarks.
build: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Only what `slosh serve` needs (the libraries and the binary): the first `make run` does not wait
# for the tests and benchmarks to compile.
build-slosh: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target slosh

run: build-slosh
	$(BUILD_DIR)/slosh serve --host $(HOST) --port $(PORT)

test: build
	@bash scripts/run-tests.sh $(BUILD_DIR)

bench: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target benchmarks
	@bash scripts/run-bench.sh $(BUILD_DIR)

# The benchmark guard (SPEC §8): a short benchmark set, normalised by a calibration loop of the
# same run, fails on more than 3 x a budget of bench/budgets.tsv (scripts/bench-check.sh).
bench-check: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_check
	@bash scripts/bench-check.sh $(BUILD_DIR)

# Rewrites bench/budgets.tsv from one run of the same set (commit the file): after a change that
# is meant to cost more, or one that made things faster.
bench-budgets: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_check
	@bash scripts/bench-check.sh $(BUILD_DIR) --update

# One clang build in build-asan/ serves the sanitizers and the fuzzers: the product (core, api,
# service, the slosh binary) with ASan + UBSan and libFuzzer's coverage, the harnesses plain, and
# the test drivers the release build compiled, linked again (docs/testing.md): test-asan builds
# the release build first. It runs the in-process tests there; what drives the
# release binary from outside (browser, node-opcua, README commands, deploy and layout checks, the
# benchmark guard) and the replicas timed against each other (slosh_cluster_job_tests, not built
# there) are left to `make test`.
ASAN_SKIP := ^(browser|deploy|layout|readme|opcua|bench)\.
$(ASAN_DIR)/build.ninja:
	cmake -S . -B $(ASAN_DIR) -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" -DSLOSH_SANITIZE=ON \
	  -DSLOSH_BUILD_FUZZERS=ON -DSLOSH_BUILD_BENCHMARKS=OFF -DSLOSH_WERROR=OFF \
	  -DSLOSH_TEST_OBJECTS_FROM=$(abspath $(BUILD_DIR))

test-asan: build $(ASAN_DIR)/build.ninja
	$(SANITIZER_ENV) cmake --build $(ASAN_DIR) -j $(JOBS)
	@$(SANITIZER_ENV) bash scripts/run-tests.sh $(ASAN_DIR) -E '$(ASAN_SKIP)'

# libFuzzer targets: fuzz/, scripts/fuzz.sh. Reproducers land in fuzz-artifacts/<target>/.
fuzz-build: deps $(ASAN_DIR)/build.ninja
	cmake --build $(ASAN_DIR) -j $(JOBS) --target fuzzers

fuzz: fuzz-build
	@bash scripts/fuzz.sh $(FUZZ_DIR) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

fuzz-smoke: fuzz-build
	@bash scripts/fuzz.sh $(FUZZ_DIR) $(FUZZ_SMOKE_SECONDS) $(FUZZ_TARGETS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

format-check:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run --Werror

clean:
	rm -rf $(BUILD_DIR)
