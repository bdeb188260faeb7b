#!/usr/bin/env bash
# The amd64 packages on a brand-new Debian 12 root: run there by
# scripts/fresh-machine-test.sh --packages DIR (as root, from a clean clone,
# with the .deb files in DEBS). Checks, in order:
#   1. `apt-get install ./sinew_*.deb` pulls in what sinewd needs: it runs the
#      default configuration (/etc/sinew/sinewd.toml, a conffile) for 2 s;
#      the user sinew exists and the unit is in /lib/systemd/system;
#   2. systemd-analyze verifies the unit and rates it (printed);
#   3. sinew-tools compiles the built-in arm, and libsinew-dev serves the
#      consumer project (C, C++, C++ with hal; find_package) and cc with
#      pkg-config: all four print the same line;
#   4. purging sinew removes its conffile and its state directory.
# Prints "package-smoke: PASS" at the end; any failure exits non-zero.
set -euo pipefail
debs="${1:?usage: package-smoke.sh DEBS}"
say() { echo "package-smoke: $*"; }
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt_install() { apt-get install -y -qq --no-install-recommends "$@" >/tmp/apt.log 2>&1 || { cat /tmp/apt.log; exit 1; }; }

say "1. apt-get install $(basename "$debs"/sinew_*.deb)"
apt_install "$debs"/sinew_*.deb
dpkg-query -W -f='${Conffiles}\n' sinew | grep -q '/etc/sinew/sinewd.toml' || { say "/etc/sinew/sinewd.toml is not a conffile"; exit 1; }
getent passwd sinew >/dev/null || { say "no user sinew after installation"; exit 1; }
[ -f /lib/systemd/system/sinewd.service ] || { say "no /lib/systemd/system/sinewd.service"; exit 1; }
[ -f /usr/share/man/man1/sinewd.1.gz ] || { say "no manual page /usr/share/man/man1/sinewd.1.gz"; exit 1; }
say "sinewd --config /etc/sinew/sinewd.toml --duration 2"
(cd /tmp && sinewd --config /etc/sinew/sinewd.toml --duration 2) >/tmp/sinewd.out 2>&1 ||
  { cat /tmp/sinewd.out; say "the installed sinewd failed"; exit 1; }
{ grep -E '^(verdict|final tick)' /tmp/sinewd.out || true; } | sed 's/^/  | /'
grep -qE '^final tick [0-9]+: step p50 ' /tmp/sinewd.out || { cat /tmp/sinewd.out; say "no final statistics line"; exit 1; }

say "2. systemd-analyze verify and security"
apt_install systemd
systemd-analyze verify /lib/systemd/system/sinewd.service
systemd-analyze security --offline=yes /lib/systemd/system/sinewd.service | tail -n 1 | sed 's/^/  | /'

say "3. sinew-tools and libsinew-dev: rigc, the consumers"
apt_install "$debs"/sinew-tools_*.deb "$debs"/libsinew-dev_*.deb g++ cmake make pkgconf
rigc rigs/arm.toml -o /tmp/arm.rig >/tmp/rigc.out 2>&1 || { cat /tmp/rigc.out; exit 1; }
src=tests/sim_core/capi/consumer
cmake -S "$src" -B /tmp/consumer -DCMAKE_BUILD_TYPE=Release >/tmp/consumer.log 2>&1 &&
  cmake --build /tmp/consumer >>/tmp/consumer.log 2>&1 || { cat /tmp/consumer.log; exit 1; }
# shellcheck disable=SC2046
cc -O2 "$src/consumer.c" $(pkg-config --cflags --libs sinew) -o /tmp/consumer_pkgconfig
lines=()
lines+=("$(/tmp/consumer/consumer_c /tmp/arm.rig)")
lines+=("$(/tmp/consumer/consumer_cpp /tmp/arm.rig)")
lines+=("$(/tmp/consumer/consumer_hal /tmp/arm.rig /tmp/consumer_hal.log)")
lines+=("$(/tmp/consumer_pkgconfig /tmp/arm.rig)")
printf '  | %s\n' "${lines[@]}"
for l in "${lines[@]}"; do
  [ "$l" = "${lines[0]}" ] || { say "the consumers disagree"; exit 1; }
done
[[ "${lines[0]}" == *"moved 1"* ]] || { say "the skin did not move"; exit 1; }

say "4. apt-get purge sinew"
apt-get purge -y -qq sinew >/tmp/apt.log 2>&1 || { cat /tmp/apt.log; exit 1; }
[ ! -e /etc/sinew/sinewd.toml ] || { say "purge left /etc/sinew/sinewd.toml"; exit 1; }
[ ! -e /usr/bin/sinewd ] || { say "purge left /usr/bin/sinewd"; exit 1; }
say PASS
