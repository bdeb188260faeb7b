#include "frame_message.hpp"

#include <cmath>
#include <cstring>

#include "json_text.hpp"
#include "sim_core/skeleton/pose.hpp"

namespace sinew::view {

namespace {

struct FloatArrays {
  std::vector<std::pair<std::string, size_t>> names;
  std::vector<float> values;

  void add(const char* name, size_t count) { names.emplace_back(name, count); }
  void push(double v) { values.push_back(static_cast<float>(v)); }
};

double metres(int32_t q12_20, int32_t length_exponent) {
  return std::ldexp(static_cast<double>(q12_20), length_exponent - 20);
}

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

void add_overlays(const ShadowPipeline& shadow, int32_t e, FloatArrays* a, JsonText& j) {
  const pipeline::Pipeline& p = shadow.state();
  const rig::Rig& rig = *p.rig;
  // Skeleton: model-space joint origins.
  a->add("joints", 3 * rig.joint_count());
  for (uint32_t k = 0; k < rig.joint_count(); ++k)
    for (int c = 0; c < 3; ++c) a->push(metres(p.engine.model[k].t[c], e));
  // SPH particles (every joint's, concatenated), pressure rho - rho0 in
  // normalised density units (Q8.24), yielded 0/1.
  size_t particles = 0;
  for (uint32_t s = 0; s < p.sph.count; ++s) particles += p.sph.joint[s].pressure.size();
  a->add("sph_position", 3 * particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (size_t k = 0; k < p.sph.joint[s].pressure.size(); ++k)
      for (int c = 0; c < 3; ++c) a->push(metres(p.sph.joint[s].position[c][k], e));
  a->add("sph_pressure", particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (const auto d : p.sph.joint[s].pressure) a->push(std::ldexp(static_cast<double>(d), -24));
  a->add("sph_yielded", particles);
  for (uint32_t s = 0; s < p.sph.count; ++s)
    for (const uint8_t y : p.sph.joint[s].yielded) a->push(y);
  j.key("sph_joints").open_array();
  for (uint32_t s = 0; s < p.sph.count; ++s) {
    j.open_object();
    j.key("joint").number(p.sph.model[s].joint.distal_joint);
    j.key("yielded").boolean(p.sph.joint[s].joint_yielded);
    j.key("yielded_particles").number(p.sph.joint[s].yielded_particles);
    j.close_object();
  }
  j.close_array();
  // Metaballs: centre and radius (r0 x the volume-preserving scale).
  const size_t balls = p.metaballs.on ? p.metaballs.state.ball_center.size() : 0;
  a->add("metaballs", 4 * balls);
  for (size_t b = 0; b < balls; ++b) {
    const fx::Vec3& c = p.metaballs.state.ball_center[b];
    a->push(metres(c.x, e));
    a->push(metres(c.y, e));
    a->push(metres(c.z, e));
    const double scale = std::ldexp(static_cast<double>(p.metaballs.state.ball_scale[b]), -30);
    a->push(metres(p.metaballs.state.model->ball_radius[b], e) * scale);
  }
  // Muscles: their surface vertices (rings of slices).
  const size_t muscle_vertices = p.anatomy.on ? p.anatomy.muscles.vertex[0].size() : 0;
  a->add("muscles", 3 * muscle_vertices);
  for (size_t v = 0; v < muscle_vertices; ++v)
    for (int c = 0; c < 3; ++c) a->push(metres(p.anatomy.muscles.vertex[c][v], e));
  // Bar-nets: each net's free nodes at their smooth-skinned positions.
  size_t nodes = 0;
  for (uint32_t n = 0; n < p.barnet.count; ++n) nodes += p.barnet.net[n].skinned[0].size();
  a->add("barnet", 3 * nodes);
  for (uint32_t n = 0; n < p.barnet.count; ++n)
    for (size_t k = 0; k < p.barnet.net[n].skinned[0].size(); ++k)
      for (int c = 0; c < 3; ++c) a->push(metres(p.barnet.net[n].skinned[c][k], e));
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
  FloatArrays a;
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
