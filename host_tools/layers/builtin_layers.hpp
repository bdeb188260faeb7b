// The layer tables of the built-in rigs, the same as their commented specs
// under rigs/ (rigs/arm.toml, rigs/hand.toml); a test compiles both and
// compares the blobs byte for byte. They are here as code so the build can
// compile the built-in blobs without a TOML or glTF parser, in every preset.
#pragma once

#include <string>

#include "rig_layers.hpp"

namespace sinew::layers {

// "arm" or "hand"; false for another name.
bool builtin_layers(const std::string& name, LayerSpecs* out);

// The built-in rig `name` with its layers, compiled: the blob the daemon
// embeds for [rig] builtin = "<name>".
bool compile_builtin(const std::string& name, std::vector<uint8_t>* blob, std::vector<std::string>* report,
                     std::string* error);

}  // namespace sinew::layers
