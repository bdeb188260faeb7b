// The sph layer's offline side (layers/common/layer_compile.hpp): its
// [[sph]] tables and their compilation into SPHJ sections.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host_tools/layers/common/layer_compile.hpp"

namespace sinew::layers {

struct SphTable {
  JointRef joint;  // the joint whose bend the tissue carries; its parent's bone is the other side
  uint32_t particles = 500;
  double radius = 0;           // capsule radius; 0: 0.8 x the skin radius around the joint
  double half_length = 0;      // capsule half length; 0: min(2.2 x radius, 0.4 x the shorter bone)
  double tissue_mass = 0;      // kg; 0: 1000 kg/m^3 x the capsule volume (model units read as metres)
  double yield_angle_deg = 0;  // 0: the joint's maximum flexion, at most 90 degrees (SphBuildOptions)
  std::string force_input;     // external input of the force at the distal bone's end; "" -> "<joint>.force"
  double surface_tension = 0;  // sigma, N/m (0: off; docs/sph.md)
};

template <>
struct HostLayer<pipeline::Stage::kSph> {
  using Tables = std::vector<SphTable>;
  static void bent_joints(const Tables& tables, std::vector<const JointRef*>* joints);
  // Each joint's force input, "<joint>.force" unless the table names one.
  static bool declare_inputs(const rigc::RigSpec& spec, const Tables& tables, std::vector<ExternalInputTable>* external,
                             std::string* error);
  static bool compile(const LayerCompile& c, const Tables& tables, std::string* error);
};

}  // namespace sinew::layers
