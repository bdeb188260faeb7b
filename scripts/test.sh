#!/usr/bin/env bash
# Builds and runs the whole test suite:
#   dev      clang Debug (-O1) with ASan+UBSan: every unit, property,
#            integration test, and the fuzz targets' short runs
#   release  gcc Release: the same tests at -O3, and the benchmarks' smoke runs
#   aarch64  cross build (gcc) under qemu-user: sim_core, hal and firmware
#            tests, and the integration tests through the aarch64 daemon
#   armhf    cross build (gcc) under qemu-user: sim_core unit and determinism
#            tests
# So every test runs under both compilers, and sim_core's determinism hashes
# come from clang -O1, gcc -O3 and the two cross builds.
# Every build prints its `determinism-hash` lines; they must all agree.
# A preset's tests run while the next preset builds (one suite at a time).
# Last, beside the last suite, scripts/fresh-machine-test.sh runs the main job
# (scripts/run.sh) in a fresh Debian 12 root; skipped when not root, when
# chroot cannot work here, or with SINEW_SKIP_FRESH_MACHINE=1.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh test

jobs="$(nproc)"
# Ordered for the overlap below: the armhf suite (qemu, the longest) runs on
# beside the dev and aarch64 builds, the aarch64 suite (qemu) beside the
# longest build (release), and the last suite, which nothing hides, is one
# of the two shortest.
presets=(armhf dev aarch64 release)
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

# One preset's tests run while the next preset builds: the tests are
# load-proof (docs/testing.md; scripts/test-under-load.sh checks them with
# every core busy), and many of them wait on sockets, daemons and qemu, so
# the build fills the cores they leave idle. Only one test suite runs at a
# time (the suites share loopback ports and names). SINEW_CI_SERIAL=1 runs
# every step alone, for timing one step or reading its output in order.
serial="${SINEW_CI_SERIAL:-0}"
pending_preset=""
pending_pid=""
# Suites that open no socket, daemon or device (armhf builds sim_core only)
# do not wait for the others: the armhf suite, the longest (qemu), runs on
# beside the next builds and suites, filling the cores they leave idle
# while they wait on daemons and sockets, and is collected at the end.
independent_presets=(armhf)
independent_presets_running=()
independent_pids=()
failed=()

run_tests() {  # preset: ctest into build/<preset>/ctest-output.log, time in .seconds
  local preset="$1" start=$SECONDS rc=0
  ctest --preset "$preset" -j "$jobs" --output-on-failure \
    > "build/$preset/ctest-output.log" 2>&1 || rc=$?
  echo $((SECONDS - start)) > "build/$preset/ctest-output.seconds"
  return $rc
}

collect_tests() {  # preset pid: waits for that suite, prints its output, records it
  local preset="$1" pid="$2" rc=0
  wait "$pid" || rc=$?
  echo "=== $preset: test output"
  cat "build/$preset/ctest-output.log"
  local tested
  tested="$(cat "build/$preset/ctest-output.seconds" 2>/dev/null || echo '?')"
  local i
  for i in "${!timings[@]}"; do
    if [[ "${timings[$i]}" == "$(printf '%-8s' "$preset") build"* ]]; then
      timings[i]="${timings[$i]}  test ${tested}"
    fi
  done
  echo "=== $preset: tested in $tested s (exit $rc)"
  # The determinism lines this build's tests printed, for the cross-build
  # comparison (ctest keeps every test's output in LastTest.log).
  grep '^determinism-hash' "build/$preset/Testing/Temporary/LastTest.log" | sed "s/^/$preset /" >> "$hash_log" || true
  if [ "$rc" -ne 0 ]; then failed+=("$preset"); fi
}

finish_tests() {  # the pending suite (the one that uses loopback), if any
  [ -n "$pending_preset" ] || return 0
  local preset="$pending_preset" pid="$pending_pid"
  pending_preset=""
  pending_pid=""
  collect_tests "$preset" "$pid"
}

finish_independent_tests() {
  local i
  for i in "${!independent_presets_running[@]}"; do
    collect_tests "${independent_presets_running[$i]}" "${independent_pids[$i]}"
  done
  independent_presets_running=()
  independent_pids=()
}

abandon_tests() {  # a build failed: stop the suites still running
  local pid
  for pid in $pending_pid "${independent_pids[@]}"; do
    pkill -TERM -P "$pid" 2>/dev/null || true
    kill "$pid" 2>/dev/null || true
  done
}
trap 'abandon_tests; print_timings' EXIT

for preset in "${presets[@]}"; do
  echo "=== $preset: configure and build"
  start=$SECONDS
  # CMake reads a preset's toolchain only when it creates a build tree, so a
  # tree configured before CMakePresets.json changed (e.g. dev moved from
  # gcc to clang) is configured afresh; ninja then rebuilds only what the
  # new commands change.
  presets_sum="$(sha256sum CMakePresets.json | cut -d' ' -f1)"
  fresh=()
  if [ "$(cat "build/$preset/.presets-sha256" 2>/dev/null)" != "$presets_sum" ]; then fresh=(--fresh); fi
  cmake --preset "$preset" "${fresh[@]}" >/dev/null
  echo "$presets_sum" > "build/$preset/.presets-sha256"
  cmake --build --preset "$preset" -j "$jobs"
  built=$((SECONDS - start))
  timings+=("$(printf '%-8s build %5d' "$preset" "$built")")
  echo "=== $preset: built in $built s"
  echo "=== $preset: test"
  if [[ " ${independent_presets[*]} " == *" $preset "* ]]; then
    run_tests "$preset" &
    independent_presets_running+=("$preset")
    independent_pids+=($!)
    if [ "$serial" = 1 ]; then finish_independent_tests; fi
    continue
  fi
  finish_tests  # the previous preset's suite, if it is still running
  run_tests "$preset" &
  pending_preset="$preset"
  pending_pid=$!
  if [ "$serial" = 1 ]; then finish_tests; fi
done

# The README's first command on a fresh machine: the main job must build and
# run with only the runtime packages (1–1.5 min with the cached base root,
# up to 3.5 min without). It runs beside the last suite: its main job binds
# only the default configuration's fixed port (15020, which no test uses;
# tests take ephemeral ports) and asserts nothing about timing.
fresh_pid=""
fresh_start=0
start_fresh_root() {
  [ "${SINEW_SKIP_FRESH_MACHINE:-0}" = 1 ] && return 0
  fresh_start=$SECONDS
  scripts/fresh-machine-test.sh --skip-if-unsupported > build/fresh-root.log 2>&1 &
  fresh_pid=$!
}
finish_fresh_root() {
  echo "=== fresh Debian 12 root: scripts/run.sh"
  if [ -z "$fresh_pid" ]; then
    echo "fresh-machine-test: SKIP: SINEW_SKIP_FRESH_MACHINE=1"
    return 0
  fi
  local rc=0
  wait "$fresh_pid" || rc=$?
  fresh_pid=""
  cat build/fresh-root.log
  timings+=("$(printf '%-8s %5d' "fresh root" "$((SECONDS - fresh_start))")")
  echo "=== fresh Debian 12 root: done in $((SECONDS - fresh_start)) s (exit $rc)"
  if [ "$rc" -ne 0 ]; then failed+=("fresh root"); fi
}

if [ "$serial" != 1 ]; then start_fresh_root; fi
finish_tests
finish_independent_tests
if [ "$serial" = 1 ]; then start_fresh_root; fi
finish_fresh_root

# The Debian packages (scripts/package.sh: CPack, lintian without error) of
# the three trees, once their suites are done (the packaging reconfigures a
# tree's install rules). Then the arm64 package's sinewd under qemu-user, and
# the amd64 packages in a fresh Debian 12 root (scripts/lib/package-smoke.sh).
# One at a time: both run the default configuration, whose Modbus port is fixed.
if [ ${#failed[@]} -eq 0 ]; then
  echo "=== Debian packages"
  start=$SECONDS
  for preset in release aarch64 armhf; do
    scripts/package.sh --preset "$preset" --no-build || failed+=("packages ($preset)")
  done
  scripts/lib/foreign-package-smoke.sh build/aarch64/packages || failed+=("arm64 package under qemu-user")
  timings+=("$(printf '%-8s %5d' "packages" "$((SECONDS - start))")")
  if [ "${SINEW_SKIP_FRESH_MACHINE:-0}" != 1 ] && [ ${#failed[@]} -eq 0 ]; then
    start=$SECONDS
    echo "=== fresh Debian 12 root: the amd64 packages"
    scripts/fresh-machine-test.sh --skip-if-unsupported --packages build/release/packages || failed+=("packages in a fresh root")
    timings+=("$(printf '%-8s %5d' "pkg root" "$((SECONDS - start))")")
  fi
fi
if [ "${#failed[@]}" -gt 0 ]; then
  echo "=== failed: ${failed[*]}" >&2
  exit 1
fi

echo "=== determinism across builds"
cat "$hash_log"
scripts/compare-hashes.sh "$hash_log"
echo "all test suites passed"
