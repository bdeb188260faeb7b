#!/usr/bin/env bash
# Opt-in fuzz campaign: each libFuzzer target for SECONDS (default 600) in the
# clang build, keeping what it finds in build/clang/tests/fuzz/corpus/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
scripts/install-deps.sh test
cmake --preset clang >/dev/null
cmake --build --preset clang -j "$(nproc)" --target candump_parser_fuzz can_frame_decoder_fuzz config_parser_fuzz
for t in candump:candump_parser_fuzz can_frame:can_frame_decoder_fuzz config:config_parser_fuzz; do
  corpus="${t%%:*}" target="${t##*:}"
  mkdir -p "build/clang/tests/fuzz/corpus/$corpus"
  "build/clang/tests/fuzz/$target" -max_total_time="$seconds" -max_len=4096 \
    "build/clang/tests/fuzz/corpus/$corpus" "tests/fuzz/corpus/$corpus"
done
