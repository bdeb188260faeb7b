// Regenerates a run's full frames from its recording (firmware/runtime/
// recording.hpp): loads the rig the recording names (checking its hash),
// builds the pipeline with the recorded options, and steps it once per
// recorded tick with the recorded inputs, through pipeline_step as the
// daemon's tick does. The frames are written as a frame log, byte for byte the
// one a `log` sink of the same run and shape writes.
#pragma once

#include <cstdint>
#include <string>

namespace sinew::log_tool {

struct RenderOptions {
  std::string recording;
  std::string rig;              // "builtin:arm", "builtin:hand" or a blob file
  std::string out;              // must not exist
  bool normals = false;         // as the `log` sink's `normals` key
  uint64_t every_n_frames = 1;  // as the `log` sink's `every_n_frames` key
};

struct RenderResult {
  uint64_t frames_read = 0, frames_written = 0;
  bool recording_intact = true;  // false: it ended in damage (frames up to it were rendered)
  std::string recording_stop;
};

// False with a message when nothing could be rendered (wrong rig, not a
// recording, an existing output); damage in the recording is in the result.
bool render_recording(const RenderOptions& options, RenderResult* result, std::string* error);

}  // namespace sinew::log_tool
