#!/usr/bin/env bash
# Real-kernel tests: boots Debian's bookworm kernel (linux-image-6.1.0-*-amd64)
# under qemu-system-x86_64 (software emulation, no KVM) with a busybox
# initramfs, creates vcan0 and a gpio-sim chip, and runs sinew's SocketCAN
# and libgpiod tests there. Details and timings: docs/real-kernel-tests.md.
#
# Usage: scripts/kernel-test.sh [--build-dir DIR]
#   --build-dir DIR  take the test programs from an existing build configured
#                    with -DSINEW_KERNEL_TESTS=ON (ctest passes its own);
#                    default: configure and build build/kernel (Release).
#
# Everything downloaded or built once is kept under build/kernel-cache/<kernel>/
# (the kernel packages, the extracted headers, the out-of-tree gpio-sim.ko).
# qemu exits 0 even when the guest panics, so success is the PASS marker the
# guest prints on the serial console.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"

build_dir=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "kernel-test: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

start=$(date +%s.%N)
say() { printf 'kernel-test: %s\n' "$*"; }
die() { printf 'kernel-test: %s\n' "$*" >&2; exit 1; }

# --- host tools --------------------------------------------------------------
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
missing=()
for pair in qemu-system-x86_64:qemu-system-x86 cpio:cpio cansend:can-utils make:make gcc-12:gcc-12 xz:xz-utils; do
  command -v "${pair%%:*}" >/dev/null || missing+=("${pair#*:}")
done
dpkg-query -W -f='${Status}' busybox-static 2>/dev/null | grep -q "install ok installed" || missing+=(busybox-static)
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# --- the kernel: resolved at run time, since old ABI packages disappear -------
resolve_image() {
  apt-cache show --no-all-versions linux-image-amd64 2>/dev/null |
    sed -n 's/^Depends:.*\(linux-image-6\.1\.0-[0-9]*-amd64\).*/\1/p' | sed -n 1p
}
image_pkg=$(resolve_image)
if [ -z "$image_pkg" ]; then  # no package lists yet (fresh container)
  "${sudo_cmd[@]}" apt-get update -qq
  image_pkg=$(resolve_image)
fi
[ -n "$image_pkg" ] || die "cannot resolve a linux-image-6.1.0-*-amd64 package from linux-image-amd64 (is this Debian 12?)"
abi="${image_pkg#linux-image-}"                # e.g. 6.1.0-56-amd64
version=$(apt-cache show --no-all-versions "$image_pkg" | awk '/^Version:/ {print $2; exit}')
cache="$root/build/kernel-cache/$abi"
kroot="$cache/root"
headers="$kroot/usr/src/linux-headers-$abi"
say "kernel $abi ($version), cache ${cache#"$root"/}"

if [ ! -f "$cache/.fetched" ]; then
  say "downloading the kernel packages (once)"
  rm -rf "$cache" && mkdir -p "$cache/debs" "$kroot"
  (cd "$cache/debs" &&
    apt-get download -q "$image_pkg" "linux-headers-$abi" "linux-headers-${abi%-amd64}-common" \
      "linux-kbuild-6.1=$version" "linux-source-6.1=$version" 2>&1 | grep -v '^W: Download is performed unsandboxed' || true)
  for pkg in "$image_pkg" "linux-headers-$abi" "linux-headers-${abi%-amd64}-common" linux-kbuild-6.1 linux-source-6.1; do
    deb=$(ls "$cache/debs/${pkg}_"*.deb 2>/dev/null | sed -n 1p)
    [ -n "$deb" ] || die "apt-get download did not fetch $pkg"
    dpkg-deb -x "$deb" "$kroot"
  done
  # The headers' Makefile includes the common part by absolute path: point it into the cache.
  sed -i "s|^include /usr/src/|include $kroot/usr/src/|" "$headers/Makefile"
  mkdir -p "$cache/src"
  tar -xJf "$kroot/usr/src/linux-source-6.1.tar.xz" -C "$cache/src" --strip-components=1 \
    linux-source-6.1/drivers/gpio/gpio-sim.c linux-source-6.1/drivers/gpio/gpiolib.h \
    linux-source-6.1/kernel/irq/irq_sim.c
  rm -f "$kroot/usr/src/linux-source-6.1.tar.xz" "$cache/debs/"linux-source-6.1_*.deb
  touch "$cache/.fetched"
fi

# --- gpio-sim.ko out of tree ---------------------------------------------------
# Bookworm kernels do not build gpio-sim (nor the irq_sim helper it selects);
# both are built as modules against the headers. irq_sim.c calls
# handle_simple_irq(irq_to_desc(...)), and irq_to_desc is not exported to
# modules: generic_handle_irq_safe does the same through an exported call.
mod="$cache/mod"
if [ ! -f "$mod/gpio-sim.ko" ] || [ ! -f "$mod/irq_sim.ko" ]; then
  say "building gpio-sim.ko and irq_sim.ko (once)"
  rm -rf "$mod" && mkdir -p "$mod"
  cp "$cache/src/drivers/gpio/gpio-sim.c" "$cache/src/drivers/gpio/gpiolib.h" "$cache/src/kernel/irq/irq_sim.c" "$mod/"
  sed -i 's|handle_simple_irq(irq_to_desc(irqnum));|generic_handle_irq_safe(irqnum);|' "$mod/irq_sim.c"
  grep -q 'generic_handle_irq_safe(irqnum);' "$mod/irq_sim.c" || die "irq_sim.c: the line to patch was not found"
  printf '\n#include <linux/module.h>\nMODULE_LICENSE("GPL");\nMODULE_DESCRIPTION("interrupt simulator");\n' >>"$mod/irq_sim.c"
  echo 'obj-m += irq_sim.o gpio-sim.o' >"$mod/Kbuild"
  make -s -C "$headers" M="$mod" modules >"$mod/build.log" 2>&1 || { cat "$mod/build.log"; die "module build failed"; }
fi

# --- the test programs -------------------------------------------------------
if [ -z "$build_dir" ]; then
  build_dir="$root/build/kernel"
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSINEW_BENCH=OFF \
      -DSINEW_KERNEL_TESTS=ON >/dev/null
  fi
  cmake --build "$build_dir" --target can_tests can_kernel_tests gpio_kernel_tests -j2 >/dev/null
fi
programs=("$build_dir/tests/hal/can/can_tests" "$build_dir/tests/kernel/can_kernel_tests"
  "$build_dir/tests/kernel/gpio_kernel_tests")
for p in "${programs[@]}"; do [ -x "$p" ] || die "missing $p (configure $build_dir with -DSINEW_KERNEL_TESTS=ON)"; done

# --- initramfs ---------------------------------------------------------------
ird="$cache/initramfs"
rm -rf "$ird" && mkdir -p "$ird"/{bin,dev,proc,sys,tmp,lib/modules,sys/kernel/config}
cp /bin/busybox "$ird/bin/"
kmods="$kroot/lib/modules/$abi/kernel"
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko \
  fs/configfs/configfs.ko; do
  cp "$kmods/$m" "$ird/lib/modules/"
done
cp "$mod/irq_sim.ko" "$mod/gpio-sim.ko" "$ird/lib/modules/"
# Programs with the shared libraries they load (at the same paths).
copy_with_libs() {
  cp "$1" "$ird/bin/"
  ldd "$1" | grep -o '/[^ ]*' | while read -r lib; do
    mkdir -p "$ird$(dirname "$lib")"
    cp -L "$lib" "$ird$lib"
  done
}
for p in "${programs[@]}" "$(command -v cansend)" "$(command -v cangen)"; do copy_with_libs "$p"; done

cat >"$ird/init" <<'INIT'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
failed=0
result() { echo "KTEST $1 $2 $3"; [ "$2" = PASS ] || failed=1; }
for m in can can-raw can-dev vcan configfs irq_sim gpio-sim; do
  insmod /lib/modules/$m.ko || echo "insmod $m failed"
done
mount -t configfs none /sys/kernel/config
if ip link add dev vcan0 type vcan && ip link set vcan0 up; then result setup-vcan0 PASS; else result setup-vcan0 FAIL; fi
g=/sys/kernel/config/gpio-sim/sinew
if mkdir $g && mkdir $g/bank0 && echo 8 > $g/bank0/num_lines && echo 1 > $g/live; then
  export SINEW_GPIO_SIM_CHIP=$(cat $g/bank0/chip_name)
  export SINEW_GPIO_SIM_SYSFS=/sys/devices/platform/$(cat $g/dev_name)/$SINEW_GPIO_SIM_CHIP
  echo "gpio-sim: $SINEW_GPIO_SIM_CHIP at $SINEW_GPIO_SIM_SYSFS"
  result setup-gpio-sim PASS
else
  result setup-gpio-sim FAIL
fi
# A gtest program passes when it exits 0 and skipped nothing (here every
# test has what it needs).
gtest() {
  name=$1; shift
  t0=$(cut -d' ' -f1 /proc/uptime)
  "$@" > /tmp/out 2>&1; rc=$?
  t1=$(cut -d' ' -f1 /proc/uptime)
  cat /tmp/out
  if [ $rc -eq 0 ] && ! grep -q '^\[  SKIPPED \]' /tmp/out; then r=PASS; else r=FAIL; fi
  result "$name" $r "($(grep -c '^\[       OK \]' /tmp/out) ok, $(grep -c '^\[  FAILED  \] [A-Za-z]' /tmp/out) failed, $(grep -c '^\[  SKIPPED \]' /tmp/out) skipped; ${t0}s -> ${t1}s)"
}
gtest socketcan can_tests --gtest_filter='SocketCanSource.*:SocketCanWriter.*'
gtest can-kernel can_kernel_tests
gtest gpio-kernel gpio_kernel_tests
if [ $failed -eq 0 ]; then echo "SINEW-KERNEL-TESTS: PASS"; else echo "SINEW-KERNEL-TESTS: FAIL"; fi
poweroff -f
INIT
chmod +x "$ird/init"
(cd "$ird" && find . | cpio -o -H newc --quiet | gzip -1 >"$cache/initramfs.cpio.gz")

# --- boot --------------------------------------------------------------------
log="$cache/console.log"
say "booting $abi under qemu-system-x86_64 (TCG)"
boot_start=$(date +%s.%N)
timeout 900 qemu-system-x86_64 -accel tcg -m 1024 -smp 1 -display none -monitor none -serial stdio -no-reboot \
  -kernel "$kroot/boot/vmlinuz-$abi" -initrd "$cache/initramfs.cpio.gz" \
  -append "console=ttyS0 panic=-1 quiet" </dev/null >"$log" 2>&1 || true
end=$(date +%s.%N)
tr -d '\r' <"$log" | grep -aE '^(KTEST|gpio-sim:|\[  (FAILED|SKIPPED) |  cansend|cangen:|joint stream|down/up|gpio-sim encoder|limit via|sync:|overflow:|200 rounds)' || true
awk -v s="$start" -v b="$boot_start" -v e="$end" 'BEGIN { printf "kernel-test: VM %.1f s, total %.1f s\n", e - b, e - s }'
if tr -d '\r' <"$log" | grep -aq '^SINEW-KERNEL-TESTS: PASS'; then
  say "PASS"
else
  say "FAIL (no PASS marker; console log: ${log#"$root"/})"
  tail -n 40 "$log" >&2
  exit 1
fi
