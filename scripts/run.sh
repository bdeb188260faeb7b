#!/usr/bin/env bash
# Builds sinew (Release) and runs the main job: the runtime daemon on the
# built-in arm rig, fed by the simulated rig's motion, printing live statistics.
# Extra arguments go to sinewd (e.g. --duration 0 to run until Ctrl-C).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh runtime
cmake --preset run >/dev/null
cmake --build --preset run -j "$(nproc)" --target sinewd
exec build/run/firmware/sinewd --config firmware/config/default.toml "$@"
