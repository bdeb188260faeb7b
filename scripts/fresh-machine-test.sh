#!/usr/bin/env bash
# Checks the README's first command on a brand-new Debian 12 machine: builds a
# minimal bookworm root (debootstrap --variant=minbase) from this machine's
# apt mirror, puts a clean clone of HEAD in it and runs
# `scripts/run.sh --duration 3` there under chroot. Passes when run.sh exits 0
# and sinewd printed its per-second statistics.
#
# Usage: scripts/fresh-machine-test.sh [--deps PROFILE | --packages DIR] [--skip-if-unsupported]
#   --deps PROFILE         instead of run.sh, run `scripts/install-deps.sh PROFILE`
#                          in the fresh root (e.g. `--deps test`)
#   --packages DIR         instead of run.sh, install the Debian packages in DIR
#                          (scripts/package.sh) there and check them
#                          (scripts/lib/package-smoke.sh)
#   --skip-if-unsupported  exit 0 with SKIP when not root, or when debootstrap,
#                          mount or chroot cannot work here (scripts/test.sh)
#
# Needs root (re-runs itself with sudo otherwise, except with
# --skip-if-unsupported). The debootstrap result is
# cached as a tarball in ${XDG_CACHE_HOME:-~/.cache}/sinew, keyed by suite and
# architecture, so only the first run downloads the base system; every run
# still downloads the packages install-deps.sh installs. Environment:
#   SINEW_FRESH_MIRROR   Debian mirror URL (default: the one apt uses here)
#   SINEW_FRESH_TIMEOUT  seconds allowed for the run in the root (default 1800)
#   SINEW_FRESH_REFRESH=1  rebuild the cached base root
set -euo pipefail

suite=bookworm
mode=run
deps_profile=""
packages_dir=""
skip_unsupported=0
while [ $# -gt 0 ]; do
  case "$1" in
    --deps) mode=deps; deps_profile="${2:?--deps needs a profile}"; shift 2 ;;
    --packages) mode=packages; packages_dir="$(cd "${2:?--packages needs a directory}" && pwd)"; shift 2 ;;
    --skip-if-unsupported) skip_unsupported=1; shift ;;
    *) echo "fresh-machine-test: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

fail() { echo "fresh-machine-test: FAIL: $*"; exit 1; }
unsupported() {
  if [ "$skip_unsupported" = 1 ]; then
    echo "fresh-machine-test: SKIP: $*"
    exit 0
  fi
  fail "$*"
}

if [ "$(id -u)" -ne 0 ]; then
  [ "$skip_unsupported" = 1 ] && unsupported "not root (run scripts/fresh-machine-test.sh as root)"
  if command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    exec sudo -n --preserve-env=SINEW_FRESH_MIRROR,SINEW_FRESH_TIMEOUT,SINEW_FRESH_REFRESH,XDG_CACHE_HOME \
      "$0" "$@"
  fi
  unsupported "needs root (chroot, mount, debootstrap) and passwordless sudo is not available"
fi

repo="$(cd "$(dirname "$0")/.." && pwd)"
head="$(git -C "$repo" rev-parse HEAD)"
if [ -n "$(git -C "$repo" status --porcelain --untracked-files=no)" ]; then
  echo "fresh-machine-test: note: uncommitted changes are not tested (the root gets a clone of HEAD $head)"
fi
arch="$(dpkg --print-architecture)"

# The Debian mirror this machine's apt uses for $suite: deb822 .sources files
# first, then one-line sources.list entries.
find_mirror() {
  local f
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    # Stanzas are separated by blank lines; keys are case-insensitive.
    awk -v suite="$suite" '
      function flush() {
        if (types ~ /(^| )deb( |$)/ && (" " suites " ") ~ (" " suite " ") && enabled != "no" && uri != "") {
          print uri; found = 1; exit
        }
        types = suites = uri = enabled = ""
      }
      /^[ \t]*$/ { flush(); next }
      /^#/ { next }
      {
        key = tolower($1); sub(/:$/, "", key); val = $0; sub(/^[^:]*:[ \t]*/, "", val)
        if (key == "types") types = val
        else if (key == "suites") suites = val
        else if (key == "uris") { split(val, u, /[ \t]+/); uri = u[1] }
        else if (key == "enabled") enabled = tolower(val)
      }
      END { if (!found) flush() }' "$f"
  done
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    # deb [options] URI SUITE COMPONENTS...
    sed -e 's/#.*//' -e 's/\[[^]]*\]//' "$f" | awk -v suite="$suite" '$1 == "deb" && $3 == suite { print $2 }'
  done
}
mirror="${SINEW_FRESH_MIRROR:-$(find_mirror | sed -n 1p)}"
mirror="${mirror%/}"
[ -n "$mirror" ] || unsupported "no apt source for '$suite' found in /etc/apt (set SINEW_FRESH_MIRROR)"

# Everything mounted or created below is undone on exit, pass or fail.
work_dirs=()
run_pid=""
cleanup() {
  local status=$? d proc_dir proc_root m
  if [ -n "${run_pid:-}" ]; then kill "$run_pid" 2>/dev/null || true; fi
  for d in "${work_dirs[@]}"; do
    [ -d "$d" ] || continue
    # Processes still running inside the root (e.g. after a timeout).
    for proc_dir in /proc/[0-9]*; do
      proc_root="$(readlink "$proc_dir/root" 2>/dev/null)" || continue
      if [ "$proc_root" = "$d" ] || [[ "$proc_root" == "$d"/* ]]; then
        kill -KILL "${proc_dir#/proc/}" 2>/dev/null || true
      fi
    done
    # Innermost mounts first.
    while read -r m; do
      umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || true
    done < <(awk -v d="$d" '$5 == d || index($5, d "/") == 1 { print $5 }' /proc/self/mountinfo | sort -r)
    if awk -v d="$d" '$5 == d || index($5, d "/") == 1 { found = 1 } END { exit !found }' /proc/self/mountinfo; then
      echo "fresh-machine-test: warning: could not unmount everything under $d; left in place" >&2
    else
      rm -rf --one-file-system "$d"
    fi
  done
  exit "$status"
}
trap cleanup EXIT
trap 'echo "fresh-machine-test: FAIL: interrupted"; exit 130' INT
trap 'echo "fresh-machine-test: FAIL: terminated"; exit 143' TERM

if ! command -v debootstrap >/dev/null; then
  echo "fresh-machine-test: installing debootstrap"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y -qq --no-install-recommends debootstrap >/dev/null 2>&1 ||
    { apt-get update -qq && apt-get install -y -qq --no-install-recommends debootstrap >/dev/null; } ||
    unsupported "could not install debootstrap with apt-get"
fi

cache_dir="${XDG_CACHE_HOME:-$HOME/.cache}/sinew"
tarball="$cache_dir/debootstrap-$suite-$arch-minbase.tar.gz"
mkdir -p "$cache_dir"
total_start=$SECONDS

if [ ! -s "$tarball" ] || [ "${SINEW_FRESH_REFRESH:-0}" = 1 ]; then
  echo "fresh-machine-test: debootstrap --variant=minbase $suite ($arch) from $mirror"
  start=$SECONDS
  stage="$(mktemp -d "$cache_dir/debootstrap.XXXXXX")"
  work_dirs+=("$stage")
  base="$stage/base"  # the new root's directory
  if ! debootstrap --variant=minbase --arch="$arch" "$suite" "$base" "$mirror" > "$stage.log" 2>&1; then
    tail -n 20 "$stage.log"
    rm -f "$stage.log"
    unsupported "debootstrap failed (log above)"
  fi
  rm -f "$stage.log"
  # debootstrap leaves its apt lists and .debs behind: a fresh machine has
  # neither, and install-deps.sh must do its own apt-get update.
  rm -rf "$base/var/lib/apt/lists/"* "$base/var/cache/apt/archives/"*.deb
  tar -C "$base" --numeric-owner -czf "$stage/base.tar.gz" .
  mv "$stage/base.tar.gz" "$tarball"
  rm -rf --one-file-system "$stage"
  echo "fresh-machine-test: base root cached in $tarball ($(du -h "$tarball" | cut -f1), $((SECONDS - start)) s)"
else
  echo "fresh-machine-test: cached base root $tarball"
fi

root="$(mktemp -d "${TMPDIR:-/tmp}/sinew-fresh.XXXXXX")"
work_dirs+=("$root")
tar -C "$root" --numeric-owner -xzf "$tarball"

# Device nodes the build and apt use (created by debootstrap, but recreated
# in case the tarball was made where mknod was not allowed); nothing of the
# host's /dev is mounted.
make_node() {
  local path="$root/dev/$1"
  [ -c "$path" ] && return 0
  rm -f "$path"
  mknod -m "$4" "$path" c "$2" "$3" || unsupported "cannot create device nodes (mknod $path)"
}
mkdir -p "$root/dev/pts" "$root/proc"
make_node null 1 3 666
make_node zero 1 5 666
make_node full 1 7 666
make_node random 1 8 666
make_node urandom 1 9 666
make_node tty 5 0 666
rm -f "$root/dev/ptmx"
ln -s pts/ptmx "$root/dev/ptmx"
mount -t proc proc "$root/proc" || unsupported "cannot mount proc in the root"
mount -t devpts -o newinstance,ptmxmode=0666,mode=620 devpts "$root/dev/pts" ||
  unsupported "cannot mount a new devpts instance in the root"
cp /etc/resolv.conf "$root/etc/resolv.conf"
chroot "$root" /bin/true || unsupported "chroot does not work here"

# A clean clone of HEAD (no build tree, nothing uncommitted).
git init -q "$root/src/sinew"
git -C "$root/src/sinew" fetch -q --depth 1 "file://$repo" "$head"
git -C "$root/src/sinew" checkout -q --detach FETCH_HEAD

if [ "$mode" = run ]; then
  command_in_root="scripts/run.sh --duration 3"
elif [ "$mode" = packages ]; then
  mkdir -p "$root/debs"
  cp "$packages_dir"/*.deb "$root/debs/" || fail "no .deb in $packages_dir"
  command_in_root="scripts/lib/package-smoke.sh /debs"
else
  command_in_root="scripts/install-deps.sh $deps_profile"
fi
echo "fresh-machine-test: running '$command_in_root' in a fresh $suite root (HEAD ${head:0:12})"
log="$root/fresh-machine-test.log"
start=$SECONDS
# In the background so that a signal to this script cleans up at once.
timeout --kill-after=10 "${SINEW_FRESH_TIMEOUT:-1800}" \
  chroot "$root" /usr/bin/env -i HOME=/root TERM=dumb LANG=C.UTF-8 \
  PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  /bin/bash -c "cd /src/sinew && $command_in_root" > "$log" 2>&1 < /dev/null &
run_pid=$!
status=0
wait "$run_pid" || status=$?
run_pid=""
elapsed=$((SECONDS - start))
cp "$log" "$cache_dir/fresh-machine-test.log"
echo "fresh-machine-test: '$command_in_root' exited with status $status after $elapsed s"
sed 's/^/  | /' "$log" | tail -n 40
echo "fresh-machine-test: full output in $cache_dir/fresh-machine-test.log"

if [ "$status" = 124 ] || [ "$status" = 137 ]; then
  fail "'$command_in_root' timed out after ${SINEW_FRESH_TIMEOUT:-1800} s"
fi
[ "$status" = 0 ] || fail "'$command_in_root' exited with status $status after $elapsed s (output above)"
if [ "$mode" = run ]; then
  # sinewd prints a statistics line every second and a final one.
  stats_re='^stats tick [0-9]+: step p50 [0-9.]+ us p99 [0-9.]+ us max [0-9.]+ us, deadline misses [0-9]+'
  n_stats="$(grep -cE "$stats_re" "$log" || true)"
  [ "$n_stats" -ge 2 ] || fail "run.sh exited 0 but sinewd printed $n_stats per-second statistics lines (expected at least 2)"
  grep -qE '^final tick [0-9]+: step p50 ' "$log" || fail "run.sh exited 0 but sinewd printed no final statistics line"
  echo "fresh-machine-test: PASS: scripts/run.sh built and ran sinewd in a fresh Debian $suite root" \
    "($n_stats statistics lines; run.sh $elapsed s, total $((SECONDS - total_start)) s)"
elif [ "$mode" = packages ]; then
  grep -q '^package-smoke: PASS' "$log" || fail "package-smoke.sh exited 0 without its PASS line"
  echo "fresh-machine-test: PASS: the packages installed, ran and served the consumers in a fresh Debian $suite root" \
    "(package-smoke $elapsed s, total $((SECONDS - total_start)) s)"
else
  echo "fresh-machine-test: PASS: scripts/install-deps.sh $deps_profile completed in a fresh Debian $suite root" \
    "(install-deps $elapsed s, total $((SECONDS - total_start)) s)"
fi
