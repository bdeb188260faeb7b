#include "bvh_drive.hpp"

#include <cmath>
#include <numbers>

#include "text_scan.hpp"

namespace sinew::motion {

bool resolve_bvh_joints(const Bvh& bvh, const std::vector<RigJointDofs>& rig, const std::vector<BvhJointName>& table,
                        std::vector<int>* bvh_joint_of_rig, std::string* error) {
  bvh_joint_of_rig->assign(rig.size(), -1);
  for (const BvhJointName& entry : table) {
    size_t r = 0;
    while (r < rig.size() && rig[r].name != entry.rig_joint) ++r;
    if (r == rig.size()) return *error = cat(entry.where, ": the rig has no joint ", quoted(entry.rig_joint)), false;
    const int b = bvh.find_joint(entry.bvh_joint);
    if (b < 0) return *error = cat(entry.where, ": the BVH file has no joint ", quoted(entry.bvh_joint)), false;
    (*bvh_joint_of_rig)[r] = b;
  }
  bool any = false;
  for (size_t r = 0; r < rig.size(); ++r) {
    bool in_table = false;
    for (const BvhJointName& entry : table) in_table |= entry.rig_joint == rig[r].name;
    if (!in_table) (*bvh_joint_of_rig)[r] = bvh.find_joint(rig[r].name);
    any |= (*bvh_joint_of_rig)[r] >= 0;
  }
  if (!any) {
    std::string names;
    for (const RigJointDofs& j : rig) names += (names.empty() ? "" : ", ") + quoted(j.name);
    return *error =
               cat("no rig joint (", names, ") names a BVH joint; map them in the spec's [motion.bvh_joints] table"),
           false;
  }
  return true;
}

double twist_degrees(const Quaternion& q, const Vec3& axis) {
  const double along = q.x * axis[0] + q.y * axis[1] + q.z * axis[2];
  double degrees = 2.0 * std::atan2(along, q.w) * (180.0 / std::numbers::pi);
  if (degrees > 180.0) degrees -= 360.0;
  if (degrees <= -180.0) degrees += 360.0;
  return degrees;
}

bool bvh_to_joint_tracks(const Bvh& bvh, const std::vector<RigJointDofs>& rig, const std::vector<BvhJointName>& table,
                         JointTracks* out, std::string* error) {
  std::vector<int> source;
  if (!resolve_bvh_joints(bvh, rig, table, &source, error)) return false;
  if (bvh.frame_count == 0) return *error = "the BVH file has no frames", false;
  JointTracks tracks;
  for (const RigJointDofs& j : rig)
    for (size_t d = 0; d < j.axes.size(); ++d) tracks.tracks.push_back({j.name, std::to_string(d)});
  for (size_t f = 0; f < bvh.frame_count; ++f) {
    tracks.times.push_back(static_cast<double>(f) * bvh.frame_time);
    for (size_t r = 0; r < rig.size(); ++r) {
      const RigJointDofs& j = rig[r];
      if (source[r] < 0) {
        tracks.values.insert(tracks.values.end(), j.axes.size(), 0.0);
        continue;
      }
      const auto b = static_cast<size_t>(source[r]);
      const Quaternion q = local_rotation(bvh, b, f);
      const Vec3 t = local_translation(bvh, b, f);
      const Vec3& rest = bvh.joints[b].offset;
      for (const Vec3& axis : j.axes) {
        const double value = j.rotation
                                 ? twist_degrees(q, axis)
                                 : (t[0] - rest[0]) * axis[0] + (t[1] - rest[1]) * axis[1] + (t[2] - rest[2]) * axis[2];
        if (!std::isfinite(value))
          return *error = cat("frame ", std::to_string(f + 1), ", joint ", quoted(bvh.joints[b].name),
                              ": the DOF value is not finite"),
                 false;
        tracks.values.push_back(value);
      }
    }
  }
  *out = std::move(tracks);
  return true;
}

}  // namespace sinew::motion
