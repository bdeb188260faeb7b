// The sph layer's [[sph]] tables (docs/sph.md, docs/rig-format.md).
#pragma once

#include "host_tools/rigc/tables/rigc_table.hpp"

namespace sinew::rigc {

template <>
struct RigcTable<pipeline::Stage::kSph> {
  using Tables = layers::HostLayer<pipeline::Stage::kSph>::Tables;
  static bool owns(std::string_view key) { return key == "sph"; }
  static bool read(const std::string& path, const toml::table& root, Tables* out, std::string* error);
};

}  // namespace sinew::rigc
