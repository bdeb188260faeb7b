#pragma once
// tinygltf, included the one way the project allows: nlohmann/json first, and
// the implementation lives in sinew_tinygltf (host_tools/gltf) only.
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>
#include <string>

namespace sinew::oracle::detail {

// Loads a .gltf or .glb (chosen by the file's magic bytes, not its name) and
// rejects required extensions that would change the geometry the oracle reads
// (mesh compression): silently reading zeros there would make a wrong oracle.
bool load_model(const std::string& path, tinygltf::Model* model, std::string* error);

}  // namespace sinew::oracle::detail
