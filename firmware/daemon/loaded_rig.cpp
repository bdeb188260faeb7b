#include "loaded_rig.hpp"

#include <cstring>
#include <fstream>
#include <iterator>

#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::firmware {

bool load_rig(const std::string& builtin, const std::string& blob_path, LoadedRig* out, std::string* error) {
  std::vector<uint8_t> bytes;
  if (!builtin.empty()) {
    rigc::RigSpec spec;
    if (!rigc::builtin_rig(builtin, rigc::SkinChoice::kDualQuaternion, &spec))
      return *error = "unknown built-in rig " + builtin, false;
    rigc::CompileReport report;
    if (!rigc::compile_rig(spec, &bytes, &report, error)) return false;
  } else {
    std::ifstream f(blob_path, std::ios::binary);
    if (!f) return *error = blob_path + ": cannot open", false;
    bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  out->blob.assign(bytes.size() / 8 + 1, 0);
  if (!bytes.empty()) std::memcpy(out->blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(out->blob.data());
  size_t arena_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(data, bytes.size(), &arena_bytes);
  if (st.ok()) {
    out->arena.assign(arena_bytes / 8 + 1, 0);
    st = rig::rig_init(data, bytes.size(), out->arena.data(), out->arena.size() * 8, &out->rig);
  }
  if (!st.ok()) return *error = (blob_path.empty() ? builtin : blob_path) + ": " + st.message, false;
  out->input_names.clear();
  out->external.clear();
  for (uint32_t j = 0; j < out->rig.joint_count(); ++j) {
    const std::string joint = out->rig.names.empty() ? "joint" + std::to_string(j) : std::string(out->rig.names[j]);
    for (uint32_t d = 0; d < out->rig.joints[j].dof_count; ++d)
      out->input_names.push_back(joint + "." + std::to_string(d));
  }
  return true;
}

uint32_t LoadedRig::add_external(ExternalInput input) {
  input_names.push_back(input.name);
  external.push_back(std::move(input));
  return input_count() - 1;
}

}  // namespace sinew::firmware
