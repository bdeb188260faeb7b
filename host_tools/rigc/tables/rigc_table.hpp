// A layer's tables in a TOML rig spec (docs/rig-format.md lists every key):
// RigcTable<Stage>, specialised in tables/<layer>_table.hpp, names the
// top-level tables the layer owns and reads them into the layer's
// HostLayer<Stage>::Tables (host_tools/layers/<layer>/<layer>_compile.hpp).
// toml_layers.cpp runs every stage's, in the order of the stage list.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <string_view>

#include "host_tools/layers/rig_layers.hpp"
#include "sim_core/pipeline/stage.hpp"

namespace sinew::rigc {

template <pipeline::Stage S>
struct RigcTable;

// Skinning is the core spec ([rig], [[joint]], [[synergy]]; toml_spec.cpp).
template <>
struct RigcTable<pipeline::Stage::kSkinning> {
  using Tables = layers::HostLayer<pipeline::Stage::kSkinning>::Tables;
  static bool owns(std::string_view) { return false; }
  static bool read(const std::string&, const toml::table&, Tables*, std::string*) { return true; }
};

}  // namespace sinew::rigc
