// The contract between the spec-driven compilation (rig_layers.cpp) and each
// layer's offline side: what a layer's compile step sees (the rig spec, the
// compiled core loaded as the board loads it, its geometry, the tick rate
// and the blob's external inputs) and where it puts its sections and report
// lines. Each layer specialises HostLayer<Stage> in
// host_tools/layers/<layer>/<layer>_compile.hpp with its spec tables and two
// steps; rig_layers.cpp runs them in the order of sim_core's stage list.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/layers/sections/layer_section.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/pipeline/layer_format.hpp"
#include "sim_core/pipeline/stage.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::layers {

// A joint named in a spec: by name, or by glTF node index where the model's
// nodes have no names. `where` ("file:line: key") prefixes every message.
struct JointRef {
  std::string name;
  int node = -1;  // >= 0: by glTF node index
  std::string where;
};

// An [[external_input]] table, or an input a layer declares for itself.
struct ExternalInputTable {
  std::string name, unit = "N", quantity = "force";
  double min = -40, max = 40;
  std::string where;
};

struct LayerCompile {
  const rigc::RigSpec& spec;
  const rig::Rig& rig;  // the compiled core, loaded by sim_core's loader
  const RigGeometry& geometry;
  uint32_t rate_hz;                                       // the tick rate the rig is built for
  std::span<const pipeline::ExternalInputRecord> inputs;  // the blob's external inputs, in index order
  std::vector<LayerSection>* sections;
  std::vector<std::string>* report;

  // The index of the external input named `name`, or kNoExternalInput.
  uint32_t input_index(const std::string& name) const;
};

// A layer's offline side, specialised per stage of sim_core's stage list:
//   Tables: what the rig spec says of the layer (empty(): the layer is off);
//   bent_joints: the joints the layer bends through an angle (they get a
//     rotational DOF if they have none; add_layer_dofs);
//   declare_inputs: the external inputs the layer reads and that the spec
//     need not declare (declare_input adds them unless declared);
//   compile: builds the layer and appends its sections and report lines.
template <pipeline::Stage S>
struct HostLayer;

// Skinning is the core rig (rigc's compile_rig), not a layer section.
template <>
struct HostLayer<pipeline::Stage::kSkinning> {
  struct Tables {
    bool empty() const { return true; }
  };
  static void bent_joints(const Tables&, std::vector<const JointRef*>*) {}
  static bool declare_inputs(const rigc::RigSpec&, const Tables&, std::vector<ExternalInputTable>*, std::string*) {
    return true;
  }
  static bool compile(const LayerCompile&, const Tables&, std::string*) { return true; }
};

// Adds `input` unless an input of its name is declared already.
void declare_input(std::vector<ExternalInputTable>* external, const ExternalInputTable& input);

// The joint index a reference names, or -1 with a message.
int resolve_joint(const rigc::RigSpec& spec, const JointRef& ref, std::string* error);

// *error = "where: problem" (or the problem alone); false.
bool layer_fail(const std::string& where, const std::string& problem, std::string* error);

// A number as a report line shows it (4 significant digits).
std::string report_number(double v);

}  // namespace sinew::layers
