// Reads any glTF 2.0 accessor into doubles, bounds-checked: every component
// type, normalized integers, byteStride, sparse substitution.
#pragma once

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <string>
#include <vector>

namespace sinew::rigc {

// out receives count * components values, row by row. Returns false with a
// message naming the accessor on any out-of-bounds or malformed field.
bool read_accessor(const tinygltf::Model& model, int accessor, std::vector<double>* out, int* components,
                   std::string* error);

}  // namespace sinew::rigc
