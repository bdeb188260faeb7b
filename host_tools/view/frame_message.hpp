// One frame as the page receives it: a binary WebSocket message
//   u32 JSON length J | J bytes of JSON | zero padding to a multiple of 4 |
//   float32 arrays, little-endian, in the order and sizes the JSON's
//   "arrays" lists ([name, float count] pairs).
// Positions are in metres (rig units x 2^length_exponent). The JSON carries
// the tick, time, inputs (value in its unit, status bits), the step-time
// history and the playback state; a rig/stream mismatch is sent as "error"
// with no arrays, so the page shows it instead of a blank canvas.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "hal/output/pose_decode.hpp"
#include "shadow_pipeline.hpp"
#include "view_rig.hpp"

namespace sinew::view {

struct PlaybackState {
  bool replay = false;  // a frame log (else a live UDP stream)
  bool playing = false;
  double speed = 1;
  double start_s = 0, end_s = 0;  // the log's time range (seconds since its first frame)
  double time_s = 0;              // the playback position in that range (the scrubber)
  double frame_time_s = 0;        // the shown frame's time: the last frame at or before time_s
};

struct StreamCounters {
  uint64_t frames = 0;       // frames received or read
  uint64_t frames_lost = 0;  // sequence gaps (UDP)
  uint64_t mismatched = 0;   // frames refused: another shape than the rig's
  // Per input: the same value as in the frame of the tick before (a value
  // held between samples, or a steady input; the frame has no "new sample"
  // bit). Empty when unknown.
  std::vector<uint8_t> input_held;
};

// "" when the frame fits the rig; else why not (shown on the page).
std::string rig_stream_mismatch(const ViewRig& rig, const hal::output::DecodedPose& pose);

// The message for `pose`. shadow: the pipeline stepped with this frame's
// inputs (null when the frame does not fit the rig: then `error` is sent).
// history: the latest steps' stage times, oldest first.
std::vector<uint8_t> frame_message(const ViewRig& rig, const hal::output::DecodedPose& pose,
                                   const ShadowPipeline* shadow, const std::deque<ShadowStep>& history,
                                   uint64_t budget_ns, const PlaybackState& playback, const StreamCounters& counters,
                                   const std::string& error);

// A message with no frame (e.g. waiting for the stream): the JSON only.
std::vector<uint8_t> status_message(const PlaybackState& playback, const StreamCounters& counters,
                                    const std::string& error);

}  // namespace sinew::view
