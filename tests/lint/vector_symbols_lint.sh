#!/usr/bin/env bash
# Fails if a static library exports a weak (link-once) function that holds
# a VEX- or EVEX-encoded (AVX, AVX2, AVX-512) instruction. The linker keeps one copy of each weak function for the whole
# program: if that copy came from a kernel compiled for AVX, the baseline
# callers of the same inline function would run AVX instructions too, and a
# CPU without AVX would fault in code that never chose a vector kernel
# (sim_core/fixed/isa_region.hpp).
# Usage: vector_symbols_lint.sh LIBRARY.a...
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 LIBRARY.a..." >&2; exit 2; }
status=0
for lib in "$@"; do
  [ -f "$lib" ] || { echo "vector_symbols_lint: no such library: $lib" >&2; exit 2; }
  # member<TAB>symbol of every weak function (nm -A: "lib:member:addr W symbol").
  weak=$(nm -A --defined-only "$lib" 2>/dev/null | awk '$2 == "W" { n = split($1, p, ":"); print p[n - 1] "\t" $3 }')
  # member<TAB>symbol of every function with an instruction whose mnemonic
  # starts with v: only the VEX and EVEX encodings do (vpxor, vmovd, ...).
  avx=$(objdump -d --no-show-raw-insn "$lib" | awk '
    /^[^ ]+:[ \t]+file format/ { member = $1; sub(":$", "", member); next }
    /^[0-9a-f]+ <.*>:$/ { fn = $2; gsub("^<|>:$", "", fn); next }
    /^ *[0-9a-f]+:\t/ && $2 ~ /^v/ { if (member != "" && fn != "" && !((member, fn) in seen)) { seen[member, fn] = 1; print member "\t" fn } }')
  bad=$(comm -12 <(printf '%s\n' "$weak" | sort -u) <(printf '%s\n' "$avx" | sort -u) | sed '/^$/d')
  if [ -n "$bad" ]; then
    echo "vector_symbols_lint: $lib exports weak functions compiled with AVX:"
    printf '%s\n' "$bad" | while IFS=$'\t' read -r member sym; do
      echo "  $member: $(printf '%s' "$sym" | c++filt)"
    done
    status=1
  fi
done
[ $status -eq 0 ] && echo "vector_symbols_lint: no weak function holds an AVX instruction in: $*"
exit $status
