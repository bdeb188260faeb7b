#!/usr/bin/env bash
# Builds and runs the whole test suite:
#   dev      gcc Debug with ASan+UBSan: every unit, property, integration test
#   release  gcc Release: the same tests at -O3, and the benchmarks' smoke runs
#   clang    clang RelWithDebInfo: unit and determinism tests
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
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  echo "=== $preset: test"
  ctest --preset "$preset" -j "$jobs" --output-on-failure
  # Collect the determinism lines of this build for the cross-build comparison.
  while read -r exe; do
    emu=()
    case "$preset" in
      aarch64) emu=(qemu-aarch64-static -L /) ;;  # as cmake/toolchain-aarch64.cmake
      armhf) emu=(qemu-arm-static -L /usr/arm-linux-gnueabihf) ;;
    esac
    "${emu[@]}" "$exe" --gtest_brief=1 | grep '^determinism-hash' | sed "s/^/$preset /" >> "$hash_log"
  done < <(find "build/$preset/tests" -maxdepth 2 -type f -name '*determinism_tests')
done

echo "=== determinism across builds"
cat "$hash_log"
scripts/compare-hashes.sh "$hash_log"
echo "all test suites passed"
