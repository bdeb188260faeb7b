#!/usr/bin/env bash
# Builds and runs the whole test suite:
#   dev      gcc Debug with ASan+UBSan: every unit, property, integration test
#   release  gcc Release: the same tests at -O3, and the benchmarks' smoke runs
#   clang    clang RelWithDebInfo: sim_core, hal and firmware tests, short fuzz runs
#   aarch64  cross build under qemu-user: sim_core, hal and firmware tests,
#            and the integration tests through the aarch64 daemon
#   armhf    cross build under qemu-user: sim_core unit and determinism tests
# Every build prints its `determinism-hash` lines; they must all agree.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh test

jobs="$(nproc)"
presets=(dev release clang aarch64 armhf)
hash_log="build/determinism-hashes.txt"
mkdir -p build
: > "$hash_log"

for preset in "${presets[@]}"; do
  echo "=== $preset: configure and build"
  start=$SECONDS
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  echo "=== $preset: built in $((SECONDS - start)) s; test"
  start=$SECONDS
  ctest --preset "$preset" -j "$jobs" --output-on-failure
  echo "=== $preset: tested in $((SECONDS - start)) s"
  # The determinism lines this build's tests printed, for the cross-build
  # comparison (ctest keeps every test's output in LastTest.log).
  grep '^determinism-hash' "build/$preset/Testing/Temporary/LastTest.log" | sed "s/^/$preset /" >> "$hash_log"
done

echo "=== determinism across builds"
cat "$hash_log"
scripts/compare-hashes.sh "$hash_log"
echo "all test suites passed"
