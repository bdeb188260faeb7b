#include "gltf_accessor.hpp"

#include <cstring>

namespace sinew::rigc {
namespace {

int component_bytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

double decode(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<signed char>(*p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Reads `count` elements of `components` values from a buffer view region.
bool read_view(const tinygltf::Model& model, int view_index, size_t offset, size_t count, int components, int type,
               bool normalized, size_t stride_override, std::vector<double>* out, const std::string& what,
               std::string* error) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
    return *error = what + ": bufferView index out of range", false;
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(view_index)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    return *error = what + ": buffer index out of range", false;
  const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
  const size_t elem = static_cast<size_t>(component_bytes(type)) * static_cast<size_t>(components);
  const size_t stride = stride_override != 0 ? stride_override : (view.byteStride != 0 ? view.byteStride : elem);
  if (view.byteOffset + view.byteLength > data.size()) return *error = what + ": bufferView exceeds its buffer", false;
  if (count > 0 && offset + (count - 1) * stride + elem > view.byteLength)
    return *error = what + ": accessor exceeds its bufferView", false;
  const unsigned char* base = data.data() + view.byteOffset + offset;
  out->resize(count * static_cast<size_t>(components));
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < components; ++c)
      (*out)[i * static_cast<size_t>(components) + static_cast<size_t>(c)] =
          decode(base + i * stride + static_cast<size_t>(c) * static_cast<size_t>(component_bytes(type)), type, normalized);
  return true;
}

}  // namespace

bool read_accessor(const tinygltf::Model& model, int accessor, std::vector<double>* out, int* components,
                   std::string* error) {
  const std::string what = "accessor " + std::to_string(accessor);
  if (accessor < 0 || static_cast<size_t>(accessor) >= model.accessors.size())
    return *error = what + ": index out of range", false;
  const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(accessor)];
  const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (n <= 0 || component_bytes(a.componentType) == 0) return *error = what + ": unsupported type", false;
  *components = n;
  const size_t count = a.count;
  if (a.bufferView >= 0) {
    if (!read_view(model, a.bufferView, a.byteOffset, count, n, a.componentType, a.normalized, 0, out, what, error))
      return false;
  } else {
    out->assign(count * static_cast<size_t>(n), 0.0);  // no bufferView: zeros (sparse may fill)
  }
  if (a.sparse.isSparse) {
    std::vector<double> indices, values;
    if (!read_view(model, a.sparse.indices.bufferView, static_cast<size_t>(a.sparse.indices.byteOffset),
                   static_cast<size_t>(a.sparse.count), 1, a.sparse.indices.componentType, false, 0, &indices,
                   what + " sparse indices", error) ||
        !read_view(model, a.sparse.values.bufferView, static_cast<size_t>(a.sparse.values.byteOffset),
                   static_cast<size_t>(a.sparse.count), n, a.componentType, a.normalized, 0, &values,
                   what + " sparse values", error))
      return false;
    for (size_t i = 0; i < indices.size(); ++i) {
      const size_t target = static_cast<size_t>(indices[i]);
      if (target >= count) return *error = what + ": sparse index beyond count", false;
      for (int c = 0; c < n; ++c)
        (*out)[target * static_cast<size_t>(n) + static_cast<size_t>(c)] = values[i * static_cast<size_t>(n) + static_cast<size_t>(c)];
    }
  }
  return true;
}

}  // namespace sinew::rigc
