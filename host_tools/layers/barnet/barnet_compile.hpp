// The barnet layer's offline side (layers/common/layer_compile.hpp): its
// [[barnet]] tables and their compilation into BNET sections.
#pragma once

#include <string>
#include <vector>

#include "host_tools/layers/common/layer_compile.hpp"

namespace sinew::layers {

struct BarnetTable {
  JointRef joint;
  int segments = 8, rings = 7;
  double ring_step = 0;  // 0: 0.65 x the skin radius
  double force = 0;      // 0: 1.1 x the skin radius (q x model units)
  // External inputs, declared (N, force, +-40; scalar, [1/256, 256]) if no
  // [[external_input]] has the name. force_input: activation 0 at 0, 1 at
  // force_input_full (its unit) instead of the flexion; q_input: scales every
  // bar's force density by its value.
  std::string force_input = {};
  std::string q_input = {};
  double force_input_full = 40;
  // barnet-driven-skinning's nets, on any rig: "joint", a ring net around
  // `joint` (Figure 2); "muscles", the flexor/extensor net along the bone
  // before `joint` (Figure 3; `segments` even, `force` apply); "wrinkles", a
  // wrinkle net on the skin mesh on the fold side of `joint` (Figure 6;
  // `force` applies). On the built-in arm only, the arm's own "arm-muscles"
  // and "arm-wrinkles" (the elbow's; the ring keys are ignored). Every net
  // takes force_input and q_input.
  std::string net = "joint";
};

template <>
struct HostLayer<pipeline::Stage::kBarnet> {
  using Tables = std::vector<BarnetTable>;
  static void bent_joints(const Tables& tables, std::vector<const JointRef*>* joints);
  // Each net's force and force-density inputs.
  static bool declare_inputs(const rigc::RigSpec& spec, const Tables& tables, std::vector<ExternalInputTable>* external,
                             std::string* error);
  static bool compile(const LayerCompile& c, const Tables& tables, std::string* error);
};

}  // namespace sinew::layers
