#include "barnet_layer.hpp"

#include <vector>

#include "host_tools/layers/barnet/arm_net.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/barnet/barnet.hpp"

namespace sinew::firmware {

namespace {

class BarnetLayer final : public PoseLayer {
 public:
  const char* name() const override { return "barnet"; }
  bool apply(engine::Engine& engine, std::span<const int32_t> inputs) override {
    if (!barnet::barnet_step(&state_, {engine.model, inputs}, outputs_).ok()) return false;
    for (size_t k = 0; k < model_.wrap.size(); ++k)
      for (int c = 0; c < 3; ++c) engine.vertices.position[c][model_.wrap[k].vertex] = outputs_.skin[c][k];
    return true;
  }

  layers::barnet::BarnetBuild build_;
  barnet::BarnetModel model_;
  std::vector<uint64_t> memory_;
  barnet::BarnetState state_;
  std::vector<int32_t> out_[6];
  barnet::StepOutputs outputs_;
};

}  // namespace

std::unique_ptr<PoseLayer> make_arm_barnet_layer(const rig::Rig& rig, std::string* error) {
  auto layer = std::make_unique<BarnetLayer>();
  const rigc::RigSpec arm = rigc::builtin_arm();
  layers::barnet::NetSpec net;
  if (!layers::barnet::arm_elbow_net(arm, {}, &net, error) ||
      !layers::barnet::build_barnet(net, arm, &layer->build_, error))
    return *error = "barnet layer: " + *error, nullptr;
  layer->model_ = layer->build_.model();
  if (layer->build_.length_exponent != rig.length_exponent || layer->model_.vertex_count != rig.vertex_count() ||
      layer->model_.joint_count != rig.joint_count())
    return *error = "barnet layer: built for a different rig than the one loaded", nullptr;
  layer->memory_.assign(barnet::barnet_state_bytes(layer->model_) / 8 + 1, 0);
  const barnet::Status s =
      barnet::barnet_init(layer->model_, layer->memory_.data(), layer->memory_.size() * 8, &layer->state_);
  if (!s.ok()) return *error = std::string("barnet layer: ") + s.message, nullptr;
  for (int c = 0; c < 3; ++c) {
    layer->out_[c].assign(layer->model_.nodes.size(), 0);
    layer->out_[3 + c].assign(layer->model_.wrap.size(), 0);
    layer->outputs_.node[c] = layer->out_[c];
    layer->outputs_.skin[c] = layer->out_[3 + c];
  }
  return layer;
}

}  // namespace sinew::firmware
