// The single translation unit that instantiates tinygltf. Images are not
// decoded: sinew reads geometry, skins and animations only.
#include <nlohmann/json.hpp>
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
