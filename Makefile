# Thin wrapper (README): `make check` and `make run` install missing Debian packages (as root), configure
# and build into build/, then run. `make bench` builds in Release and runs the benchmarks.
PACKAGES := cmake g++ make libeigen3-dev libmujoco-dev libqhull-dev liburdfdom-dev libyaml-cpp-dev \
            googletest libgtest-dev libbenchmark-dev liborocos-kdl-dev libcli11-dev nlohmann-json3-dev gnuplot-nox python3 \
            valgrind bc libsleef-dev
BUILD ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps configure build check run clean

all: build

deps:
	@missing=""; for p in $(PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing Debian packages:$$missing"; \
	    apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $$missing; \
	  else \
	    echo "missing Debian packages:$$missing"; echo "install them with: sudo apt-get install$$missing"; exit 1; \
	  fi; \
	fi

configure: deps
	@test -f $(BUILD)/CMakeCache.txt || cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD) -j$(JOBS)

check: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

run: build
	./$(BUILD)/lowpair validate --report $(BUILD)/report

clean:
	rm -rf $(BUILD)

# Benchmarks (bench/README.md): Release build, Google Benchmark JSON to $(BENCH_OUT), filter $(BENCH_FILTER).
BENCH_OUT ?= $(BUILD)/bench.json
BENCH_FILTER ?= .
.PHONY: bench
bench: configure
	BUILD=$(BUILD) BENCH_OUT=$(BENCH_OUT) BENCH_FILTER='$(BENCH_FILTER)' bash bench/run.sh
