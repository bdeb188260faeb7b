// Reads any glTF 2.0 accessor into doubles, bounds-checked: every component
// type, normalized integers, byteStride, sparse substitution.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sinew::rigc {

// out receives count * components values, row by row. Returns false with a
// message naming the accessor on any out-of-bounds or malformed field: every
// offset, stride and count is checked against its bufferView and buffer with
// overflow-safe arithmetic, the count against `max_count` before anything is
// allocated, and float data must be finite.
bool read_accessor(const tinygltf::Model& model, int accessor, size_t max_count, std::vector<double>* out,
                   int* components, std::string* error);

// The accessor's componentType, or -1 if the index is out of range.
int accessor_component_type(const tinygltf::Model& model, int accessor);

}  // namespace sinew::rigc
