// An independent reader of GLB files for the export tests: the container of
// glTF 2.0 §4.4 (header, JSON and BIN chunks) and FLOAT accessor data, with
// every check a reader must make, so the writer's output is parsed back, not
// trusted.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sinew::test {

struct ParsedGlb {
  uint32_t version = 0, total_length = 0, json_length = 0, bin_length = 0;
  nlohmann::json doc;
  std::vector<uint8_t> bin;
};

inline uint32_t glb_u32(const std::vector<uint8_t>& b, size_t at) {
  return uint32_t{b[at]} | uint32_t{b[at + 1]} << 8 | uint32_t{b[at + 2]} << 16 | uint32_t{b[at + 3]} << 24;
}

// "" when the bytes are a well-formed GLB with a JSON and a BIN chunk.
inline std::string parse_glb(const std::vector<uint8_t>& b, ParsedGlb* out) {
  if (b.size() < 28) return "shorter than a header and a chunk header";
  if (glb_u32(b, 0) != 0x46546C67u) return "bad magic";
  out->version = glb_u32(b, 4);
  out->total_length = glb_u32(b, 8);
  if (out->total_length != b.size()) return "header length is not the file size";
  out->json_length = glb_u32(b, 12);
  if (glb_u32(b, 16) != 0x4E4F534Au) return "first chunk is not JSON";
  if (out->json_length % 4 != 0) return "JSON chunk length is not a multiple of 4";
  const size_t bin_at = 20 + size_t{out->json_length};
  if (bin_at + 8 > b.size()) return "JSON chunk runs past the file";
  out->doc = nlohmann::json::parse(b.begin() + 20, b.begin() + static_cast<std::ptrdiff_t>(bin_at), nullptr, false);
  if (out->doc.is_discarded()) return "JSON chunk does not parse";
  out->bin_length = glb_u32(b, bin_at);
  if (glb_u32(b, bin_at + 4) != 0x004E4942u) return "second chunk is not BIN";
  if (out->bin_length % 4 != 0) return "BIN chunk length is not a multiple of 4";
  if (bin_at + 8 + out->bin_length != b.size()) return "BIN chunk does not end the file";
  out->bin.assign(b.begin() + static_cast<std::ptrdiff_t>(bin_at + 8), b.end());
  return "";
}

inline std::vector<uint8_t> read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The floats of a tightly packed FLOAT accessor (empty if it is not one).
inline std::vector<float> accessor_floats(const ParsedGlb& glb, size_t index) {
  const nlohmann::json& a = glb.doc["accessors"][index];
  if (a["componentType"] != 5126) return {};
  const std::string type = a["type"];
  const size_t comps = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
  const nlohmann::json& v = glb.doc["bufferViews"][a["bufferView"].get<size_t>()];
  const size_t offset = v["byteOffset"].get<size_t>() + a.value("byteOffset", size_t{0});
  const size_t n = a["count"].get<size_t>() * comps;
  if (comps == 0 || offset + 4 * n > glb.bin.size() || 4 * n > v["byteLength"].get<size_t>()) return {};
  std::vector<float> out(n);
  std::memcpy(out.data(), glb.bin.data() + offset, 4 * n);
  return out;
}

}  // namespace sinew::test
