// A small glTF 2.0 binary (GLB) builder: one buffer held in the BIN chunk,
// buffer views appended at 4-byte alignment, accessors over them, and the
// JSON document (nlohmann-json) the caller fills with meshes, nodes and
// animations. finish() lays out the container of the glTF 2.0 spec §4.4:
// a 12-byte header, the JSON chunk padded with spaces and the BIN chunk
// padded with zeros, each to a multiple of 4 bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace sinew::gltf_export {

inline constexpr uint32_t kGlbMagic = 0x46546C67u;       // "glTF"
inline constexpr uint32_t kGlbJsonChunk = 0x4E4F534Au;   // "JSON"
inline constexpr uint32_t kGlbBinChunk = 0x004E4942u;    // "BIN\0"
inline constexpr int kTargetArrayBuffer = 34962;         // vertex attributes
inline constexpr int kTargetElementArrayBuffer = 34963;  // indices
inline constexpr int kComponentFloat = 5126;
inline constexpr int kComponentUnsignedInt = 5125;

class GlbBuilder {
 public:
  explicit GlbBuilder(const std::string& generator);

  // The document: "asset", "buffers", "bufferViews" and "accessors" are
  // kept by the builder; the caller adds the rest.
  nlohmann::json& document() { return doc_; }

  // Appends bytes to the BIN chunk at a 4-byte aligned offset and returns the
  // new bufferView's index. target: 0 (none: animation data), or one of the
  // kTarget* values.
  int add_view(const void* data, size_t bytes, int target);

  // A FLOAT accessor of `count` elements of `type` ("SCALAR", "VEC3",
  // "VEC4"): values holds count * components floats. With min_max, the
  // accessor carries the per-component min and max (required for POSITION
  // and animation inputs, spec §3.6.2.4 and §3.11).
  int add_float_accessor(std::span<const float> values, const char* type, bool min_max, int target);

  // A SCALAR UNSIGNED_INT accessor (triangle indices).
  int add_index_accessor(std::span<const uint32_t> indices);

  size_t bin_bytes() const { return bin_.size(); }

  // The whole GLB file. The builder stays usable (finish is const).
  std::vector<uint8_t> finish() const;

 private:
  nlohmann::json doc_;
  std::vector<uint8_t> bin_;
};

// Components of an accessor type: 1 for SCALAR, 3 for VEC3, 4 for VEC4; 0 for
// a name this builder does not write.
int type_components(const std::string& type);

}  // namespace sinew::gltf_export
