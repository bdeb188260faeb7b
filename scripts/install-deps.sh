#!/usr/bin/env bash
# Installs the Debian 12 packages sinew needs, skipping those already present.
# Usage: scripts/install-deps.sh [runtime|test]
#   runtime: what building and running the main job needs
#   test:    everything the full test suite needs (cross toolchains, qemu-user,
#            and the arm64 builds of the firmware's libraries for the aarch64
#            preset, which adds arm64 as a dpkg foreign architecture; node and
#            npm for the viewer and the glTF validator when no nodejs package is
#            installed)
set -euo pipefail

profile="${1:-test}"

runtime_pkgs=(
  build-essential cmake ninja-build pkgconf git
  libtomlplusplus-dev libtinygltf-dev nlohmann-json3-dev libcli11-dev libxxhash-dev
  libgpiod-dev libmodbus-dev libzstd-dev libsystemd-dev
  # ROS 2 over DDS: Cyclone DDS, and idlc to generate the message types at build time
  cyclonedds-dev cyclonedds-tools
)
test_pkgs=(
  "${runtime_pkgs[@]}"
  clang clang-format libgtest-dev googletest libbenchmark-dev librapidcheck-dev libeigen3-dev
  g++-aarch64-linux-gnu g++-arm-linux-gnueabihf qemu-user-static
  can-utils
  # the builds compile through ccache when it is present (cmake/sinew_options.cmake)
  ccache
  debootstrap
  # the Debian packages (scripts/package.sh: dpkg-shlibdeps, lintian) and the
  # instruction counts per stage (scripts/callgrind-stages.sh)
  dpkg-dev lintian help2man valgrind
  # sinew-view and its browser tests (host only: the board needs none of it)
  libcivetweb-dev chromium
)
# The aarch64 preset cross-builds hal/ and the firmware: their libraries as
# arm64 multiarch packages, pkgconf:arm64 for aarch64-linux-gnu-pkg-config, and
# the arm64 C and C++ runtime its tests run on under qemu-user.
# (No armhf equivalent: the armhf preset builds sim_core only.)
cross_arm64_pkgs=(
  libgpiod-dev:arm64 libmodbus-dev:arm64 libtomlplusplus-dev:arm64 libzstd-dev:arm64 pkgconf:arm64
  libc6:arm64 libstdc++6:arm64
  # sd_notify in the arm64 sinewd: the package's service has its watchdog on a board too
  libsystemd-dev:arm64
)

case "$profile" in
  runtime) wanted=("${runtime_pkgs[@]}") ;;
  test) wanted=("${test_pkgs[@]}" "${cross_arm64_pkgs[@]}") ;;
  *) echo "install-deps: unknown profile '$profile' (runtime|test)" >&2; exit 2 ;;
esac

# Node and npm for the viewer's page (three.js from its lockfile), its browser
# tests' probe and the Khronos glTF validator of the export tests
# (tests/host_tools/export): Debian's nodejs and npm, only when no nodejs package is
# installed (another repository's nodejs ships its own npm, which Debian's npm
# package would conflict with), and npm alone when a nodejs has no npm.
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
if [ "$profile" = test ]; then
  if ! installed nodejs; then
    wanted+=(nodejs npm)
  elif ! installed npm && ! dpkg -S "$(command -v npm 2>/dev/null || echo /nonexistent)" >/dev/null 2>&1; then
    wanted+=(npm)
  fi
fi

missing=()
for p in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
if [[ " ${missing[*]}" == *:arm64* ]] &&
   [ "$(dpkg --print-architecture)" != arm64 ] &&
   ! dpkg --print-foreign-architectures | grep -qx arm64; then
  echo "install-deps: adding arm64 as a foreign architecture"
  "${sudo_cmd[@]}" dpkg --add-architecture arm64
fi
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
