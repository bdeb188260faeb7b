// The built-in arm compiled and loaded, its anatomy built, the engine and
// both layer states initialised: one call steps engine -> muscles -> skin.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "host_tools/layers/anatomy/anatomy_build.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/muscle/muscle_step.hpp"

namespace sinew::test {

inline int32_t deg(double d) { return static_cast<int32_t>(std::llround(d / 360.0 * 4294967296.0)); }

class ArmAnatomy {
 public:
  // `tweak` may edit the anatomy spec before it is built.
  template <typename Tweak>
  explicit ArmAnatomy(Tweak tweak) : spec_(rigc::builtin_arm()) {
    std::vector<uint8_t> bytes;
    ok_ = rigc::compile_rig(spec_, &bytes, &report_, &error_);
    if (!ok_) return;
    blob_.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob_.data(), bytes.data(), bytes.size());
    const auto* data = reinterpret_cast<const uint8_t*>(blob_.data());
    size_t rig_bytes = 0;
    ok_ = rig::rig_validate(data, bytes.size(), &rig_bytes).ok();
    rig_arena_.assign(rig_bytes / 8 + 1, 0);
    ok_ = ok_ && rig::rig_init(data, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_).ok();
    if (!ok_) return;
    engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
    ok_ = engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_);
    inputs_.assign(rig_.input_count, 0);
    anatomy_spec_ = anatomy_build::arm_anatomy(spec_);
    tweak(anatomy_spec_);
    ok_ = ok_ && anatomy_build::build_anatomy(rig_, anatomy_spec_, &model_, &error_);
    if (!ok_) return;
    muscle_model_ = model_.muscle_model();
    skin_model_ = model_.skin_model();
    muscle_memory_.assign(muscle::muscle_state_bytes(muscle_model_) / 8 + 1, 0);
    skin_memory_.assign(elastic_skin::skin_state_bytes(skin_model_) / 8 + 1, 0);
    muscle::LayerStatus st =
        muscle::muscle_init(muscle_model_, muscle_memory_.data(), muscle_memory_.size() * 8, &muscles_);
    if (st.ok()) st = elastic_skin::skin_init(skin_model_, skin_memory_.data(), skin_memory_.size() * 8, &skin_);
    if (!st.ok()) error_ = st.message;
    ok_ = st.ok();
  }
  ArmAnatomy() : ArmAnatomy([](anatomy_build::AnatomySpec&) {}) {}
  ArmAnatomy(const ArmAnatomy&) = delete;  // the models' spans point into this object
  ArmAnatomy& operator=(const ArmAnatomy&) = delete;

  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }
  const rig::Rig& rig() const { return rig_; }
  const rigc::RigSpec& spec() const { return spec_; }
  int32_t length_exponent() const { return report_.length_exponent; }
  engine::Engine& engine() { return engine_; }
  std::vector<int32_t>& inputs() { return inputs_; }
  int input(const std::string& name) const {
    const auto names = rigc::input_names(spec_);
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    return -1;
  }
  void set(const std::string& name, double degrees) { inputs_[static_cast<size_t>(input(name))] = deg(degrees); }

  // engine -> muscles -> skin; returns the first failing status. workers:
  // the skin step's loops over these (null: this thread).
  muscle::LayerStatus step(const layer::Workers* workers = nullptr) {
    muscle::LayerStatus st = step_muscles();
    // 1 kHz: the dynamic skin's tick (the static one ignores the rate).
    elastic_skin::SkinTick tick{1000, {}};
    tick.workers = workers;
    if (st.ok()) st = elastic_skin::skin_step(skin_model_, muscle_model_, muscles_, engine_.model, tick, &skin_);
    return st;
  }
  // engine -> muscles only.
  muscle::LayerStatus step_muscles() {
    if (!engine::engine_step(&engine_, inputs_))
      return muscle::layer_fail(muscle::LayerError::kBadInput, "engine", -1, "inputs", "rejected");
    return muscle::muscle_step(muscle_model_, engine_.model, &muscles_);
  }

  anatomy_build::AnatomyModel& model() { return model_; }
  muscle::MuscleModel& muscle_model() { return muscle_model_; }
  elastic_skin::SkinModel& skin_model() { return skin_model_; }
  muscle::MuscleState& muscles() { return muscles_; }
  elastic_skin::SkinState& skin() { return skin_; }

  double metres(int64_t len) const { return std::ldexp(static_cast<double>(len), report_.length_exponent - 20); }
  double skin_pos(int axis, uint32_t v) const { return metres(skin_.position[axis][v]); }
  double muscle_vertex(int axis, uint32_t m, uint32_t slice, uint32_t j) const {
    return metres(muscles_.vertex[axis][muscle::muscle_vertex_index(muscles_.ring_vertices, m, slice, j)]);
  }

 private:
  rigc::RigSpec spec_;
  rigc::CompileReport report_;
  bool ok_ = false;
  std::string error_;
  std::vector<uint64_t> blob_, rig_arena_, engine_arena_, muscle_memory_, skin_memory_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<int32_t> inputs_;
  anatomy_build::AnatomySpec anatomy_spec_;
  anatomy_build::AnatomyModel model_;
  muscle::MuscleModel muscle_model_;
  elastic_skin::SkinModel skin_model_;
  muscle::MuscleState muscles_;
  elastic_skin::SkinState skin_;
};

}  // namespace sinew::test
