#include "toml_spec.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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

// A chain's weights must sum to 1 (the chain's values then sum to the
// command); this admits decimal spellings such as 0.3 + 0.3 + 0.4.
constexpr double kWeightSumTolerance = 1e-6;

// One [[synergy]] table. Either a coupling (`target`, `dof`, `gain`: the
// target DOF adds gain x the source, which keeps all of its command) or a
// chain (`chain`, optional `weights`: anatomically-based §3, the command is
// spread over the chain's DOFs, whose values sum to it). A chain lists input
// names ("joint.dof") and must hold the source; the source keeps its own
// weight, every other member becomes a shared SynergySpec.
bool read_synergy(const std::string& path, const toml::node& sn, RigSpec* out, std::string* error) {
  const toml::table* s = sn.as_table();
  if (s == nullptr) return *error = where(path, &sn, "[[synergy]]") + " must be a table", false;
  for (const auto& [key, node] : *s) {
    static const char* const kKeys[] = {"source", "target", "dof", "gain", "chain", "weights"};
    bool known = false;
    for (const char* k : kKeys) known |= key.str() == k;
    if (!known) return *error = where(path, &node, "[[synergy]] " + std::string(key.str())) + ": unknown key", false;
  }
  const std::string src = (*s)["source"].value_or<std::string>("");
  const int source = input_index(*out, src);
  if (source < 0) return *error = where(path, &sn, "[[synergy]] source") + ": no input named '" + src + "'", false;
  const toml::array* chain = (*s)["chain"].as_array();
  if (chain == nullptr) {
    if ((*s)["weights"].node() != nullptr)
      return *error = where(path, (*s)["weights"].node(), "[[synergy]] weights") + ": only with chain", false;
    SynergySpec spec;
    spec.source_input = source;
    const std::string target = (*s)["target"].value_or<std::string>("");
    spec.target_joint = joint_index(*out, target);
    if (spec.target_joint < 0)
      return *error = where(path, &sn, "[[synergy]] target") + ": no joint named '" + target + "'", false;
    spec.target_dof = (*s)["dof"].value_or(0);
    spec.gain = (*s)["gain"].value_or(1.0);
    out->synergies.push_back(spec);
    return true;
  }
  for (const char* k : {"target", "dof", "gain"})
    if (const toml::node* n = (*s)[k].node())
      return *error = where(path, n, std::string("[[synergy]] ") + k) + ": not with chain (use weights)", false;
  const toml::node* chain_node = (*s)["chain"].node();
  std::vector<int> members;
  for (const toml::node& m : *chain) {
    const std::optional<std::string> name = m.value<std::string>();
    const int input = name ? input_index(*out, *name) : -1;
    if (input < 0)
      return *error = where(path, &m, "[[synergy]] chain") + ": no input named '" + name.value_or("") + "'", false;
    for (const int other : members)
      if (other == input) return *error = where(path, &m, "[[synergy]] chain") + ": '" + *name + "' twice", false;
    members.push_back(input);
  }
  if (members.size() < 2) return *error = where(path, chain_node, "[[synergy]] chain") + ": at least 2 inputs", false;
  size_t source_at = members.size();
  for (size_t i = 0; i < members.size(); ++i)
    if (members[i] == source) source_at = i;
  if (source_at == members.size())
    return *error = where(path, chain_node, "[[synergy]] chain") + ": must hold the source '" + src + "'", false;
  for (const SynergySpec& e : out->synergies)
    if (e.share && e.source_input == source)
      return *error = where(path, &sn, "[[synergy]] source") + ": '" + src + "' already heads a chain", false;
  // Default: equal shares (the paper's 12 degrees over 12 vertebrae).
  std::vector<double> weights(members.size(), 1.0 / static_cast<double>(members.size()));
  if (const toml::node* wn = (*s)["weights"].node()) {
    const toml::array* w = wn->as_array();
    if (w == nullptr || w->size() != members.size())
      return *error = where(path, wn, "[[synergy]] weights") + ": one number per chain input", false;
    double sum = 0;
    for (size_t i = 0; i < members.size(); ++i) {
      const std::optional<double> v = w->get(i)->value<double>();
      if (!v || !(*v >= 0 && *v <= 1))
        return *error = where(path, w->get(i), "[[synergy]] weights") + ": each in [0, 1]", false;
      weights[i] = *v;
      sum += *v;
    }
    if (!(std::fabs(sum - 1) <= kWeightSumTolerance))
      return *error = where(path, wn, "[[synergy]] weights") + ": must sum to 1, not " + std::to_string(sum), false;
  }
  const std::vector<std::string> names = input_names(*out);
  for (size_t i = 0; i < members.size(); ++i) {
    if (i == source_at) continue;
    const std::string& name = names[static_cast<size_t>(members[i])];
    const size_t dot = name.rfind('.');
    SynergySpec spec;
    spec.source_input = source;
    spec.target_joint = joint_index(*out, name.substr(0, dot));
    spec.target_dof = std::stoi(name.substr(dot + 1));
    spec.gain = weights[i];
    spec.share = true;
    out->synergies.push_back(spec);
  }
  return true;
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
    static const char* const kTables[] = {"rig", "joint", "synergy", "motion"};
    bool known = is_layer_table(key.str());
    for (const char* k : kTables) known |= key.str() == k;
    if (!known) return *error = where(path, &node, std::string(key.str())) + ": unknown table", false;
  }
  if (const toml::table* rig = t["rig"].as_table())
    for (const auto& [key, node] : *rig)
      if (key.str() != "source" && key.str() != "skinning" && key.str() != "rate_hz")
        return *error = where(path, &node, "[rig] " + std::string(key.str())) + ": unknown key", false;
  const auto source = t["rig"]["source"].value<std::string>();
  if (!source)
    return *error = path + ": [rig] source is required (\"builtin:arm\", \"builtin:hand\" or a glTF path)", false;
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
    for (const toml::node& sn : *syn)
      if (!read_synergy(path, sn, out, error)) return false;
  }
  // The [motion] table is checked here too, so rigc refuses a bad one.
  std::vector<motion::BvhJointName> bvh_joints;
  return read_toml_motion(path, t, *out, &bvh_joints, error) && read_toml_layers(path, t, layer_specs, error);
}

}  // namespace sinew::rigc
