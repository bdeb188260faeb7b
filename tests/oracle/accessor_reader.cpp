#include "accessor_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace sinew::oracle::detail {
namespace {

size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // includes DOUBLE, which glTF 2.0 does not allow
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

int matrix_rows(int type) {
  switch (type) {
    case TINYGLTF_TYPE_MAT2:
      return 2;
    case TINYGLTF_TYPE_MAT3:
      return 3;
    case TINYGLTF_TYPE_MAT4:
      return 4;
    default:
      return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "unknown";
  }
}

template <typename T>
T load(const unsigned char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof value);  // glTF is little-endian, as are all sinew hosts
  return value;
}

// Normalised integers map to [-1, 1] or [0, 1] by the glTF 2.0 formulas.
double decode(const unsigned char* bytes, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load<int8_t>(bytes);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double v = load<uint8_t>(bytes);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load<int16_t>(bytes);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double v = load<uint16_t>(bytes);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      const double v = load<uint32_t>(bytes);
      return normalized ? v / 4294967295.0 : v;
    }
    default:
      return static_cast<double>(load<float>(bytes));
  }
}

// Byte offset of each component inside one element: matrix columns start on
// 4-byte boundaries (glTF 2.0 "Data Alignment"), everything else is packed.
std::vector<size_t> component_offsets(int type, size_t size, size_t* element_bytes) {
  const int rows = matrix_rows(type);
  std::vector<size_t> offsets;
  if (rows == 0) {
    for (int c = 0; c < component_count(type); ++c) offsets.push_back(static_cast<size_t>(c) * size);
    *element_bytes = offsets.size() * size;
    return offsets;
  }
  const size_t column_bytes = (static_cast<size_t>(rows) * size + 3) / 4 * 4;
  for (int col = 0; col < rows; ++col)
    for (int row = 0; row < rows; ++row)
      offsets.push_back(static_cast<size_t>(col) * column_bytes + static_cast<size_t>(row) * size);
  *element_bytes = static_cast<size_t>(rows) * column_bytes;
  return offsets;
}

// The bytes of a buffer view, checked against its buffer.
bool view_bytes(const tinygltf::Model& model, int view_index, const std::string& what, const unsigned char** data,
                size_t* length, std::string* error) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size()) {
    *error = what + ": bufferView " + std::to_string(view_index) + " does not exist";
    return false;
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(view_index)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size()) {
    *error =
        what + ": bufferView " + std::to_string(view_index) + " names missing buffer " + std::to_string(view.buffer);
    return false;
  }
  const std::vector<unsigned char>& buffer = model.buffers[static_cast<size_t>(view.buffer)].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
    *error = what + ": bufferView " + std::to_string(view_index) + " (offset " + std::to_string(view.byteOffset) +
             ", length " + std::to_string(view.byteLength) + ") runs past its buffer of " +
             std::to_string(buffer.size()) + " bytes";
    return false;
  }
  *data = buffer.data() + view.byteOffset;
  *length = view.byteLength;
  return true;
}

// True when `count` records of `record` bytes, `stride` apart, fit in `length` bytes from `offset`.
bool fits(size_t length, size_t offset, size_t count, size_t stride, size_t record) {
  if (count == 0) return offset <= length;
  if (offset > length || length - offset < record) return false;
  return count - 1 <= (length - offset - record) / stride;
}

bool apply_sparse(const tinygltf::Model& model, const tinygltf::Accessor& accessor, const std::string& what,
                  const std::vector<size_t>& offsets, size_t element_bytes, AccessorData* out, std::string* error) {
  const auto& sparse = accessor.sparse;
  if (sparse.count < 1 || static_cast<size_t>(sparse.count) > accessor.count) {
    *error =
        what + ": sparse count " + std::to_string(sparse.count) + " is not in 1.." + std::to_string(accessor.count);
    return false;
  }
  const auto count = static_cast<size_t>(sparse.count);
  const size_t index_size = component_size(sparse.indices.componentType);
  if (sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || index_size == 0 ||
      sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
      sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT) {
    *error = what + ": sparse indices must be unsigned byte, short or int";
    return false;
  }
  const unsigned char* indices = nullptr;
  const unsigned char* values = nullptr;
  size_t indices_length = 0, values_length = 0;
  if (!view_bytes(model, sparse.indices.bufferView, what + " sparse indices", &indices, &indices_length, error) ||
      !view_bytes(model, sparse.values.bufferView, what + " sparse values", &values, &values_length, error))
    return false;
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0 ||
      !fits(indices_length, static_cast<size_t>(sparse.indices.byteOffset), count, index_size, index_size) ||
      !fits(values_length, static_cast<size_t>(sparse.values.byteOffset), count, element_bytes, element_bytes)) {
    *error = what + ": sparse indices or values run past their bufferView";
    return false;
  }
  indices += sparse.indices.byteOffset;
  values += sparse.values.byteOffset;
  const size_t components = offsets.size();
  for (size_t i = 0; i < count; ++i) {
    const auto target = static_cast<size_t>(decode(indices + i * index_size, sparse.indices.componentType, false));
    if (target >= accessor.count) {
      *error = what + ": sparse index " + std::to_string(target) + " is out of range (count " +
               std::to_string(accessor.count) + ")";
      return false;
    }
    for (size_t c = 0; c < components; ++c)
      out->values[target * components + c] =
          decode(values + i * element_bytes + offsets[c], accessor.componentType, accessor.normalized);
  }
  return true;
}

}  // namespace

bool read_accessor(const tinygltf::Model& model, int index, int type, const std::string& what, AccessorData* out,
                   std::string* error) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    *error = what + ": accessor " + std::to_string(index) + " does not exist";
    return false;
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string name = what + " (accessor " + std::to_string(index) + ")";
  if (accessor.type != type) {
    *error = name + ": expected " + type_name(type) + ", found " + type_name(accessor.type);
    return false;
  }
  const size_t size = component_size(accessor.componentType);
  if (size == 0) {
    *error = name + ": unsupported componentType " + std::to_string(accessor.componentType);
    return false;
  }
  size_t element_bytes = 0;
  const std::vector<size_t> offsets = component_offsets(type, size, &element_bytes);
  const size_t components = offsets.size();
  out->count = accessor.count;
  out->components = static_cast<int>(components);

  if (accessor.bufferView < 0) {
    // No bufferView means all zeros (then sparse substitution); the count is
    // unchecked by any buffer, so refuse absurd ones before allocating.
    if (accessor.count > (size_t{1} << 26)) {
      *error = name + ": implausible count " + std::to_string(accessor.count) + " without a bufferView";
      return false;
    }
    out->values.assign(accessor.count * components, 0.0);
  } else {
    const unsigned char* data = nullptr;
    size_t length = 0;
    if (!view_bytes(model, accessor.bufferView, name, &data, &length, error)) return false;
    const size_t declared = model.bufferViews[static_cast<size_t>(accessor.bufferView)].byteStride;
    const size_t stride = declared > 0 ? declared : element_bytes;
    if (stride < element_bytes) {
      *error = name + ": byteStride " + std::to_string(stride) + " is smaller than its " +
               std::to_string(element_bytes) + "-byte elements";
      return false;
    }
    if (!fits(length, accessor.byteOffset, accessor.count, stride, element_bytes)) {
      *error = name + ": " + std::to_string(accessor.count) + " elements from byteOffset " +
               std::to_string(accessor.byteOffset) + " run past its " + std::to_string(length) + "-byte bufferView";
      return false;
    }
    out->values.assign(accessor.count * components, 0.0);
    for (size_t i = 0; i < accessor.count; ++i) {
      const unsigned char* element = data + accessor.byteOffset + i * stride;
      for (size_t c = 0; c < components; ++c)
        out->values[i * components + c] = decode(element + offsets[c], accessor.componentType, accessor.normalized);
    }
  }
  if (accessor.sparse.isSparse) return apply_sparse(model, accessor, name, offsets, element_bytes, out, error);
  return true;
}

}  // namespace sinew::oracle::detail
