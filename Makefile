# Thin wrapper (README): `make check`, `make sanitize` and `make run` install missing Debian packages (as root), configure
# and build into build/, then run. `make bench` builds in Release and runs the benchmarks.
PACKAGES := cmake g++ make libeigen3-dev libmujoco-dev libqhull-dev liburdfdom-dev libyaml-cpp-dev \
            googletest libgtest-dev libbenchmark-dev liborocos-kdl-dev libcli11-dev nlohmann-json3-dev gnuplot-nox python3 \
            libsleef-dev clang libclang-rt-14-dev libtinyxml2-dev \
            pybind11-dev python3-numpy python3-pytest ninja-build lld
# bench/callgrind.sh's instruction counts (`make callgrind`) alone need valgrind: not installed for the tests
CALLGRIND_PACKAGES := valgrind
BUILD ?= build
JOBS ?= $(shell nproc)
# CMAKE_ARGS: extra configure arguments for build/ and the sanitizer build, e.g. CMAKE_ARGS=-DLOWPAIR_WERROR=ON (CI:
# .ci/run); given, they reconfigure an existing build tree (cached options stay until changed)
CMAKE_ARGS ?=

.PHONY: all deps configure build check run clean

all: build

deps:
	@missing=""; for p in $(PACKAGES) $(EXTRA_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing Debian packages:$$missing"; \
	    apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $$missing; \
	  else \
	    echo "missing Debian packages:$$missing"; echo "install them with: sudo apt-get install$$missing"; exit 1; \
	  fi; \
	fi

# A new build tree uses Ninja: it compiles a target's files while the libraries it links are still being built,
# where Make's generator waits for them, so both cores stay busy. An existing tree keeps its generator.
new_tree_generator = $(if $(wildcard $(1)/CMakeCache.txt),,-G Ninja)

configure: deps
	@test -f $(BUILD)/CMakeCache.txt -a -z '$(CMAKE_ARGS)' || cmake -S . -B $(BUILD) $(call new_tree_generator,$(BUILD)) \
	  -DCMAKE_BUILD_TYPE=Release $(CMAKE_ARGS)

build: configure
	cmake --build $(BUILD) -j$(JOBS)

# the long studies (ctest label `study`, minutes each) are left to `make study`
check: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS) -LE study

.PHONY: study
study: build
	cmake --build $(BUILD) --target lowpair_studies -j$(JOBS)
	ctest --test-dir $(BUILD) --output-on-failure -L study

run: build
	./$(BUILD)/lowpair validate --report $(BUILD)/report

clean:
	rm -rf $(BUILD)

# Benchmarks (bench/README.md): Release build, Google Benchmark JSON to $(BENCH_OUT), filter $(BENCH_FILTER)
# (default: every benchmark, or the robot's), BENCH_ROBOT=FILE: that robot file instead of the bundled robots.
# They reach bench/run.sh through the environment, so a path or a regex is never shell text.
BENCH_OUT ?= $(BUILD)/bench.json
BENCH_FILTER ?=
BENCH_ROBOT ?=
export BENCH_OUT BENCH_FILTER BENCH_ROBOT
.PHONY: bench callgrind
bench: configure
	BUILD='$(BUILD)' bash bench/run.sh

# instructions per call on the PUMA 560 under callgrind (bench/README.md); installs valgrind when missing
callgrind: EXTRA_PACKAGES := $(CALLGRIND_PACKAGES)
callgrind: configure
	cmake --build $(BUILD) --target lowpair_callgrind_calls -j$(JOBS)
	BUILD='$(BUILD)' bash bench/callgrind.sh

# Sanitizers (CI runs this after `make check`): clang with AddressSanitizer and UndefinedBehaviorSanitizer
# (float-cast-overflow included, no recovery), the test suite except the tests tests/sanitize_skip.txt lists
# with their reasons: three that cannot run under them, the statistical ones whose every code path a
# lighter test runs under them, and those that repeat another's run. The test programs' own code is not
# instrumented; lowpair's code they call is: the sanitizer tree links the test objects $(BUILD) compiled (it
# builds $(BUILD) first; tests/CMakeLists.txt, LOWPAIR_TEST_OBJECTS_FROM) and links with lld. The examples are
# not built there: `make check` runs them, and every library call they make runs under the sanitizers in the
# library's tests. LOWPAIR_SANITIZE=1: the random-robot property tests run a tenth of their
# robots (tests/common/random_robot.hpp robotCount); tests/lsan.supp: urdfdom's own leak on a looped URDF.
SAN_BUILD ?= build-sanitize
SAN_FLAGS := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer
# -O1 and line tables only: file:line in every report, less to compile and link than -O2 -g (not timed apart)
SAN_OPT := -O1 -gline-tables-only -DNDEBUG
# SAN_SKIP_MORE: more tests to leave out, e.g. '|fuzz_replay\..*' when make fuzz-ci follows (CI: it replays
# the same inputs and their mutants).
SAN_SKIP_MORE ?=
SAN_SKIP := ^($(shell sed -n 's/^\([A-Za-z_][A-Za-z0-9_.]*\).*/\1/p' tests/sanitize_skip.txt | paste -sd'|')$(SAN_SKIP_MORE))$$
.PHONY: sanitize sanitize-build
sanitize-build: build
	@test -f $(SAN_BUILD)/CMakeCache.txt -a -z '$(CMAKE_ARGS)' || CC=clang CXX=clang++ cmake -S . -B $(SAN_BUILD) $(call new_tree_generator,$(SAN_BUILD)) \
	  -DCMAKE_BUILD_TYPE=None -DLOWPAIR_BUILD_BENCH=OFF -DLOWPAIR_BUILD_PYTHON=OFF -DLOWPAIR_BUILD_EXAMPLES=OFF -DCMAKE_CXX_FLAGS="$(SAN_FLAGS) $(SAN_OPT)" \
	  -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DLOWPAIR_TEST_OBJECTS_FROM=$(abspath $(BUILD)) $(CMAKE_ARGS)
	cmake --build $(SAN_BUILD) -j$(JOBS)
sanitize: sanitize-build
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp LOWPAIR_SANITIZE=1 \
	  ctest --test-dir $(SAN_BUILD) --output-on-failure -j$(JOBS) -LE study -E '$(SAN_SKIP)'

# Fuzzing (tests/fuzz/README.md): libFuzzer targets built with clang (-fsanitize=fuzzer,address,undefined,
# float-cast-overflow; the sanitizer and libFuzzer runtimes are in libclang-rt-14-dev) into $(FUZZ_BUILD),
# each run for FUZZ_SECONDS on a working corpus under $(FUZZ_BUILD)/corpus/ seeded from models/, scenarios/,
# tests/data/ and tests/fuzz/seeds/, FUZZ_JOBS targets at a time. Findings: $(FUZZ_BUILD)/artifacts/<target>/ (a previous run's: artifacts.previous/).
# `make check` replays the seeds and tests/fuzz/regressions/ through every target (ctest fuzz_replay.*).
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 600
FUZZ_JOBS ?= $(JOBS)
FUZZ_TARGETS ?= robot_file scenario measurements urdf mujoco numeric
# make fuzz-ci (CI): the fuzz targets under ASan/UBSan in the sanitizer build, each seed and regression fed
# as itself and as FUZZ_CI_MUTANTS mutants from a seeded generator (tests/fuzz/replay_main.cpp): the same
# bytes every run, so the same commit always gets the same verdict. A crash's input: $(SAN_BUILD)/fuzz-ci-last-*.
FUZZ_CI_MUTANTS ?= 300
.PHONY: fuzz-ci
fuzz-ci: sanitize-build
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/lsan.supp LOWPAIR_FUZZ_MUTANTS=$(FUZZ_CI_MUTANTS) LOWPAIR_FUZZ_SEED=1 \
	  LOWPAIR_FUZZ_LAST=$(CURDIR)/$(SAN_BUILD)/fuzz-ci-last \
	  ctest --test-dir $(SAN_BUILD) --output-on-failure -j$(JOBS) -R '^fuzz_replay\.'
.PHONY: fuzz fuzz-build
fuzz-build: deps
	FUZZ_BUILD=$(FUZZ_BUILD) FUZZ_SECONDS=0 FUZZ_TARGETS= bash tests/fuzz/run.sh
fuzz: deps
	FUZZ_BUILD=$(FUZZ_BUILD) FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_JOBS=$(FUZZ_JOBS) FUZZ_TARGETS='$(FUZZ_TARGETS)' \
	  bash tests/fuzz/run.sh
