// The physical layers a rig spec asks for (each layer's tables, and
// [[external_input]]; docs/rig-format.md lists every key), built for any
// skeleton by the offline builders and written into the rig blob as layer
// sections. A table holding only its required keys works
// on any model: every other parameter derives from the rig's geometry
// (layers/common/rig_geometry.hpp). Runs on the host only; the board loads
// the fixed-point results.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

// One line per layer: its offline side's tables and steps.
#include "host_tools/layers/anatomy/anatomy_compile.hpp"
#include "host_tools/layers/barnet/barnet_compile.hpp"
#include "host_tools/layers/metaballs/metaballs_compile.hpp"
#include "host_tools/layers/sph/sph_compile.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/pipeline/stage_list.hpp"

namespace sinew::layers {

// Every layer's spec tables, one member per stage of sim_core's stage list
// (sim_core/pipeline/stage_list.hpp), named after the stage and typed by the
// layer's HostLayer<Stage>::Tables (layers/<layer>/<layer>_compile.hpp).
struct LayerSpecs {
  uint32_t rate_hz = 1000;  // tick rate the rate-dependent layers are built for
#define SINEW_LAYER_SPEC_MEMBER(name, enumerator, sections, doc) HostLayer<pipeline::Stage::enumerator>::Tables name;
  SINEW_STAGE_LIST(SINEW_LAYER_SPEC_MEMBER)
#undef SINEW_LAYER_SPEC_MEMBER
  std::vector<ExternalInputTable> external;
  bool empty() const;
};

// Gives every joint a layer drives through an angle (HostLayer::bent_joints)
// and that has no rotational DOF (glTF joints have none) one rotational DOF
// about its bend axis: the normal of the plane of its parent's bone and its
// own, or a perpendicular of the parent's bone where they are collinear;
// limits +-150 degrees. Run before compile_rig; one report line per joint.
bool add_layer_dofs(rigc::RigSpec* spec, const LayerSpecs& layers, std::vector<std::string>* report,
                    std::string* error);

// Appends the layer sections to `blob` (compile_rig's output for `spec`).
// `report` gets one line per layer. Errors name the spec line and the problem.
bool compile_layers(const rigc::RigSpec& spec, const LayerSpecs& layers, std::vector<uint8_t>* blob,
                    std::vector<std::string>* report, std::string* error);

}  // namespace sinew::layers
