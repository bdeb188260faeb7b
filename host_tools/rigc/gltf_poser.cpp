#include "gltf_poser.hpp"

#include <cstring>

#include "quantize.hpp"

namespace sinew::rigc {

bool GltfPoser::open(const std::string& path, std::string* error) {
  if (!import_gltf(path, &gltf_, error)) return false;
  // glTF skins are linear blend skinning by definition.
  std::vector<uint8_t> bytes;
  if (!compile_rig(gltf_.spec, &bytes, &report_, error)) return *error = path + ": " + *error, false;
  blob_.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(blob_.data(), bytes.data(), bytes.size());
  const auto* blob = reinterpret_cast<const uint8_t*>(blob_.data());
  size_t rig_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(blob, bytes.size(), &rig_bytes);
  if (!st.ok()) return *error = st.message, false;
  rig_arena_.assign(rig_bytes / 8 + 1, 0);
  st = rig::rig_init(blob, bytes.size(), rig_arena_.data(), rig_arena_.size() * 8, &rig_);
  if (!st.ok()) return *error = st.message, false;
  engine_arena_.assign(engine::engine_arena_bytes(rig_) / 8 + 1, 0);
  if (!engine::engine_init(rig_, engine_arena_.data(), engine_arena_.size() * 8, &engine_))
    return *error = "engine arena too small", false;
  locals_.resize(rig_.joint_count());
  return true;
}

bool GltfPoser::pose(int animation, double time, std::vector<std::array<double, 3>>* positions, std::string* error) {
  std::vector<NodeTrs> trs = rest_node_trs(gltf_.model);
  if (animation >= 0 && !sample_animation(gltf_.model, animation, time, &trs, error)) return false;
  const int32_t e = report_.length_exponent;
  for (size_t j = 0; j < locals_.size(); ++j) {
    const NodeTrs& n = trs[static_cast<size_t>(gltf_.joint_node[j])];
    skeleton::LocalPose& l = locals_[j];
    l.translation = {to_len(n.translation[0], e), to_len(n.translation[1], e), to_len(n.translation[2], e)};
    l.rotation = {to_fixed(n.rotation[0], 30), to_fixed(n.rotation[1], 30), to_fixed(n.rotation[2], 30),
                  to_fixed(n.rotation[3], 30)};
    fx::normalize(&l.rotation);
    l.scale = {to_fixed(n.scale[0], 24), to_fixed(n.scale[1], 24), to_fixed(n.scale[2], 24)};
  }
  if (!engine::engine_step_locals(&engine_, locals_)) return *error = "engine step rejected the pose", false;
  const uint32_t n = rig_.vertex_count();
  positions->resize(n);
  for (uint32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c)
      (*positions)[v][static_cast<size_t>(c)] = from_len(engine_.vertices.position[c][v], e);
  return true;
}

}  // namespace sinew::rigc
