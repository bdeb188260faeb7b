#include "motion_tracks.hpp"

#include <cctype>

#include "builtin_rigs.hpp"
#include "toml_motion.hpp"

namespace sinew::rigc {

bool is_bvh_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bvh";
}

bool load_motion_tracks(const std::string& path, const RigSpec& spec,
                        const std::vector<motion::BvhJointName>& bvh_joints, motion::JointTracks* out,
                        std::string* error) {
  if (is_bvh_path(path)) {
    motion::Bvh bvh;
    if (!motion::load_bvh(path, &bvh, error)) return false;
    if (!motion::bvh_to_joint_tracks(bvh, rig_joint_dofs(spec), bvh_joints, out, error))
      return *error = path + ": " + *error, false;
    return true;
  }
  if (!motion::load_csv_tracks(path, out, error)) return false;
  const std::vector<std::string> inputs = input_names(spec);
  for (const motion::TrackName& t : out->tracks) {
    const std::string name = t.joint + "." + t.dof;
    bool known = false;
    for (const std::string& i : inputs) known |= i == name;
    if (!known) return *error = path + ": column '" + name + "' names no rig input", false;
  }
  return true;
}

}  // namespace sinew::rigc
