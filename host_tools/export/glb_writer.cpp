#include "glb_writer.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace sinew::gltf_export {
namespace {

// Buffers are copied as the host holds them; GLB is little-endian.
static_assert(std::endian::native == std::endian::little, "the GLB writer copies host floats as they are");

size_t padded4(size_t n) { return (n + 3u) & ~size_t{3}; }

void put_u32(std::vector<uint8_t>* out, uint32_t v) {
  for (int b = 0; b < 4; ++b) out->push_back(static_cast<uint8_t>(v >> (8 * b)));  // GLB is little-endian
}

}  // namespace

int type_components(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  return 0;
}

GlbBuilder::GlbBuilder(const std::string& generator) {
  doc_["asset"] = {{"version", "2.0"}, {"generator", generator}};
  doc_["buffers"] = nlohmann::json::array();
  doc_["bufferViews"] = nlohmann::json::array();
  doc_["accessors"] = nlohmann::json::array();
}

int GlbBuilder::add_view(const void* data, size_t bytes, int target) {
  // Every view starts 4-byte aligned, so accessors of 4-byte components at
  // offset 0 meet the spec's alignment rule (§3.6.2.4).
  bin_.resize(padded4(bin_.size()), 0);
  const size_t offset = bin_.size();
  bin_.resize(offset + bytes);
  if (bytes > 0) std::memcpy(bin_.data() + offset, data, bytes);
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (target != 0) view["target"] = target;
  doc_["bufferViews"].push_back(view);
  return static_cast<int>(doc_["bufferViews"].size()) - 1;
}

int GlbBuilder::add_float_accessor(std::span<const float> values, const char* type, bool min_max, int target) {
  const int components = type_components(type);
  if (components == 0 || values.empty() || values.size() % static_cast<size_t>(components) != 0)
    throw std::invalid_argument(std::string("glb accessor: ") + std::to_string(values.size()) +
                                " floats do not make whole elements of " + type);
  const size_t count = values.size() / static_cast<size_t>(components);
  const int view = add_view(values.data(), values.size() * sizeof(float), target);
  nlohmann::json accessor = {
      {"bufferView", view}, {"componentType", kComponentFloat}, {"count", count}, {"type", type}};
  if (min_max) {
    std::vector<float> lo(static_cast<size_t>(components), std::numeric_limits<float>::infinity());
    std::vector<float> hi(static_cast<size_t>(components), -std::numeric_limits<float>::infinity());
    for (size_t i = 0; i < values.size(); ++i) {
      const size_t c = i % static_cast<size_t>(components);
      lo[c] = std::min(lo[c], values[i]);
      hi[c] = std::max(hi[c], values[i]);
    }
    // Stored as the doubles the floats are: nlohmann prints them so they read
    // back exactly, and validators compare them with the buffer's values.
    accessor["min"] = nlohmann::json(std::vector<double>(lo.begin(), lo.end()));
    accessor["max"] = nlohmann::json(std::vector<double>(hi.begin(), hi.end()));
  }
  doc_["accessors"].push_back(accessor);
  return static_cast<int>(doc_["accessors"].size()) - 1;
}

int GlbBuilder::add_index_accessor(std::span<const uint32_t> indices) {
  if (indices.empty()) throw std::invalid_argument("glb accessor: no indices");
  const int view = add_view(indices.data(), indices.size() * sizeof(uint32_t), kTargetElementArrayBuffer);
  doc_["accessors"].push_back(
      {{"bufferView", view}, {"componentType", kComponentUnsignedInt}, {"count", indices.size()}, {"type", "SCALAR"}});
  return static_cast<int>(doc_["accessors"].size()) - 1;
}

std::vector<uint8_t> GlbBuilder::finish() const {
  const size_t bin_padded = padded4(bin_.size());
  nlohmann::json doc = doc_;
  doc["buffers"] = nlohmann::json::array({{{"byteLength", bin_padded}}});
  std::string json = doc.dump();
  json.resize(padded4(json.size()), ' ');  // the JSON chunk is padded with spaces (§4.4.3.1)
  const size_t total = 12 + 8 + json.size() + 8 + bin_padded;
  if (total > std::numeric_limits<uint32_t>::max())
    throw std::length_error("glb: " + std::to_string(total) + " bytes is over the 4 GiB a GLB header can state");
  std::vector<uint8_t> out;
  out.reserve(total);
  put_u32(&out, kGlbMagic);
  put_u32(&out, 2);
  put_u32(&out, static_cast<uint32_t>(total));
  put_u32(&out, static_cast<uint32_t>(json.size()));
  put_u32(&out, kGlbJsonChunk);
  out.insert(out.end(), json.begin(), json.end());
  put_u32(&out, static_cast<uint32_t>(bin_padded));
  put_u32(&out, kGlbBinChunk);
  out.insert(out.end(), bin_.begin(), bin_.end());
  out.resize(total, 0);  // the BIN chunk is padded with zeros
  return out;
}

}  // namespace sinew::gltf_export
