#!/usr/bin/env bash
# A cross-built sinew package's daemon under qemu-user (scripts/test.sh): the
# package DIR/sinew_*_<arch>.deb is unpacked (dpkg-deb -x, not installed: the
# machine is another architecture) and its sinewd runs its own
# /etc/sinew/sinewd.toml for 2 s on the multiarch libraries of that
# architecture (scripts/install-deps.sh installs arm64's; qemu-user finds
# them in the host's multiarch paths when its own prefix is absent). Passes when it
# exits 0 with its final statistics line.
# Usage: scripts/lib/foreign-package-smoke.sh DIR
set -euo pipefail
dir="${1:?usage: foreign-package-smoke.sh DIR}"
deb="$(ls "$dir"/sinew_*.deb 2>/dev/null | sed -n 1p)"
[ -n "$deb" ] || { echo "foreign-package-smoke: no sinew_*.deb in $dir" >&2; exit 1; }
arch="$(dpkg-deb -f "$deb" Architecture)"
case "$arch" in
  arm64) emulator=qemu-aarch64-static ;;
  armhf) emulator=qemu-arm-static ;;
  *) echo "foreign-package-smoke: no emulator for $arch" >&2; exit 1 ;;
esac
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
dpkg-deb -x "$deb" "$work/root"
echo "foreign-package-smoke: $(basename "$deb") ($arch) under $emulator"
(cd "$work" && $emulator "$work/root/usr/bin/sinewd" --config "$work/root/etc/sinew/sinewd.toml" --duration 2) \
  >"$work/out" 2>&1 || { cat "$work/out"; echo "foreign-package-smoke: sinewd ($arch) failed" >&2; exit 1; }
{ grep -E '^(verdict|final tick)' "$work/out" || true; } | sed 's/^/  | /'
grep -qE '^final tick [0-9]+: step p50 ' "$work/out" || { cat "$work/out"; echo "foreign-package-smoke: no final statistics line" >&2; exit 1; }
echo "foreign-package-smoke: PASS ($arch sinewd under $emulator)"
