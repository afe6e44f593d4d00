#!/usr/bin/env bash
# Instructions per call on the PUMA 560 (bench/README.md): each operation runs CALLS times under
# callgrind with instrumentation on only around the loop (bench/callgrind_calls.cpp). Needs valgrind
# (Debian package valgrind) and the AVX2 benchmark build (valgrind 3.19 cannot decode AVX-512).
# Env: BUILD (default build), CALLS (default 2048).
set -euo pipefail
BUILD=${BUILD:-build}
CALLS=${CALLS:-2048}
exe="$BUILD/bench/lowpair_callgrind_calls"
[ -x "$exe" ] || { echo "error: $exe not built (cmake --build $BUILD --target lowpair_callgrind_calls)" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "error: valgrind not installed (apt-get install valgrind)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-28s %14s\n' operation instructions/call
for op in fk_poe fk_poe_previous fk_dh jacobian_spatial jacobian_spatial_previous jacobian_geometric batch_poe \
  batch_poe_previous batch_jacobian fk_kdl jacobian_kdl fk_mujoco jacobian_mujoco; do
  valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="$tmp/$op.out" "$exe" "$op" "$CALLS" \
    >/dev/null 2>"$tmp/$op.log" || { cat "$tmp/$op.log" >&2; exit 1; }
  ir=$(sed -n 's/^totals: *\([0-9]*\).*/\1/p' "$tmp/$op.out")
  awk -v op="$op" -v ir="$ir" -v calls="$CALLS" 'BEGIN { printf "%-28s %14.1f\n", op, ir / calls }'
done
