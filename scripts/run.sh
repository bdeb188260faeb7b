#!/usr/bin/env bash
# Builds sinew (Release) and runs the main job on the built-in default rig.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh runtime
cmake --preset run >/dev/null
cmake --build --preset run -j "$(nproc)" --target sinew-run
exec build/run/host_tools/run/sinew-run "$@"
