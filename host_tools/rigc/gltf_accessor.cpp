#include "gltf_accessor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace sinew::rigc {
namespace {

size_t component_bytes(int type) {
  switch (type) {
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
      return 0;
  }
}

// Overflow-safe size arithmetic: false when the exact result does not fit.
bool add(size_t a, size_t b, size_t* r) { return !__builtin_add_overflow(a, b, r); }
bool mul(size_t a, size_t b, size_t* r) { return !__builtin_mul_overflow(a, b, r); }

double decode(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<signed char>(*p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? *p / 255.0 : *p;
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

// Reads `count` elements of `components` values from a buffer view region,
// starting `offset` bytes into the view. `tight` ignores the view's byteStride
// (sparse index and value views are always tightly packed).
bool read_view(const tinygltf::Model& model, int view_index, size_t offset, size_t count, size_t components, int type,
               bool normalized, bool tight, std::vector<double>* out, const std::string& what, std::string* error) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
    return *error = what + ": bufferView index out of range", false;
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(view_index)];
  const std::string where = what + " (bufferView " + std::to_string(view_index) + ")";
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    return *error = where + ": buffer index out of range", false;
  const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
  const size_t cbytes = component_bytes(type);
  if (cbytes == 0) return *error = where + ": unsupported componentType " + std::to_string(type), false;
  const size_t elem = cbytes * components;
  size_t view_end = 0;
  if (!add(view.byteOffset, view.byteLength, &view_end) || view_end > data.size())
    return *error = where + ": byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                    std::to_string(view.byteLength) + " exceeds its buffer of " + std::to_string(data.size()) +
                    " bytes",
           false;
  if (!tight && view.byteStride != 0 && view.byteStride < elem)
    return *error = where + ": byteStride " + std::to_string(view.byteStride) + " is smaller than the element (" +
                    std::to_string(elem) + " bytes)",
           false;
  const size_t stride = !tight && view.byteStride != 0 ? view.byteStride : elem;
  if (count == 0) {
    out->clear();
    return true;
  }
  // The last element ends at offset + (count - 1) * stride + elem.
  size_t last = 0, end = 0;
  if (!mul(count - 1, stride, &last) || !add(last, offset, &end) || !add(end, elem, &end) || end > view.byteLength)
    return *error = where + ": byteOffset " + std::to_string(offset) + " and count " + std::to_string(count) +
                    " exceed the bufferView's " + std::to_string(view.byteLength) + " bytes",
           false;
  const unsigned char* base = data.data() + view.byteOffset + offset;
  out->resize(count * components);  // count * elem <= byteLength: cannot overflow
  for (size_t i = 0; i < count; ++i)
    for (size_t c = 0; c < components; ++c) {
      const double v = decode(base + i * stride + c * cbytes, type, normalized);
      if (!std::isfinite(v))
        return *error = what + ": element " + std::to_string(i) + " is not finite (NaN or infinity)", false;
      (*out)[i * components + c] = v;
    }
  return true;
}

}  // namespace

int accessor_component_type(const tinygltf::Model& model, int accessor) {
  if (accessor < 0 || static_cast<size_t>(accessor) >= model.accessors.size()) return -1;
  return model.accessors[static_cast<size_t>(accessor)].componentType;
}

bool read_accessor(const tinygltf::Model& model, int accessor, size_t max_count, std::vector<double>* out,
                   int* components, std::string* error) {
  const std::string what = "accessor " + std::to_string(accessor);
  if (accessor < 0 || static_cast<size_t>(accessor) >= model.accessors.size())
    return *error = what + ": index out of range", false;
  const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(accessor)];
  const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (n <= 0) return *error = what + ": unsupported type", false;
  if (component_bytes(a.componentType) == 0)
    return *error = what + ": unsupported componentType " + std::to_string(a.componentType), false;
  // glTF allows normalized only for 8- and 16-bit integers.
  if (a.normalized &&
      (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    return *error = what + ": normalized is only allowed for byte and short components", false;
  const size_t comps = static_cast<size_t>(n);
  *components = n;
  const size_t count = a.count;
  if (count > max_count)
    return *error = what + ": count " + std::to_string(count) + " exceeds the limit of " + std::to_string(max_count),
           false;
  if (a.bufferView >= 0) {
    if (!read_view(model, a.bufferView, a.byteOffset, count, comps, a.componentType, a.normalized, false, out, what,
                   error))
      return false;
  } else {
    out->assign(count * comps, 0.0);  // no bufferView: zeros (sparse may fill); count * comps <= max_count * 16
  }
  if (a.sparse.isSparse) {
    const std::string sw = what + " sparse";
    if (a.sparse.count < 1 || static_cast<size_t>(a.sparse.count) > count)
      return *error = sw + ": count " + std::to_string(a.sparse.count) + " is not within 1.." + std::to_string(count),
             false;
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
      return *error = sw + ": negative byteOffset", false;
    const int it = a.sparse.indices.componentType;
    if (it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return *error = sw + " indices: componentType must be an unsigned integer", false;
    std::vector<double> indices, values;
    const size_t sparse_count = static_cast<size_t>(a.sparse.count);
    if (!read_view(model, a.sparse.indices.bufferView, static_cast<size_t>(a.sparse.indices.byteOffset), sparse_count,
                   1, it, false, true, &indices, sw + " indices", error) ||
        !read_view(model, a.sparse.values.bufferView, static_cast<size_t>(a.sparse.values.byteOffset), sparse_count,
                   comps, a.componentType, a.normalized, true, &values, sw + " values", error))
      return false;
    for (size_t i = 0; i < indices.size(); ++i) {
      const size_t target = static_cast<size_t>(indices[i]);
      if (target >= count) return *error = sw + ": index " + std::to_string(target) + " beyond count", false;
      for (size_t c = 0; c < comps; ++c) (*out)[target * comps + c] = values[i * comps + c];
    }
  }
  return true;
}

}  // namespace sinew::rigc
