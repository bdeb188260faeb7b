// The anatomy layer's [[muscle]] (with [[muscle.slice]]), [[rubber_band]]
// and [skin] tables (docs/anatomy.md).
#pragma once

#include "host_tools/rigc/tables/rigc_table.hpp"

namespace sinew::rigc {

template <>
struct RigcTable<pipeline::Stage::kAnatomy> {
  using Tables = layers::HostLayer<pipeline::Stage::kAnatomy>::Tables;
  static bool owns(std::string_view key) { return key == "muscle" || key == "rubber_band" || key == "skin"; }
  static bool read(const std::string& path, const toml::table& root, Tables* out, std::string* error);
};

}  // namespace sinew::rigc
