#include "frame_log_clip.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "rig_clip.hpp"

namespace sinew::gltf_export {
namespace {

std::string shape_mismatch(const hal::output::FrameShape& shape, const firmware::LoadedRig& rig) {
  const uint32_t v = rig.rig.vertex_count(), i = rig.input_count();
  if (shape.vertex_count == 0)
    return "has no vertices (a recording: render it into a frame log first, sinew-log render)";
  if (shape.vertex_count != v)
    return "does not match the rig: vertex count " + std::to_string(shape.vertex_count) + " in the log, " +
           std::to_string(v) + " in the rig";
  if (shape.input_count != i)
    return "does not match the rig: input count " + std::to_string(shape.input_count) + " in the log, " +
           std::to_string(i) + " in the rig";
  if (shape.length_exponent != rig.rig.length_exponent)
    return "does not match the rig: length exponent " + std::to_string(shape.length_exponent) + " in the log, " +
           std::to_string(rig.rig.length_exponent) + " in the rig";
  return "";
}

}  // namespace

bool clip_from_frame_log(const std::string& log_path, const firmware::LoadedRig& rig, const LogSelection& selection,
                         SurfaceClip* clip, LogExportReport* report, std::string* error) {
  if (selection.every == 0 || !(selection.from_s <= selection.to_s) || std::isnan(selection.from_s))
    return *error = "the selection is empty: need --every >= 1 and --from <= --to", false;
  hal::output::FrameLogReader reader;
  if (!reader.open(log_path, error)) return false;
  if (const std::string why = shape_mismatch(reader.shape(), rig); !why.empty())
    return *error = log_path + " " + why, false;
  *report = LogExportReport{};
  report->has_normals = reader.shape().normals;
  set_rest_from_rig(rig.rig, clip);
  clip->frames.clear();

  std::vector<skeleton::LocalPose> locals(rig.rig.joint_count());
  std::vector<uint8_t> joint_flags(rig.rig.joint_count());
  std::vector<uint8_t> measured;
  hal::output::DecodedPose pose;
  uint64_t first_ns = 0, last_tick = 0, last_ns = 0, in_range = 0;
  double first_exported_s = 0;
  bool past_end = false;
  while (!past_end && reader.next(&pose)) {
    const uint64_t record = report->records++;
    if (record == 0) first_ns = pose.timestamp_ns;
    if (record > 0 && (pose.tick <= last_tick || pose.timestamp_ns <= last_ns)) {
      // A restarted daemon appends a new run to its log; a clip has one time line.
      report->stopped_early = "record " + std::to_string(record) + " starts another run (tick " +
                              std::to_string(pose.tick) + " after " + std::to_string(last_tick) +
                              "); only the first run is exported";
      break;
    }
    last_tick = pose.tick, last_ns = pose.timestamp_ns;
    const double t = static_cast<double>(pose.timestamp_ns - first_ns) * 1e-9;
    if (t < selection.from_s) continue;
    if (t > selection.to_s) {
      past_end = true;
      break;
    }
    if (in_range++ % selection.every != 0) continue;
    if (clip->frames.size() >= selection.max_frames)
      return *error = log_path + ": more than " + std::to_string(selection.max_frames) +
                      " frames selected; bound the export with --every, --from and --to",
             false;
    if (clip->frames.empty()) {
      first_exported_s = t;
      report->first_tick = pose.tick;
      report->first_time_s = t;
    }
    report->last_tick = pose.tick;
    report->last_time_s = t;
    // The DOFs the run's sources measured (kJointMeasured) take no synergy,
    // as sinewd posed them.
    measured.assign(rig.rig.input_count, 0);
    for (size_t i = 0; i < measured.size() && i < pose.input_status.size(); ++i)
      measured[i] = (pose.input_status[i] & hal::kJointMeasured) != 0 ? 1 : 0;
    skeleton::dofs_to_locals(rig.rig, pose.input_value, measured, locals, joint_flags);
    FixedFrame frame;
    for (int c = 0; c < 3; ++c) {
      frame.position[c] = pose.position[c];
      if (pose.has_normals) frame.normal[c] = pose.normal[c];
    }
    append_frame(rig.rig, t - first_exported_s, frame, locals, clip);
  }
  if (!past_end && report->stopped_early.empty() && !reader.clean_end())
    return *error = log_path + " is damaged: " + reader.stop_message(), false;
  if (clip->frames.empty()) {
    char range[160];
    std::snprintf(range, sizeof(range), ": no frame in the selected time range (%llu records read)",
                  static_cast<unsigned long long>(report->records));
    return *error = log_path + range, false;
  }
  clip->notes = {{"source", "frame log"},
                 {"first_tick", std::to_string(report->first_tick)},
                 {"last_tick", std::to_string(report->last_tick)},
                 {"first_time_s", std::to_string(report->first_time_s)},
                 {"every", std::to_string(selection.every)},
                 {"normals", report->has_normals ? "logged" : "derived from the triangles"}};
  return true;
}

}  // namespace sinew::gltf_export
