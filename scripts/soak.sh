#!/usr/bin/env bash
# Opt-in long runs: every test's soak form (SINEW_SOAK=1) in the release build.
# Not part of CI; takes tens of minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh test
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
SINEW_SOAK=1 ctest --preset release -j "$(nproc)" --output-on-failure --timeout 7200 "$@"
