#include "render.hpp"

#include <sys/stat.h>

#include <cinttypes>
#include <cstdio>

#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/recording.hpp"
#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "hal/output/frame_log_writer.hpp"

namespace sinew::log_tool {

namespace {

std::string hex64(uint64_t v) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

}  // namespace

bool render_recording(const RenderOptions& o, RenderResult* result, std::string* error) {
  hal::output::FrameLogReader reader;
  if (!reader.open(o.recording, error)) return false;
  firmware::RunDescription run;
  if (reader.metadata().empty() || reader.shape().vertex_count != 0)
    return *error = o.recording + ": a frame log, not a recording (no run description)", false;
  if (!firmware::parse_run_description(reader.metadata(), &run, error))
    return *error = o.recording + ": " + *error, false;

  firmware::LoadedRig rig;
  const std::string builtin = o.rig.rfind("builtin:", 0) == 0 ? o.rig.substr(8) : "";
  if (!firmware::load_rig(builtin, builtin.empty() ? o.rig : "", &rig, error)) return false;
  const uint64_t hash = firmware::rig_blob_hash(rig.blob.data(), rig.blob.size);
  if (hash != run.rig_xxh64 || rig.blob.size != run.rig_bytes)
    return *error = o.rig + " is not the rig of " + o.recording + " (xxh64 " + hex64(hash) + ", " +
                    std::to_string(rig.blob.size) + " bytes; the recording's: " + hex64(run.rig_xxh64) + ", " +
                    std::to_string(run.rig_bytes) + " bytes)",
           false;
  if (reader.shape().input_count != rig.input_count() || reader.shape().length_exponent != rig.rig.length_exponent)
    return *error = o.recording + ": its inputs do not match the rig's", false;

  std::vector<uint64_t> arena(pipeline::pipeline_state_bytes(rig.rig, rig.layers, run.options) / 8 + 1, 0);
  pipeline::Pipeline pipeline;
  const pipeline::PipelineStatus st =
      pipeline::pipeline_init(rig.rig, rig.layers, run.options, arena.data(), arena.size() * 8, &pipeline);
  if (!st.ok()) return *error = std::string("layers: ") + st.message, false;

  struct stat existing {};
  if (::lstat(o.out.c_str(), &existing) == 0)
    return *error = o.out + " exists: render writes a new log (remove it or choose another name)", false;
  hal::output::FrameShape shape;
  shape.vertex_count = rig.rig.vertex_count();
  shape.input_count = rig.input_count();
  shape.length_exponent = rig.rig.length_exponent;
  shape.normals = o.normals && !rig.rig.normal[0].empty();
  hal::output::FrameLogWriter writer;
  if (!writer.open(o.out, shape, {}, error)) return false;

  const engine::Engine& engine = pipeline.engine;
  hal::PoseFrame frame;
  frame.length_exponent = rig.rig.length_exponent;
  frame.vertex_count = rig.rig.vertex_count();
  for (int c = 0; c < 3; ++c) {
    frame.position[c] = engine.vertices.position[c].data();
    frame.normal[c] = engine.vertices.normal[c].empty() ? nullptr : engine.vertices.normal[c].data();
  }
  RenderResult r;
  hal::output::DecodedPose recorded;
  // Which DOFs the run's sources measured, as each frame logged it
  // (kJointMeasured): the synergies and SPH joints treat them as sinewd did.
  std::vector<uint8_t> measured(rig.rig.input_count, 0);
  pipeline::pipeline_set_measured_inputs(&pipeline, measured);
  while (reader.next(&recorded)) {
    ++r.frames_read;
    for (size_t i = 0; i < measured.size() && i < recorded.input_status.size(); ++i)
      measured[i] = (recorded.input_status[i] & hal::kJointMeasured) != 0 ? 1 : 0;
    // The inputs as the tick applied them: the run's pipeline input.
    (void)pipeline::pipeline_step(&pipeline, recorded.input_value);
    if (recorded.tick % (o.every_n_frames < 1 ? 1 : o.every_n_frames) != 0) continue;
    frame.tick = recorded.tick;
    frame.timestamp_ns = recorded.timestamp_ns;
    frame.input_count = recorded.input_count;
    frame.input_value = recorded.input_value.data();
    frame.input_status = recorded.input_status.data();
    if (!writer.write(frame)) return *error = o.out + ": " + writer.status_line(), false;
    ++r.frames_written;
  }
  writer.close();
  if (writer.stats().frames_dropped > 0 || writer.stats().sync_errors > 0)
    return *error = o.out + ": " + writer.status_line(), false;
  r.recording_intact = reader.clean_end();
  if (!r.recording_intact) r.recording_stop = reader.stop_message();
  *result = r;
  return true;
}

}  // namespace sinew::log_tool
