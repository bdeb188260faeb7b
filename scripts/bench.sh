#!/usr/bin/env bash
# Runs every benchmark of the release build, then prints one table of the
# figures each reports against its baseline from the same run, its target and
# whether it is met, and writes the table as JSON (docs/performance.md); last,
# the instructions per tick of each stage (scripts/callgrind-stages.sh).
#   scripts/bench.sh [--quick] [--json FILE]
#     --quick      short runs (a smoke check of the table, figures are noisy)
#     --json FILE  where the JSON goes (default build/release/bench-summary.json)
# Benchmarks are measurements, not tests: the exit code is non-zero only when a
# bench fails to run, never because a target is not met.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
json=build/release/bench-summary.json
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --json) json="$2"; shift ;;
    *) echo "bench.sh: unknown argument $1 (--quick, --json FILE)" >&2; exit 2 ;;
  esac
  shift
done

scripts/install-deps.sh test
cmake --preset release >/dev/null
benches=(sinew-bench-skinning sinew-bench-sph sinew-bench-metaballs sinew-bench-barnet sinew-bench-anatomy
         sinew-bench-pipeline sinew-bench-latency)
cmake --build --preset release -j "$(nproc)" --target "${benches[@]}" sinew-bench-table

bin=build/release/host_tools/bench
rows=$(mktemp)
trap 'rm -f "$rows"' EXIT
export SINEW_BENCH_SUMMARY="$rows"
if [ "$quick" = 1 ]; then gb=(--benchmark_min_time=0.01); steps=200; ticks=(--ticks 500 --paced-ticks 500)
else gb=(--benchmark_min_time=0.5); steps=5000; ticks=(); fi
run() {
  echo "== $*"
  "$@"
}
run "$bin/sinew-bench-skinning" "${gb[@]}"
run "$bin/sph/sinew-bench-sph" "${gb[@]}"
run "$bin/metaballs/sinew-bench-metaballs" "${gb[@]}"
run "$bin/barnet/sinew-bench-barnet" "${gb[@]}"
run "$bin/anatomy/sinew-bench-anatomy" "${gb[@]}"
run "$bin/sinew-bench-pipeline" --steps "$steps"
run "$bin/sinew-bench-latency" "${ticks[@]}"
echo
echo "== summary (every ratio is against a baseline measured in the same run)"
"$bin/common/sinew-bench-table" "$rows" --json "$json"
echo
echo "== instructions per tick per stage (callgrind; independent of load and clock)"
if [ "$quick" = 1 ]; then cg_steps=10; else cg_steps=100; fi
scripts/callgrind-stages.sh --build-dir build/release --steps "$cg_steps"
