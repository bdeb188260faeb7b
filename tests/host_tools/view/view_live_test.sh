#!/usr/bin/env bash
# sinew-view on the daemon's live UDP stream: sinewd offline with the
# simulated rig and every layer on sends its frames to sinew-view; headless
# Chromium opens the page. Passes when the 3D view shows the mesh (pixels
# other than the background over a good part of the view), the input panel
# lists every input of the rig with a health state, and the step-time chart
# has steps.
#   view_live_test.sh SINEWD SINEW_VIEW OUT_DIR
SINEWD="$1" SINEW_VIEW="$2" OUT_DIR="$3"
source "$(dirname "$0")/view_common.sh"

udp_port=$base_port http_port=$((base_port + 1))
start_view "$http_port" --udp "$udp_port" --bind 127.0.0.1 --rig arm
daemon_config "$work/live.toml" "[[sink]]
type = \"udp\"
name = \"udp\"
host = \"127.0.0.1\"
port = $udp_port"
# The UDP sink sends without blocking: on a busy machine the loopback may
# refuse a datagram, which the daemon reports as a dropped frame (exit 1).
# The page needs only some frames; anything else is a failure.
daemon_status=0
"$SINEWD" --config "$work/live.toml" > "$work/daemon.out" 2>&1 || daemon_status=$?
if [ "$daemon_status" != 0 ] &&
   ! { [ "$daemon_status" = 1 ] && grep -q 'frames dropped by the sinks' "$work/daemon.out"; }; then
  echo "FAIL: sinewd exited $daemon_status"; cat "$work/daemon.out"; exit 1
fi

probe 1 "http://127.0.0.1:$http_port/?show=metaballs,muscles,barnet" "$OUT_DIR/view_live.png" > "$work/live.json" ||
  { echo "FAIL: page probe"; cat "$work/live.json"; cat "$work/view-$http_port.log"; exit 1; }
cat "$work/live.json"; echo
status=0
check() { if [ "$(json "$work/live.json" "$1")" != true ]; then echo "FAIL: $2"; status=1; else echo "ok: $2"; fi; }
check "j.error === ''" "no error banner"
# The page frames the arm's bounding sphere at 1.3 x its radius: its
# silhouette covers well over 5 % of the view (a sphere so framed covers
# ~20 %; the arm is thinner); a blank canvas has none (the mismatch page of
# view_replay, which draws no mesh, checks that the count can fail).
check "j.drawnPixels > 0.05 * j.viewPixels" "the mesh is drawn ($(json "$work/live.json" "j.drawnPixels") pixels)"
check "j.rigInputs.length === 8" "the rig's 8 inputs (docs/frame-formats.md: the built-in arm has 8)"
check "JSON.stringify(j.inputRows.map((r) => r[0])) === JSON.stringify(j.rigInputs)" "the input panel lists every input by name"
check "j.inputRows.every((r) => ['fresh', 'held', 'stale', 'rejected'].includes(r[2]))" "every input has a health state"
check "/^[0-9]+ steps/.test(j.chart) && parseInt(j.chart, 10) > 0" "the step-time chart has steps"
check "j.chart.includes('deadline misses')" "the chart counts deadline misses"
# The SPH particles fill a capsule centred on the elbow (joint 1), +-80 mm
# along the bone (docs/sph.md): their centroid lies within that of the
# elbow of the drawn frame, whatever the pose.
check "j.sphCentroid !== null && Math.hypot(...j.sphCentroid.map((c, i) => c - j.joints[3 + i])) < 0.08" \
  "the SPH particles sit at the elbow ($(json "$work/live.json" "(1000 * Math.hypot(...j.sphCentroid.map((c, i) => c - j.joints[3 + i]))).toFixed(1)") mm from it)"
exit $status
