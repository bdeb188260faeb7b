#!/usr/bin/env bash
# The daemon soak: the default job (built-in arm, metaballs and bar-net on,
# live at 1 kHz, the simulated rig over CAN and Modbus) for MINUTES, with
# every fault kind cycling on its own input, a recording sink and a UDP sink
# with sinew-receive checking the stream. Reports RSS at start and end,
# frames lost, skipped ticks, deadline misses, step p50/p99/max and the
# per-fault counters; fails when a frame is lost anywhere, the recording is
# not intact, or RSS grows.
#
#   scripts/soak-daemon.sh [MINUTES] [--build-dir DIR] [--realtime] [--smoke]
#
# --realtime runs the tick thread SCHED_FIFO 80 and the sinks' I/O threads
# SCHED_FIFO 40 with memory locked, as on a board (needs root or
# CAP_SYS_NICE and CAP_IPC_LOCK; what was applied is in the output). With
# two or more CPUs it also pins the tick thread to the last CPU and the I/O
# threads and the receiver to CPU 0, and the I/O threads poll their rings
# every 500 us (io_poll_us), so the tick makes no system call for output.
# The receiver runs SCHED_FIFO 30 when permitted.
#
# MINUTES defaults to 60 (opt-in; not in CI). The release build's test suite
# runs a 2-minute form (soak_daemon_smoke) with --build-dir, which skips the
# install and build steps, and --smoke, which makes it pass on any machine
# under any load (docs/testing.md): the sinks' rings hold 2 s of frames, the
# receiver waits 20 s for a late start, and UDP datagrams that a busy
# machine's loopback drops (and the daemon's exit status 1 for them) are
# reported, not failed. Everything else is still failed: a crash, a
# recording that is damaged or misses a tick, no datagram at all, RSS growth.
set -euo pipefail
cd "$(dirname "$0")/.."

minutes=60
build_dir=""
smoke=0
realtime=""
receiver_prefix=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --smoke) smoke=1; shift ;;
    --realtime)
      realtime=$'[realtime]\nfifo_priority = 80\nio_fifo_priority = 40\nlock_memory = true\nio_poll_us = 500'
      cpus="$(nproc)"
      if [ "$cpus" -ge 2 ]; then
        realtime+=$'\n'"cpu = $((cpus - 1))"$'\nio_cpu = 0'
        receiver_prefix=(taskset -c 0)
        if chrt -f 30 true 2>/dev/null; then receiver_prefix+=(chrt -f 30); fi
      fi
      shift ;;
    *) minutes="$1"; shift ;;
  esac
done
case "$minutes" in
  ''|*[!0-9.]*) echo "soak-daemon: MINUTES must be a number, not '$minutes'" >&2; exit 2 ;;
esac

if [ -z "$build_dir" ]; then
  scripts/install-deps.sh test
  cmake --preset release >/dev/null
  cmake --build --preset release -j "$(nproc)" --target sinewd sinew-receive sinew-log
  build_dir=build/release
fi
sinewd="$build_dir/firmware/sinewd"
receive="$build_dir/host_tools/receiver/sinew-receive"
sinew_log="$build_dir/host_tools/log/sinew-log"
for exe in "$sinewd" "$receive" "$sinew_log"; do
  [ -x "$exe" ] || { echo "soak-daemon: $exe is not built" >&2; exit 2; }
done

work="$(mktemp -d "${TMPDIR:-/tmp}/sinew-soak.XXXXXX")"
trap 'kill "${receiver_pid:-}" 2>/dev/null || true; rm -rf "$work"' EXIT
seconds="$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }')"
# Ports from the process id, so two soaks (or a soak and the tests) do not meet.
udp_port=$((30000 + $$ % 10000))
modbus_port=$((40000 + $$ % 10000))

# Every 10 s, each fault kind for 0.3 s (one a second) on its own input (bus-off and the
# Modbus faults act on the whole bus or link).
faults() {
  local t=0 kinds=(
    'kind = "drop"\ninput = "shoulder.0"'
    'kind = "delay"\ninput = "shoulder.1"\ndelay_ms = 40.0'
    'kind = "duplicate"\ninput = "shoulder.2"'
    'kind = "corrupt"\ninput = "elbow.0"'
    'kind = "stuck-counter"\ninput = "forearm_twist.0"'
    'kind = "out-of-range"\ninput = "wrist.0"'
    'kind = "bus-off"'
    'kind = "modbus-timeout"'
    'kind = "modbus-exception"'
  )
  while [ "$t" -lt "$seconds" ]; do
    local k=0
    for kind in "${kinds[@]}"; do
      printf '[[source.fault]]\n%b\nfrom_s = %d.5\nto_s = %d.8\n' "$kind" $((t + k)) $((t + k))
      k=$((k + 1))
    done
    t=$((t + 10))
  done
}

smoke_realtime=""
receiver_timeout=5
if [ "$smoke" = 1 ]; then
  receiver_timeout=20
  if [ -z "$realtime" ]; then smoke_realtime=$'[realtime]\nsink_ring_frames = 2048'; else smoke_realtime='sink_ring_frames = 2048'; fi
fi
config="$work/soak.toml"
{
  cat <<EOF
[rig]
builtin = "arm"
[loop]
rate_hz = 1000
duration_s = $seconds
stats_interval_s = 10.0
mode = "live"
[layers]
metaballs = true
barnet = true
$realtime
$smoke_realtime
[[source]]
type = "simulated-rig"
name = "rig-can"
period_ms = 10.0
modbus_port = $modbus_port
EOF
  faults
  cat <<EOF
[[source]]
type = "modbus"
name = "rig-modbus"
port = $modbus_port
layout = "simulated-rig"
period_ms = 10.0
timeout_ms = 100.0
[[sink]]
type = "record"
name = "record"
path = "$work/soak.rec"
[[sink]]
type = "udp"
name = "udp"
host = "127.0.0.1"
port = $udp_port
EOF
} > "$config"

"${receiver_prefix[@]}" "$receive" --port "$udp_port" --bind 127.0.0.1 --quiet --timeout "$receiver_timeout" \
  2> "$work/receive.err" &
receiver_pid=$!
# The UDP sink's socket is connected: a datagram sent before the receiver is
# bound is refused, so the daemon starts once the receiver says it listens.
for _ in $(seq 300); do
  grep -q 'listening on' "$work/receive.err" 2>/dev/null && break
  kill -0 "$receiver_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q 'listening on' "$work/receive.err" || { echo "soak-daemon: sinew-receive did not start"; cat "$work/receive.err"; exit 1; }

"$sinewd" --config "$config" > "$work/daemon.out" 2>&1 &
daemon_pid=$!
rss_kb() { awk '/^VmRSS/ { print $2 }' "/proc/$daemon_pid/status" 2>/dev/null || echo 0; }
# RSS once warm (10 s, or a tenth of a short run), then the last reading before exit.
sleep "$(awk -v s="$seconds" 'BEGIN { print (s >= 100 ? 10 : s / 10) }')"
rss_start="$(rss_kb)"
rss_end="$rss_start"
while kill -0 "$daemon_pid" 2>/dev/null; do
  now="$(rss_kb)"
  [ -n "$now" ] && [ "$now" != 0 ] && rss_end="$now"
  sleep 1
done
daemon_status=0
wait "$daemon_pid" || daemon_status=$?
wait "$receiver_pid" || true
receiver_pid=""

final="$(grep '^final tick' "$work/daemon.out" || true)"
ticks="$(sed -n 's/^final tick \([0-9]*\):.*/\1/p' <<< "$final")"
skipped="$(sed -n 's/^skipped ticks (more than a period late): \([0-9]*\)/\1/p' "$work/daemon.out")"
skipped="${skipped:-0}"
received="$(sed -n 's/.*delivered \([0-9]*\), lost \([0-9]*\).*/\1/p' "$work/receive.err" | tail -1)"
udp_lost="$(sed -n 's/.*delivered \([0-9]*\), lost \([0-9]*\).*/\2/p' "$work/receive.err" | tail -1)"
"$sinew_log" verify "$work/soak.rec" > "$work/verify.out" 2>&1 && recording_ok=1 || recording_ok=0
recorded="$(sed -n 's/^  \([0-9]*\) frames.*/\1/p' "$work/verify.out" | sed -n 1p)"

echo "=== sinewd soak: $minutes min live at 1 kHz, built-in arm (metaballs, bar-net), faults cycling every 10 s${realtime:+, SCHED_FIFO}"
grep -E '^(SCHED_FIFO|affinity|mlockall|sink .* I/O thread)' "$work/daemon.out" || true
echo "$final"
grep -E '^  (source|sink|rejected|tick by stage)' "$work/daemon.out" | tail -n 8 || true
echo "skipped ticks:        $skipped of $((${ticks:-0} + skipped)) ($(awk -v s="$skipped" -v t="${ticks:-0}" 'BEGIN { printf "%.4f", ((s + t) > 0 ? 100 * s / (s + t) : 0) }') %)"
echo "RSS (kB):             ${rss_start} once warm, ${rss_end} at the end"
echo "recording:            ${recorded:-?} frames, $(sed -n '$p' "$work/verify.out")"
echo "UDP received:         ${received:-?} frames, lost ${udp_lost:-?}"
echo "daemon exit status:   $daemon_status"

status=0
udp_complete=0
if [ "${received:-x}" = "${ticks:-y}" ] && [ "${udp_lost:-1}" = 0 ]; then udp_complete=1; fi
if [ "$smoke" = 1 ] && [ "$udp_complete" = 0 ]; then
  # Load-proof form: the recording below must still hold every tick, so a
  # drop the daemon reports (exit 1) can only be the UDP sink's.
  echo "UDP not complete (reported, not failed in the smoke: a busy machine's loopback drops datagrams)"
  [ "${received:-0}" -gt 0 ] 2>/dev/null || { echo "FAIL: UDP delivered no frame"; status=1; }
  case "$daemon_status" in
    0) ;;
    1) grep -q 'frames dropped by the sinks' "$work/daemon.out" ||
         { echo "FAIL: sinewd exited 1"; status=1; } ;;
    *) echo "FAIL: sinewd exited $daemon_status"; status=1 ;;
  esac
else
  [ "$daemon_status" = 0 ] || { echo "FAIL: sinewd exited $daemon_status (frames dropped by a sink?)"; status=1; }
  [ "$udp_complete" = 1 ] ||
    { echo "FAIL: UDP delivered ${received:-?} of ${ticks:-?} frames (lost ${udp_lost:-?})"; status=1; }
fi
[ "$recording_ok" = 1 ] || { echo "FAIL: the recording is not intact"; cat "$work/verify.out"; status=1; }
[ "${recorded:-x}" = "${ticks:-y}" ] || { echo "FAIL: recording holds ${recorded:-?} frames, sinewd ran ${ticks:-?} ticks"; status=1; }
# No allocation after init: RSS once warm must not grow (1 MiB allows for
# pages of the stack and of stdio touched late).
[ $((rss_end - rss_start)) -le 1024 ] || { echo "FAIL: RSS grew from $rss_start to $rss_end kB"; status=1; }
[ "$status" = 0 ] && echo "soak-daemon: ok"
exit "$status"
