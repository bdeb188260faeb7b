#!/usr/bin/env bash
# One step of a fuzz campaign that accumulates across working sessions:
#
#   scripts/fuzz-campaign.sh TARGET MINUTES [--jobs N]
#
# 1. builds TARGET in the clang preset;
# 2. runs it for MINUTES at `nice -n 19` from the committed corpus
#    (tests/fuzz/corpus/<corpus>/: the hand-written seeds at its top and
#    what earlier campaigns kept in campaign/), new inputs going to a
#    scratch folder in the build tree;
# 3. merges the scratch inputs and the committed campaign/ folder into a
#    minimal set (libFuzzer's -merge=1: an input stays only if it adds
#    coverage over the seeds and the inputs kept before it) and writes that
#    set back to tests/fuzz/corpus/<corpus>/campaign/ (commit it). A target
#    whose inputs are large (the rig blobs: about 46 KB each, so a thousand
#    kept inputs would add 50 MB of binary files to the repository) keeps
#    its set as one archive instead, tests/fuzz/corpus/<corpus>.campaign.tar.zst
#    (<NAME>.campaign.tar.zst for an "archive=NAME" entry)
#    (beside the seed folder, so that no run reads it as an input), unpacked
#    into the build tree for the run and packed again, byte for byte
#    reproducibly, after the merge;
# 4. appends the run to tests/fuzz/campaigns.tsv (date, commit, target,
#    seconds, executions, coverage at start and end, corpus kept, findings)
#    and rewrites the cumulative table in docs/fuzzing.md from that ledger.
#
# A finding (crash, sanitizer report, leak, input slower than TIMEOUT s or
# an allocation over MALLOC_LIMIT_MB) is kept in
# build/clang/tests/fuzz/findings/<target>/ and recorded in the ledger as
# open; the script then exits 1. Fix the code, add a regression test and the
# input to the seeds as crash-<what broke>, and record the fix with
#   scripts/fuzz-campaign.sh --close TARGET "what was fixed, and where"
# TARGETS: scripts/lib/fuzz-targets.sh; docs/fuzzing.md explains each.
# --jobs N runs N libFuzzer workers (-fork=N) instead of one process.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/fuzz-targets.sh

ledger=tests/fuzz/campaigns.tsv
doc=docs/fuzzing.md
timeout="${TIMEOUT:-30}"
malloc_limit="${MALLOC_LIMIT_MB:-512}"

usage() { sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
lookup() {
  local entry
  for entry in $sinew_fuzz_targets; do
    if [ "${entry%%:*}" = "$1" ]; then echo "$entry"; return 0; fi
  done
  echo "fuzz-campaign: no target '$1' (one of: $(for e in $sinew_fuzz_targets; do printf '%s ' "${e%%:*}"; done))" >&2
  exit 2
}

ledger_header=$'date\tcommit\ttarget\tseconds\texecutions\tcov_start\tcov_end\tcorpus_inputs\tcorpus_bytes\tfindings'
ensure_ledger() { [ -s "$ledger" ] || printf '%s\n' "$ledger_header" > "$ledger"; }

# Rewrites the part of docs/fuzzing.md between the ledger markers: per target,
# the campaigns, their executions and hours added up, the coverage and corpus
# of the latest one, and whether a finding is still open (a row whose
# findings start with "open:" and no later "closed:" row of that target).
render_doc() {
  local table
  table=$(awk -F'\t' -v all="$sinew_fuzz_targets" '
    function thousands(n,   s) {
      s = sprintf("%d", n)
      while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", s)
      return s
    }
    NR == 1 { next }
    {
      t = $3; runs[t]++; secs[t] += $4; execs[t] += $5
      if ($5 > 0) { cov[t] = $7; corpus[t] = $8 " (" int($9 / 1024) " KB)"; last[t] = $1 }
      if ($10 ~ /^open:/) open[t] = substr($10, 6)
      else if ($10 ~ /^closed:/) open[t] = ""
    }
    END {
      print "| target | campaigns | executions | hours | exec/s (mean) | coverage (latest) | corpus kept (latest) | latest | open finding | 10 million reached |"
      print "|---|---|---|---|---|---|---|---|---|---|"
      n = split(all, entries, /[ \n]+/)
      for (i = 1; i <= n; i++) {
        split(entries[i], f, ":"); t = f[1]
        if (t == "") continue
        rate = 0
        if (secs[t] > 0) rate = int(execs[t] / secs[t])
        printf "| `%s` | %d | %s | %.1f | %d | %s | %s | %s | %s | %s |\n", t, runs[t] + 0, thousands(execs[t] + 0),
          secs[t] / 3600, rate, ((t in cov) ? cov[t] : "-"), ((t in corpus) ? corpus[t] : "-"),
          ((t in last) ? last[t] : "-"), ((open[t] != "") ? open[t] : "none"), ((execs[t] >= 10000000) ? "yes" : "no")
      }
    }' "$ledger")
  local begin='<!-- campaign-ledger:begin (scripts/fuzz-campaign.sh rewrites this table from tests/fuzz/campaigns.tsv) -->'
  local end='<!-- campaign-ledger:end -->'
  grep -qF "$begin" "$doc" || { echo "fuzz-campaign: $doc has no ledger markers" >&2; exit 2; }
  awk -v begin="$begin" -v end="$end" -v table="$table" '
    $0 == begin { print; print table; skip = 1; next }
    $0 == end { skip = 0 }
    !skip { print }' "$doc" > "$doc.tmp"
  mv "$doc.tmp" "$doc"
}

if [ "${1:-}" = "--close" ]; then
  [ $# -eq 3 ] || usage
  lookup "$2" >/dev/null
  ensure_ledger
  printf '%s\t%s\t%s\t0\t0\t-\t-\t-\t0\tclosed: %s\n' "$(date -u +%Y-%m-%d)" "$(git rev-parse --short HEAD)" "$2" \
    "$(tr '\t\n' '  ' <<<"$3")" >> "$ledger"
  render_doc
  echo "fuzz-campaign: recorded the fix of $2's finding in $ledger and $doc"
  exit 0
fi
if [ "${1:-}" = "--render" ]; then ensure_ledger; render_doc; exit 0; fi

[ $# -ge 2 ] || usage
target="$1"
minutes="$2"
shift 2
jobs=0
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) jobs="$2"; shift 2 ;;
    *) usage ;;
  esac
done
[[ "$minutes" =~ ^[0-9]+$ ]] && [ "$minutes" -gt 0 ] || { echo "fuzz-campaign: MINUTES must be a positive integer" >&2; exit 2; }
[[ "$jobs" =~ ^[0-9]+$ ]] || { echo "fuzz-campaign: --jobs must be a non-negative integer" >&2; exit 2; }
IFS=: read -r target corpus max_len storage <<<"$(lookup "$target")"
# "archive=NAME": the kept set is NAME's, for targets that share their seeds
# but not what they keep (each merge keeps what adds to its own coverage).
set_name=$corpus
case "${storage:-}" in archive=*) set_name=${storage#archive=}; storage=archive ;; esac

scripts/install-deps.sh test
cmake --preset clang >/dev/null
cmake --build --preset clang -j "$(nproc)" --target "$target"

build=build/clang/tests/fuzz
seeds=tests/fuzz/corpus/$corpus
kept=$seeds/campaign
archive=""
extra_inputs=()
scratch=$build/campaign/$set_name
findings=$build/findings/$target
log=$findings/campaign.log
rm -rf "$scratch"
if [ "${storage:-}" = archive ]; then
  # The kept set lives in the archive; it is read from a build-tree folder
  # (not under the seed folder, so it is named as an input folder of its own).
  archive=tests/fuzz/corpus/$set_name.campaign.tar.zst
  kept=$build/campaign/$set_name.kept
  rm -rf "$kept"
  mkdir -p "$kept"
  if [ -f "$archive" ]; then tar --zstd -xf "$archive" -C "$kept"; fi
  extra_inputs=("$kept")
fi
mkdir -p "$scratch" "$kept" "$findings"
rm -f "$findings"/crash-* "$findings"/leak-* "$findings"/timeout-* "$findings"/oom-* "$findings"/slow-unit-*

fork=()
if [ "$jobs" -gt 0 ]; then fork=(-fork="$jobs" -ignore_crashes=0); fi
echo "fuzz-campaign: $target for $minutes min at nice 19 from $seeds (max_len $max_len)"
start=$SECONDS
status=0
nice -n 19 "$build/$target" -max_total_time=$((minutes * 60)) -max_len="$max_len" -timeout="$timeout" \
  -malloc_limit_mb="$malloc_limit" -print_final_stats=1 -artifact_prefix="$findings/" "${fork[@]}" \
  "$scratch" "$seeds" "${extra_inputs[@]}" >"$log" 2>&1 || status=$?
seconds=$((SECONDS - start))
tail -n 12 "$log"

# Executions: the final stats of a single process, or the last status line's
# count ("#N" of a fork run's pulses). Coverage: libFuzzer's edge count once
# the corpus is loaded (INITED) and at the end.
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
if [ -z "$execs" ]; then execs=$(grep -oE '^#[0-9]+' "$log" | tail -n 1 | tr -d '#'); fi
execs="${execs:-0}"
cov_start=$(grep -m1 -E 'INITED' "$log" | grep -oE 'cov: [0-9]+' | grep -oE '[0-9]+' || true)
cov_end=$(grep -E 'cov: [0-9]+' "$log" | tail -n 1 | grep -oE 'cov: [0-9]+' | grep -oE '[0-9]+' || true)

found=$(find "$findings" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) -printf '%f ' || true)
findings_field="none"
if [ "$status" -ne 0 ] || [ -n "$found" ]; then
  findings_field="open: exit $status ${found:-(no artifact; see the log)}"
fi

# Minimise: the seeds first (they are always kept), then every input of the
# committed campaign folder and of this run that adds coverage beyond them.
merged=$build/campaign/$set_name.merged
rm -rf "$merged"
mkdir -p "$merged"
find "$seeds" -maxdepth 1 -type f ! -name README.md -exec cp {} "$merged/" \;
seed_names=$(find "$seeds" -maxdepth 1 -type f -printf '%f\n')
nice -n 19 "$build/$target" -merge=1 -max_len="$max_len" -timeout="$timeout" -malloc_limit_mb="$malloc_limit" \
  "$merged" "$kept" "$scratch" >"$findings/merge.log" 2>&1 || {
  echo "fuzz-campaign: the merge failed (log: $findings/merge.log); the committed corpus is left as it was" >&2
  exit 1
}
for name in $seed_names; do rm -f "$merged/$name"; done
rm -rf "$kept"
mkdir -p "$kept"
if [ -n "$(ls -A "$merged")" ]; then cp "$merged"/* "$kept/"; fi
inputs=$(find "$kept" -type f | wc -l)
bytes=$(find "$kept" -type f -printf '%s\n' | awk '{ s += $1 } END { print s + 0 }')
if [ -n "$archive" ]; then
  # Sorted names, no times or owners: the same set packs to the same bytes.
  tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner -C "$kept" -cf - . | zstd -q -19 -f -o "$archive"
  kept=$archive
fi

ensure_ledger
printf '%s\t%s\t%s\t%d\t%d\t%s\t%s\t%d\t%d\t%s\n' "$(date -u +%Y-%m-%d)" "$(git rev-parse --short HEAD)" "$target" \
  "$seconds" "$execs" "${cov_start:--}" "${cov_end:--}" "$inputs" "$bytes" "$findings_field" >> "$ledger"
render_doc

rate=0
[ "$seconds" -gt 0 ] && rate=$((execs / seconds))
echo "fuzz-campaign: $target: $execs executions in $seconds s ($rate exec/s), cov ${cov_start:--} -> ${cov_end:--}," \
  "$inputs inputs kept in $kept; findings: $findings_field"
echo "fuzz-campaign: commit $kept, $ledger and $doc"
[ "$findings_field" = none ] || exit 1
