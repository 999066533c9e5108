#!/usr/bin/env bash
# Runs every fuzz target of the readers (tests/fuzz) for SECONDS each, from its committed seeds and
# regressions, with ASan + UBSan; stops at the first crash, leak, sanitizer report, timeout or
# out-of-memory, leaving the input in ARTIFACTS (copy it into tests/fuzz/regressions/<target>/).
# Prints the executions of each target and their total.
#   scripts/fuzz.sh [SECONDS=60] [BUILD=build-fuzz] [ARTIFACTS=fuzz-artifacts]
# Builds BUILD with clang first if it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build="${2:-build-fuzz}"
artifacts="$(realpath -m "${3:-fuzz-artifacts}")"
targets=(${FUZZ_TARGETS:-stl off obj ply vtu domain})  # FUZZ_TARGETS="vtu ply": some of them
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFROTH_FUZZ=ON -DFROTH_BUILD_TESTS=OFF \
    -DFROTH_BUILD_BENCH=OFF
fi
cmake --build "$build" -j2 --target "${targets[@]/#/froth_fuzz_}"
mkdir -p "$artifacts"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
total=0
for t in "${targets[@]}"; do
  mkdir -p "$work/$t"
  cp tests/fuzz/corpus/"$t"/* tests/fuzz/regressions/"$t"/* "$work/$t/"  # the committed files stay as they are
  log="$work/$t.log"
  # One process: -rss_limit_mb and -malloc_limit_mb make a reader that believes a lying count
  # (gigabytes for a few bytes) a finding; -timeout makes a hang one.
  if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/tests/fuzz/froth_fuzz_$t" "$work/$t" -max_total_time="$seconds" -max_len=16384 -timeout=10 \
      -rss_limit_mb=2048 -malloc_limit_mb=1024 -artifact_prefix="$artifacts/$t-" -print_final_stats=1 \
      >"$log" 2>&1; then
    tail -60 "$log"
    echo "fuzz: froth_fuzz_$t found a problem; its input is in $artifacts" >&2
    exit 1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
  echo "fuzz: $t: $runs executions in ${seconds} s, $cov, corpus $(ls "$work/$t" | wc -l) inputs"
  total=$((total + runs))
done
echo "fuzz: $total executions over ${#targets[@]} targets, no findings"
