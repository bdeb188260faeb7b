#include "gltf_poser.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "builtin_rigs.hpp"
#include "host_tools/layers/rig_layers.hpp"
#include "motion_tracks.hpp"
#include "quantize.hpp"
#include "toml_motion.hpp"
#include "toml_spec.hpp"

namespace sinew::rigc {

bool GltfPoser::open(const std::string& path, std::string* error) {
  if (!import_gltf(path, &gltf_, error)) return false;
  // glTF skins are linear blend skinning by definition.
  std::vector<uint8_t> bytes;
  if (!compile_rig(gltf_.spec, &bytes, &report_, error)) return *error = path + ": " + *error, false;
  blob_.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(blob_.data(), bytes.data(), bytes.size());
  const auto* blob = reinterpret_cast<const uint8_t*>(blob_.data());
  size_t rig_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(blob, bytes.size(), &rig_bytes);
  if (!st.ok()) return *error = st.message, false;
  rig_arena_.assign(rig_bytes / 8 + 1, 0);
  st = rig::rig_init(blob, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_);
  if (!st.ok()) return *error = st.message, false;
  engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
  if (!engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_))
    return *error = "engine arena too small", false;
  locals_.resize(rig_.joint_count());
  return true;
}

bool GltfPoser::open_spec(const std::string& spec_path, uint32_t tick_hz, std::string* error, bool need_animations) {
  if (tick_hz < 13 || tick_hz > 100000) return *error = "tick rate must be 13..100000 Hz", false;
  tick_hz_ = tick_hz;
  RigSpec spec;
  layers::LayerSpecs layer_specs;
  if (!load_toml_rig(spec_path, &spec, &layer_specs, error)) return false;
  std::string source;
  try {
    source = toml::parse_file(spec_path)["rig"]["source"].value_or<std::string>("");
  } catch (const toml::parse_error& e) {
    return *error = spec_path + ": " + std::string(e.description()), false;
  }
  const bool builtin = source.rfind("builtin:", 0) == 0 || source.empty();
  if (builtin && need_animations)
    return *error = spec_path + ": [rig] source must be a glTF model to pose its animations", false;
  if (!builtin) {
    const std::string model = (std::filesystem::path(spec_path).parent_path() / source).string();
    if (!import_gltf(model, &gltf_, error)) return false;
    if (gltf_.joint_node.size() != spec.joints.size())
      return *error = spec_path + ": internal: the spec's joints differ from the model's", false;
  }
  if (!load_toml_motion(spec_path, spec, &bvh_joints_, error)) return false;
  std::vector<uint8_t> bytes;
  if (!layers::add_layer_dofs(&spec, layer_specs, &layer_report_, error) ||
      !compile_rig(spec, &bytes, &report_, error) ||
      !layers::compile_layers(spec, layer_specs, &bytes, &layer_report_, error))
    return *error = spec_path + ": " + *error, false;
  spec_ = spec;
  blob_.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(blob_.data(), bytes.data(), bytes.size());
  const auto* blob = reinterpret_cast<const uint8_t*>(blob_.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(blob, bytes.size(), &rig_bytes);
  rig_arena_.assign(rig_bytes / 8 + 1, 0);
  if (st.ok()) st = rig::rig_init(blob, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_);
  if (st.ok()) st = pipeline::layers_validate(rig_, blob, bytes.size(), &layer_bytes);
  layer_arena_.assign(layer_bytes / 8 + 1, 0);
  if (st.ok())
    st = pipeline::layers_init(rig_, blob, bytes.size(), layer_arena_.data(), layer_arena_.size() * 8, &layers_);
  if (!st.ok()) return *error = spec_path + ": " + st.message, false;
  locals_.resize(rig_.joint_count());
  with_layers_ = true;
  if (!restart_pipeline(error)) return *error = spec_path + ": " + *error, false;
  return true;
}

bool GltfPoser::restart_pipeline(std::string* error) {
  pipeline::PipelineOptions options;  // every layer the spec compiled, at the simulation's rate
  options.tick_hz = tick_hz_;
  pipeline_arena_.assign(pipeline::pipeline_state_bytes(rig_, layers_, options) / 8 + 1, 0);
  const pipeline::PipelineStatus ps =
      pipeline::pipeline_init(rig_, layers_, options, pipeline_arena_.data(), pipeline_arena_.size() * 8, &pipeline_);
  if (!ps.ok()) return *error = ps.message, false;
  sim_animation_ = -2;
  return true;
}

bool GltfPoser::set_locals(int animation, double time, std::string* error) {
  std::vector<NodeTrs> trs = rest_node_trs(gltf_.model);
  if (animation >= 0 && !sample_animation(gltf_.model, animation, time, &trs, error)) return false;
  const int32_t e = report_.length_exponent;
  for (size_t j = 0; j < locals_.size(); ++j) {
    const NodeTrs& n = trs[static_cast<size_t>(gltf_.joint_node[j])];
    skeleton::LocalPose& l = locals_[j];
    l.translation = {to_len(n.translation[0], e), to_len(n.translation[1], e), to_len(n.translation[2], e)};
    l.rotation = {to_fixed(n.rotation[0], 30), to_fixed(n.rotation[1], 30), to_fixed(n.rotation[2], 30),
                  to_fixed(n.rotation[3], 30)};
    fx::normalize(&l.rotation);
    l.scale = {to_fixed(n.scale[0], 24), to_fixed(n.scale[1], 24), to_fixed(n.scale[2], 24)};
  }
  return true;
}

bool GltfPoser::pose(int animation, double time, std::vector<std::array<double, 3>>* positions, std::string* error) {
  const int32_t e = report_.length_exponent;
  const engine::Engine* engine = &engine_;
  if (with_layers_) {
    // Tick by tick from the animation's start (or from the last time asked,
    // when this one is later); the last tick lands on the requested time.
    double start = 0, end = 0;
    if (animation >= 0 && !animation_range(gltf_.model, animation, &start, &end, error)) return false;
    const double target = animation >= 0 ? std::clamp(time, start, end) : 0.0;
    if (sim_animation_ != animation || target < sim_time_) {
      if (!restart_pipeline(error)) return false;
      sim_animation_ = animation;
      sim_time_ = start;
      if (!set_locals(animation, start, error)) return false;
      const pipeline::PipelineStatus st = pipeline::pipeline_step_locals(&pipeline_, locals_, {});
      if (!st.ok()) return *error = std::string("pipeline: ") + st.message, false;
    }
    const double dt = 1.0 / tick_hz_;
    for (uint64_t k = 1; sim_time_ < target; ++k) {
      const double next = std::min(target, start + (std::floor((sim_time_ - start) * tick_hz_ + 1e-9) + 1) * dt);
      sim_time_ = next;
      // The external inputs (force sensors) read 0: an animation carries none.
      if (!set_locals(animation, sim_time_, error)) return false;
      const pipeline::PipelineStatus st = pipeline::pipeline_step_locals(&pipeline_, locals_, {});
      if (!st.ok()) return *error = std::string("pipeline: ") + st.message, false;
      (void)k;
    }
    engine = &pipeline_.engine;
  } else {
    if (!set_locals(animation, time, error)) return false;
    if (!engine::engine_step_locals(&engine_, locals_)) return *error = "engine step rejected the pose", false;
  }
  const uint32_t n = rig_.vertex_count();
  positions->resize(n);
  for (uint32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) (*positions)[v][static_cast<size_t>(c)] = from_len(engine->vertices.position[c][v], e);
  return true;
}

bool GltfPoser::set_motion(const std::string& path, std::string* error) {
  if (!with_layers_) return *error = "a motion file needs a rig spec (--spec)", false;
  if (!load_motion_tracks(path, spec_, bvh_joints_, &tracks_, error)) return false;
  const std::vector<std::string> names = input_names(spec_);
  track_of_input_.assign(names.size(), -1);
  for (size_t i = 0; i < names.size(); ++i) {
    const size_t dot = names[i].rfind('.');
    if (const auto c = tracks_.find(names[i].substr(0, dot), names[i].substr(dot + 1)))
      track_of_input_[i] = static_cast<int>(*c);
  }
  sim_animation_ = -2;
  return true;
}

void GltfPoser::set_motion_inputs(double time) {
  inputs_.assign(pipeline_.input_count, 0);  // external inputs (force sensors) read 0: a motion file has none
  size_t i = 0;
  for (const JointSpec& j : spec_.joints)
    for (size_t d = 0; d < j.dofs.size(); ++d, ++i) {
      if (track_of_input_[i] < 0) continue;
      const double v = motion::sample_track(tracks_, static_cast<size_t>(track_of_input_[i]), time);
      inputs_[i] = j.dof_kind == DofKind::kRotation ? to_angle(v) : to_len(v, report_.length_exponent);
    }
}

bool GltfPoser::pose_motion(double time, std::vector<std::array<double, 3>>* positions, std::string* error) {
  constexpr int kMotion = -3;  // sim_animation_ while a motion file is simulated
  if (tracks_.times.empty()) return *error = "no motion file set", false;
  if (!std::isfinite(time)) return *error = "the time must be finite", false;
  const double start = tracks_.times.front(), end = tracks_.times.back();
  const double target = std::clamp(time, start, end);
  const double dt = 1.0 / tick_hz_;
  auto tick = [&](double t) {
    set_motion_inputs(t);
    const pipeline::PipelineStatus st = pipeline::pipeline_step(&pipeline_, inputs_);
    if (!st.ok()) *error = std::string("pipeline: ") + st.message;
    return st.ok();
  };
  if (sim_animation_ != kMotion || target < sim_time_) {
    if (!restart_pipeline(error)) return false;
    sim_animation_ = kMotion;
    sim_time_ = start;
    if (!tick(start)) return false;
  }
  while (sim_time_ < target) {
    sim_time_ = std::min(target, start + (std::floor((sim_time_ - start) * tick_hz_ + 1e-9) + 1) * dt);
    if (!tick(sim_time_)) return false;
  }
  const int32_t e = report_.length_exponent;
  const uint32_t n = rig_.vertex_count();
  positions->resize(n);
  for (uint32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c)
      (*positions)[v][static_cast<size_t>(c)] = from_len(pipeline_.engine.vertices.position[c][v], e);
  return true;
}

}  // namespace sinew::rigc
