#include "synthetic_gltf.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace sinew::oracle::testing {
namespace {

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* const alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    unsigned value = 0;
    for (size_t k = 0; k < 3; ++k) value = (value << 8) | (k < n ? bytes[i + k] : 0u);
    for (size_t k = 0; k < 4; ++k) out += k <= n ? alphabet[(value >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

// Files handed out by temp_path, removed when the test program exits.
struct TempFiles {
  std::vector<std::string> paths;
  ~TempFiles() {
    for (const std::string& path : paths) std::remove(path.c_str());
  }
};

TempFiles& temp_files() {
  static TempFiles files;
  return files;
}

}  // namespace

GltfBuilder::GltfBuilder() {
  doc = {{"asset", {{"version", "2.0"}}},
         {"bufferViews", nlohmann::json::array()},
         {"accessors", nlohmann::json::array()}};
}

int GltfBuilder::add_raw_view(const std::vector<unsigned char>& raw, int byte_stride) {
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", bytes_.size()}, {"byteLength", raw.size()}};
  if (byte_stride > 0) view["byteStride"] = byte_stride;
  bytes_.insert(bytes_.end(), raw.begin(), raw.end());
  bytes_.resize((bytes_.size() + 3) / 4 * 4, 0);
  doc["bufferViews"].push_back(view);
  return static_cast<int>(doc["bufferViews"].size()) - 1;
}

int GltfBuilder::add_accessor(int view, int component_type, size_t count, const std::string& type,
                              const nlohmann::json& extra) {
  nlohmann::json accessor = {{"componentType", component_type}, {"count", count}, {"type", type}};
  if (view >= 0) accessor["bufferView"] = view;
  accessor.update(extra);
  doc["accessors"].push_back(accessor);
  return static_cast<int>(doc["accessors"].size()) - 1;
}

std::string GltfBuilder::write(const std::string& file_name) const {
  nlohmann::json out = doc;
  out["buffers"] = nlohmann::json::array(
      {{{"byteLength", bytes_.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes_)}}});
  const std::string path = temp_path(file_name);
  std::ofstream(path) << out.dump();
  return path;
}

std::string temp_path(const std::string& file_name) {
  const std::string unique = "sinew_oracle_" + std::to_string(getpid()) + "_" + file_name;
  const std::string path = (std::filesystem::temp_directory_path() / unique).string();
  temp_files().paths.push_back(path);
  return path;
}

}  // namespace sinew::oracle::testing
