#include "gltf_model.hpp"

#include <array>
#include <cstdint>
#include <fstream>

namespace sinew::oracle::detail {
namespace {

bool starts_with(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

// Extensions that may be required without affecting skinned vertex positions,
// or (KHR_mesh_quantization) that the generic accessor reader already covers.
bool extension_is_harmless(const std::string& name) {
  return name == "KHR_mesh_quantization" || name == "KHR_lights_punctual" || starts_with(name, "KHR_materials_") ||
         starts_with(name, "KHR_texture_") || starts_with(name, "EXT_texture_");
}

}  // namespace

bool load_model(const std::string& path, tinygltf::Model* model, std::string* error) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    *error = "cannot read " + path;
    return false;
  }
  std::array<unsigned char, 12> header{};
  file.read(reinterpret_cast<char*>(header.data()), static_cast<std::streamsize>(header.size()));
  const auto header_bytes = static_cast<size_t>(file.gcount());
  const bool binary = header_bytes >= 4 && header[0] == 'g' && header[1] == 'l' && header[2] == 'T' && header[3] == 'F';
  file.clear();
  file.seekg(0, std::ios::end);
  const auto file_bytes = static_cast<uint64_t>(file.tellg());
  file.close();
  if (file_bytes == 0) {
    *error = path + ": empty file";
    return false;
  }
  if (binary) {
    // Name the commonest corruption plainly: a copy cut short.
    const uint64_t declared = header_bytes == 12 ? uint64_t{header[8]} | uint64_t{header[9]} << 8 |
                                                       uint64_t{header[10]} << 16 | uint64_t{header[11]} << 24
                                                 : 12;
    if (declared > file_bytes) {
      *error = path + ": truncated .glb: its header declares " + std::to_string(declared) + " bytes, the file has " +
               std::to_string(file_bytes);
      return false;
    }
  }

  tinygltf::TinyGLTF loader;
  std::string load_error, load_warning;
  bool loaded = false;
  try {
    loaded = binary ? loader.LoadBinaryFromFile(model, &load_error, &load_warning, path)
                    : loader.LoadASCIIFromFile(model, &load_error, &load_warning, path);
  } catch (const std::exception& e) {
    load_error = e.what();
  }
  if (!loaded) {
    *error = path + ": not a readable glTF 2.0 " + (binary ? "binary (.glb)" : "text (.gltf)") + " file";
    if (!load_error.empty()) *error += ": " + load_error;
    while (!error->empty() && (error->back() == '\n' || error->back() == ' ')) error->pop_back();
    return false;
  }
  for (const std::string& name : model->extensionsRequired) {
    if (!extension_is_harmless(name)) {
      *error = path + ": requires extension " + name + ", which the oracle does not support";
      return false;
    }
  }
  return true;
}

}  // namespace sinew::oracle::detail
