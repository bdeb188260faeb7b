#!/usr/bin/env bash
# Refreshes firmware/builtin/builtin_rigs.tar.zst, the built-in rigs' blobs
# the firmware embeds, from this tree's rig compiler:
#
#   scripts/update-builtin-rigs.sh [PRESET]     (default: release)
#
# builds sinew-builtin-rig in PRESET, compiles the arm and the hand, and packs
# the two blobs (names sorted, times and owners zeroed, so the archive is the
# same for the same blobs). Run it when a change to the rig compiler or a
# layer builder changes a blob: BuiltinRigs.CheckedInBlobsAreTheCompilersOutput
# fails until then. A blob change is a numerics change: commit it with the
# golden hashes it moves.
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" --target sinew_compiled_builtin_rigs
compiled="build/$preset/rigs-compiled"
out="$PWD/firmware/builtin/builtin_rigs.tar.zst"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$compiled/arm.rig" "$compiled/hand.rig" "$work/"
(cd "$work" && cmake -E tar cf "$out" --zstd "--mtime=1970-01-01 00:00:00 UTC" arm.rig hand.rig)
echo "update-builtin-rigs: wrote firmware/builtin/builtin_rigs.tar.zst ($(stat -c %s "$out") bytes)"
sha256sum "$compiled/arm.rig" "$compiled/hand.rig"
