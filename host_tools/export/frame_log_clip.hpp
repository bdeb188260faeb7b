// A frame log (docs/frame-formats.md) of a rig, sampled into a SurfaceClip:
// the logged positions and normals (normals derived from the triangles when
// the log has none), and the joint transforms the logged inputs give through
// sim_core's skeleton (skeleton::dofs_to_locals: the log carries inputs as
// applied, not transforms).
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "firmware/rig/loaded_rig.hpp"
#include "surface_clip.hpp"

namespace sinew::gltf_export {

struct LogSelection {
  double from_s = 0;  // seconds from the log's first frame
  double to_s = std::numeric_limits<double>::infinity();
  uint32_t every = 1;  // every N-th frame of [from, to], starting with the first
  uint32_t max_frames = kMaxExportFrames;
};

struct LogExportReport {
  uint64_t records = 0;  // records read
  uint64_t first_tick = 0, last_tick = 0;
  double first_time_s = 0, last_time_s = 0;  // of the exported frames, from the log's first frame
  bool has_normals = false;                  // the log carried them
  std::string stopped_early;                 // why reading stopped before the end ("" if it did not)
};

// False with a message naming the log and the problem: not a frame log, a
// damaged or truncated record, a rig that does not match the log, nothing in
// the selection, or too many frames.
bool clip_from_frame_log(const std::string& log_path, const firmware::LoadedRig& rig, const LogSelection& selection,
                         SurfaceClip* clip, LogExportReport* report, std::string* error);

}  // namespace sinew::gltf_export
