#include "loaded_rig.hpp"

#include "firmware/builtin/builtin_rigs.hpp"
#include "sim_core/pipeline/stage_table.hpp"

namespace sinew::firmware {

namespace {

std::string joint_name(const rig::Rig& rig, uint32_t j) {
  return rig.names.empty() ? "joint" + std::to_string(j) : std::string(rig.names[j]);
}

}  // namespace

bool load_rig_bytes(hal::BlobBytes bytes, const std::string& origin, LoadedRig* out, std::string* error) {
  LoadedRig r;
  r.blob = std::move(bytes);
  size_t arena_bytes = 0, layer_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(r.blob.data(), r.blob.size, &arena_bytes);
  if (st.ok()) {
    r.arena.assign(arena_bytes / 8 + 1, 0);
    st = rig::rig_init(r.blob.data(), r.blob.size, r.arena.data(), r.arena.size() * 8, &r.rig);
  }
  if (st.ok()) st = pipeline::layers_validate(r.rig, r.blob.data(), r.blob.size, &layer_bytes);
  if (st.ok()) {
    r.layer_arena.assign(layer_bytes / 8 + 1, 0);
    st = pipeline::layers_init(r.rig, r.blob.data(), r.blob.size, r.layer_arena.data(), r.layer_arena.size() * 8,
                               &r.layers);
  }
  if (!st.ok()) return *error = origin + ": " + st.message, false;
  // Inputs are named by the joint DOF they drive. The format lets an input
  // drive none (or only synergies): it is still read, checked and logged,
  // under the name "input<k>", so every index 0 .. input_count - 1 has one.
  r.input_names.resize(r.rig.input_count);
  for (uint32_t j = 0; j < r.rig.joint_count(); ++j)
    for (uint32_t d = 0; d < r.rig.joints[j].dof_count; ++d) {
      std::string& name = r.input_names[r.rig.joints[j].first_input + d];
      if (name.empty()) name = joint_name(r.rig, j) + "." + std::to_string(d);
    }
  for (uint32_t k = 0; k < r.rig.input_count; ++k) {
    if (!r.input_names[k].empty()) continue;
    r.input_names[k] = "input" + std::to_string(k);
    r.unused_inputs.push_back(k);
  }
  for (const pipeline::ExternalInputRecord& e : r.layers.external) {
    r.input_names.push_back(e.name);
    r.external.push_back(
        {e.name, e.unit, e.min, e.max, e.quantity == static_cast<uint32_t>(pipeline::InputQuantity::kForce)});
  }
  // The spans of `rig` and `layers` point into the arenas' heap blocks,
  // which moving the vectors keeps in place.
  *out = std::move(r);
  return true;
}

bool load_rig(const std::string& builtin, const std::string& blob_path, LoadedRig* out, std::string* error) {
  if (!builtin.empty()) {
    const std::span<const uint8_t> blob = builtin_rig_blob(builtin);
    if (blob.empty()) return *error = "unknown built-in rig " + builtin + " (arm, hand)", false;
    return load_rig_bytes(hal::blob_from_bytes(blob.data(), blob.size()), "built-in " + builtin, out, error);
  }
  // The header first: a large file that is not a rig is refused after one
  // 64-byte read.
  const hal::PrefixCheck header{sizeof(rig::FileHeader),
                                [](const uint8_t* head, size_t n, uint64_t file_bytes, std::string* why) {
                                  const rig::LoadStatus st = rig::rig_check_prefix(head, n, file_bytes);
                                  if (!st.ok()) *why = st.message;
                                  return st.ok();
                                }};
  hal::BlobBytes bytes;
  if (!hal::read_blob_file(blob_path, kMaxRigFileBytes, &bytes, error, header)) return false;
  return load_rig_bytes(std::move(bytes), blob_path, out, error);
}

std::string describe_layers(const LoadedRig& r) {
  char text[1024];
  pipeline::describe_layers(r.rig, r.layers, text, sizeof text);
  return text;
}

}  // namespace sinew::firmware
