#include "toml_motion.hpp"

#include "builtin_rigs.hpp"

namespace sinew::rigc {
namespace {

std::string line_of(const std::string& path, const toml::node* n, const std::string& key) {
  std::string s = path;
  if (n != nullptr) s += ":" + std::to_string(n->source().begin.line);
  return s + ": " + key;
}

}  // namespace

bool read_toml_motion(const std::string& path, const toml::table& t, const RigSpec& spec,
                      std::vector<motion::BvhJointName>* out, std::string* error) {
  out->clear();
  const toml::node* m = t.get("motion");
  if (m == nullptr) return true;
  const toml::table* motion = m->as_table();
  if (motion == nullptr) return *error = line_of(path, m, "[motion]") + " must be a table", false;
  for (const auto& [key, node] : *motion)
    if (key.str() != "bvh_joints")
      return *error = line_of(path, &node, "[motion] " + std::string(key.str())) + ": unknown key", false;
  const toml::node* b = motion->get("bvh_joints");
  if (b == nullptr) return true;
  const toml::table* names = b->as_table();
  if (names == nullptr)
    return *error = line_of(path, b, "[motion] bvh_joints") + " must be a table of rig joint = \"BVH joint\"", false;
  for (const auto& [key, node] : *names) {
    const std::string rig_joint(key.str());
    const std::string where = line_of(path, &node, "[motion.bvh_joints] " + rig_joint);
    const auto bvh_joint = node.value_exact<std::string>();
    if (!bvh_joint || bvh_joint->empty())
      return *error = where + " must be a BVH joint name (a non-empty string)", false;
    if (joint_index(spec, rig_joint) < 0) return *error = where + ": the rig has no joint '" + rig_joint + "'", false;
    out->push_back({rig_joint, *bvh_joint, where});
  }
  return true;
}

bool load_toml_motion(const std::string& path, const RigSpec& spec, std::vector<motion::BvhJointName>* out,
                      std::string* error) {
  toml::table t;
  try {  // Debian's toml++ is built with exceptions: parse errors arrive as toml::parse_error
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    *error = path + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description());
    return false;
  }
  return read_toml_motion(path, t, spec, out, error);
}

std::vector<motion::RigJointDofs> rig_joint_dofs(const RigSpec& spec) {
  std::vector<motion::RigJointDofs> out;
  for (const JointSpec& j : spec.joints) {
    motion::RigJointDofs r;
    r.name = j.name;
    r.rotation = j.dof_kind == DofKind::kRotation;
    for (const DofSpec& d : j.dofs) r.axes.push_back(d.axis);
    out.push_back(r);
  }
  return out;
}

}  // namespace sinew::rigc
