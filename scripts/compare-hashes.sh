#!/usr/bin/env bash
# Fails unless every build printed the same hash for every workload.
# Input lines: "<build> determinism-hash <workload> <hex>".
set -euo pipefail
log="$1"
[ -s "$log" ] || { echo "compare-hashes: no determinism lines in $log" >&2; exit 1; }
builds=$(awk '{print $1}' "$log" | sort -u | wc -l)
bad=0
for w in $(awk '{print $3}' "$log" | sort -u); do
  distinct=$(awk -v w="$w" '$3 == w {print $4}' "$log" | sort -u | wc -l)
  seen=$(awk -v w="$w" '$3 == w {print $1}' "$log" | sort -u | wc -l)
  if [ "$distinct" -ne 1 ] || [ "$seen" -ne "$builds" ]; then
    echo "compare-hashes: workload '$w' differs across builds (or is missing from one)" >&2
    bad=1
  else
    echo "compare-hashes: $w identical in $builds builds"
  fi
done
exit $bad
