// A run of the deformed surface, ready to export: the rest surface, the
// skeleton, and sampled frames. Host-side data in glTF's terms: metres,
// float, xyz interleaved, quaternions as (x, y, z, w).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sinew::gltf_export {

// The default bound on exported frames: at 4192 vertices a frame is about
// 100 KB of morph target, so 1000 frames make about 100 MB.
inline constexpr uint32_t kMaxExportFrames = 1000;

struct JointTransform {
  float translation[3] = {0, 0, 0};  // metres, in the parent's frame
  float rotation[4] = {0, 0, 0, 1};  // unit quaternion x, y, z, w
  float scale[3] = {1, 1, 1};
};

struct ClipJoint {
  std::string name;
  int32_t parent = -1;  // -1 for a root; otherwise an earlier joint
};

struct ClipFrame {
  double time_s = 0;                   // seconds from the first exported frame
  std::vector<float> position;         // 3 * V, metres, the rig's model space
  std::vector<float> normal;           // 3 * V, unit
  std::vector<JointTransform> joints;  // one per joint, local
};

struct SurfaceClip {
  std::string generator;             // asset.generator, e.g. "sinew-export"
  std::vector<float> rest_position;  // 3 * V, metres
  std::vector<float> rest_normal;    // 3 * V, unit
  std::vector<uint32_t> triangles;   // 3 per triangle, < V
  std::vector<ClipJoint> joints;
  std::vector<JointTransform> rest_joints;  // one per joint
  std::vector<ClipFrame> frames;            // times strictly increasing
  // Free-form facts about the source (the log, the rig), kept in the
  // document's extras.
  std::vector<std::pair<std::string, std::string>> notes;

  uint32_t vertex_count() const { return static_cast<uint32_t>(rest_position.size() / 3); }
};

}  // namespace sinew::gltf_export
