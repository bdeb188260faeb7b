// A built-in rig compiled, loaded and ready to step, for engine tests.
#pragma once

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"

namespace sinew::test {

class LoadedRig {
 public:
  explicit LoadedRig(const rigc::RigSpec& spec) : spec_(spec) {
    std::vector<uint8_t> bytes;
    std::string error;
    ok_ = rigc::compile_rig(spec_, &bytes, &report_, &error);
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
  }
  bool ok() const { return ok_; }
  const rig::Rig& rig() const { return rig_; }
  engine::Engine& engine() { return engine_; }
  std::vector<int32_t>& inputs() { return inputs_; }
  const rigc::RigSpec& spec() const { return spec_; }
  const rigc::CompileReport& report() const { return report_; }
  int input(const std::string& name) const {
    const auto names = rigc::input_names(spec_);
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    return -1;
  }
  bool step(const layer::Workers* workers = nullptr) { return engine::engine_step(&engine_, inputs_, workers); }
  double position(int axis, uint32_t v) const {
    return std::ldexp(static_cast<double>(engine_.vertices.position[axis][v]), report_.length_exponent - 20);
  }

 private:
  rigc::RigSpec spec_;
  rigc::CompileReport report_;
  bool ok_ = false;
  std::vector<uint64_t> blob_, rig_arena_, engine_arena_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<int32_t> inputs_;
};

// Degrees -> signed binary angle.
inline int32_t degrees(double d) { return static_cast<int32_t>(std::llround(d / 360.0 * 4294967296.0)); }

}  // namespace sinew::test
