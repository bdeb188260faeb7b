#!/usr/bin/env bash
# Opt-in: the sinew package as a service under systemd as PID 1, in a virtual
# machine (Debian 12's kernel under qemu-system-x86_64, software emulation),
# and systemd's watchdog restarting a hung daemon (docs/service.md).
#
#   1. A fresh bookworm root (debootstrap --variant=minbase, cached as by
#      scripts/fresh-machine-test.sh) gets linux-image-amd64, systemd-sysv and
#      the amd64 sinew package (scripts/package.sh), sinewd.service enabled.
#   2. Booted from an ext4 image made of that root. A one-shot unit waits
#      until sinewd is active and has sent WATCHDOG=1, stops it with SIGSTOP
#      (its tick loop hangs: no more WATCHDOG=1), and waits, bounded, for
#      systemd to kill it and start a new main process that is active again.
#   3. The guest prints the journal of sinewd.service and a PASS or FAIL
#      marker on the serial console, then powers off.
# Passes only on the PASS marker, which the guest prints when the journal shows
# the watchdog timeout after the SIGSTOP, the restart, and a new process.
#
# Usage: scripts/service-vm-test.sh [--packages DIR]
#   --packages DIR  the .deb files (default build/release/packages; built
#                   with scripts/package.sh when missing)
# Needs root (debootstrap, chroot, mkfs.ext4 -d with owners) and apt access.
# The guest config runs the built-in arm at 100 Hz with plain skinning, so that
# the emulated machine keeps its ticks (the watchdog is the subject, not speed).
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$PWD"
packages="$repo/build/release/packages"
while [ $# -gt 0 ]; do
  case "$1" in
    --packages) packages="$(cd "${2:?--packages needs a directory}" && pwd)"; shift 2 ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    *) echo "service-vm-test: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
say() { printf 'service-vm-test: %s\n' "$*"; }
die() { printf 'service-vm-test: FAIL: %s\n' "$*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot, mkfs.ext4 -d)"
start=$SECONDS

missing=()
for pair in qemu-system-x86_64:qemu-system-x86 debootstrap:debootstrap mkfs.ext4:e2fsprogs; do
  command -v "${pair%%:*}" >/dev/null || missing+=("${pair#*:}")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; }
fi
if ! ls "$packages"/sinew_*_amd64.deb >/dev/null 2>&1; then
  say "no sinew_*_amd64.deb in $packages: building the packages"
  scripts/package.sh --preset release
  packages="$repo/build/release/packages"
fi
deb="$(ls "$packages"/sinew_*_amd64.deb | sed -n 1p)"

# --- the root ------------------------------------------------------------------
cache_dir="${XDG_CACHE_HOME:-$HOME/.cache}/sinew"
tarball="$cache_dir/debootstrap-bookworm-amd64-minbase.tar.gz"
mirror="${SINEW_FRESH_MIRROR:-}"
if [ -z "$mirror" ]; then
  mirror="$(sed -n 's/^URIs:[ \t]*\([^ \t]*\).*/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | sed -n 1p)"
  [ -n "$mirror" ] || mirror="$(awk '$1 == "deb" && $3 == "bookworm" { print $2; exit }' /etc/apt/sources.list 2>/dev/null)"
fi
work="$(mktemp -d "${TMPDIR:-/tmp}/sinew-vm.XXXXXX")"
root="$work/root"
cleanup() {
  for m in "$root/dev/pts" "$root/proc" "$root/sys"; do umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || true; done
  rm -rf --one-file-system "$work"
}
trap cleanup EXIT
mkdir -p "$cache_dir" "$root"
if [ ! -s "$tarball" ]; then
  say "debootstrap --variant=minbase bookworm from $mirror"
  debootstrap --variant=minbase bookworm "$work/base" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -n 20 "$work/debootstrap.log"; die "debootstrap failed"; }
  rm -rf "$work/base/var/lib/apt/lists/"* "$work/base/var/cache/apt/archives/"*.deb
  tar -C "$work/base" --numeric-owner -czf "$tarball" . && rm -rf "$work/base"
fi
tar -C "$root" --numeric-owner -xzf "$tarball"
mount -t proc proc "$root/proc"
mount -t sysfs sys "$root/sys"
mkdir -p "$root/dev/pts" && mount -t devpts -o newinstance devpts "$root/dev/pts"
cp /etc/resolv.conf "$root/etc/resolv.conf"
cp "$deb" "$root/tmp/"
in_root() { chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive "$@"; }
say "installing linux-image-amd64, systemd-sysv and $(basename "$deb") in the root"
in_root apt-get update -qq
in_root apt-get install -y -qq --no-install-recommends linux-image-amd64 initramfs-tools systemd-sysv \
  "/tmp/$(basename "$deb")" >"$work/apt.log" 2>&1 || { tail -n 30 "$work/apt.log"; die "apt-get install in the root failed"; }
kernel="$(ls "$root"/boot/vmlinuz-* | sed -n 1p)"
initrd="$(ls "$root"/boot/initrd.img-* | sed -n 1p)"
[ -f "$kernel" ] && [ -f "$initrd" ] || die "no kernel or initramfs in the root's /boot"

# The guest's configuration: the default one, lighter (see above).
sed -e 's/^rate_hz = .*/rate_hz = 100/' -e 's/^metaballs = true/metaballs = false/' \
  -e 's/^barnet = true/barnet = false/' "$root/etc/sinew/sinewd.toml" >"$root/etc/sinew/sinewd.toml.vm"
mv "$root/etc/sinew/sinewd.toml.vm" "$root/etc/sinew/sinewd.toml"
echo "/dev/vda / ext4 defaults 0 1" >"$root/etc/fstab"
echo sinew-vm >"$root/etc/hostname"
in_root systemctl enable sinewd.service >/dev/null 2>&1
cat >"$root/usr/local/sbin/sinew-watchdog-test" <<'GUEST'
#!/bin/bash
# In the guest: hang sinewd with SIGSTOP and watch systemd's watchdog restart it.
say() { echo "WDTEST $*"; }
verdict() {
  say "journal of sinewd.service:"
  journalctl -b -u sinewd.service -o short-monotonic --no-pager | sed 's/^/WDJOURNAL /'
  echo "SINEW-WATCHDOG-TEST: $1"
  systemctl --no-block poweroff
  exit 0
}
uptime_s() { cut -d' ' -f1 /proc/uptime | cut -d. -f1; }
# Active, with a main process that has pinged the watchdog at least once
# (bounded by the guest's clock: systemctl itself is slow under emulation).
deadline=$(($(uptime_s) + 300))
while [ "$(uptime_s)" -lt "$deadline" ]; do
  if [ "$(systemctl show -p ActiveState --value sinewd)" = active ] &&
     [ -n "$(systemctl show -p WatchdogTimestampMonotonic --value sinewd | grep -v '^0$')" ]; then break; fi
  sleep 0.5
done
[ "$(systemctl show -p ActiveState --value sinewd)" = active ] || { say "sinewd did not become active"; verdict FAIL; }
[ "$(systemctl show -p WatchdogTimestampMonotonic --value sinewd)" != 0 ] ||
  { say "sinewd is active but has not pinged systemd's watchdog (WatchdogUSec $(systemctl show -p WatchdogUSec --value sinewd))"; verdict FAIL; }
pid="$(systemctl show -p MainPID --value sinewd)"
restarts0="$(systemctl show -p NRestarts --value sinewd)"
say "sinewd active, main pid $pid, WatchdogUSec $(systemctl show -p WatchdogUSec --value sinewd), restarts $restarts0"
cursor="$(journalctl -u sinewd.service -n 0 --show-cursor --no-pager | sed -n 's/^-- cursor: //p')"
t0="$(cut -d' ' -f1 /proc/uptime)"
kill -STOP "$pid"
say "SIGSTOP to $pid at uptime $t0 s"
deadline=$(($(uptime_s) + 120))
while [ "$(uptime_s)" -lt "$deadline" ]; do
  now="$(systemctl show -p MainPID --value sinewd)"
  if [ "$now" != "$pid" ] && [ "$now" != 0 ] && [ "$(systemctl show -p ActiveState --value sinewd)" = active ]; then
    t1="$(cut -d' ' -f1 /proc/uptime)"
    say "new main pid $now active at uptime $t1 s ($(awk -v a="$t1" -v b="$t0" 'BEGIN { printf "%.1f", a - b }') s after SIGSTOP), restarts $(systemctl show -p NRestarts --value sinewd)"
    # After the SIGSTOP: systemd's watchdog fired, killed the process, restarted the unit.
    after="$(journalctl -u sinewd.service --after-cursor="$cursor" --no-pager)"
    if grep -q 'Watchdog timeout' <<<"$after" && grep -q "Killing process $pid " <<<"$after" &&
       grep -q 'Scheduled restart job' <<<"$after"; then verdict PASS; fi
    say "restarted, but the journal after the SIGSTOP shows no watchdog timeout, kill and restart"
    verdict FAIL
  fi
  sleep 0.25
done
say "no restart within 120 s of the SIGSTOP"
verdict FAIL
GUEST
chmod 755 "$root/usr/local/sbin/sinew-watchdog-test"
cat >"$root/etc/systemd/system/sinew-watchdog-test.service" <<'UNIT'
[Unit]
Description=sinew: hang sinewd and watch the watchdog restart it
After=sinewd.service
Wants=sinewd.service
[Service]
Type=oneshot
ExecStart=/usr/local/sbin/sinew-watchdog-test
StandardOutput=journal+console
StandardError=journal+console
[Install]
WantedBy=multi-user.target
UNIT
in_root systemctl enable sinew-watchdog-test.service >/dev/null 2>&1
in_root systemctl mask getty@tty1.service serial-getty@ttyS0.service >/dev/null 2>&1 || true
cp "$kernel" "$work/vmlinuz"
cp "$initrd" "$work/initrd.img"
for m in "$root/dev/pts" "$root/proc" "$root/sys"; do umount "$m"; done
rm -f "$root/etc/resolv.conf" "$root/tmp/"*.deb
say "making the ext4 image ($(du -sh "$root" | cut -f1))"
mkfs.ext4 -q -F -L sinew-vm -d "$root" "$work/root.img" 3G

log="$work/console.log"
say "booting $(basename "$kernel") under qemu-system-x86_64 (TCG) with systemd as PID 1"
boot=$SECONDS
timeout 1500 qemu-system-x86_64 -accel tcg -m 2048 -smp 2 -display none -monitor none -serial stdio -no-reboot \
  -kernel "$work/vmlinuz" -initrd "$work/initrd.img" \
  -append "root=/dev/vda rw console=ttyS0 panic=-1 systemd.show_status=0 quiet" \
  -drive "file=$work/root.img,format=raw,if=virtio" -nic none </dev/null >"$log" 2>&1 || true
mkdir -p "$repo/build"
tr -d '\r' <"$log" >"$repo/build/service-vm-console.log"
# The test unit's lines reach the console through the journal, as
# "[uptime] sinew-watchdog-test[pid]: LINE".
guest='^\[ *[0-9.]+\] sinew-watchdog-test\[[0-9]+\]: '
{ grep -aE "${guest}(WDTEST|WDJOURNAL|SINEW-WATCHDOG-TEST)" "$repo/build/service-vm-console.log" || true; } |
  sed -E -e "s/${guest}//" -e 's/^WDJOURNAL /  journal | /'
say "VM $((SECONDS - boot)) s, total $((SECONDS - start)) s; console log build/service-vm-console.log"
grep -aqE "${guest}SINEW-WATCHDOG-TEST: PASS" "$repo/build/service-vm-console.log" || die "no PASS marker (see the console log)"
say PASS
