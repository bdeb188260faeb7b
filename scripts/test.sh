#!/usr/bin/env bash
# Builds and runs the whole test suite:
#   dev      gcc Debug with ASan+UBSan: every unit, property, integration test
#   release  gcc Release: the same tests at -O3, and the benchmarks' smoke runs
#   clang    clang RelWithDebInfo: sim_core, hal and firmware tests, short fuzz runs
#   aarch64  cross build under qemu-user: sim_core, hal and firmware tests,
#            and the integration tests through the aarch64 daemon
#   armhf    cross build under qemu-user: sim_core unit and determinism tests
# Every build prints its `determinism-hash` lines; they must all agree.
# Last, scripts/fresh-machine-test.sh runs the main job (scripts/run.sh) in a
# fresh Debian 12 root; skipped when not root, when chroot cannot work here,
# or with SINEW_SKIP_FRESH_MACHINE=1.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh test

jobs="$(nproc)"
presets=(dev release clang aarch64 armhf)
hash_log="build/determinism-hashes.txt"
mkdir -p build
: > "$hash_log"

# Each step's wall time, printed at the end (also when a step fails), so a
# run shows where its time went (docs/testing.md, "CI time").
timings=()
suite_start=$SECONDS
print_timings() {
  echo "=== time per step (wall clock, s)"
  printf '%s\n' "${timings[@]}"
  echo "total $((SECONDS - suite_start)) s"
}
trap print_timings EXIT

for preset in "${presets[@]}"; do
  echo "=== $preset: configure and build"
  start=$SECONDS
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  built=$((SECONDS - start))
  timings+=("$(printf '%-8s build %5d' "$preset" "$built")")
  echo "=== $preset: built in $built s; test"
  start=$SECONDS
  ctest --preset "$preset" -j "$jobs" --output-on-failure
  tested=$((SECONDS - start))
  timings[-1]="$(printf '%-8s build %5d  test %5d' "$preset" "$built" "$tested")"
  echo "=== $preset: tested in $tested s"
  # The determinism lines this build's tests printed, for the cross-build
  # comparison (ctest keeps every test's output in LastTest.log).
  grep '^determinism-hash' "build/$preset/Testing/Temporary/LastTest.log" | sed "s/^/$preset /" >> "$hash_log"
done

echo "=== determinism across builds"
cat "$hash_log"
scripts/compare-hashes.sh "$hash_log"

# The README's first command on a fresh machine: the main job must build and
# run with only the runtime packages (1–1.5 min with the cached base root,
# up to 3.5 min without).
echo "=== fresh Debian 12 root: scripts/run.sh"
if [ "${SINEW_SKIP_FRESH_MACHINE:-0}" = 1 ]; then
  echo "fresh-machine-test: SKIP: SINEW_SKIP_FRESH_MACHINE=1"
else
  start=$SECONDS
  scripts/fresh-machine-test.sh --skip-if-unsupported
  timings+=("$(printf '%-8s %5d' "fresh root" "$((SECONDS - start))")")
  echo "=== fresh Debian 12 root: done in $((SECONDS - start)) s"
fi
echo "all test suites passed"
