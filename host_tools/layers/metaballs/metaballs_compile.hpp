// The metaballs layer's offline side (layers/common/layer_compile.hpp): its
// [metaballs] table and its compilation into an MBAL section.
#pragma once

#include <string>
#include <vector>

#include "host_tools/layers/common/layer_compile.hpp"
#include "host_tools/layers/metaballs/options.hpp"

namespace sinew::layers {

struct MetaballsTable {
  bool on = false;
  std::string where;
  double ball_spacing = 0;  // 0: 0.22 x the mean skin radius (at most 3000 balls along the bones)
  // Every other [metaballs] key (docs/metaballs.md); ball_spacing above and
  // the rig's rate_hz override theirs.
  metaballs_build::Options options;
  bool empty() const { return !on; }
};

template <>
struct HostLayer<pipeline::Stage::kMetaballs> {
  using Tables = MetaballsTable;
  static void bent_joints(const Tables&, std::vector<const JointRef*>*) {}
  static bool declare_inputs(const rigc::RigSpec&, const Tables&, std::vector<ExternalInputTable>*, std::string*) {
    return true;
  }
  static bool compile(const LayerCompile& c, const Tables& table, std::string* error);
};

}  // namespace sinew::layers
