#!/usr/bin/env bash
# Runs a preset's whole ctest suite while every core is kept busy, to show
# that no test depends on the machine's speed or load (docs/testing.md).
#
#   scripts/test-under-load.sh [--preset P] [--runs N] [--load N] [--no-build]
#     --preset P   the CMake preset whose suite runs (default dev)
#     --runs N     how many suite runs in a row (default 3); all must pass
#     --load N     busy processes, one pinned to each of the first N CPUs
#                  (default: nproc, i.e. every core)
#     --no-build   use the preset's build tree as it is
#
# The busy processes are plain shell loops at the tests' own priority (not
# niced), each pinned to one CPU with taskset, so every test thread shares
# its core with one that never sleeps. ctest runs with -j nproc as
# scripts/test.sh does. The report lists every test that failed or exceeded
# its timeout in any run, and the slowest tests of the last run with their
# timeouts, so a margin that is running out shows before it fails. Exit 0
# only when every run passed.
set -euo pipefail
cd "$(dirname "$0")/.."

preset=dev
runs=3
load="$(nproc)"
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --preset) preset="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --load) load="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    *) echo "test-under-load: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "test-under-load: --runs must be a positive integer" >&2; exit 2; }
[[ "$load" =~ ^[0-9]+$ ]] || { echo "test-under-load: --load must be a non-negative integer" >&2; exit 2; }

jobs="$(nproc)"
if [ "$build" = 1 ]; then
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
fi
[ -f "build/$preset/CTestTestfile.cmake" ] || { echo "test-under-load: build/$preset is not built" >&2; exit 2; }

out="build/$preset/under-load"
mkdir -p "$out"

busy=()
stop_load() {
  if [ "${#busy[@]}" -gt 0 ]; then kill "${busy[@]}" 2>/dev/null || true; wait "${busy[@]}" 2>/dev/null || true; fi
  busy=()
}
trap stop_load EXIT
cpus=$(nproc --all)
for ((i = 0; i < load; i++)); do
  taskset -c "$((i % cpus))" bash -c 'while :; do :; done' &
  busy+=("$!")
done
echo "test-under-load: $preset, $runs runs, $load busy processes (pinned to CPUs 0..$((load - 1)) mod $cpus), ctest -j $jobs"

failed_runs=0
: > "$out/problems.txt"
for ((run = 1; run <= runs; run++)); do
  log="$out/run-$run.log"
  start=$SECONDS
  status=0
  ctest --preset "$preset" -j "$jobs" --output-on-failure >"$log" 2>&1 || status=$?
  wall=$((SECONDS - start))
  # ctest's result lines: "  12/345 Test  #12: name ......***Failed    3.21 sec"
  # (or ***Timeout, ***Exception, Not Run).
  problems=$(grep -E '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*(\*\*\*|Not Run)' "$log" || true)
  summary=$(grep -E '^[0-9]+% tests passed' "$log" | tail -n 1 || true)
  echo "run $run: ${summary:-no ctest summary} (exit $status, ${wall} s)"
  if [ "$status" -ne 0 ]; then
    failed_runs=$((failed_runs + 1))
    echo "$problems" | sed "s/^/  run $run: /" | tee -a "$out/problems.txt"
  fi
done
stop_load

echo
echo "slowest tests of the last run (seconds, and the test's timeout):"
grep -E '^ *[0-9]+/[0-9]+ Test +#[0-9]+: ' "$out/run-$runs.log" |
  sed -E 's/^ *[0-9]+\/[0-9]+ Test +#[0-9]+: ([^ ]+) .* ([0-9.]+) sec$/\2 \1/' | sort -rn | sed -n 1,12p |
  while read -r secs name; do
    # This one test's properties only: parsing the whole suite's JSON in
    # CMake takes minutes.
    ctest --preset "$preset" --show-only=json-v1 -R "^${name//./\\.}\$" >"$out/test.json" 2>/dev/null || true
    limit=$(cmake -DJSON="$out/test.json" -P scripts/lib/test-timeouts.cmake 2>&1 | awk -v n="$name" '$1 == n { print $2 }')
    printf '  %8s  %-60s timeout %s\n' "$secs" "$name" "${limit:-default}"
  done

if [ "$failed_runs" -ne 0 ]; then
  echo "test-under-load: FAIL: $failed_runs of $runs runs had failures (logs in $out/)"
  exit 1
fi
echo "test-under-load: PASS: $runs of $runs runs passed with $load busy processes"
