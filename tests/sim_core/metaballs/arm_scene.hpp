// The built-in arm compiled, loaded, driven by the engine and deformed by the
// metaballs layer: one scene per test. Poses are set as joint rotations
// (engine_step_locals), so a 180-degree forearm twist is reachable although
// the twist DOF is limited to +-100 degrees.
#pragma once

#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/metaballs/step.hpp"

namespace sinew::test {

inline metaballs_build::Options arm_options() {
  metaballs_build::Options o;
  o.ball_spacing = 0.01;
  return o;
}

class ArmScene {
 public:
  explicit ArmScene(rigc::SkinChoice method = rigc::SkinChoice::kDualQuaternion,
                    const metaballs_build::Options& options = arm_options())
      : ArmScene(rigc::builtin_arm(method), options) {}
  // Any rig spec (e.g. the built-in hand); pose_dofs drives it.
  ArmScene(rigc::RigSpec spec, const metaballs_build::Options& options) : spec_(std::move(spec)) {
    std::vector<uint8_t> bytes;
    if (!rigc::compile_rig(spec_, &bytes, &report_, &error_)) return;
    blob_.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob_.data(), bytes.data(), bytes.size());
    const auto* data = reinterpret_cast<const uint8_t*>(blob_.data());
    size_t rig_bytes = 0;
    if (!rig::rig_validate(data, bytes.size(), &rig_bytes).ok()) {
      error_ = "rig_validate";
      return;
    }
    rig_arena_.assign(rig_bytes / 8 + 1, 0);
    if (!rig::rig_init(data, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_).ok()) {
      error_ = "rig_init";
      return;
    }
    engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
    if (!engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_)) {
      error_ = "engine_init";
      return;
    }
    if (!metaballs_build::build(spec_, options, &build_, &error_)) return;
    model_ = build_.model();
    state_memory_.assign(metaballs::metaballs_state_bytes(model_) / 8 + 1, 0);
    const metaballs::LayerStatus s =
        metaballs::metaballs_init(model_, state_memory_.data(), state_memory_.size() * 8, &state_);
    if (!s.ok()) {
      error_ = s.message;
      return;
    }
    for (int a = 0; a < 3; ++a) out_[a].assign(rig_.vertex_count(), 0);
    locals_.resize(rig_.joint_count());
    ok_ = true;
  }
  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }

  // Joint rotations in degrees about each joint's first DOF axis, then one
  // engine step and one metaballs step.
  bool pose(double shoulder, double elbow, double twist) {
    skeleton::rest_locals(rig_, locals_);
    rotate("shoulder", shoulder);
    rotate("elbow", elbow);
    rotate("forearm_twist", twist);
    if (!engine::engine_step_locals(&engine_, locals_)) return false;
    return metaballs::metaballs_step(&state_, engine_.model, output()).ok();
  }

  // Any DOF of any joint (degrees about the DOF's axis), others at rest.
  struct DofAngle {
    std::string joint;
    int dof = 0;
    double degrees = 0;
  };
  bool pose_dofs(const std::vector<DofAngle>& angles) {
    skeleton::rest_locals(rig_, locals_);
    for (const DofAngle& a : angles) rotate(a.joint.c_str(), a.degrees, a.dof);
    if (!engine::engine_step_locals(&engine_, locals_)) return false;
    return metaballs::metaballs_step(&state_, engine_.model, output()).ok();
  }
  // A DOF's limits in degrees.
  double dof_limit_deg(int joint, int dof, bool upper) const {
    const rig::JointRecord& r = rig_.joints[static_cast<size_t>(joint)];
    const int32_t a = upper ? r.dof_max[dof] : r.dof_min[dof];
    return static_cast<double>(a) / 4294967296.0 * 360.0;
  }

  skin::SkinnedVertices output() {
    skin::SkinnedVertices v;
    for (int a = 0; a < 3; ++a) v.position[a] = out_[a];
    return v;
  }
  // Metres: metaballs output, engine (LBS/DQS) output, rest.
  double mb(int axis, uint32_t v) const { return len(out_[axis][v]); }
  double skinned(int axis, uint32_t v) const { return len(engine_.vertices.position[axis][v]); }
  double rest(int axis, uint32_t v) const { return len(rig_.position[axis][v]); }
  double len(int32_t x) const { return std::ldexp(static_cast<double>(x), report_.length_exponent - 20); }

  const rigc::RigSpec& spec() const { return spec_; }
  const rig::Rig& rig() const { return rig_; }
  engine::Engine& engine() { return engine_; }
  const metaballs_build::Build& build() const { return build_; }
  const metaballs::MetaballModel& model() const { return model_; }
  metaballs::MetaballState& state() { return state_; }

 private:
  void rotate(const char* joint, double degrees, int dof = 0) {
    const int j = rigc::joint_index(spec_, joint);
    const rig::JointRecord& r = rig_.joints[static_cast<size_t>(j)];
    const fx::Vec3 axis{r.dof_axis[dof][0], r.dof_axis[dof][1], r.dof_axis[dof][2]};
    const auto angle = static_cast<fx::Angle>(static_cast<uint32_t>(std::llround(degrees / 360.0 * 4294967296.0)));
    fx::Quat& q = locals_[static_cast<size_t>(j)].rotation;
    q = fx::mul(q, fx::quat_from_axis_angle(axis, angle));
  }

  rigc::RigSpec spec_;
  rigc::CompileReport report_;
  std::string error_;
  bool ok_ = false;
  std::vector<uint64_t> blob_, rig_arena_, engine_arena_, state_memory_;
  rig::Rig rig_;
  engine::Engine engine_;
  metaballs_build::Build build_;
  metaballs::MetaballModel model_;
  metaballs::MetaballState state_;
  std::vector<fx::Len> out_[3];
  std::vector<skeleton::LocalPose> locals_;
};

}  // namespace sinew::test
