// The built-in arm compiled and loaded, its engine, and an SPH elastic elbow
// built around it, stepped the way docs/sph.md describes: engine_step for the
// commanded pose, then sph_step on the engine's model transforms.
#pragma once

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace sinew::test {

class SphArm {
 public:
  explicit SphArm(const layers::SphBuildOptions& options, rigc::SkinChoice skin = rigc::SkinChoice::kDualQuaternion)
      : spec_(rigc::builtin_arm(skin)) {
    std::vector<uint8_t> bytes;
    rigc::CompileReport report;
    if (!rigc::compile_rig(spec_, &bytes, &report, &error_)) return;
    blob_.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob_.data(), bytes.data(), bytes.size());
    const auto* data = reinterpret_cast<const uint8_t*>(blob_.data());
    size_t rig_bytes = 0;
    if (!rig::rig_validate(data, bytes.size(), &rig_bytes).ok()) {
      error_ = "rig validate";
      return;
    }
    rig_arena_.assign(rig_bytes / 8 + 1, 0);
    if (!rig::rig_init(data, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_).ok()) {
      error_ = "rig init";
      return;
    }
    engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
    if (!engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_)) {
      error_ = "engine init";
      return;
    }
    inputs_.assign(rig_.input_count, 0);
    if (!layers::build_sph(spec_, options, &built_, &error_)) return;
    model_ = built_.model();
    const sph::LayerStatus v = sph::sph_validate(model_, rig_);
    if (!v.ok()) {
      error_ = v.message;
      return;
    }
    sph_arena_.assign(sph::sph_state_bytes(model_) / 8 + 1, 0);
    const sph::LayerStatus s = sph::sph_init(model_, engine_.model, sph_arena_.data(), sph_arena_.size() * 8, &state_);
    if (!s.ok()) {
      error_ = s.message;
      return;
    }
    ok_ = true;
  }
  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }
  const rigc::RigSpec& spec() const { return spec_; }
  const layers::SphBuilt& built() const { return built_; }
  const sph::SphModel& model() const { return model_; }
  sph::SphState& state() { return state_; }
  engine::Engine& engine() { return engine_; }
  const rig::Rig& rig() const { return rig_; }
  std::vector<int32_t>& inputs() { return inputs_; }
  int input(const std::string& name) const {
    const auto names = rigc::input_names(spec_);
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    return -1;
  }

  // One tick: the engine's commanded pose, then the SPH joint under `force_n`
  // (newtons, model space, at the wrist).
  sph::LayerStatus tick(double fx_n, double fy_n, double fz_n, bool tresca = true) {
    engine::engine_step(&engine_, inputs_);
    sph::SphInputs in;
    in.transforms = engine_.model;
    in.force = {newtons(fx_n), newtons(fy_n), newtons(fz_n)};
    in.tresca = tresca;
    return sph::sph_step(&state_, in);
  }
  double bend_degrees() const { return static_cast<double>(static_cast<int32_t>(state_.bend)) / 4294967296.0 * 360.0; }
  double metres(int32_t len) const { return std::ldexp(static_cast<double>(len), built_.length_exponent - 20); }
  static int32_t newtons(double f) { return static_cast<int32_t>(std::llround(f * 65536.0)); }

 private:
  rigc::RigSpec spec_;
  std::string error_;
  bool ok_ = false;
  std::vector<uint64_t> blob_, rig_arena_, engine_arena_, sph_arena_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<int32_t> inputs_;
  layers::SphBuilt built_;
  sph::SphModel model_;
  sph::SphState state_;
};

// Static bend (radians) of the distal tissue held by the elastic tension
// alone under `fy_newtons` toward +y at the load point, at the rest pose:
// each distal particle (mass m) takes the load as the rigid-body
// acceleration tau r / (m I_sum) and the pull -k_e theta r, so they balance
// at theta = tau / (k_e sum m r_perp^2) (docs/sph.md, "Gains"). Pressure
// only adds stiffness against the crease's compression.
inline double elastic_static_bend(SphArm& arm, double fy_newtons, const layers::SphBuildOptions& o) {
  const sph::SphModel& m = arm.model();
  const fx::Mat34& d = arm.engine().model[m.joint.distal_joint];
  const double lin = 1.0 / 16777216.0;
  double axis[3], load[3], centre[3];
  const fx::Vec3 a = m.joint.axis, lp = m.joint.load_point;
  const double al[3] = {a.x / 1073741824.0, a.y / 1073741824.0, a.z / 1073741824.0};
  const double ll[3] = {arm.metres(lp.x), arm.metres(lp.y), arm.metres(lp.z)};
  for (int r = 0; r < 3; ++r) {
    axis[r] = (d.m[r][0] * al[0] + d.m[r][1] * al[1] + d.m[r][2] * al[2]) * lin;
    load[r] = (d.m[r][0] * ll[0] + d.m[r][1] * ll[1] + d.m[r][2] * ll[2]) * lin;
    centre[r] = arm.metres(d.t[r]);
  }
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& v : axis) v /= norm;
  // tau = (r x F) . n with F = (0, fy, 0): (r_z * 0 - ...) = -r_z fy n_x + r_x fy n_z.
  const double tau = fy_newtons * (load[0] * axis[2] - load[2] * axis[0]);
  const double mass = o.tissue_mass / m.particle_count();
  double inertia = 0;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    if (m.bone[i] != static_cast<uint8_t>(sph::Bone::kDistal)) continue;
    double r[3] = {arm.metres(m.rest_model[0][i]) - centre[0], arm.metres(m.rest_model[1][i]) - centre[1],
                   arm.metres(m.rest_model[2][i]) - centre[2]};
    const double along = r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2];
    for (int c = 0; c < 3; ++c) r[c] -= along * axis[c];
    inertia += mass * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  return tau / (o.elastic_stiffness * inertia);
}

}  // namespace sinew::test
