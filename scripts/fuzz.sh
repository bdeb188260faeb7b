#!/usr/bin/env bash
# Opt-in fuzz campaign: every libFuzzer target of the clang build in turn,
# keeping what each finds in build/clang/tests/fuzz/corpus/<corpus>/ (the
# committed seeds in tests/fuzz/corpus/<corpus>/ are read, never written).
#   scripts/fuzz.sh [SECONDS]      each target for SECONDS (default 600)
#   RUNS=N scripts/fuzz.sh         each target for N executions instead
#   TARGETS="udp_receiver_fuzz gltf_import_fuzz" scripts/fuzz.sh   only these
#   TIMEOUT=S                      an input running longer is a finding (default 30)
#   MALLOC_LIMIT_MB=M              a single allocation larger is a finding (default 512)
#   JOBS=N                         build parallelism (default: all cores)
# Findings (crash, leak, timeout, out-of-memory inputs) are written to
# build/clang/tests/fuzz/findings/<target>/. At the end it prints each
# target's executions, wall time and executions per second, and exits 1 if
# any target found something. docs/fuzzing.md describes the targets.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
runs="${RUNS:-}"
timeout="${TIMEOUT:-30}"
malloc_limit="${MALLOC_LIMIT_MB:-512}"
source scripts/lib/fuzz-targets.sh
all="$sinew_fuzz_targets"
selected=()
for entry in $all; do
  target="${entry%%:*}"
  if [ -z "${TARGETS:-}" ] || [[ " $TARGETS " == *" $target "* ]]; then selected+=("$entry"); fi
done
[ "${#selected[@]}" -gt 0 ] || { echo "fuzz.sh: no target matches TARGETS='${TARGETS:-}'" >&2; exit 2; }

scripts/install-deps.sh test
cmake --preset clang >/dev/null
targets=()
for entry in "${selected[@]}"; do targets+=("${entry%%:*}"); done
cmake --build --preset clang -j "${JOBS:-$(nproc)}" --target "${targets[@]}"

out=build/clang/tests/fuzz
if [ -n "$runs" ]; then limit=(-runs="$runs"); else limit=(-max_total_time="$seconds"); fi
summary=()
found=0
for entry in "${selected[@]}"; do
  IFS=: read -r target corpus max_len _ <<<"$entry"
  mkdir -p "$out/corpus/$corpus" "$out/findings/$target"
  log="$out/findings/$target/last-run.log"
  echo "== $target (${limit[*]}, corpus $corpus)"
  start=$(date +%s)
  status=0
  "$out/$target" "${limit[@]}" -max_len="$max_len" -timeout="$timeout" -malloc_limit_mb="$malloc_limit" -print_final_stats=1 \
    -artifact_prefix="$out/findings/$target/" "$out/corpus/$corpus" "tests/fuzz/corpus/$corpus" \
    >"$log" 2>&1 || status=$?
  wall=$(($(date +%s) - start))
  tail -n 20 "$log"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  execs="${execs:-?}"
  rate="?"
  if [ "$execs" != "?" ] && [ "$wall" -gt 0 ]; then rate=$((execs / wall)); fi
  size=$(find "$out/corpus/$corpus" -type f | wc -l)
  result="ok"
  if [ "$status" -ne 0 ]; then result="FINDING (exit $status, see $log)"; found=1; fi
  summary+=("$(printf '%-24s %12s execs %7ss %9s exec/s %7s corpus  %s' "$target" "$execs" "$wall" "$rate" "$size" "$result")")
done
echo
echo "== summary (corpus: inputs kept in $out/corpus/<corpus>/)"
printf '%s\n' "${summary[@]}"
exit "$found"
