#!/usr/bin/env bash
# `make fuzz` (tests/fuzz/README.md): builds the libFuzzer targets with clang into $FUZZ_BUILD and runs each
# for $FUZZ_SECONDS on a working corpus ($FUZZ_BUILD/corpus/<target>, seeded from the committed seeds and
# kept between runs; the committed seeds are never written). $FUZZ_JOBS targets run at a time.
# Crash inputs go to $FUZZ_BUILD/artifacts/<target>/, logs to $FUZZ_BUILD/logs/<target>.log.
# Exit status: 0 when no target found anything, 1 otherwise (the artifacts are listed).
#
# Deterministic mode (`make fuzz-ci`, what CI runs): FUZZ_RUNS=N runs each target for exactly N inputs with
# libFuzzer seed FUZZ_SEED (default 1) on a fresh copy of the committed seeds, in one process, stopping at
# the first finding. No clock decides anything (no time limit, no RSS watchdog: a malloc limit instead), so
# the same commit fuzzes the same inputs and gets the same verdict every time. FUZZ_BIN_DIR: where the
# fuzz_<target> executables are (default $FUZZ_BUILD; make fuzz-ci: the sanitizer build's tests/fuzz/).
set -euo pipefail
cd "$(dirname "$0")/../.."
FUZZ_BUILD=${FUZZ_BUILD:-build-fuzz}
FUZZ_SECONDS=${FUZZ_SECONDS:-600}
FUZZ_JOBS=${FUZZ_JOBS:-$(nproc)}
FUZZ_TARGETS=${FUZZ_TARGETS-robot_file scenario measurements urdf mujoco numeric}
FUZZ_OPTIONS=${FUZZ_OPTIONS:-}
FUZZ_RUNS=${FUZZ_RUNS:-0}
FUZZ_SEED=${FUZZ_SEED:-1}
FUZZ_BIN_DIR=${FUZZ_BIN_DIR:-$FUZZ_BUILD}
FLAGS="-fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer"

if [ "$FUZZ_BIN_DIR" = "$FUZZ_BUILD" ]; then
  if [ ! -f "$FUZZ_BUILD/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S tests/fuzz -B "$FUZZ_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$FLAGS"
  fi
  cmake --build "$FUZZ_BUILD" -j"$(nproc)"
fi

seeds() {  # the seed files of target $1
  case $1 in
    robot_file) ls models/*.yaml ;;
    scenario) ls scenarios/*.yaml ;;
    urdf) ls models/*.urdf ;;
    mujoco) ls models/*.xml models/*.urdf tests/data/mjcf/*.xml ;;
  esac
  ls -d tests/fuzz/seeds/"$1"/* tests/fuzz/regressions/"$1"/* 2>/dev/null || true
}
options() {  # libFuzzer options of target $1
  case $1 in
    robot_file|scenario) echo "-dict=tests/fuzz/dict/yaml.dict -max_len=16384" ;;
    measurements) echo "-dict=tests/fuzz/dict/csv.dict -max_len=16384" ;;
    # 512 KiB: long enough for nesting and size limits (a 40,000-level URDF is 280 KB)
    urdf|mujoco) echo "-dict=tests/fuzz/dict/xml.dict -max_len=524288" ;;
    numeric) echo "-max_len=1024" ;;
  esac
}

# Deterministic: N inputs from a fresh corpus of the committed seeds, one process, stop at a finding.
run_fixed() {
  local t=$1 corpus=$FUZZ_BUILD/ci-corpus/$1 artifacts=$FUZZ_BUILD/artifacts/$1/
  rm -rf "$corpus" "$artifacts"
  mkdir -p "$corpus" "$artifacts" "$FUZZ_BUILD/logs"
  seeds "$t" | while read -r f; do cp "$f" "$corpus/seed_$(basename "$f")"; done
  # shellcheck disable=SC2046
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS} \
  "$FUZZ_BIN_DIR/fuzz_$t" "$corpus" $(options "$t") -runs="$FUZZ_RUNS" -seed="$FUZZ_SEED" -timeout=600 \
    -rss_limit_mb=0 -malloc_limit_mb=2048 -artifact_prefix="$artifacts" -print_final_stats=1 -close_fd_mask=3 \
    $FUZZ_OPTIONS >"$FUZZ_BUILD/logs/$t.log" 2>&1
}

run_one() {
  local t=$1 corpus=$FUZZ_BUILD/corpus/$1 artifacts=$FUZZ_BUILD/artifacts/$1/
  # a previous run's findings move to artifacts.previous/<target>/ (copy what matters to regressions/)
  if ls "$artifacts" 2>/dev/null | grep -q .; then
    mkdir -p "$FUZZ_BUILD/artifacts.previous/$t" && mv "$artifacts"* "$FUZZ_BUILD/artifacts.previous/$t/"
  fi
  mkdir -p "$corpus" "$artifacts" "$FUZZ_BUILD/logs"
  seeds "$t" | while read -r f; do cp "$f" "$corpus/seed_$(basename "$f")"; done
  # -fork=1 -ignore_crashes=1 ...: a finding is saved and the run goes on (a child process per batch).
  # -close_fd_mask=3: the readers' and MuJoCo's messages stay out of the log (sanitizer reports still
  # appear); replay a crash input with the binary alone to see them.
  # shellcheck disable=SC2046
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS} \
  "$FUZZ_BUILD/fuzz_$t" "$corpus" $(options "$t") -max_total_time="$FUZZ_SECONDS" -timeout=30 \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -rss_limit_mb=2048 -artifact_prefix="$artifacts" -print_final_stats=1 -close_fd_mask=3 $FUZZ_OPTIONS \
    >"$FUZZ_BUILD/logs/$t.log" 2>&1
}

pids=() names=() status=0
for t in $FUZZ_TARGETS; do
  while [ "$(jobs -rp | wc -l)" -ge "$FUZZ_JOBS" ]; do sleep 1; done
  if [ "$FUZZ_RUNS" -gt 0 ]; then
    echo "fuzz_$t: $FUZZ_RUNS inputs, seed $FUZZ_SEED"
    run_fixed "$t" & pids+=($!) names+=("$t")
  else
    echo "fuzz_$t: ${FUZZ_SECONDS}s"
    run_one "$t" & pids+=($!) names+=("$t")
  fi
done
for i in "${!pids[@]}"; do
  if ! wait "${pids[$i]}"; then status=1; echo "fuzz_${names[$i]}: FAILED (see $FUZZ_BUILD/logs/${names[$i]}.log)"; fi
done

for t in $FUZZ_TARGETS; do
  log=$FUZZ_BUILD/logs/$t.log
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  echo "fuzz_$t: ${last:-no progress line}"
  if ls "$FUZZ_BUILD/artifacts/$t/" 2>/dev/null | grep -q .; then
    status=1
    for a in "$FUZZ_BUILD/artifacts/$t"/*; do echo "  finding: $a (replay: $FUZZ_BIN_DIR/fuzz_$t $a)"; done
  fi
done
exit $status
