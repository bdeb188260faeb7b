#include "metaballs_layer.hpp"

#include <vector>

#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/metaballs/state.hpp"
#include "sim_core/metaballs/step.hpp"

namespace sinew::firmware {

namespace {

class MetaballsLayer final : public PoseLayer {
 public:
  const char* name() const override { return "metaballs"; }
  bool apply(engine::Engine& engine, std::span<const int32_t>) override {
    return metaballs::step(&state_, engine.model, engine.vertices).ok();
  }

  metaballs_build::Build build_;
  metaballs::MetaballModel model_;
  std::vector<uint64_t> memory_;
  metaballs::MetaballState state_;
};

}  // namespace

std::unique_ptr<PoseLayer> make_arm_metaballs_layer(const rig::Rig& rig, std::string* error) {
  auto layer = std::make_unique<MetaballsLayer>();
  metaballs_build::Options options;
  options.ball_spacing = 0.01;
  if (!metaballs_build::build(rigc::builtin_arm(), options, &layer->build_, error)) return nullptr;
  layer->model_ = layer->build_.model();
  if (layer->build_.vertex_count != rig.vertex_count() || layer->build_.joint_count != rig.joint_count())
    return *error = "metaballs layer: built for a different rig than the one loaded", nullptr;
  layer->memory_.assign(metaballs::state_bytes(layer->model_) / 8 + 1, 0);
  const metaballs::Status s =
      metaballs::init(layer->model_, layer->memory_.data(), layer->memory_.size() * 8, &layer->state_);
  if (!s.ok()) return *error = std::string("metaballs layer: ") + s.message, nullptr;
  return layer;
}

}  // namespace sinew::firmware
