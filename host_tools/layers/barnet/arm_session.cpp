#include "arm_session.hpp"

#include <cmath>
#include <cstring>
#include <utility>

#include "host_tools/rigc/quantize.hpp"

namespace sinew::layers::barnet {

namespace bn = sinew::barnet;

ArmSession::ArmSession(rigc::SkinChoice method, const ArmNetOptions& options)
    : ArmSession(method, [&options](const rigc::RigSpec& arm, NetSpec* net, std::string* error) {
        return arm_elbow_net(arm, options, net, error);
      }) {}

ArmSession::ArmSession(rigc::SkinChoice method, const NetBuilder& build_net)
    : ArmSession(rigc::builtin_arm(method), build_net) {}

ArmSession::ArmSession(rigc::RigSpec rig, const NetBuilder& build_net) : spec_(std::move(rig)) {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  if (!rigc::compile_rig(spec_, &bytes, &report, &error_)) return;
  blob_.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(blob_.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(blob_.data());
  size_t rig_bytes = 0;
  rig::LoadStatus ls = rig::rig_validate(data, bytes.size(), &rig_bytes);
  if (ls.ok()) {
    rig_arena_.assign(rig_bytes / 8 + 1, 0);
    ls = rig::rig_init(data, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_);
  }
  if (!ls.ok()) {
    error_ = std::string("rig: ") + ls.message;
    return;
  }
  engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
  if (!engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_)) {
    error_ = "engine: init failed";
    return;
  }
  inputs_.assign(rig_.input_count, 0);

  NetSpec net;
  if (!build_net(spec_, &net, &error_) || !build_barnet(net, spec_, &build_, &error_)) return;
  if (build_.length_exponent != rig_.length_exponent) {
    error_ = "barnet: length exponent differs from the rig's";
    return;
  }
  model_ = build_.model();
  external_.assign(model_.external_count, 0);
  const size_t bytes_needed = bn::barnet_state_bytes(model_);
  barnet_arena_.assign(bytes_needed / 8 + 1, 0);
  const bn::LayerStatus s = bn::barnet_init(model_, barnet_arena_.data(), barnet_arena_.size() * 8, &state_);
  if (!s.ok()) {
    error_ = std::string("barnet: ") + s.message;
    return;
  }
  for (size_t c = 0; c < 3; ++c) {
    out_[c].assign(model_.nodes.size(), 0);
    out_[3 + c].assign(model_.wrap.size(), 0);
    outputs_.node[c] = out_[c];
    outputs_.skin[c] = out_[3 + c];
  }
}

bool ArmSession::engine_step() { return engine::engine_step(&engine_, inputs_); }

bool ArmSession::step() {
  if (!engine::engine_step(&engine_, inputs_)) return false;
  const bn::LayerStatus s = bn::barnet_step(&state_, {engine_.model, inputs_, external_}, outputs_);
  return s.ok();
}

int ArmSession::input(const std::string& name) const {
  const auto names = rigc::input_names(spec_);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

double ArmSession::metres(int32_t len) const {
  return std::ldexp(static_cast<double>(len), build_.length_exponent - 20);
}

int32_t degrees_to_angle(double degrees) { return rigc::to_angle(degrees); }

}  // namespace sinew::layers::barnet
