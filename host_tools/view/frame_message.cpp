#include "frame_message.hpp"

#include <cmath>
#include <cstring>

#include "json_text.hpp"
// One line per stage: what the viewer draws of it.
#include "overlays/anatomy_overlay.hpp"
#include "overlays/barnet_overlay.hpp"
#include "overlays/metaballs_overlay.hpp"
#include "overlays/skinning_overlay.hpp"
#include "overlays/sph_overlay.hpp"
#include "sim_core/skeleton/pose.hpp"

namespace sinew::view {

namespace {

void add_playback(JsonText& j, const PlaybackState& p, const StreamCounters& c, const std::string& error) {
  j.key("source").string(p.replay ? "log" : "udp");
  j.key("playing").boolean(p.playing);
  j.key("speed").number(p.speed);
  j.key("start_s").number(p.start_s);
  j.key("end_s").number(p.end_s);
  j.key("time_s").number(p.time_s);
  j.key("frame_time_s").number(p.frame_time_s);
  j.key("frames").number(c.frames);
  j.key("frames_lost").number(c.frames_lost);
  j.key("mismatched").number(c.mismatched);
  if (!error.empty()) j.key("error").string(error);
}

std::vector<uint8_t> assemble(const std::string& json, const std::vector<float>& values) {
  std::vector<uint8_t> out(4 + json.size());
  const auto n = static_cast<uint32_t>(json.size());
  for (int b = 0; b < 4; ++b) out[static_cast<size_t>(b)] = static_cast<uint8_t>(n >> (8 * b));
  std::memcpy(out.data() + 4, json.data(), json.size());
  out.resize((out.size() + 3) / 4 * 4, 0);
  const size_t at = out.size();
  out.resize(at + values.size() * 4);
  // The page reads them as a Float32Array: little-endian, as every host the
  // viewer runs on (x86-64, aarch64) stores them.
  if (!values.empty()) std::memcpy(out.data() + at, values.data(), values.size() * 4);
  return out;
}

// Every stage's overlay, in stage order.
void add_overlays(const ShadowPipeline& shadow, int32_t e, OverlayArrays* a, JsonText& j) {
  const pipeline::Pipeline& p = shadow.state();
#define SINEW_STAGE_OVERLAY(name, enumerator, sections, doc) ViewOverlay<pipeline::Stage::enumerator>::add(p, e, a, j);
  SINEW_STAGE_LIST(SINEW_STAGE_OVERLAY)
#undef SINEW_STAGE_OVERLAY
}

}  // namespace

std::string rig_stream_mismatch(const ViewRig& rig, const hal::output::DecodedPose& pose) {
  const rig::Rig& r = rig.loaded.rig;
  if (pose.vertex_count != r.vertex_count())
    return "rig/stream mismatch: the stream has " + std::to_string(pose.vertex_count) + " vertices, the rig " +
           rig.name + " has " + std::to_string(r.vertex_count());
  if (pose.input_count != rig.loaded.input_count())
    return "rig/stream mismatch: the stream has " + std::to_string(pose.input_count) + " inputs, the rig " + rig.name +
           " has " + std::to_string(rig.loaded.input_count());
  if (pose.length_exponent != r.length_exponent)
    return "rig/stream mismatch: length exponent " + std::to_string(pose.length_exponent) + " in the stream, " +
           std::to_string(r.length_exponent) + " in the rig " + rig.name;
  return "";
}

std::vector<uint8_t> frame_message(const ViewRig& rig, const hal::output::DecodedPose& pose,
                                   const ShadowPipeline* shadow, const std::deque<ShadowStep>& history,
                                   uint64_t budget_ns, const PlaybackState& playback, const StreamCounters& counters,
                                   const std::string& error) {
  JsonText j;
  OverlayArrays a;
  j.open_object();
  j.key("type").string("frame");
  j.key("tick").number(pose.tick);
  j.key("timestamp_ns").number(pose.timestamp_ns);
  add_playback(j, playback, counters, error);
  // A mismatched stream's inputs are not the rig's: not listed under its names.
  j.key("inputs").open_array();
  for (uint32_t i = 0; i < (error.empty() ? pose.input_count : 0); ++i) {
    j.open_object();
    j.key("raw").number(pose.input_value[i]);
    if (i < rig.input_unit.size()) j.key("value").number(input_display_value(rig, i, pose.input_value[i]));
    j.key("status").number(static_cast<uint32_t>(pose.input_status[i]));
    j.key("held").boolean(i < counters.input_held.size() && counters.input_held[i] != 0);
    j.close_object();
  }
  j.close_array();
  j.key("budget_ns").number(budget_ns);
  j.key("stages").open_array();
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) j.string(pipeline::stage_name(static_cast<pipeline::Stage>(s)));
  j.close_array();
  j.key("history").open_array();
  for (const ShadowStep& h : history) {
    j.open_array();
    j.number(h.tick);
    for (const uint64_t ns : h.stage_ns) j.number(ns);
    j.close_array();
  }
  j.close_array();
  if (shadow != nullptr) {
    const int32_t e = pose.length_exponent;
    const uint32_t v = pose.vertex_count;
    a.add("position", 3 * size_t{v});
    for (uint32_t k = 0; k < v; ++k)
      for (int c = 0; c < 3; ++c) a.push(metres(pose.position[c][k], e));
    if (pose.has_normals) {
      a.add("normal", 3 * size_t{v});
      for (uint32_t k = 0; k < v; ++k)
        for (int c = 0; c < 3; ++c) a.push(std::ldexp(static_cast<double>(pose.normal[c][k]), -30));
    }
    // What the layers added: the distance from the plain-skinned surface.
    a.add("displacement", v);
    for (uint32_t k = 0; k < v; ++k) {
      double d2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = metres(pose.position[c][k], e) - metres(shadow->plain_skin(c)[k], e);
        d2 += d * d;
      }
      a.push(std::sqrt(d2));
    }
    add_overlays(*shadow, e, &a, j);
    // Joint limits reached: the stream's clamped bits on the joint's inputs,
    // and the re-stepped skeleton's own flag.
    j.key("joint_limit").open_array();
    const rig::Rig& r = rig.loaded.rig;
    for (uint32_t k = 0; k < r.joint_count(); ++k) {
      bool clamped = (shadow->state().engine.joint_flags[k] & skeleton::kJointClamped) != 0;
      for (uint32_t d = 0; d < r.joints[k].dof_count; ++d) {
        const uint32_t in = r.joints[k].first_input + d;
        if (in < pose.input_count && (pose.input_status[in] & hal::kJointClampedStatus) != 0) clamped = true;
      }
      j.boolean(clamped);
    }
    j.close_array();
  }
  j.key("arrays").open_array();
  for (const auto& [name, count] : a.names) {
    j.open_array();
    j.string(name);
    j.number(static_cast<uint64_t>(count));
    j.close_array();
  }
  j.close_array();
  j.close_object();
  return assemble(j.take(), a.values);
}

std::vector<uint8_t> status_message(const PlaybackState& playback, const StreamCounters& counters,
                                    const std::string& error) {
  JsonText j;
  j.open_object();
  j.key("type").string("status");
  add_playback(j, playback, counters, error);
  j.key("arrays").open_array();
  j.close_array();
  j.close_object();
  return assemble(j.take(), {});
}

}  // namespace sinew::view
