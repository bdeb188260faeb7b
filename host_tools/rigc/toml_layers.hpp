// The layer tables of a TOML rig spec (each layer's, read by its
// tables/<layer>_table.cpp; [[external_input]]; and [rig] rate_hz), read into
// layers::LayerSpecs. Unknown keys and wrong types are refused with the
// file, the line and the key. docs/rig-format.md lists every key.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <string_view>

#include "host_tools/layers/rig_layers.hpp"
#include "rig_spec.hpp"

namespace sinew::rigc {

bool read_toml_layers(const std::string& path, const toml::table& t, layers::LayerSpecs* out, std::string* error);

// A top-level table a layer owns, or [[external_input]].
bool is_layer_table(std::string_view key);

}  // namespace sinew::rigc
