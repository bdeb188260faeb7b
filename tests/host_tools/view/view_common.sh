# Shared by the viewer's browser tests: the tools, ports, cleanup and the
# page probe (page_probe.mjs). Sourced with: SINEWD SINEW_VIEW OUT_DIR set.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
chromium="${CHROMIUM:-$(command -v chromium || true)}"
if [ -z "$chromium" ]; then
  echo "SKIP: chromium is not installed (scripts/install-deps.sh test installs it)"
  exit 77
fi
export CHROMIUM="$chromium"
mkdir -p "$OUT_DIR"
work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
# Ports from the process id: tests running at once do not collide.
base_port=$((20000 + ($$ * 7) % 20000))

# start_view ARGS...: sinew-view in the background, its log in $work; waits
# until its page is served.
start_view() {
  local port="$1"; shift
  "$SINEW_VIEW" --http-port "$port" "$@" > "$work/view-$port.log" 2>&1 &
  pids+=($!)
  # A liveness bound (60 s): the page is usually served within a second.
  for _ in $(seq 600); do
    if node -e "fetch('http://127.0.0.1:$port/').then(r=>process.exit(r.ok?0:1),()=>process.exit(1))"; then return 0; fi
    sleep 0.1
  done
  echo "FAIL: sinew-view did not serve its page on port $port"; cat "$work/view-$port.log"; exit 1
}

# probe MIN_FRAMES URL PNG [URL PNG ...]: prints each page's state as a JSON
# line (one browser opens the pages in turn).
probe() {
  echo "[${SECONDS}s] opening ${*:2}" >&2
  # 120 s for the page to show MIN_FRAMES frames: a liveness bound (headless
  # Chromium alone can take tens of seconds to start on a busy machine).
  node --no-warnings "$here/page_probe.mjs" "$1" 120 "${@:2}"
}

# json FILE EXPR: a JavaScript expression over the probe's JSON (as `j`),
# printed (node is there: npm and the probe need it).
json() { node -e "const j = JSON.parse(require('fs').readFileSync(process.argv[1], 'utf8')); console.log($2)" "$1"; }

# daemon_config FILE SINK_TOML: 0.6 s at 100 Hz (short: the sanitizer build
# steps every layer in tens of ms), the built-in arm, every layer on, offline,
# fed by the simulated rig (as tests/integration's every-layer runs).
daemon_config() {
  cat > "$1" <<TOML
[rig]
builtin = "arm"
[inputs]
default_period_ms = 10.0
[loop]
rate_hz = 100
duration_s = 0.6
stats_interval_s = 0
mode = "offline"
[layers]
sph = true
metaballs = true
barnet = true
anatomy = true
[[source]]
type = "simulated-rig"
name = "rig"
period_ms = 10.0
$2
TOML
}
