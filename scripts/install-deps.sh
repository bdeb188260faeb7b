#!/usr/bin/env bash
# Installs the Debian 12 packages sinew needs, skipping those already present.
# Usage: scripts/install-deps.sh [runtime|test]
#   runtime: what building and running the main job needs
#   test:    everything the full test suite needs (cross toolchains, qemu-user, ...)
set -euo pipefail

profile="${1:-test}"

runtime_pkgs=(
  build-essential cmake ninja-build pkgconf git
  libtomlplusplus-dev libtinygltf-dev nlohmann-json3-dev libcli11-dev libxxhash-dev
  libgpiod-dev libmodbus-dev
)
test_pkgs=(
  "${runtime_pkgs[@]}"
  clang libgtest-dev googletest libbenchmark-dev librapidcheck-dev libeigen3-dev
  g++-aarch64-linux-gnu g++-arm-linux-gnueabihf qemu-user-static
  can-utils
)

case "$profile" in
  runtime) wanted=("${runtime_pkgs[@]}") ;;
  test) wanted=("${test_pkgs[@]}") ;;
  *) echo "install-deps: unknown profile '$profile' (runtime|test)" >&2; exit 2 ;;
esac

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
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
