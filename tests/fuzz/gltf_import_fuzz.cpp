// libFuzzer target: any bytes as a glTF model, a .glb when they start with
// the magic "glTF", else a .gltf (JSON), imported from memory as rigc imports
// a file (tinygltf, the accessors, skins, the node hierarchy) and compiled
// into a rig blob. No external buffer is read: the harness gives no base
// directory. A blob the compiler produces must be one the loader accepts.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "host_tools/rigc/gltf_import.hpp"
#include "sim_core/rig/rig.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sinew::rigc::GltfRig gltf;
  std::string error;
  if (!sinew::rigc::import_gltf_from_memory(std::span<const uint8_t>(data, size), "fuzz", "", &gltf, &error)) {
    if (error.empty()) __builtin_trap();
    return 0;
  }
  std::vector<uint8_t> blob;
  sinew::rigc::CompileReport report;
  if (!sinew::rigc::compile_rig(gltf.spec, &blob, &report, &error)) {
    if (error.empty()) __builtin_trap();
    return 0;
  }
  // The loader wants 8-byte alignment, as a blob read from a file has.
  std::vector<uint64_t> aligned(blob.size() / 8 + 1);
  std::memcpy(aligned.data(), blob.data(), blob.size());
  const auto* p = reinterpret_cast<const uint8_t*>(aligned.data());
  size_t rig_bytes = 0;
  if (!sinew::rig::rig_validate(p, blob.size(), &rig_bytes).ok()) __builtin_trap();
  std::vector<uint64_t> arena(rig_bytes / 8 + 1);
  sinew::rig::Rig rig;
  if (!sinew::rig::rig_init(p, blob.size(), arena.data(), arena.size() * 8, &rig).ok()) __builtin_trap();
  if (rig.vertex_count() != report.vertices) __builtin_trap();
  return 0;
}
