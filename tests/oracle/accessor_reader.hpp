#pragma once
// Generic glTF accessor reading: every component type, normalisation,
// byteStride, matrix column padding and sparse substitution, bounds-checked,
// returned as doubles so the oracle never depends on how a file stores data.
#include <cstddef>
#include <string>
#include <vector>

#include "gltf_model.hpp"

namespace sinew::oracle::detail {

struct AccessorData {
  std::vector<double> values;  // count * components; matrices column-major, as in glTF
  size_t count = 0;
  int components = 0;

  double at(size_t element, int component) const {
    return values[element * static_cast<size_t>(components) + static_cast<size_t>(component)];
  }
};

// Reads accessor `index` of element type `type` (TINYGLTF_TYPE_VEC3, ...).
// `what` names the accessor's role in error messages ("POSITION of mesh 0 primitive 1").
bool read_accessor(const tinygltf::Model& model, int index, int type, const std::string& what, AccessorData* out,
                   std::string* error);

}  // namespace sinew::oracle::detail
