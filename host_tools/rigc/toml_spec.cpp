#include "toml_spec.hpp"

#include <toml++/toml.h>

#include <filesystem>

#include "builtin_rigs.hpp"
#include "gltf_import.hpp"
#include "toml_layers.hpp"
#include "toml_motion.hpp"

namespace sinew::rigc {
namespace {

std::string where(const std::string& path, const toml::node* n, const std::string& key) {
  std::string s = path;
  if (n != nullptr) s += ":" + std::to_string(n->source().begin.line);
  return s + ": " + key;
}

bool read_vec3(const toml::node* n, Vec3d* out) {
  const toml::array* a = n != nullptr ? n->as_array() : nullptr;
  if (a == nullptr || a->size() != 3) return false;
  for (size_t i = 0; i < 3; ++i) {
    const auto v = a->get(i)->value<double>();
    if (!v) return false;
    (*out)[i] = *v;
  }
  return true;
}

int input_index(const RigSpec& spec, const std::string& name) {
  const std::vector<std::string> names = input_names(spec);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

bool load_toml_spec(const std::string& path, RigSpec* out, std::string* error) {
  layers::LayerSpecs ignored;
  return load_toml_rig(path, out, &ignored, error);
}

bool load_toml_rig(const std::string& path, RigSpec* out, layers::LayerSpecs* layer_specs, std::string* error) {
  toml::table t;
  try {  // Debian's toml++ is built with exceptions: parse errors arrive as toml::parse_error
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    *error = path + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description());
    return false;
  }
  for (const auto& [key, node] : t) {
    static const char* const kTables[] = {"rig",  "joint",  "synergy",        "sph",   "metaballs", "muscle",
                                          "skin", "barnet", "external_input", "motion"};
    bool known = false;
    for (const char* k : kTables) known |= key.str() == k;
    if (!known) return *error = where(path, &node, std::string(key.str())) + ": unknown table", false;
  }
  if (const toml::table* rig = t["rig"].as_table())
    for (const auto& [key, node] : *rig)
      if (key.str() != "source" && key.str() != "skinning" && key.str() != "rate_hz")
        return *error = where(path, &node, "[rig] " + std::string(key.str())) + ": unknown key", false;
  const auto source = t["rig"]["source"].value<std::string>();
  if (!source) return *error = path + ": [rig] source is required (\"builtin:arm\", \"builtin:hand\" or a glTF path)", false;
  const std::string skinning = t["rig"]["skinning"].value_or<std::string>("dqs");
  if (skinning != "lbs" && skinning != "dqs")
    return *error = where(path, t["rig"]["skinning"].node(), "[rig] skinning") + " must be \"lbs\" or \"dqs\"", false;
  const SkinChoice method = skinning == "dqs" ? SkinChoice::kDualQuaternion : SkinChoice::kLinear;
  if (source->rfind("builtin:", 0) == 0) {
    if (!builtin_rig(source->substr(8), method, out))
      return *error = where(path, t["rig"]["source"].node(), "[rig] source") + ": unknown built-in rig", false;
  } else {
    const std::filesystem::path model = std::filesystem::path(path).parent_path() / *source;
    GltfRig gltf;
    if (!import_gltf(model.string(), &gltf, error)) return false;
    *out = gltf.spec;
    out->source_node = gltf.joint_node;
    for (VertexSpec& v : out->vertices) v.dual_quaternion = method == SkinChoice::kDualQuaternion;
  }
  if (const toml::array* joints = t["joint"].as_array()) {
    for (const toml::node& jn : *joints) {
      const toml::table* j = jn.as_table();
      const auto name = j != nullptr ? (*j)["name"].value<std::string>() : std::nullopt;
      if (!name) return *error = where(path, &jn, "[[joint]] name") + " is required", false;
      const int index = joint_index(*out, *name);
      if (index < 0) return *error = where(path, &jn, "[[joint]] name") + ": no joint named '" + *name + "'", false;
      JointSpec& js = out->joints[static_cast<size_t>(index)];
      const std::string kind = (*j)["kind"].value_or<std::string>("rotation");
      if (kind != "rotation" && kind != "translation")
        return *error = where(path, &jn, "[[joint]] kind") + " must be \"rotation\" or \"translation\"", false;
      js.dof_kind = kind == "rotation" ? DofKind::kRotation : DofKind::kTranslation;
      js.dofs.clear();
      if (const toml::array* dofs = (*j)["dofs"].as_array()) {
        for (const toml::node& dn : *dofs) {
          const toml::table* d = dn.as_table();
          DofSpec dof;
          if (d == nullptr || !read_vec3((*d)["axis"].node(), &dof.axis))
            return *error = where(path, &dn, *name + " dofs.axis") + " must be an array of 3 numbers", false;
          dof.min = (*d)["min"].value_or(-180.0);
          dof.max = (*d)["max"].value_or(180.0);
          js.dofs.push_back(dof);
        }
      }
      if (js.dofs.size() > 3) return *error = where(path, &jn, *name + " dofs") + ": at most 3", false;
    }
  }
  // Synergies refer to input names, which depend on the final DOFs: read them last.
  if (const toml::array* syn = t["synergy"].as_array()) {
    for (const toml::node& sn : *syn) {
      const toml::table* s = sn.as_table();
      SynergySpec spec;
      const std::string src = s != nullptr ? (*s)["source"].value_or<std::string>("") : "";
      spec.source_input = input_index(*out, src);
      if (spec.source_input < 0) return *error = where(path, &sn, "[[synergy]] source") + ": no input named '" + src + "'", false;
      const std::string target = (*s)["target"].value_or<std::string>("");
      spec.target_joint = joint_index(*out, target);
      if (spec.target_joint < 0) return *error = where(path, &sn, "[[synergy]] target") + ": no joint named '" + target + "'", false;
      spec.target_dof = (*s)["dof"].value_or(0);
      spec.gain = (*s)["gain"].value_or(1.0);
      out->synergies.push_back(spec);
    }
  }
  // The [motion] table is checked here too, so rigc refuses a bad one.
  std::vector<motion::BvhJointName> bvh_joints;
  return read_toml_motion(path, t, *out, &bvh_joints, error) && read_toml_layers(path, t, layer_specs, error);
}

}  // namespace sinew::rigc
