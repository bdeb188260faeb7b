// The built-in arm with its elbow bar-net (or any rig with any net),
// compiled, loaded and ready to step: the engine gives the bone global
// transforms, the bar-net step the node and wrapped skin positions. Shared
// by the bar-net tests, benchmark and determinism workload. Memory is
// allocated here, once, before any step.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "arm_net.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/barnet/barnet.hpp"
#include "sim_core/engine/engine.hpp"

namespace sinew::layers::barnet {

class ArmSession {
 public:
  // Builds a net for the arm (its NetSpec from the arm's RigSpec); false
  // with a message on an error.
  using NetBuilder = std::function<bool(const rigc::RigSpec& arm, NetSpec* net, std::string* error)>;

  explicit ArmSession(rigc::SkinChoice method = rigc::SkinChoice::kLinear, const ArmNetOptions& options = {});
  // The arm with another net: e.g. arm_muscle_net (Figure 3) or
  // arm_wrinkle_net (Figure 6).
  ArmSession(rigc::SkinChoice method, const NetBuilder& net);
  // Any rig (e.g. rigc::builtin_hand) with a net built for it.
  ArmSession(rigc::RigSpec rig, const NetBuilder& net);
  ArmSession(const ArmSession&) = delete;
  ArmSession& operator=(const ArmSession&) = delete;

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }

  // One engine step from `inputs` (signed binary angles per rig input), then
  // one bar-net step. Returns false on an error (see error()).
  bool step();
  bool engine_step();  // the smooth-skinning baseline alone

  std::vector<int32_t>& inputs() { return inputs_; }
  // The net's external inputs (Q16.16, model().external_count of them),
  // passed to every step; all 0 until set.
  std::vector<int32_t>& external() { return external_; }
  int input(const std::string& name) const;
  const rigc::RigSpec& spec() const { return spec_; }
  const rig::Rig& rig() const { return rig_; }
  engine::Engine& engine() { return engine_; }
  const BarnetBuild& build() const { return build_; }
  const sinew::barnet::BarnetModel& model() const { return model_; }
  sinew::barnet::BarnetState& state() { return state_; }
  const sinew::barnet::StepOutputs& outputs() const { return outputs_; }
  int32_t length_exponent() const { return build_.length_exponent; }

  // Model-space metres of a Len value.
  double metres(int32_t len) const;

 private:
  rigc::RigSpec spec_;
  std::string error_;
  std::vector<uint64_t> blob_, rig_arena_, engine_arena_, barnet_arena_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<int32_t> inputs_, external_;
  BarnetBuild build_;
  sinew::barnet::BarnetModel model_;
  sinew::barnet::BarnetState state_;
  std::vector<int32_t> out_[6];
  sinew::barnet::StepOutputs outputs_;
};

// Degrees -> signed binary angle (exact for multiples of 360 / 2^32 turn).
int32_t degrees_to_angle(double degrees);

}  // namespace sinew::layers::barnet
