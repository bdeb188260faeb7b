#!/usr/bin/env bash
# Builds sinew's Debian packages from a preset's build tree with CPack and
# checks them with lintian (cmake/sinew_package.cmake, docs/packaging.md):
#   release  -> sinew, sinew-tools and libsinew-dev for amd64
#   aarch64  -> sinew and libsinew-dev for arm64 (no host tools there)
#   armhf    -> libsinew-dev (the core alone) for armhf
# The packages land in build/<preset>/packages. The tree is configured with
# the Debian layout (SINEW_DEBIAN_LAYOUT=ON, prefix /usr) for the packaging
# and given back its own settings afterwards; objects are not rebuilt (the
# layout changes install rules only).
#
# Usage: scripts/package.sh [--preset NAME] [--no-build] [--no-lintian]
#   --no-build    the tree is already built (CI)
#   --no-lintian  skip the lintian check
# Fails when a package cannot be built or lintian reports an error (E:);
# its warnings are printed.
set -euo pipefail
cd "$(dirname "$0")/.."

preset=release
build=1
check=1
while [ $# -gt 0 ]; do
  case "$1" in
    --preset) preset="${2:?--preset needs a name}"; shift 2 ;;
    --no-build) build=0; shift ;;
    --no-lintian) check=0; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "package: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
tree="build/$preset"
say() { printf 'package: %s\n' "$*"; }

missing=()
command -v dpkg-shlibdeps >/dev/null || missing+=(dpkg-dev)
command -v help2man >/dev/null || missing+=(help2man)
[ "$check" = 0 ] || command -v lintian >/dev/null || missing+=(lintian)
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    { "${sudo_cmd[@]}" apt-get update -qq && "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }
fi

if [ ! -f "$tree/CMakeCache.txt" ]; then
  [ "$build" = 1 ] || { echo "package: $tree is not configured (drop --no-build)" >&2; exit 1; }
  cmake --preset "$preset" >/dev/null
fi
old_prefix="$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$tree/CMakeCache.txt")"
restore() { cmake -S . -B "$tree" -DSINEW_DEBIAN_LAYOUT=OFF "-DCMAKE_INSTALL_PREFIX=${old_prefix:-/usr/local}" >/dev/null; }
trap restore EXIT
cmake -S . -B "$tree" -DSINEW_DEBIAN_LAYOUT=ON -DCMAKE_INSTALL_PREFIX=/usr >/dev/null
if [ "$build" = 1 ]; then
  cmake --build "$tree" -j "$(nproc)"
fi

# Manual pages for the programs the packages hold (cmake/sinew_package.cmake
# lists them): help2man from each one's --help, run by name (so the page
# shows no build path), under qemu-user for a cross-built program.
rm -rf "$tree/man" && mkdir -p "$tree/man"
version="$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$tree/CMakeCache.txt")"
# The pages' date is the release's (its changelog entry), not today's.
SOURCE_DATE_EPOCH="$(dpkg-parsechangelog -l packaging/debian/changelog -S Timestamp)"
export SOURCE_DATE_EPOCH
wrappers="$(mktemp -d)"
while IFS='=' read -r prog path; do
  [ -n "$prog" ] && [ -x "$path" ] || continue
  case "$(readelf -h "$path" | sed -n 's/^ *Machine: *//p')" in
    AArch64) emulator="qemu-aarch64-static -L /" ;;
    ARM) emulator="qemu-arm-static -L /" ;;
    *) emulator="" ;;
  esac
  printf '#!/bin/sh\nexec %s "%s" "$@"\n' "$emulator" "$path" >"$wrappers/$prog"
  chmod +x "$wrappers/$prog"
  # The summary is the first line of --help after "<program>: ", when it has one.
  summary="$(PATH="$wrappers:$PATH" "$prog" --help 2>&1 | sed -n "1s/^$prog: //p")"
  PATH="$wrappers:$PATH" help2man --no-info --section=1 --version-string="$version" \
    --name="${summary:-part of sinew, the deterministic rig runtime}" "$prog" | gzip -9n >"$tree/man/$prog.1.gz"
done <"$tree/debian/man-programs.txt"
rm -rf "$wrappers"

rm -rf "$tree/packages"
(cd "$tree" && cpack --config CPackConfig.cmake >cpack.log 2>&1) || { cat "$tree/cpack.log"; exit 1; }
mapfile -t debs < <(ls "$tree"/packages/*.deb)
[ ${#debs[@]} -gt 0 ] || { cat "$tree/cpack.log"; echo "package: cpack made no package" >&2; exit 1; }
for deb in "${debs[@]}"; do
  say "$(basename "$deb"): $(du -h "$deb" | cut -f1), $(dpkg-deb -f "$deb" Depends)"
done

if [ "$check" = 1 ]; then
  # Errors fail; warnings and information are shown. The packages are built
  # by CPack, not from a Debian source package, so the source-side checks
  # (debian/ directory, upload) do not apply.
  status=0
  lintian --tag-display-limit 0 --fail-on error "${debs[@]}" >"$tree/lintian.log" 2>&1 || status=$?
  sed 's/^/  lintian | /' "$tree/lintian.log"
  errors=$(grep -c '^E:' "$tree/lintian.log" || true)
  warnings=$(grep -c '^W:' "$tree/lintian.log" || true)
  if [ "$status" -ne 0 ] || [ "$errors" -gt 0 ]; then
    echo "package: lintian reported $errors errors (exit $status)" >&2
    exit 1
  fi
  say "lintian: 0 errors, $warnings warnings (${#debs[@]} packages)"
fi
say "packages in $tree/packages"
