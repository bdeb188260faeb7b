#!/usr/bin/env bash
# sinew-view replaying a frame log: sinewd offline (simulated rig, every
# layer) writes a 0.6 s log; the page opened at ?t=0.1 and at ?t=0.5 (paused
# there) shows the frame of that time, and the two screenshots differ (the
# simulated rig swings the arm between them). A viewer given another rig
# than the log's shows the mismatch on the page.
#   view_replay_test.sh SINEWD SINEW_VIEW OUT_DIR
SINEWD="$1" SINEW_VIEW="$2" OUT_DIR="$3"
source "$(dirname "$0")/view_common.sh"

daemon_config "$work/replay.toml" "[[sink]]
type = \"log\"
name = \"log\"
normals = true
path = \"$work/run.log\""
"$SINEWD" --config "$work/replay.toml" > "$work/daemon.out" 2>&1 || { echo "FAIL: sinewd"; cat "$work/daemon.out"; exit 1; }

http_port=$((base_port + 2))
start_view "$http_port" --log "$work/run.log" --rig arm
status=0
probe 1 "http://127.0.0.1:$http_port/?t=0.1" "$OUT_DIR/view_replay_t0.1.png" \
  "http://127.0.0.1:$http_port/?t=0.5" "$OUT_DIR/view_replay_t0.5.png" > "$work/pages.json" ||
  { echo "FAIL: page probe"; cat "$work/pages.json"; exit 1; }
sed -n 1p "$work/pages.json" > "$work/t0.1.json"
sed -n 2p "$work/pages.json" > "$work/t0.5.json"
for t in 0.1 0.5; do
  cat "$work/t$t.json"
  # The frame shown is the last at or before t: within one tick (10 ms).
  if [ "$(json "$work/t$t.json" "Math.abs(j.timeS - $t) <= 0.0101 && j.error === ''")" != true ]; then
    echo "FAIL: the page at ?t=$t shows time $(json "$work/t$t.json" "j.timeS")"; status=1
  fi
  if [ "$(json "$work/t$t.json" "j.drawnPixels > 0.05 * j.viewPixels")" != true ]; then
    echo "FAIL: no mesh drawn at t=$t"; status=1
  fi
done
diff_json="$(node "$here/page_probe.mjs" --diff "$OUT_DIR/view_replay_t0.1.png" "$OUT_DIR/view_replay_t0.5.png")"
echo "$diff_json"
# The arm moves between the two times: a good number of the view's pixels
# change (a re-encoded identical frame changes none).
differing="$(node -e "console.log(JSON.parse(process.argv[1]).differingPixels)" "$diff_json")"
if [ "$differing" -lt 2000 ]; then echo "FAIL: the two times give the same image ($differing pixels differ)"; status=1
else echo "ok: scrubbing to two times gives two images ($differing pixels differ)"; fi

# Another rig than the log's: the page says so instead of drawing nothing.
mismatch_port=$((base_port + 3))
start_view "$mismatch_port" --log "$work/run.log" --rig hand
probe 0 "http://127.0.0.1:$mismatch_port/" "$OUT_DIR/view_mismatch.png" > "$work/mismatch.json" ||
  { echo "FAIL: page probe (mismatch)"; cat "$work/mismatch.json"; exit 1; }
cat "$work/mismatch.json"; echo
if [ "$(json "$work/mismatch.json" "j.error.includes('rig/stream mismatch')")" != true ]; then
  echo "FAIL: no mismatch error on the page"; status=1
else echo "ok: a rig/stream mismatch shows on the page"; fi
# ... and draws no surface: the pixel count of the checks above is near zero.
if [ "$(json "$work/mismatch.json" "j.drawnPixels < 0.005 * j.viewPixels")" != true ]; then
  echo "FAIL: the mismatch page's view is not empty ($(json "$work/mismatch.json" "j.drawnPixels") pixels)"; status=1
else echo "ok: the mismatched stream is not drawn"; fi
exit $status
