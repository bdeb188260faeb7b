// Poses a glTF skin through sinew's fixed-point pipeline: the animation is
// sampled on the host (double), converted to fixed-point local transforms,
// and everything after that - model transforms, skinning matrices, LBS - runs
// in sim_core exactly as on the board.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_import.hpp"
#include "sim_core/engine/engine.hpp"

namespace sinew::rigc {

class GltfPoser {
 public:
  bool open(const std::string& path, std::string* error);
  // Skinned world-space positions of every skinned primitive (document
  // order), in glTF units.
  bool pose(int animation, double time, std::vector<std::array<double, 3>>* positions, std::string* error);
  const CompileReport& report() const { return report_; }
  const tinygltf::Model& model() const { return gltf_.model; }

 private:
  GltfRig gltf_;
  CompileReport report_;
  std::vector<uint64_t> blob_;  // 8-byte aligned storage
  std::vector<uint64_t> rig_arena_, engine_arena_;
  rig::Rig rig_;
  engine::Engine engine_;
  std::vector<skeleton::LocalPose> locals_;
};

}  // namespace sinew::rigc
