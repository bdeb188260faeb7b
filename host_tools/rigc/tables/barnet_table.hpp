// The barnet layer's [[barnet]] tables (docs/barnet.md).
#pragma once

#include "host_tools/rigc/tables/rigc_table.hpp"

namespace sinew::rigc {

template <>
struct RigcTable<pipeline::Stage::kBarnet> {
  using Tables = layers::HostLayer<pipeline::Stage::kBarnet>::Tables;
  static bool owns(std::string_view key) { return key == "barnet"; }
  static bool read(const std::string& path, const toml::table& root, Tables* out, std::string* error);
};

}  // namespace sinew::rigc
