#!/usr/bin/env bash
# Builds the benchmarks in $BUILD (Release), runs them and prints lowpair's speed-ups over MuJoCo and KDL
# from this run's medians (bench/README.md). Env: BUILD (default build), BENCH_OUT (JSON, default
# $BUILD/bench.json), BENCH_FILTER (regex; default every benchmark, or with BENCH_ROBOT that robot's),
# BENCH_ROBOT (a robot file, .yaml: benchmark it instead of the bundled robots; passed as one argument,
# --robot=FILE, never through a shell command), BENCH_SMOKE=1 (each benchmark runs ~1 ms, no
# repetitions: a seconds-long check that everything builds, agrees and runs), BENCH_NO_BUILD=1 (use the
# existing binary), JOBS (build parallelism, default 2).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
BUILD=${BUILD:-build}
BENCH_OUT=${BENCH_OUT:-$BUILD/bench.json}
BENCH_FILTER=${BENCH_FILTER:-}
BENCH_ROBOT=${BENCH_ROBOT:-}

if [ -z "${BENCH_NO_BUILD:-}" ]; then
  # the library recompiled with the benchmark flags (bench/CMakeLists.txt); make check builds without the copy
  cmake -S "$root" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DLOWPAIR_BUILD_BENCH=ON -DLOWPAIR_BENCH_LIBRARY_COPY=ON >/dev/null
  cmake --build "$BUILD" --target lowpair_bench -j"${JOBS:-2}"
elif [ -z "${BENCH_SMOKE:-}" ] && ! grep -q '^LOWPAIR_BENCH_LIBRARY_COPY:BOOL=ON' "$BUILD/CMakeCache.txt" 2>/dev/null; then
  echo "note: $BUILD was built without the benchmark flags' library copy (LOWPAIR_BENCH_LIBRARY_COPY=OFF, as make check" >&2
  echo "builds it): these timings are not comparable with bench/README.md's" >&2
fi
exe="$BUILD/bench/lowpair_bench"
[ -x "$exe" ] || { echo "error: $exe not built (configure with -DLOWPAIR_BUILD_BENCH=ON)" >&2; exit 2; }

if [ -n "${BENCH_SMOKE:-}" ]; then
  args=(--benchmark_min_time=0.001)
else
  args=(--benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
        --benchmark_report_aggregates_only=true)
fi
[ -z "$BENCH_FILTER" ] || args+=(--benchmark_filter="$BENCH_FILTER")
robot_args=()
[ -z "$BENCH_ROBOT" ] || robot_args=(--robot="$BENCH_ROBOT")
mkdir -p "$(dirname "$BENCH_OUT")"
# a robot file that cannot be benchmarked: one line `error: FILE: what` and exit 2 from here, nothing run
"$exe" "${args[@]}" "${robot_args[@]}" --benchmark_out="$BENCH_OUT" --benchmark_out_format=json
echo
python3 "$here/report.py" "$BENCH_OUT"
# the Python module's batched FK against the C++ batch in the same run (python/bench_fk.py, docs/python.md; the C++
# timers are the extension _lowpair_bench, python/bench/timers.cpp)
if [ -z "${BENCH_SMOKE:-}" ] && [ -f "$BUILD/python/lowpair/__init__.py" -o -z "${BENCH_NO_BUILD:-}" ]; then
  robot_args=()
  [ -z "$BENCH_ROBOT" ] || robot_args=(--robot "$BENCH_ROBOT")
  cmake --build "$BUILD" --target lowpair_python lowpair_python_bench -j"${JOBS:-2}" >/dev/null &&
    PYTHONPATH="$BUILD/python" /usr/bin/python3 "$root/python/bench_fk.py" "${robot_args[@]}"
fi
