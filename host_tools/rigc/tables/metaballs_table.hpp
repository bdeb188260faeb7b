// The metaballs layer's [metaballs] table and its [[metaballs.jiggle]],
// [[metaballs.bulge]] and [[metaballs.action_line]] (docs/metaballs.md).
#pragma once

#include "host_tools/rigc/tables/rigc_table.hpp"

namespace sinew::rigc {

template <>
struct RigcTable<pipeline::Stage::kMetaballs> {
  using Tables = layers::HostLayer<pipeline::Stage::kMetaballs>::Tables;
  static bool owns(std::string_view key) { return key == "metaballs"; }
  static bool read(const std::string& path, const toml::table& root, Tables* out, std::string* error);
};

}  // namespace sinew::rigc
