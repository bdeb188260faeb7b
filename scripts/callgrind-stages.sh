#!/usr/bin/env bash
# Instructions per tick of each pipeline stage, counted by callgrind: a
# figure that does not move with the machine's load or clock, so it can be
# compared across noisy machines and projected to a board (docs/performance.md,
# "Instructions per tick"). Runs `sinew-run` (one thread, the kernels the CPU
# selects) under valgrind for each job and prints a table of the inclusive
# instruction count of each stage's step function and of the whole
# pipeline_step, divided by the number of ticks.
#
# Usage: scripts/callgrind-stages.sh [--build-dir DIR] [--rig arm|hand] [--steps N]
#   --build-dir DIR  a built release tree (default build/release)
#   --rig NAME       built-in rig (default arm)
#   --steps N        ticks per job (default 100)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
rig=arm
steps=100
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build="$2"; shift 2 ;;
    --rig) rig="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "callgrind-stages: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
run="$build/host_tools/run/sinew-run"
[ -x "$run" ] || { echo "callgrind-stages: no $run (build the release preset)" >&2; exit 1; }
if ! command -v valgrind >/dev/null || ! command -v callgrind_annotate >/dev/null; then
  echo "callgrind-stages: installing valgrind"
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends valgrind >/dev/null
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# The stages, in the stage table's order (sim_core/pipeline/stage_list.hpp).
stages=(skinning sph metaballs barnet anatomy)
jobs=("none:skinning only" "metaballs,barnet:default job (metaballs, bar-net)" "all:every layer")
declare -A count
for job in "${jobs[@]}"; do
  layers="${job%%:*}"
  valgrind --tool=callgrind --callgrind-out-file="$work/$layers.out" \
    "$run" --rig "$rig" --steps "$steps" --layers "$layers" >"$work/$layers.log" 2>&1 ||
    { cat "$work/$layers.log"; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$work/$layers.out" >"$work/$layers.txt" 2>/dev/null
  for stage in "${stages[@]}" pipeline; do
    if [ "$stage" = pipeline ]; then fn='sinew::pipeline::pipeline_step('; else fn="sinew::pipeline::stages::${stage}_step("; fi
    ir="$({ grep -F "$fn" "$work/$layers.txt" || true; } | sed -n 1p | awk '{ gsub(",", "", $1); print $1 }')"
    count["$layers/$stage"]="${ir:-0}"
  done
done

# Every layer's job runs every stage: a stage without a count means its step
# function was renamed or inlined away, and the table would be wrong.
for stage in "${stages[@]}" pipeline; do
  if [ "${count["all/$stage"]}" = 0 ]; then
    echo "callgrind-stages: no count for ${stage}'s step function in the every-layer job" >&2
    exit 1
  fi
done

printf '\ninstructions per tick (callgrind Ir, inclusive, mean of %s ticks), rig %s, %s\n\n' "$steps" "$rig" \
  "$(uname -m), the kernels the CPU selects"
printf '| stage |'
for job in "${jobs[@]}"; do printf ' %s |' "${job#*:}"; done
printf '\n|---|'
for _ in "${jobs[@]}"; do printf -- '---:|'; done
printf '\n'
for stage in "${stages[@]}" pipeline; do
  label="$stage"
  [ "$stage" = pipeline ] && label="whole step (pipeline_step)"
  printf '| %s |' "$label"
  for job in "${jobs[@]}"; do
    ir="${count["${job%%:*}/$stage"]}"
    if [ "$ir" = 0 ]; then printf ' - |'; else awk -v ir="$ir" -v n="$steps" 'BEGIN { printf " %.3g M |", ir / n / 1e6 }'; fi
  done
  printf '\n'
done
